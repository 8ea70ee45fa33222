"""Issue 15 (B3b): the UNDEX plate scene's two plates alone, dry: is the 3D quarter's low maximum (0.69 of the r-z
twin's) the plate's own response?

    python docs/studies/underwater_explosion_plate_dry.py                 # the 3D quarter and the r-z twin, dry
    python docs/studies/underwater_explosion_plate_dry.py --variants      # and the 3D variants below
    python docs/studies/underwater_explosion_plate_dry.py --variants --extra   # and the r-z hourglass variants and
                                                                       # both plates at 2.5 mm (4 elements thick)
    python docs/studies/underwater_explosion_plate_dry.py --fine --work study_undex_plate_dry_fine   # at 1.25 mm

The plates are taken from the two wet decks themselves, so that material, section (stiffness hourglass 0.1),
mesh and clamp are theirs by construction: decks/underwater_explosion_plate_3d_ale.yaml (a quarter, 40 x 40 x 2
hex8 of 5 mm, every node at r >= 0.15 m fixed: a staircase clamp; the normal displacement held on the symmetry
planes) and its r-z twin, decks/underwater_explosion_axisymmetric_ale.yaml with the 5 mm plate of
docs/studies/underwater_explosion_plate_3d.py (``rz_scene``: 40 x 2 quads, the nodes at r >= 0.15 m fixed). Removed:
the tank, the charge, the coupling, the ALE boundaries and the probes. Load: an impulse, the initial velocity
v_z = V0 = 80 m/s (about the wet runs' peak centre velocity, 88.7 / 88.5 m/s) on every free plate node (the nodes
at r < 0.15 m), the plate at rest and stress free otherwise (LS-DYNA *INITIAL_VELOCITY); to END = 0.8 ms, the wet
decks' end. Compared: the centre's (axis, mid-thickness) displacement maximum, its time, u(END).

Variants on the 3D side (one change each): hourglass coefficient 0.03 (stiffness) or viscous 0.1; 4 hex8 through
the thickness (2.5 mm in z only); the clamp one node row further in (every node at r >= 0.145 m fixed, the free
nodes inside r = 0.145: the staircase's other bound). Extra: the r-z twin with the same two hourglass variants, and
both plates refined to 2.5 mm (in plane and through the thickness: 4 elements thick; the 3D quarter 80 x 80 x 4),
and the 3D quarter at 2.5 mm in plane only (80 x 80 x 2). Also printed: the hourglass energy at the maximum's time
over internal plus hourglass energy (glstat).
"""
from __future__ import annotations

import argparse
import copy
import math
import time
from pathlib import Path

import numpy as np
import yaml

from sphfem_cli import api

ROOT = Path(__file__).resolve().parents[2]
DECK_3D = ROOT / "decks/underwater_explosion_plate_3d_ale.yaml"
DECK_RZ = ROOT / "decks/underwater_explosion_axisymmetric_ale.yaml"
V0 = 80.0  # m/s, the impulse: about the wet runs' peak centre velocity
END = 8.0e-4
H, THICKNESS, LENGTH, RIM = 0.005, 0.01, 0.20, 0.15


def _dry(data: dict) -> dict:
    """The wet deck's plate alone: no tank, charge, coupling, ALE boundaries, probes or field output."""
    data = copy.deepcopy(data)
    for key in ("equations_of_state", "detonations", "couplings"):
        data.pop(key, None)
    data["materials"] = {"steel": data["materials"]["steel"]}
    data["sections"] = {"plate": data["sections"]["plate"]}
    data["parts"] = {"plate": data["parts"]["plate"]}
    data["boundaries"] = [b for b in data["boundaries"] if b["type"] != "ale_boundary"]
    data["control"]["end_time"] = END
    data["output"]["interval"] = 1.0
    data["output"]["fields"] = []
    data["output"].pop("probes", None)
    data["initial"] = [{"type": "velocity", "set": "free", "velocity": None}]
    return data


def deck_3d(thickness_layers: int = 2, hourglass: dict | None = None, rim: float = RIM, h: float = H) -> dict:
    """The 3D quarter's plate, dry; the clamp every node at r >= rim (r measured in the plane); h in plane."""
    data = _dry(yaml.safe_load(DECK_3D.read_text()))
    data["parts"]["plate"]["geometry"]["box"]["divisions"] = [round(LENGTH / h), round(LENGTH / h), thickness_layers]
    if hourglass is not None:
        data["sections"]["plate"]["hourglass"] = hourglass
    # the shipped rim set: distance from (0, 0, t/2) in [rim - 5e-5, 0.3]; nodes at r >= rim - 1.3e-4 (z = 0, t)
    outer = 0.3
    data["sets"]["rim"] = {"type": "node", "part": "plate", "tolerance": (outer - rim + 5e-5) / 2,
                           "sphere": {"center": [0.0, 0.0, THICKNESS / 2], "radius": (outer + rim - 5e-5) / 2}}
    # its complement: distance in [0, rim - 5e-5 - 1e-7]
    inner = (rim - 5e-5 - 1e-7) / 2
    data["sets"]["free"] = {"type": "node", "part": "plate", "tolerance": inner,
                            "sphere": {"center": [0.0, 0.0, THICKNESS / 2], "radius": inner}}
    data["initial"][0]["velocity"] = [0.0, 0.0, V0]
    return data


def deck_rz(hourglass: dict | None = None, h: float = H) -> dict:
    """The r-z twin's plate (docs/studies/underwater_explosion_plate_3d.py, rz_scene at 5 mm), dry; h in r and z."""
    data = _dry(yaml.safe_load(DECK_RZ.read_text()))
    data["parts"]["plate"]["geometry"]["box"] = {"min": [0.0, 0.0], "max": [LENGTH, THICKNESS],
                                                 "divisions": [round(LENGTH / h), round(THICKNESS / h)]}
    if hourglass is not None:
        data["sections"]["plate"]["hourglass"] = hourglass
    data["output"]["histories"] = [{"name": "centre", "point": [0.0, THICKNESS / 2],
                                    "quantities": ["displacement", "velocity", "von_mises"]}]
    data["sets"]["free"] = {"type": "node", "part": "plate", "box": {"min": [-0.1, -0.1], "max": [RIM - 1e-4, 0.1]}}
    data["initial"][0]["velocity"] = [0.0, V0]
    return data


def check_sets(data: dict) -> tuple[int, int, float, float]:
    """(free nodes, fixed nodes, largest free r, smallest fixed r): the two sets must split the plate's nodes."""
    loaded = api.load(data, base_dir=ROOT)
    model = loaded.model
    free, rim = model.target_nodes(None, "free"), model.target_nodes(None, "rim")
    free, rim = np.unique(np.asarray(free)), np.unique(np.asarray(rim))
    assert not np.intersect1d(free, rim).size and free.size + rim.size == model.n_nodes, (free.size, rim.size)
    x = model.coordinates
    r = np.hypot(x[:, 0], x[:, 1]) if x.shape[1] == 3 else x[:, 0]
    return free.size, rim.size, float(r[free].max()), float(r[rim].min())


def run(name: str, data: dict, work: Path) -> dict:
    folder = work / name
    cpu = time.process_time()
    result = api.run(data, folder, threads=1, overwrite=True, base_dir=ROOT)
    cpu = time.process_time() - cpu
    hist = result.histories()
    centre, glstat = hist["centre"], hist["glstat"]
    axial = "displacement_z" if "displacement_z" in centre else "displacement_y"
    t, u = centre["time"], centre[axial]
    i = int(np.argmax(u))
    j = int(np.argmin(np.abs(glstat["time"] - t[i])))
    hg_share = float(glstat["hourglass"][j] / (glstat["internal"][j] + glstat["hourglass"][j]))
    return {"hg_share": hg_share, "ke0": float(glstat["kinetic"][0]), "name": name, "status": result.status, "end": float(t[-1]), "u_max": float(u[i]), "t_max": float(t[i]),
            "u_end": float(u[-1]), "u_min_after": float(u[i:].min()), "cpu": cpu,
            "energy_ratio": float(glstat["energy_ratio"][-1]), "steps": result.steps, "t": t, "u": u}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--variants", action="store_true", help="also the 3D variants")
    parser.add_argument("--extra", action="store_true",
                        help="also the r-z twin's hourglass variants and both plates at 2.5 mm (4 elements thick)")
    parser.add_argument("--fine", action="store_true",
                        help="also both plates at 1.25 mm (8 elements thick; the 3D quarter 160 x 160 x 8, ~15 min CPU)")
    parser.add_argument("--work", type=Path, default=Path("study_undex_plate_dry"))
    args = parser.parse_args()
    args.work.mkdir(exist_ok=True)
    cases = [("rz", deck_rz()), ("3d", deck_3d())]
    if args.variants:
        cases += [("3d_hg0.03", deck_3d(hourglass={"type": "stiffness", "coefficient": 0.03})),
                  ("3d_hg_viscous0.1", deck_3d(hourglass={"type": "viscous", "coefficient": 0.1})),
                  ("3d_4layers", deck_3d(thickness_layers=4)),
                  ("3d_rim0.145", deck_3d(rim=0.145))]
    if args.extra:
        cases += [("rz_hg0.03", deck_rz(hourglass={"type": "stiffness", "coefficient": 0.03})),
                  ("rz_hg_viscous0.1", deck_rz(hourglass={"type": "viscous", "coefficient": 0.1})),
                  ("rz_h2.5", deck_rz(h=0.0025)),
                  ("3d_h2.5_2layers", deck_3d(h=0.0025)),
                  ("3d_h2.5", deck_3d(thickness_layers=4, h=0.0025))]
    if args.fine:
        cases += [("rz_h1.25", deck_rz(h=0.00125)), ("3d_h1.25", deck_3d(thickness_layers=8, h=0.00125))]
    rows = []
    for name, data in cases:
        n_free, n_rim, r_free, r_rim = check_sets(data)
        row = run(name, data, args.work)
        rows.append(row)
        print(f"{name}: free nodes {n_free} (r <= {r_free * 1e3:.2f} mm), fixed {n_rim} (r >= {r_rim * 1e3:.2f} mm); "
              f"{row['status']} at {row['end'] * 1e3:.3f} ms, {row['steps']} steps; u_max {row['u_max'] * 1e3:.3f} mm "
              f"at {row['t_max'] * 1e3:.3f} ms, u(0.8 ms) {row['u_end'] * 1e3:.3f} mm, min after the maximum "
              f"{row['u_min_after'] * 1e3:.3f} mm, initial kinetic energy {row['ke0']:.1f} J, hourglass energy at the "
              f"maximum {row['hg_share'] * 100:.1f} % of internal + hourglass, energy ratio {row['energy_ratio']:.4f}, CPU {row['cpu']:.1f} s",
              flush=True)
    rz = rows[0]
    print("\n| case | peak u (mm) | t_peak (ms) | u(0.8 ms) (mm) | peak / r-z | hourglass share | CPU s |\n"
          "|---|---|---|---|---|---|---|")
    for row in rows:
        print(f"| {row['name']} | {row['u_max'] * 1e3:.2f} | {row['t_max'] * 1e3:.3f} | {row['u_end'] * 1e3:.2f} | "
              f"{row['u_max'] / rz['u_max']:.3f} | {row['hg_share'] * 100:.1f} % | {row['cpu']:.1f} |")
    if not math.isnan(rz["u_max"]):
        np.savez(args.work / "histories.npz", **{row["name"] + "_t": row["t"] for row in rows},
                 **{row["name"] + "_u": row["u"] for row in rows})


if __name__ == "__main__":
    main()
