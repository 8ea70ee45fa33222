"""Issue 15 (B3b): the underwater explosion under a clamped circular plate in 3D (a quarter, hex8 ALE with the
3D lagrange_in_solid coupling) against its r-z twin at equal element size.

    python docs/studies/underwater_explosion_plate_3d.py --plot docs/studies/underwater_explosion_plate_3d.png
                                           # h = 5 and 10 mm, 3D and r-z, to 0.8 ms (3D 5 mm: 315 s CPU)
    python docs/studies/underwater_explosion_plate_3d.py --sizes 0.01     # the coarse pair only (3D 42 s CPU)
    python docs/studies/underwater_explosion_plate_3d.py --sizes --rz 0.01 0.005 0.0025   # r-z series

Decks: decks/underwater_explosion_plate_3d_ale.yaml (the quarter, 5 mm) and, as its r-z twin, the r-z deck
decks/underwater_explosion_axisymmetric_ale.yaml with overrides that give it the same scene (``rz_scene``):
TNT sphere of radius 15 mm centred on the axis 0.10 m under the wet face, steel plate 10 mm thick clamped at
r = 0.15 m in a rigid wall, water to r (x, y) = 0.20 m and z = -0.25 m (non-reflecting with the charge's centre
as source), void to z = 0.05 m, the mesh shifted down by h/2 (the wet face z = 0 mid-element; the deck's header
says why). Only sizes differ from the r-z deck; its physics (EOS, cut-off, Q2 default, coupling with
L_c = h/2, plate hourglass) is kept. Element size h applies to the water and, in plane, to the
plate; the plate has round(0.01 / h) elements through its thickness (2 at 5 mm, 1 at 10 mm).

Compared (3D over r-z, each at the same h) to END = 0.8 ms, past both plates' maxima (the 3D run reaches it at 5 and
10 mm since the fog nodes' zero velocity between the remap sweeps, issue 15 b3b2): the plate centre's largest
displacement u_max and its time t_max, the peak velocity, the loading phase as before (u at 0.3 ms, u_03, and the
RMS over 0-0.3 ms of the difference of the displacement histories, sampled every 2 us in both, over the r-z u_03),
the peak pressure of the element under the plate centre (plate_pressure: the corner element (h/2, h/2, -h) in 3D,
the first ring (h/2, -h) in r-z, one element under the one the wet face cuts; their centres are 0.71 h and 0.5 h off
the axis) and the free-field peak 0.10 m from the charge at 45 degrees (standoff_pressure), the charges as filled.

--rz: r-z twins only, at these sizes (to a GCI with three); --tank L ZB ZT: the r-z twin in a larger tank
(the open-water check of the 3D deck's tank, r-z only). --plot FILE: displacement histories of the pairs.
Completed runs in the work folder are read, not rerun (--work, default study_undex_plate_3d).
"""
from __future__ import annotations

import argparse
import math
import time
from pathlib import Path

import numpy as np

from sphfem_cli import api
from sphfem_cli.study.metrics import describe, three_grid

ROOT = Path(__file__).resolve().parents[2]
DECK_3D = ROOT / "decks/underwater_explosion_plate_3d_ale.yaml"
DECK_RZ = ROOT / "decks/underwater_explosion_axisymmetric_ale.yaml"
CHARGE_Z, CHARGE_RADIUS, THICKNESS, RIM = -0.10, 0.015, 0.01, 0.15
TANK = (0.20, -0.25, 0.05)  # water to r (x, y) = L, z from ZB; void to ZT
END = 9.0e-4  # the 3D deck's end: past both plates' maxima (0.74 ms at 5 mm with the viscous hourglass form)
LOADING = 3.0e-4  # the loading phase, compared since the first runs (the 3D run stopped at 0.345 ms then)
SPHERE = 1630.0 * 4.0 / 3.0 * math.pi * CHARGE_RADIUS ** 3


def layers(h: float) -> int:
    return max(1, round(THICKNESS / h))


def rz_scene(h: float, tank=TANK) -> dict:
    """Overrides that turn the r-z deck into the 3D deck's scene at element size h (same sizes, same physics);
    the mesh shifted down by h/2 as the 3D deck's, so that the wet face z = 0 lies mid-element."""
    length, zb, zt = tank[0], tank[1] - h / 2, tank[2] - h / 2
    return {
        "control.end_time": END,
        "parts.tank.geometry.box": {"min": [0.0, zb], "max": [length, zt], "element_size": h},
        "sections.plate.hourglass": {"type": "viscous", "coefficient": 0.1},  # the 3D deck's plate section
        "parts.tank.fill": [{"material": "water", "box": {"min": [0.0, zb], "max": [length, 0.0]}},
                            {"material": "tnt", "ball": {"center": [0.0, CHARGE_Z], "radius": CHARGE_RADIUS}}],
        "parts.plate.geometry.box": {"min": [0.0, 0.0], "max": [length, THICKNESS],
                                     "divisions": [round(length / h), layers(h)]},
        "output.interval": 1.0,
        "output.histories": [{"name": "centre", "point": [0.0, THICKNESS / 2],
                              "quantities": ["displacement", "velocity", "von_mises"]}],
        "output.probes": [{"name": "plate_pressure", "type": "pressure", "point": [h / 2, -h]},
                          {"name": "standoff_pressure", "type": "pressure", "point": [0.07071, -0.02929]}],
    }


def solid_scene(h: float) -> dict:
    """Overrides of the 3D deck at element size h (none at its own 5 mm but the field output)."""
    length, zb, zt = TANK[0], TANK[1] - h / 2, TANK[2] - h / 2
    return {"control.end_time": END,
            "parts.tank.geometry.box": {"min": [0.0, 0.0, zb], "max": [length, length, zt], "element_size": h},
            "parts.tank.fill.0.box.min": [0.0, 0.0, zb], "output.interval": 1.0,
            "parts.plate.geometry.box.divisions": [round(length / h), round(length / h), layers(h)],
            "output.probes.0.point": [h / 2, h / 2, -h]}


def _read(folder: Path) -> dict:
    hist = {}
    for csv in (folder / "histories").glob("*.csv"):
        hist[csv.stem] = np.genfromtxt(csv, delimiter=",", names=True)
    return hist


def run(dimension: int, h: float, work: Path, tank=TANK) -> dict:
    """One run (or its stored result); the plate centre's and the probes' figures."""
    tag = "" if tank == TANK else "_tank{:g}_{:g}".format(tank[0], -tank[1])
    folder = work / f"{dimension}d_h{h * 1e3:g}mm{tag}"
    glstat = folder / "histories" / "glstat.csv"
    cpu = math.nan
    stopped = folder / "diagnostics.txt"  # written when a guard stops the run
    done = glstat.exists() and (stopped.exists()
                                or np.genfromtxt(glstat, delimiter=",", names=True)["time"][-1] >= END * (1 - 1e-9))
    if not done:
        deck, overrides = (DECK_3D, solid_scene(h)) if dimension == 3 else (DECK_RZ, rz_scene(h, tank))
        cpu = time.process_time()
        api.run(deck, folder, overrides, threads=1, overwrite=True)
        cpu = time.process_time() - cpu
    hist = _read(folder)
    if stopped.exists():
        print(f"   {folder.name} STOPPED at t = {hist['glstat']['time'][-1] * 1e3:.4f} ms: "
              + stopped.read_text().splitlines()[1][9:])
    centre = hist["centre"]
    axial = "displacement_z" if dimension == 3 else "displacement_y"
    u, v = centre[axial], centre["velocity_z" if dimension == 3 else "velocity_y"]
    out = {"dim": dimension, "h": h, "cpu": cpu, "t": centre["time"], "u": u, "v": v,
           "steps": len(hist["glstat"]), "energy_ratio": float(hist["glstat"]["energy_ratio"][-1]),
           "charge": float(hist["ale_materials"]["mass_tnt"][0]) * (4.0 if dimension == 3 else 1.0)}
    i = int(np.argmax(u))
    out["u_max"], out["t_max"] = float(u[i]), float(centre["time"][i])
    out["v_max"] = float(v.max())
    out["u_03"] = float(np.interp(LOADING, centre["time"], u))
    out["vm_max"] = float(centre["von_mises"].max())
    for probe in ("plate_pressure", "standoff_pressure"):
        p = hist[probe]["pressure"]
        out[probe] = float(p.max())
        out[probe + "_t"] = float(hist[probe]["time"][int(np.argmax(p))])
    return out


def rms_gap(solid: dict, rz: dict) -> float:
    """RMS over the loading phase [0, LOADING] of u_3D - u_rz (r-z interpolated to the 3D samples), over the r-z
    u(LOADING)."""
    early = solid["t"] <= LOADING * (1 + 1e-9)
    gap = solid["u"][early] - np.interp(solid["t"][early], rz["t"], rz["u"])
    return float(np.sqrt(np.mean(gap ** 2)) / rz["u_03"])


def summary(run_: dict) -> str:
    return (f"{run_['dim']}D h {run_['h'] * 1e3:g} mm: charge {run_['charge'] * 1e3:.2f} g (sphere {SPHERE * 1e3:.2f}), "
            f"u_max {run_['u_max'] * 1e3:.3f} mm at {run_['t_max'] * 1e3:.3f} ms, "
            f"u(0.3 ms) {run_['u_03'] * 1e3:.3f} mm, v_max {run_['v_max']:.2f} m/s, end {run_['t'][-1] * 1e3:.3f} ms, "
            f"von Mises {run_['vm_max'] / 1e6:.1f} MPa, plate_pressure {run_['plate_pressure'] / 1e6:.1f} MPa at "
            f"{run_['plate_pressure_t'] * 1e6:.1f} us, standoff {run_['standoff_pressure'] / 1e6:.1f} MPa at "
            f"{run_['standoff_pressure_t'] * 1e6:.1f} us, energy ratio {run_['energy_ratio']:.4f}, "
            f"{run_['steps']} history rows, CPU {run_['cpu']:.1f} s")


def compare(solid: dict, rz: dict) -> dict:
    keys = ("u_max", "t_max", "v_max", "u_03", "plate_pressure", "standoff_pressure", "charge")
    ratios = {key: solid[key] / rz[key] for key in keys}
    ratios["rms"] = rms_gap(solid, rz)
    print(f"== h = {solid['h'] * 1e3:g} mm, 3D / r-z: " + ", ".join(
        f"{k} {v:.4f}" for k, v in ratios.items() if k != "rms") + f"; RMS(u_3D - u_rz) over 0-0.3 ms / u_rz(0.3 ms) "
          f"{ratios['rms']:.4f}; t_max {solid['t_max'] * 1e3:.3f} / {rz['t_max'] * 1e3:.3f} ms")
    return ratios


def plot(pairs: list[tuple[dict, dict]], path: Path) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(6.4, 4.0))
    for (solid, rz), colour in zip(pairs, ("tab:blue", "tab:red", "tab:green")):
        ax.plot(rz["t"] * 1e3, rz["u"] * 1e3, color=colour, lw=1.2, label=f"r-z, h = {rz['h'] * 1e3:g} mm")
        ax.plot(solid["t"] * 1e3, solid["u"] * 1e3, color=colour, lw=1.2, ls="--",
                label=f"3D quarter, h = {solid['h'] * 1e3:g} mm")
    ax.set_xlabel("time (ms)")
    ax.set_ylabel("plate centre displacement (mm)")
    ax.set_title("UNDEX under a clamped plate: 3D quarter and r-z twin")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    print("wrote", path)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=float, nargs="*", default=[0.01, 0.005], help="sizes run in 3D and r-z (m)")
    parser.add_argument("--rz", type=float, nargs="*", default=[], help="r-z twins only at these sizes (m)")
    parser.add_argument("--tank", type=float, nargs=3, default=None, help="r-z tank L ZB ZT for --rz (m)")
    parser.add_argument("--work", type=Path, default=Path("study_undex_plate_3d"))
    parser.add_argument("--plot", type=Path, default=None)
    args = parser.parse_args()
    args.work.mkdir(exist_ok=True)
    pairs = []
    for h in args.sizes:
        solid, rz = run(3, h, args.work), run(2, h, args.work)
        print(summary(solid))
        print(summary(rz))
        compare(solid, rz)
        pairs.append((solid, rz))
    if args.plot and pairs:
        plot(pairs, args.plot)
    if args.rz:
        tank = tuple(args.tank) if args.tank else TANK
        runs = [run(2, h, args.work, tank) for h in args.rz]
        for r in runs:
            print(f"tank {tank}: " + summary(r))
        if len(runs) >= 3:
            for key in ("u_max", "v_max", "plate_pressure", "standoff_pressure"):
                conv = three_grid([r["h"] for r in runs[-3:]], [r[key] for r in runs[-3:]])
                print(f"   {key}: {describe(conv)}")


if __name__ == "__main__":
    main()
