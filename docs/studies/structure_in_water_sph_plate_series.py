"""Issue 18 A1: the structure side of decks/structure_in_water_sph.yaml at the shipped particle spacing.

    python docs/studies/structure_in_water_sph_plate_series.py            # plates 2 x 30 / 4 x 60 / 8 x 120, the deck's soft_scale
    python docs/studies/structure_in_water_sph_plate_series.py series 0.3 # the same at soft_scale 0.3
    python docs/studies/structure_in_water_sph_plate_series.py robust     # the series with the field output every 3 ms
    python docs/studies/structure_in_water_sph_plate_series.py held       # the same with the spring k held (soft_scale 0.1 (2 / n)^2)
    python docs/studies/structure_in_water_sph_plate_series.py masses     # face-node masses, the reduced mass, omega dt0
    python docs/studies/structure_in_water_sph_plate_series.py spring     # the shipped plate at soft_scale 0.03 / 0.3 / 1.0
    python docs/studies/structure_in_water_sph_plate_series.py gap        # the particles' smallest gap to the plate

The shipped deck (SPH ratio 1, dx 10 mm, alpha 0, 3 ms, energy band on) with the plate's divisions 2 x 30 /
4 x 60 / 8 x 120, the water fixed. Compared, as the mesh study and the fluid series
(docs/studies/fsi_convergence_audit.md): the peak magnitude of the displacement and of the velocity of the node
at (0.21, 0.125) (the `mid` history), and the clamp von Mises.

The contact spring. The soft constraint takes its spring from the reduced mass of the particle and the
segment's lightest node, k = s m_p / (dt0^2 (1 + m_p max_j 1 / m_j)) (sphfem_cli/contact/kernels.py
point_forces, docs/theory/contact.md), so the pair's frequency is omega dt0 = sqrt(s) on every plate and the
deck's own soft_scale runs on all three (the default series). Before 7 December 2026 it took m_p alone: a
particle (0.1 kg/m) on a face node of 0.0084 / 0.0021 kg/m (4 x 60 / 8 x 120) was a two-mass spring at
omega dt0 = 1.13 / 2.20 and the finer plates blew up, so the series then held k by soft_scale 0.1 (2 / n)^2
(`held`: with the reduced mass that is now a spring softer by (2 / n)^2 on top of the mass factor).

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
import yaml

from sphfem_cli import api
from sphfem_cli.solver.solid_domain import von_mises as solid_von_mises
from sphfem_cli.study.metrics import describe, history_columns, three_grid

ROOT = Path(__file__).resolve().parents[2]
DECK = ROOT / "decks/structure_in_water_sph.yaml"
WORK = Path("study_siw_sph_plate")
SQUARE = (0.200, 0.205, 0.195, 0.200)  # the 2 x 30 plate's clamp element


def clamp_points(n: int) -> list[list[float]]:
    """Centres of the n x 15 n plate's elements inside SQUARE (element size 10 mm / n)."""
    e = 0.010 / n
    k = round((SQUARE[1] - SQUARE[0]) / e)
    return [[SQUARE[0] + (i + 0.5) * e, SQUARE[2] + (j + 0.5) * e] for i in range(k) for j in range(k)]


def overrides(n: int, soft_scale: float, end_time: float | None = None, field_interval: float | None = None) -> dict:
    hist = [{"name": "mid", "point": [0.21, 0.125], "quantities": ["displacement", "velocity"]}]
    hist += [{"name": f"clamp{i}", "point": p, "quantities": ["stress"]} for i, p in enumerate(clamp_points(n))]
    out = {"parts.plate.geometry.box.divisions": [n, 15 * n], "contacts.0.soft_scale": soft_scale,
           "output.histories": hist}
    if end_time is not None:
        out["control.end_time"] = end_time
    if field_interval is not None:  # the field output cuts the steps: another interval, other step times
        out["output.interval"] = field_interval
    return out


def von_mises(s: dict[str, np.ndarray]) -> np.ndarray:
    """The von Mises stress of the history's stress columns (``solver.solid_domain.von_mises``)."""
    return solid_von_mises(np.column_stack([s[f"stress_{c}"] for c in ("xx", "yy", "zz", "xy", "yz", "zx")]))


def level(n: int, soft_scale: float, end_time: float | None = None, tag: str = "",
          field_interval: float | None = None) -> dict:
    folder = WORK / f"plate{n}{tag}"
    cpu = time.process_time()
    res = api.run(DECK, folder, overrides(n, soft_scale, end_time, field_interval), threads=1, overwrite=True)
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


def deck_soft_scale() -> float:
    return float(yaml.safe_load(DECK.read_text())["contacts"][0]["soft_scale"])


def node_masses() -> None:
    """Face-node mass against the particle's, the reduced-mass factor and omega dt0 with m_p alone and with m."""
    s = deck_soft_scale()
    for n in (2, 4, 8):
        model = api.load(DECK, {"parts.plate.geometry.box.divisions": [n, 15 * n]}).model
        x = model.coordinates
        face = np.isclose(x[:, 0], 0.2) & (x[:, 1] > 0.051) & (x[:, 1] < 0.199)
        m_m = float(model.mass[face].min())
        m_p = 1000.0 * 0.01**2
        print(f"plate {n} x {15 * n}: face node {m_m:.4g} kg/m, m_p / m_m {m_p / m_m:.3g}, reduced-mass factor "
              f"1 / (1 + m_p / m_m) {1 / (1 + m_p / m_m):.4f}; omega dt0 at soft_scale {s:g}: with m_p alone "
              f"{math.sqrt(s * (1 + m_p / m_m)):.3f}, with the reduced mass {math.sqrt(s):.3f}")


def series(scales: list[float], tag: str = "", field_interval: float | None = None) -> None:
    rows = [level(n, s, tag=tag, field_interval=field_interval) for n, s in zip((2, 4, 8), scales)]
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
              f"{c.extrapolated:.5g}, GCI(8 x 120) {100 * c.gci_fine:.2f} %, GCI(4 x 60) {100 * c.gci_medium:.2f} %, "
              f"asymptotic check {c.asymptotic:.3f}{err}")


def plate_gaps(results: Path) -> tuple[np.ndarray, np.ndarray]:
    """Per field frame: time and the smallest signed distance of a particle centre to the plate's outline.

    The outline is the quads' edges that belong to one element; a centre inside a quad counts negative.
    The contact acts below its thickness, dx / 2 = 5 mm (the lattice's start), so thickness - gap is the
    spring's compression."""
    import h5py

    gaps = []
    with h5py.File(results) as f:
        quads = f["plate/connectivity"][()]
        edges = np.sort(np.concatenate([quads[:, [i, (i + 1) % 4]] for i in range(4)]), axis=1)
        uniq, count = np.unique(edges, axis=0, return_counts=True)
        outline = uniq[count == 1]
        steps = sorted(k for k in f["plate"] if k.startswith("step_"))
        times = f["times"][()][:len(steps)]
        for k in steps:
            xn = f[f"plate/{k}/coordinates"][()][:, :2]
            xp = f[f"tank/{k}/coordinates"][()][:, :2]
            a, b = xn[outline[:, 0]], xn[outline[:, 1]]
            ab = b - a
            t = np.clip(np.einsum("pej,ej->pe", xp[:, None, :] - a[None], ab) / np.einsum("ej,ej->e", ab, ab), 0.0, 1.0)
            d = np.linalg.norm(xp[:, None, :] - (a[None] + t[..., None] * ab[None]), axis=2).min(axis=1)
            inside = np.zeros(len(xp), dtype=bool)
            for q in quads:
                c = xn[q]
                e = np.roll(c, -1, axis=0) - c
                cross = e[None, :, 0] * (xp[:, None, 1] - c[None, :, 1]) - e[None, :, 1] * (xp[:, None, 0] - c[None, :, 0])
                inside |= np.all(cross >= 0, axis=1) | np.all(cross <= 0, axis=1)
            gaps.append(float(np.where(inside, -d, d).min()))
    return np.asarray(times), np.array(gaps)


def gap_runs() -> None:
    """The shipped plate at soft_scale 0.03 / 0.1 / 0.3 with the field output every 20 us: the smallest gap."""
    for scale in (0.03, 0.1, 0.3):
        folder = WORK / f"gap_s{scale:g}"
        res = api.run(DECK, folder, {"contacts.0.soft_scale": scale, "output.interval": 2e-5,
                                     "output.fields": ["displacement"]}, threads=1, overwrite=True)
        t, g = plate_gaps(folder / "results.h5")
        i = int(np.argmin(g))
        print(f"soft_scale {scale:g}: {res.status}, {res.steps} steps; smallest gap {1e3 * g[i]:.4f} mm (frame {i}, "
              f"t {1e3 * t[i]:.3f} ms) against the thickness 5 mm: compression {1e3 * (0.005 - g[i]):.4f} mm; "
              f"after 0.1 ms {1e3 * g[t > 1e-4].min() if np.any(t > 1e-4) else float('nan'):.4f} mm")


def main(argv: list[str]) -> None:
    mode = argv[0] if argv else "series"
    s = deck_soft_scale()
    if mode == "masses":
        node_masses()
    elif mode == "spring":
        for scale in (0.03, 0.3, 1.0):
            r = level(2, scale, tag=f"_s{scale:g}")
            print({k: v for k, v in r.items() if k != "message"})
    elif mode == "gap":
        gap_runs()
    elif mode == "robust":
        series([s, s, s], tag="_f3ms", field_interval=0.003)
    elif mode == "held":
        series([s * (2.0 / n) ** 2 for n in (2, 4, 8)], tag="_held")
    else:
        if len(argv) > 1:
            s = float(argv[1])
        series([s, s, s], tag="" if s == deck_soft_scale() else f"_s{s:g}")


if __name__ == "__main__":
    main(sys.argv[1:])
