"""Where the hex8 step goes: ns per element-step of each pass, CPU time, one thread (issue 17).

    python benchmarks/fem_passes.py [--n 30] [--reps 5] [--calls 10] [--against DIR] [--pairs 3]

The case is ``fem_throughput.CUBE_DECK`` (elastic n^3 hex8 cube, viscous hourglass, fixed bottom,
no loads, no contact), warmed up by 5 steps. Each repetition times every pass over ``--calls``
calls with ``time.process_time`` (passes interleaved within a repetition); the table gives min and
median over the repetitions, per element and step; the derived items (B matrix, hourglass, rest,
Python) are differences of the passes' minima, one figure. Passes:

* ``step``: ``Simulation.step()``, everything;
* ``element kernel``: ``fem.kernels.solid_element_forces`` (the step's element pass), and inside it,
  measured by separate loops over the same elements that call the kernel's own functions:
  ``  gather x, v``: the element's corner coordinates, velocities and mid-step coordinates;
  ``  B matrix (2x)``: that gather plus ``hex8_gradient_faces`` (the kernel's) at mid-step and at
  x^{n+1}, less the gather;
  ``  char. length``: ``hex8_char_length``;
  ``  material``: ``rotate_stress`` + the stress update and sound speed (elastic: ``elastic_stress_update``
  and ``elastic_sound_speed``, as the kernel chooses);
  ``  hourglass``: the element kernel less the same kernel with the hourglass coefficient set to 0;
  ``  rest``: strain rate, viscosity, stable step, energy, forces (the kernel less the items above);
* ``scatter to nodes``: ``gather_nodal_forces`` (element forces summed at nodes);
* ``node update``: ``SolidDomain._solid_step`` (constraints, central difference, external work);
* ``element checks``: ``SolidDomain._check_elements`` (inverted elements, erosion);
* ``time step``: ``SolidDomain._solid_dt`` + ``Simulation._step_size``;
* ``guards``: ``Simulation.check_guards`` (finite state every step, energies every 10 steps);
* ``Python, rest``: ``step`` less every pass above (the loop's own Python).

``--against DIR`` runs the ``step`` and ``element kernel`` figures of another checkout (its root on
PYTHONPATH, e.g. ``git archive main | tar -x -C /tmp/base``) and of this one in child processes,
alternately, ``--pairs`` times, and prints min and median of the per-pair ratio.

Measured (3 December 2026, 30^3 = 27 000 elements, 1 thread, min / median of 5 repetitions x 10
calls, ns per element-step; 2-core machine shared with other helpers):

| pass | before (main 76efb01, load 4.8-5.0) | after (load 0.6) |
|---|---|---|
| step | 1715 / 1957 | 696 / 752 |
| element kernel | 1347 / 1942 | 559 / 587 |
|   gather x, v | 31 / 37 | 35 / 38 |
|   B matrix (2x) | 676 | 176 |
|   char. length | 29 / 44 | 35 / 48 |
|   material | 191 / 196 | 52 / 63 |
|   hourglass | (noise: 23-756) | 157 |
|   rest | - | 104 |
| scatter to nodes | 101 / 101 | 26 / 28 |
| node update | 15 / 15 | 13 / 14 |
| element checks, time step | 0.7 + 0.8 | 0.6 + 0.6 |
| guards | 14 / 14 | 12 / 13 |
| Python, rest | (negative: noise) | 86 |

"Python, rest" is mostly not Python: cProfile of 30 steps puts 87 % of the wall time in the
element kernel, 6 % in the scatter, 3 % in the finite-state guard and under 1 % in the Python
frames; the remainder is the element kernel running slower inside the step (its data evicted by
the other passes) than alone. The "before" derived items were differences of medians (noise).
Before/after in one run (``--against`` a copy of main 76efb01, 3 interleaved child pairs, load
0.3-0.5): step 2397 -> 920 ns (speed-up min 2.50, median 2.61), element kernel 2144 -> 729 (2.85 /
2.94). Every change keeps the results bit for bit (commit messages).

Branch hexspeed2 (factored gradient ``hex8_gradient_faces``, results moved at round-off), 3 December
2026 17:28 UTC, main 2ff2903 and the branch run alternately twice (``--reps 7``), load 3.8-4.1,
min ns per element-step of each run (two figures: run 1, run 2):

| pass | main | branch |
|---|---|---|
| step | 739, 975 | 730, 597 |
| element kernel | 666, 879 | 605, 501 |
|   B matrix (2x) | 205, 265 | 140, 107 |
|   hourglass | 210, 298 | 201, 193 |
|   material | 69, 82 | 57, 53 |
| scatter to nodes | 33, 39 | 38, 21 |

Only the B matrix moves beyond the run-to-run spread of this shared machine (an earlier pair at
load 4-5: 159 -> 102); the hourglass (the largest pass now) is unchanged.
"""
from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
if str(HERE) not in sys.path:
    sys.path.insert(0, str(HERE))


def build(n: int):
    import numba

    from fem_throughput import CUBE_DECK

    from sphfem_cli.driver import load_model
    from sphfem_cli.solver.explicit import Simulation

    numba.set_num_threads(1)
    with tempfile.TemporaryDirectory() as tmp:
        deck = Path(tmp) / "cube.yaml"
        deck.write_text(CUBE_DECK.format(n=n))
        model = load_model(str(deck)).model
    sim = Simulation(model)
    for _ in range(5):
        sim.step()
    return sim


def stage_kernels():
    """Loops over the elements calling the element kernel's own functions, one stage each."""
    import numpy as np
    from numba import njit

    from sphfem_cli.fem.geometry import hex8_char_length, hex8_gradient_faces
    from sphfem_cli.fem.kernels import rotate_stress
    from sphfem_cli.materials.ids import ELASTIC, EOS_NONE
    from sphfem_cli.materials.kernels import elastic_sound_speed, elastic_stress_update, sound_speed, update_stress
    from sphfem_cli.materials.slots import P_EOS_TYPE

    @njit
    def gather(x, v, conn, dt, out):
        xe = np.empty((8, 3))
        xm = np.empty((8, 3))
        ve = np.empty((8, 3))
        acc = 0.0
        for e in range(conn.shape[0]):
            for a in range(8):
                n = conn[e, a]
                for k in range(3):
                    xe[a, k] = x[n, k]
                    ve[a, k] = v[n, k]
                    xm[a, k] = x[n, k] - 0.5 * dt * v[n, k]
            acc += xe[3, 1] + xm[2, 2] + ve[1, 1]  # keeps the loads
        out[0] = acc

    @njit
    def gather_gradients(x, v, conn, dt, out):
        xe = np.empty((8, 3))
        xm = np.empty((8, 3))
        ve = np.empty((8, 3))
        b = np.empty((3, 8))
        bm = np.empty((3, 8))
        acc = 0.0
        for e in range(conn.shape[0]):
            for a in range(8):
                n = conn[e, a]
                for k in range(3):
                    xe[a, k] = x[n, k]
                    ve[a, k] = v[n, k]
                    xm[a, k] = x[n, k] - 0.5 * dt * v[n, k]
            acc += hex8_gradient_faces(xm, bm) + hex8_gradient_faces(xe, b) + b[1, 3] + bm[2, 5] + ve[1, 1]
        out[0] = acc

    @njit
    def char_length(x, conn, vol, out):
        xe = np.empty((8, 3))
        acc = 0.0
        for e in range(conn.shape[0]):
            for a in range(8):
                n = conn[e, a]
                for k in range(3):
                    xe[a, k] = x[n, k]
            acc += hex8_char_length(xe, vol[e])
        out[0] = acc

    @njit
    def material(stress, hist, elem_mat, mat_type, mat_param, vol, vol0, energy, dt, out):
        deps = np.empty(6)
        acc = 0.0
        for e in range(stress.shape[0]):
            m = elem_mat[e]
            p = mat_param[m]
            sig = stress[e]
            for c in range(6):
                deps[c] = 1e-12 * (c + 1)
            rotate_stress(sig, 1e-3, 2e-3, 3e-3, dt)
            rel = vol[e] / vol0[e]
            if mat_type[m] == ELASTIC and p[P_EOS_TYPE] == EOS_NONE:  # as the element kernel chooses
                elastic_stress_update(p, sig, deps)
                acc += elastic_sound_speed(p, rel)
            else:
                update_stress(mat_type[m], p, sig, hist[e], deps, dt, rel, energy[e] / vol0[e])
                acc += sound_speed(mat_type[m], p, rel, energy[e] / vol0[e])
        out[0] = acc

    return gather, gather_gradients, char_length, material


def measure(n: int, reps: int, calls: int, only_step: bool = False) -> dict[str, list[float]]:
    """{pass: [ns per element-step, one per repetition]}."""
    import numpy as np

    from sphfem_cli.fem import kernels as fem
    from sphfem_cli.fem.slots import SEC_HG_COEF

    sim = build(n)
    sd, st, m = sim.solids, sim.state, sim.model
    n_elem = m.n_elements
    dt = st.dt_prev
    sec_no_hg = m.section_param.copy()
    sec_no_hg[:, SEC_HG_COEF] = 0.0
    scratch = {k: getattr(st, k).copy() for k in ("stress", "hist", "energy", "hg_energy", "hg_force")}
    f_elem, dt_elem, vol, q = sd._f_elem.copy(), sd._dt_elem.copy(), st.volume.copy(), st.q_visc.copy()

    def element(sec):
        def call():  # on copies of the state: the step's own arrays are not advanced twice
            fem.solid_element_forces(
                st.x, st.v, m.connectivity, m.element_active, m.element_material, m.element_section,
                m.material_type, m.material_param, sec, m.volume0, dt, scratch["stress"], scratch["hist"],
                scratch["energy"], scratch["hg_energy"], scratch["hg_force"], f_elem, dt_elem, vol, q)
        return call

    out = np.zeros(1)
    f_int = st.f_int.copy()
    passes = {"step": sim.step, "element kernel": element(m.section_param)}
    if not only_step:
        gather, gather_gradients, char_length, material = stage_kernels()
        mat_stress, mat_hist = st.stress.copy(), st.hist.copy()

        def solid_step():
            sd._solid_step(st, st.time, 0.0, 0.0)  # a zero step: the nodes do not move

        def time_step():
            sd._solid_dt(st)
            sim._step_size(st)

        passes.update({
            "no hourglass": element(sec_no_hg),
            "gather x, v": lambda: gather(st.x, st.v, m.connectivity, dt, out),
            "gather + B": lambda: gather_gradients(st.x, st.v, m.connectivity, dt, out),
            "char. length": lambda: char_length(st.x, m.connectivity, st.volume, out),
            "material": lambda: material(mat_stress, mat_hist, m.element_material, m.material_type,
                                         m.material_param, st.volume, m.volume0, st.energy, dt, out),
            "scatter to nodes": lambda: fem.gather_nodal_forces(sd._f_elem, m.node_elem_ptr, m.node_elem_idx, f_int),
            "node update": solid_step,
            "element checks": lambda: sd._check_elements(st),
            "time step": time_step,
            "guards": sim.check_guards,
        })
    for f in passes.values():  # compiles the stage kernels
        f()
    times: dict[str, list[float]] = {k: [] for k in passes}
    for _ in range(reps):
        for name, f in passes.items():
            c0 = time.process_time()
            for _ in range(calls):
                f()
            times[name].append((time.process_time() - c0) / calls / n_elem * 1e9)
    if only_step:
        return times
    # Differences of passes from their minima (a difference of medians on a loaded machine is noise).
    t = {k: min(v) for k, v in times.items()}
    derived = {
        "B matrix (2x)": t["gather + B"] - t["gather x, v"],
        "hourglass": t["element kernel"] - t["no hourglass"],
    }
    derived["rest"] = (t["element kernel"] - t["gather x, v"] - derived["B matrix (2x)"] - t["char. length"]
                       - t["material"] - derived["hourglass"])
    outside = ("element kernel", "scatter to nodes", "node update", "element checks", "time step", "guards")
    derived["Python, rest"] = t["step"] - sum(t[k] for k in outside)
    derived = {k: [v] for k, v in derived.items()}
    times.update(derived)
    return times


ORDER = ("step", "element kernel", "gather x, v", "B matrix (2x)", "char. length", "material", "hourglass",
         "rest", "scatter to nodes", "node update", "element checks", "time step", "guards", "Python, rest")


def table(times: dict[str, list[float]]) -> str:
    lines = ["| pass | min ns | median ns |", "|---|---|---|"]
    for k in ORDER:
        if k in times:
            inner = k in ("gather x, v", "B matrix (2x)", "char. length", "material", "hourglass", "rest")
            lines.append(f"| {'  ' if inner else ''}{k} | {min(times[k]):.1f} | {statistics.median(times[k]):.1f} |")
    step = statistics.median(times["step"])
    lines.append(f"rate (median step): {1e3 / step:.3f} M element-steps/s")
    return "\n".join(lines)


def against(other: str, n: int, reps: int, calls: int, pairs: int) -> None:
    """The step and element-kernel figures of `other` and of this checkout, alternately, in children."""
    this = str(HERE.parent)
    rows: dict[str, list[dict]] = {"before": [], "after": []}
    for _ in range(pairs):
        for label, root in (("before", other), ("after", this)):
            env = dict(os.environ, PYTHONPATH=root, NUMBA_NUM_THREADS="1", OMP_NUM_THREADS="1")
            cmd = [sys.executable, str(Path(__file__).resolve()), "--n", str(n), "--reps", str(reps),
                   "--calls", str(calls), "--json-step"]
            res = subprocess.run(cmd, env=env, capture_output=True, text=True, check=True)
            rows[label].append(json.loads(res.stdout.strip().splitlines()[-1]))
    print(f"load average after: {' '.join(f'{x:.1f}' for x in os.getloadavg())}")
    print("| pass | before (median ns) | after (median ns) | speed-up min | speed-up median |")
    print("|---|---|---|---|---|")
    for k in ("step", "element kernel"):
        b = [min(r[k]) for r in rows["before"]]
        a = [min(r[k]) for r in rows["after"]]
        ratio = [x / y for x, y in zip(b, a)]
        print(f"| {k} | {statistics.median(b):.1f} | {statistics.median(a):.1f} | {min(ratio):.2f} | "
              f"{statistics.median(ratio):.2f} |")
    print(f"rate after (median of per-child min step): {1e3 / statistics.median(min(r['step']) for r in rows['after']):.3f}"
          " M element-steps/s")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--n", type=int, default=30)
    ap.add_argument("--reps", type=int, default=5)
    ap.add_argument("--calls", type=int, default=10)
    ap.add_argument("--against", help="root of another checkout: before/after, interleaved children")
    ap.add_argument("--pairs", type=int, default=3)
    ap.add_argument("--json-step", action="store_true", help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.json_step:
        print(json.dumps(measure(args.n, args.reps, args.calls, only_step=True)))
        return
    print(f"load average before: {' '.join(f'{x:.1f}' for x in os.getloadavg())}")
    if args.against:
        against(args.against, args.n, args.reps, args.calls, args.pairs)
        return
    times = measure(args.n, args.reps, args.calls)
    print(f"{args.n}^3 hex8, 1 thread, ns per element-step, {args.reps} repetitions x {args.calls} calls")
    print(table(times))
    print(f"load average after: {' '.join(f'{x:.1f}' for x in os.getloadavg())}")


if __name__ == "__main__":
    main()
