"""SPH step, pass by pass: ns per particle-step of every pass of the 2D dam break (issue 17).

    NUMBA_NUM_THREADS=1 python benchmarks/sph_passes.py [--sizes 71,212,500] [--steps N] [--repeat 3]

Case: ``sphfem_cli.sph.scenes.dam_break`` in 2D, a = 1 m, a/dx = size (71: 1.0e4 particles,
212: 9.0e4, 500: 5.0e5), ghost walls, the default options. Each size is built, advanced a few
steps (compilation, cell order), then timed over ``steps`` steps; the sizes are interleaved
``repeat`` times and min and median over the repetitions are printed. Every pass is timed by
wrapping the kernel the orchestration (``sph/system.py``) calls, with the process CPU time
(``time.process_time``) around each call:

* ``eos``: ``eos.update_particle_state`` (p, c, h);
* ``ghosts``: ``walls.make_ghosts``;
* ``cell sort``: ``search.sort_points`` (binning, gather into cell order, search radius); the
  binning alone (``search.bin_points``) is timed by a second call with the same arguments and
  printed as ``  binning`` (it is inside ``cell sort``, not added to the total);
* ``rates``: ``rates.fluid_rates``;
* ``time step``: ``integration.stable_time_step``;
* ``leapfrog``: ``integration.advance_particles``;
* ``reorder``: ``SphSystem._reorder`` (every ``reorder_every`` evaluations; averaged over all steps);
* ``rest``: the step's CPU time minus the passes above (Python orchestration, small arrays);
* ``probe (step)`` (with ``--probe``): the whole step of the fused-step probe
  (``../shared/bench/roofline_sph.py``, ``peers.py``'s ``sph2d`` peer: its cell build and rates on its
  own lattice of about the same count), timed after each size's sphfem run in the same repetition.

The load average (``os.getloadavg``) is printed before and after: on a shared machine the CPU
time of a pass includes cache and memory-bandwidth contention from the other processes.

Measured (3 December 2026, 1 thread, the 2-core machine shared with other sessions, load
average 6.4 -> 7.5; min / median of 3 interleaved repetitions, ns per particle-step; code of
main at bc9aa7c, no kernel changed on this branch, so there is no "after" yet):

=========  ==============  ==============  ===============
pass       10 082          89 888          500 000
=========  ==============  ==============  ===============
eos        81.0 / 83.9     79.7 / 80.8     77.0 / 78.2
ghosts     20.3 / 21.8     12.4 / 13.3     11.2 / 11.9
cell sort  44.8 / 46.7     46.0 / 47.6     59.6 / 104.7
rates      592.5 / 642.0   599.8 / 633.4   614.5 / 752.0
time step  18.8 / 20.2     16.3 / 16.6     15.0 / 15.7
leapfrog   39.2 / 41.8     38.2 / 40.0     37.6 / 39.1
reorder    9.6 / 11.3      9.3 / 9.5       0 (8 steps < reorder_every)
rest       34.8 / 35.2     6.4 / 6.6       2.3 / 2.4
total      841.1 / 902.7   808.5 / 847.7   864.5 / 1004.2
binning    22.6 / 24.8     22.5 / 23.7     26.8 / 36.6
=========  ==============  ==============  ===============

The cell sort at 9e4 particles is 47 ns (binning 22, gather into cell order and search radius
25), not the 116 of issue 17. From 1e4 to 5e5 the total grows +3 % by the minimum and +11 % by
the median; the growth and the spread sit in the cell sort and the rates at 5e5 (memory bound,
most sensitive to the other processes' load).

Branch sphrates (issue 17), 3 December 2026 13:32 UTC, ``--sizes 212 --repeat 3``, main (bd62e13;
9f53b3b, merged at 13:33, changes only sph/axisymmetric.py, off this path; main with its own numba
cache) and the branch run alternately twice, load average 5.0-5.8; min / median, ns per
particle-step:

=========  ===============  ===============  ===============  ===============
pass       main (1st)       branch (1st)     main (2nd)       branch (2nd)
=========  ===============  ===============  ===============  ===============
eos        85.4 / 85.5      86.5 / 88.2      72.7 / 80.3      81.2 / 82.3
ghosts     13.8 / 14.3      13.9 / 14.1      11.9 / 13.3      10.3 / 10.6
cell sort  51.4 / 52.5      53.2 / 53.6      45.3 / 51.7      40.3 / 44.2
rates      681.7 / 685.8    550.6 / 565.0    572.7 / 679.0    428.3 / 476.5
time step  17.9 / 18.3      17.9 / 18.0      15.8 / 17.5      14.4 / 15.0
leapfrog   41.2 / 42.5      43.1 / 43.6      35.9 / 40.1      30.6 / 33.2
reorder    9.9 / 10.4       11.5 / 11.6      9.4 / 10.8       6.9 / 10.0
rest       6.8 / 7.7        7.6 / 7.9        6.7 / 7.4        5.7 / 5.8
total      910.0 / 919.0    788.2 / 812.8    770.4 / 905.8    617.7 / 692.4
=========  ===============  ===============  ===============  ===============

The rates pass is 19-25 % shorter (``search.neighbour_list``: the neighbour list grown before the
scan instead of inside it, unsigned slots); the leapfrog is one pass (``advance_particles``), within
the noise of the three it replaced (23.5 against 24.5 ns timed alone). Everything else is
unchanged code. Results are bit-identical to main's.
"""
from __future__ import annotations

import argparse
import os
import statistics
import time

PASSES = ("eos", "ghosts", "cell sort", "rates", "time step", "leapfrog", "reorder")


class PassTimer:
    """Wraps the kernels ``sph/system.py`` calls and accumulates their CPU time per pass."""

    def __init__(self):
        from sphfem_cli.sph import eos, integration, rates, search, system, walls

        self.t = {k: 0.0 for k in PASSES + ("  binning",)}
        self._undo = []
        self._wrap(eos, "update_particle_state", "eos")
        self._wrap(walls, "make_ghosts", "ghosts")
        self._wrap(rates, "fluid_rates", "rates")
        self._wrap(integration, "stable_time_step", "time step")
        self._wrap(integration, "advance_particles", "leapfrog")
        self._wrap(system.SphSystem, "_reorder", "reorder")
        sort, binning, t = search.sort_points, search.bin_points, self.t

        def timed_sort(*a):
            c0 = time.process_time()
            binning(a[0], a[6], a[8], a[9], a[11], a[14], a[18], a[20])
            c1 = time.process_time()
            out = sort(*a)
            t["  binning"] += c1 - c0
            t["cell sort"] += time.process_time() - c1
            return out

        self._undo.append((search, "sort_points", sort))
        search.sort_points = timed_sort

    def _wrap(self, owner, name, key):
        f, t = getattr(owner, name), self.t

        def timed(*a, **kw):
            c0 = time.process_time()
            out = f(*a, **kw)
            t[key] += time.process_time() - c0
            return out

        self._undo.append((owner, name, f))
        setattr(owner, name, timed)

    def reset(self):
        for k in self.t:
            self.t[k] = 0.0

    def restore(self):
        for owner, name, f in reversed(self._undo):
            setattr(owner, name, f)


def run_once(ps, steps, timer):
    """ns per particle-step of every pass (and the binning's second call) over ``steps`` steps."""
    timer.reset()
    c0 = time.process_time()
    for _ in range(steps):
        ps.advance(0.9)
    total = time.process_time() - c0 - timer.t["  binning"]
    work = ps.n * steps * 1e-9
    out = {k: v / work for k, v in timer.t.items()}
    out["rest"] = (total - sum(timer.t[k] for k in PASSES)) / work
    out["total"] = total / work
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", default="71,212,500", help="a/dx of each case")
    ap.add_argument("--steps", type=int, default=None, help="timed steps per size (default 4e6 / particles, >= 3)")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--probe", action="store_true",
                    help="also time the fused-step probe (peers.py's sph2d peer) at each size, interleaved")
    args = ap.parse_args()

    import numba

    from sphfem_cli.sph import scenes

    numba.set_num_threads(1)
    sizes = [int(s) for s in args.sizes.split(",")]
    timer = PassTimer()
    systems = {}
    probes = {}
    for s in sizes:
        ps = scenes.dam_break(a=1.0, dx=1.0 / s, dim=2)
        for _ in range(3):
            ps.advance(0.9)
        systems[s] = ps
        if args.probe:  # the probe's lattice of 2 nside^2 ~ ps.n points (peers.sph2d_case), compiled here
            from peers import sph2d_case

            probes[s] = sph2d_case(s, args.steps or max(3, int(4e6 / ps.n))).peer
    load0 = os.getloadavg()
    res = {s: [] for s in sizes}
    for _ in range(args.repeat):
        for s in sizes:
            ps = systems[s]
            steps = args.steps or max(3, int(4e6 / ps.n))
            res[s].append(run_once(ps, steps, timer))
            if args.probe:
                res[s][-1]["probe (step)"] = 1e9 / probes[s]()
    load1 = os.getloadavg()
    timer.restore()
    print(f"numba {numba.__version__}, 1 thread, load average {load0[0]:.1f} -> {load1[0]:.1f}; "
          f"ns per particle-step, min / median of {args.repeat} interleaved repetitions (CPU time)")
    keys = PASSES + ("rest", "total", "  binning") + (("probe (step)",) if args.probe else ())
    print(f"{'pass':12s}" + "".join(f"{f'{systems[s].n} particles':>22s}" for s in sizes))
    for k in keys:
        row = f"{k:12s}"
        for s in sizes:
            v = [r[k] for r in res[s]]
            row += f"{min(v):>12.1f} / {statistics.median(v):>7.1f}"
        print(row)


if __name__ == "__main__":
    main()
