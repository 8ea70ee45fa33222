"""Issue 15: the axisymmetric free-field UNDEX against the 3D octant at equal element size, and the
axisymmetric peak pressure refined to a GCI.

    python docs/studies/underwater_explosion_axi_vs_3d.py            # from the repository root, ~60 min CPU
    python docs/studies/underwater_explosion_axi_vs_3d.py --pair 0.01 --levels 0.005 0.0025 0.00125
    python docs/studies/underwater_explosion_axi_vs_3d.py --pair --levels --far 0.0025 0.00125   # to 25 radii

Decks: decks/underwater_explosion_3d_ale.yaml (hex8 octant) and its r-z twin
decks/underwater_explosion_free_field_axisymmetric_ale.yaml, both to 0.12 ms, histories every 0.2 us.
Probes are replaced by a dense ray: in 3D the element centres on the diagonal, (i + 1/2) h (1, 1, 1); in r-z
points every 5 mm along the same direction (54.74 deg off the axis). A probe reads the element whose centre
is nearest, so each peak is placed at that centre's distance R_c. No r-z centre lies at a 3D centre's
distance ((i+1/2)^2 + (j+1/2)^2 = 3 (k+1/2)^2 has no integer solution: the left side is 2 mod 4, the right
side odd), so the r-z peaks are interpolated log-log in R_c to the 3D distances.

Prints: per pair size, the two charges as filled (whole sphere), each 3D distance with both peaks, the
ratio and both arrival times; per r-z level, the peak at R = 0.06 ... 0.20 m and the e-folding length of
the pulse in elements (theta times the shock speed dR/dt of the arrival times, over h); then the observed
order and GCI (Roache, safety factor 1.25, ratio 2) of the peaks on the last three levels.

--far: the r-z deck on a 0.6 m mesh to 0.42 ms, probes on the same ray at R = 0.10 ... 0.50 m (5 to 25 charge
radii), each peak against Cole's similitude P = 52.4 (W^(1/3) / R)^1.13 MPa (Cole 1948; W the charge as filled,
in kg; R the probe's element centre, m), which is fitted to measurements from about 10 charge radii out.
"""
from __future__ import annotations

import argparse
import math
import sys
import time
from pathlib import Path

import numpy as np

from sphfem_cli import api
from sphfem_cli.study.metrics import describe, three_grid

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))
from tests.reference_data import value  # noqa: E402

# Cole's similitude, Swisdak's TNT constants (tests/data/underwater_explosion_free_field.{yaml,md})
COLE_P = tuple(value("underwater_explosion_free_field", k) for k in ("cole_peak_k", "cole_peak_alpha"))
DECK_3D = ROOT / "decks/underwater_explosion_3d_ale.yaml"
DECK_RZ = ROOT / "decks/underwater_explosion_free_field_axisymmetric_ale.yaml"
WORK = Path("study_undex_axi_vs_3d")
RAY = (math.sqrt(2.0 / 3.0), math.sqrt(1.0 / 3.0))  # (r, z) of the unit diagonal direction
R_MIN, R_MAX = 0.04, 0.20
R_TABLE = (0.06, 0.08, 0.10, 0.12, 0.14, 0.16, 0.18, 0.20)


def ray_probes(dimension: int, h: float) -> list[dict]:
    if dimension == 3:
        centres = [(i + 0.5) * h for i in range(int(R_MAX / (math.sqrt(3.0) * h)) + 1)]
        return [{"name": f"d_{i:03d}", "type": "pressure", "point": [c, c, c]}
                for i, c in enumerate(centres) if R_MIN <= math.sqrt(3.0) * c <= R_MAX]
    radii = np.arange(R_MIN, R_MAX + 1e-9, 0.005)
    return [{"name": f"d_{round(r * 1000):03d}", "type": "pressure", "point": [r * RAY[0], r * RAY[1]]}
            for r in radii]


def peaks(dimension: int, h: float, extra: dict | None = None) -> dict:
    """Run one deck at element size h; the peak pressure, its time and the e-folding time per sampled R_c.

    extra: further deck overrides (docs/studies/underwater_explosion_blast1d.py sets the bulk viscosity)."""
    deck = DECK_3D if dimension == 3 else DECK_RZ
    probes = ray_probes(dimension, h)
    overrides = {"parts.pool.geometry.box.element_size": h, "output.history_interval": 2.0e-7,
                 "output.interval": 1.0, "output.probes": probes, **(extra or {})}
    cpu = time.process_time()
    result = api.run(deck, WORK / f"{dimension}d_h{h * 1e3:g}mm", overrides, threads=1, overwrite=True)
    cpu = time.process_time() - cpu
    assert result.completed, result.message
    hist = result.histories()
    rows = {}
    for probe in probes:
        centre = (np.floor(np.asarray(probe["point"]) / h) + 0.5) * h
        t, p = hist[probe["name"]]["time"], hist[probe["name"]]["pressure"]
        i = int(np.argmax(p))
        below = np.nonzero(p[i:] < p[i] / math.e)[0]
        theta = t[i + below[0]] - t[i] if below.size else math.nan
        rows[round(float(np.linalg.norm(centre)), 9)] = (float(p[i]), float(t[i]), theta)
    r_c = np.array(sorted(rows))
    peak, arrival, theta = (np.array([rows[r][k] for r in r_c]) for k in range(3))
    charge = hist["ale_materials"]["mass_tnt"][0] * (8.0 if dimension == 3 else 2.0)
    return {"h": h, "r_c": r_c, "peak": peak, "arrival": arrival, "theta": theta, "charge": charge, "cpu": cpu}


def loglog(run: dict, r: np.ndarray, key: str = "peak") -> np.ndarray:
    return np.exp(np.interp(np.log(r), np.log(run["r_c"]), np.log(run[key])))


def compare_pair(h: float) -> None:
    solid, rz = peaks(3, h), peaks(2, h)
    print(f"\n== h = {h * 1e3:g} mm: charge as filled 3D {solid['charge']:.5f} kg, r-z {rz['charge']:.5f} kg "
          f"(sphere {1630.0 * 4.0 / 3.0 * math.pi * 0.02 ** 3:.5f}); CPU 3D {solid['cpu']:.1f} s, r-z {rz['cpu']:.1f} s")
    inside = (solid["r_c"] >= rz["r_c"][0]) & (solid["r_c"] <= rz["r_c"][-1])
    r = solid["r_c"][inside]
    ratio = loglog(rz, r) / solid["peak"][inside]
    arrival = np.interp(r, rz["r_c"], rz["arrival"])
    print("   R_c (m)   3D (MPa)  r-z (MPa)  r-z/3D   arrival 3D / r-z (us)")
    for k, rr in enumerate(r):
        print(f"   {rr:.4f}   {solid['peak'][inside][k] / 1e6:8.1f}  {loglog(rz, r)[k] / 1e6:8.1f}   {ratio[k]:.4f}"
              f"   {solid['arrival'][inside][k] * 1e6:6.1f} / {arrival[k] * 1e6:6.1f}")
    print(f"   r-z/3D: mean {ratio.mean():.4f}, min {ratio.min():.4f}, max {ratio.max():.4f}")


def converge(levels: list[float]) -> None:
    runs = [peaks(2, h) for h in levels]
    radii = np.array(R_TABLE)
    print("\n== r-z levels: peak (MPa) at R, e-folding length (elements) = theta dR/dt / h")
    for run in runs:
        speed = np.gradient(run["r_c"], run["arrival"])
        length = loglog(run, radii, "theta") * np.interp(radii, run["r_c"], speed) / run["h"]
        print(f"   h = {run['h'] * 1e3:g} mm (charge {run['charge']:.5f} kg, CPU {run['cpu']:.1f} s): "
              + ", ".join(f"{r:.2f} m {p / 1e6:.1f} ({n:.1f})" for r, p, n in zip(radii, loglog(run, radii), length)))
    if len(runs) >= 3:
        sizes = ", ".join(f"{run['h'] * 1e3:g}" for run in runs[-3:])
        print(f"== observed order and GCI, levels {sizes} mm")
        for k, r in enumerate(radii):
            conv = three_grid([run["h"] for run in runs[-3:]], [loglog(run, radii)[k] for run in runs[-3:]])
            print(f"   R = {r:.2f} m: {describe(conv)}")


FAR_SIZE, FAR_END = 0.6, 4.2e-4  # m, s: the shock passes 0.5 m by about 0.33 ms
FAR_RADII = (0.10, 0.15, 0.20, 0.25, 0.30, 0.35, 0.40, 0.45, 0.50)


def far_field(h: float) -> None:
    probes = [{"name": f"d_{round(r * 1000):03d}", "type": "pressure", "point": [r * RAY[0], r * RAY[1]]}
              for r in FAR_RADII]
    overrides = {"parts.pool.geometry.box.max": [FAR_SIZE, FAR_SIZE], "parts.pool.geometry.box.element_size": h,
                 "control.end_time": FAR_END, "output.history_interval": 2.0e-7, "output.interval": 1.0,
                 "output.probes": probes}
    cpu = time.process_time()
    result = api.run(DECK_RZ, WORK / f"far_h{h * 1e3:g}mm", overrides, threads=1, overwrite=True)
    cpu = time.process_time() - cpu
    assert result.completed, result.message
    hist = result.histories()
    charge = hist["ale_materials"]["mass_tnt"][0] * 2.0
    print(f"\n== far field, h = {h * 1e3:g} mm, {FAR_SIZE} m mesh (charge {charge:.5f} kg, CPU {cpu:.1f} s)")
    for probe in probes:
        r_c = float(np.linalg.norm((np.floor(np.asarray(probe["point"]) / h) + 0.5) * h))
        peak = float(np.nanmax(hist[probe["name"]]["pressure"]))
        cole = COLE_P[0] * (charge ** (1.0 / 3.0) / r_c) ** COLE_P[1]
        print(f"   R_c {r_c:.4f} m ({r_c / 0.02:4.1f} radii): peak {peak / 1e6:6.1f} MPa, Cole {cole / 1e6:6.1f}, "
              f"ratio {peak / cole:.3f}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--pair", type=float, nargs="*", default=[0.01, 0.005], help="element sizes run in both (m)")
    parser.add_argument("--levels", type=float, nargs="*", default=[0.0025, 0.00125, 0.000625],
                        help="r-z element sizes for the GCI, coarse to fine, ratio 2 (m)")
    parser.add_argument("--far", type=float, nargs="*", default=[], help="r-z element sizes for the far field (m)")
    args = parser.parse_args()
    WORK.mkdir(exist_ok=True)
    for h in args.pair:
        compare_pair(h)
    if args.levels:
        converge(args.levels)
    for h in args.far:
        far_field(h)


if __name__ == "__main__":
    main()
