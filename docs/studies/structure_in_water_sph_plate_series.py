"""Issue 18 A1: the structure side of decks/structure_in_water_sph.yaml at the shipped particle spacing.

    python docs/studies/structure_in_water_sph_plate_series.py            # plates 2 x 30 / 4 x 60 / 8 x 120
    python docs/studies/structure_in_water_sph_plate_series.py stability  # why soft_scale 0.1 fails on finer plates
    python docs/studies/structure_in_water_sph_plate_series.py spring     # the 4 x 60 plate with the spring k / 4

The shipped deck (SPH ratio 1, dx 10 mm, alpha 0, 3 ms, energy band on) with the plate's divisions 2 x 30 /
4 x 60 / 8 x 120, the water fixed. Compared, as the mesh study and the fluid series
(docs/studies/fsi_convergence_audit.md): the peak magnitude of the displacement and of the velocity of the node
at (0.21, 0.125) (the `mid` history), and the clamp von Mises.

The contact spring held fixed. The deck's soft constraint sets the spring per particle from the first step,
k = soft_scale m_p / dt0^2 (sphfem_cli/contact/system.py), and dt0 is the plate's step, which falls with the
element: soft_scale 0.1 on the 8 x 120 plate is a spring 16 times stiffer than the shipped one. The series
holds k (the shipped 1.9e10 N/m per particle, 0.5 um under 1 MPa) by soft_scale 0.1 (2 / n)^2 on the n x 15 n
plate: 0.1 / 0.025 / 0.00625, so that only the plate changes. The `stability` runs show why the deck's 0.1
cannot be kept: the soft constraint's frequency sqrt(soft_scale) / dt0 is the spring on the particle's own
mass; a particle on a face node of mass m_m moves it as a two-mass spring, omega^2 = k (1 / m_p + 1 / m_m),
omega dt0 = sqrt(soft_scale (1 + m_p / m_m)), on top of the plate's own frequency near its limit at
timestep_scale 0.9. The lattice puts every wet-face particle level with a node (y = 0.055 + 0.01 j), so the
full node mass counts.

The clamp von Mises, one quantity on every plate: the deck's `clamp` point (0.2025, 0.1975) is the centre of
the 2 x 30 plate's corner element [0.200, 0.205] x [0.195, 0.200] (one-point quadrature: its stress is the
element's mean) and a node of the finer plates. The quantity is the von Mises of the mean stress over that
5 x 5 mm square: the one element at 2 x 30, the mean of its 4 / 16 elements (equal areas) at 4 x 60 / 8 x 120.
Its peak over 3 ms. The square holds the clamped corner (0.200, 0.200), where the stress is singular but
integrable, so its mean has a limit; a point value there has none (docs/studies/structure_in_water.md,
"The von Mises at the clamp").

Order / GCI: sphfem_cli.study.metrics.three_grid with h = 1 / n, Fs 1.25. One thread.
"""
from __future__ import annotations

import math
import sys
import time
from pathlib import Path

import numpy as np

from sphfem_cli import api
from sphfem_cli.solver.solid_domain import von_mises as solid_von_mises
from sphfem_cli.study.metrics import describe, history_columns, three_grid

ROOT = Path(__file__).resolve().parents[2]
DECK = ROOT / "decks/structure_in_water_sph.yaml"
WORK = Path("study_siw_sph_plate")
SQUARE = (0.200, 0.205, 0.195, 0.200)  # the 2 x 30 plate's clamp element
SOFT_SHIPPED = 0.1


def clamp_points(n: int) -> list[list[float]]:
    """Centres of the n x 15 n plate's elements inside SQUARE (element size 10 mm / n)."""
    e = 0.010 / n
    k = round((SQUARE[1] - SQUARE[0]) / e)
    return [[SQUARE[0] + (i + 0.5) * e, SQUARE[2] + (j + 0.5) * e] for i in range(k) for j in range(k)]


def overrides(n: int, soft_scale: float, end_time: float | None = None) -> dict:
    hist = [{"name": "mid", "point": [0.21, 0.125], "quantities": ["displacement", "velocity"]}]
    hist += [{"name": f"clamp{i}", "point": p, "quantities": ["stress"]} for i, p in enumerate(clamp_points(n))]
    out = {"parts.plate.geometry.box.divisions": [n, 15 * n], "contacts.0.soft_scale": soft_scale,
           "output.histories": hist}
    if end_time is not None:
        out["control.end_time"] = end_time
    return out


def von_mises(s: dict[str, np.ndarray]) -> np.ndarray:
    """The von Mises stress of the history's stress columns (``solver.solid_domain.von_mises``)."""
    return solid_von_mises(np.column_stack([s[f"stress_{c}"] for c in ("xx", "yy", "zz", "xy", "yz", "zx")]))


def level(n: int, soft_scale: float, end_time: float | None = None, tag: str = "") -> dict:
    folder = WORK / f"plate{n}{tag}"
    cpu = time.process_time()
    res = api.run(DECK, folder, overrides(n, soft_scale, end_time), threads=1, overwrite=True)
    cpu = time.process_time() - cpu
    out = {"n": n, "soft_scale": soft_scale, "status": res.status, "steps": res.steps, "t_end": float(res.time),
           "cpu": cpu, "message": res.message}
    if res.status != "completed":
        return out
    h = folder / "histories"
    mid = history_columns(h / "mid.csv")
    comps = ("stress_xx", "stress_yy", "stress_zz", "stress_xy", "stress_yz", "stress_zx")
    tables = [history_columns(h / f"clamp{i}.csv") for i in range(len(clamp_points(n)))]
    mean = {c: np.mean([t[c] for t in tables], axis=0) for c in comps}
    g = history_columns(h / "glstat.csv")
    out.update({
        "u_peak_mm": 1e3 * float(np.max(np.hypot(mid["displacement_x"], mid["displacement_y"]))),
        "t_u_peak_ms": 1e3 * float(mid["time"][np.argmax(np.hypot(mid["displacement_x"], mid["displacement_y"]))]),
        "ux_peak_mm": 1e3 * float(np.max(np.abs(mid["displacement_x"]))),
        "v_peak": float(np.max(np.hypot(mid["velocity_x"], mid["velocity_y"]))),
        "vm_peak_mpa": 1e-6 * float(np.max(von_mises(mean))),
        "dt_20us": float(g["dt"][1]), "energy_ratio_end": float(g["energy_ratio"][-1]),
    })
    return out


def node_masses() -> None:
    """Face-node mass against the particle's and the two-mass omega dt0 at the deck's soft_scale 0.1."""
    m_p = 1000.0 * 0.01**2
    for n in (2, 4, 8):
        model = api.load(DECK, {"parts.plate.geometry.box.divisions": [n, 15 * n]}).model
        x = model.coordinates
        face = np.isclose(x[:, 0], 0.2) & (x[:, 1] > 0.051) & (x[:, 1] < 0.199)
        m_m = float(model.mass[face].max())
        print(f"plate {n} x {15 * n}: face node {m_m:.4g} kg/m, m_p / m_m {m_p / m_m:.3g}, omega dt0 at "
              f"soft_scale 0.1: {math.sqrt(0.1 * (1 + m_p / m_m)):.3f}; at 0.1 (2/n)^2: "
              f"{math.sqrt(0.1 * (2 / n) ** 2 * (1 + m_p / m_m)):.3f}")


def main(argv: list[str]) -> None:
    mode = argv[0] if argv else "series"
    if mode == "stability":
        node_masses()
        for n, s in ((4, 0.1), (8, 0.1), (8, 0.025), (8, 0.0125)):
            r = level(n, s, 0.0005, tag=f"_s{s:g}")
            print(f"plate {n} x {15 * n}, soft_scale {s:g} (omega dt0 from the particle alone "
                  f"{math.sqrt(s):.3f}): {r['status']} at t = {r['t_end']:.4g} s, step {r['steps']} "
                  f"{r['message'][:160]}")
        return
    if mode == "spring":
        for s in (0.025, 0.025 / 4):
            r = level(4, s, tag=f"_s{s:g}")
            print({k: v for k, v in r.items() if k != "message"})
        return
    rows = [level(n, SOFT_SHIPPED * (2.0 / n) ** 2) for n in (2, 4, 8)]
    for r in rows:
        print({k: v for k, v in r.items() if k != "message"})
    if any(r["status"] != "completed" for r in rows):
        return
    h = [1.0 / r["n"] for r in rows]
    for key in ("u_peak_mm", "ux_peak_mm", "v_peak", "vm_peak_mpa"):
        c = three_grid(h, [r[key] for r in rows])
        shipped = rows[0][key]
        err = f", shipped {100 * (shipped / c.extrapolated - 1):+.2f} % from Richardson" if math.isfinite(c.extrapolated) else ""
        print(f"{key}: {' / '.join(f'{r[key]:.5g}' for r in rows)}: {describe(c)}, Richardson "
              f"{c.extrapolated:.5g}, GCI(4 x 60) {100 * c.gci_medium:.2f} %, asymptotic check {c.asymptotic:.3f}{err}")


if __name__ == "__main__":
    main(sys.argv[1:])
