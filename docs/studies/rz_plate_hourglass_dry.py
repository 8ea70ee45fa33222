"""Issues 15 (B3b) / 18: the hourglass control of the shipped r-z plates, chosen by a dry convergence study.

    python docs/studies/rz_plate_hourglass_dry.py --scene undex                    # levels 1, 2, 4: ~90 s CPU
    python docs/studies/rz_plate_hourglass_dry.py --scene bird --levels 0.5 1 2    # ~200 s CPU (level 4: ~380 s a run)
    python docs/studies/rz_plate_hourglass_dry.py --scene bird --levels 4 --forms viscous0.1    # one form's 4x level
    python docs/studies/rz_plate_hourglass_dry.py --table            # the tables and GCI from the runs made

The plates are taken from the shipped wet decks (material, section, element size, clamp are theirs by
construction); the fluid, the bird, couplings, contacts and probes are removed:

- undex: the steel plate of decks/underwater_explosion_axisymmetric_{ale,sph}.yaml (the same plate in both:
  5 mm thick, 2.5 x 1.25 mm quads, radius 0.15 m clamped in r and z at the rim). The decks run the plate part
  on into a fixed wall (r = 0.15..0.40 / 0.72, every node there fixed); elements whose nodes are all fixed give
  no force to a free node, so here the part ends at r = 0.15 (60 x 4 at the shipped level; the rim column of
  nodes fixed). Load: the initial velocity v_z = V_UNDEX = 28.84 m/s (the ALE deck's measured peak centre
  velocity, its header) on every free node (r < 0.15), the plate at rest and stress free otherwise (LS-DYNA
  *INITIAL_VELOCITY), as docs/studies/underwater_explosion_plate_dry.py does for the 3D scene. End 1 ms, the
  decks' end.
- bird: the aluminium 2024-T3 plate of decks/bird_strike_axisymmetric_plate_{sph,ale,lagrangian}.yaml (4 mm,
  radius 0.25 m, 100 x 4 quads of 2.5 x 1 mm, the rim's nodes fixed in r and z). The bird's load lasts about
  L / v = 2 ms against the plate's peak at 1.2 ms, so it is not an impulse: the dry load is the bird's
  steady-flow force spread over its footprint, p = rho v^2 = 10 MPa on the plate's face r <= D / 2 = 0.05 m
  for T = L / v = 2 ms (Wilbeck 1978's steady-flow phase: force rho v^2 A, duration L / v), impulse
  rho v^2 A L / v = m v = 157.1 N s (the wet decks transfer 1.05-1.12 m v). End 5 ms, the decks' end.

Levels: the shipped mesh and 2x and 4x finer in both directions (undex 60 x 4, 120 x 8, 240 x 16; for the bird
plate, whose 4x level costs about 380 s CPU a run, 0.5x / 1x / 2x: 50 x 2, 100 x 4, 200 x 8), each with the
stiffness form 0.1 (shipped before 7 December 2026) and the viscous form 0.1, and the stiffness form 0.03 at the
shipped level; `--forms` runs only the forms named (the bird plate's 4x level, 400 x 16, was run with the
stiffness form 0.1 and, on 7 December 2026 after the decks took it, with the viscous form 0.1). Measured: the centre's (axis, mid-thickness node) displacement maximum, its
time, its value at the end (undex u(1 ms); bird w(5 ms) and the permanent deflection, the mean over 3.5-5 ms
as docs/studies/bird_strike_plate.md defines it), the hourglass energy over internal plus hourglass energy
(glstat) at the maximum's time and at the end, the energy ratio's largest departure from 1. Observed order,
Richardson extrapolation and GCI (Celik et al. 2008) per form over every three successive levels run (ratio 2),
the three finest last: sphfem_cli.study.metrics.three_grid.
"""
from __future__ import annotations

import argparse
import copy
import json
import math
import time
from pathlib import Path

import numpy as np
import yaml

from sphfem_cli import api
from sphfem_cli.study.metrics import three_grid

ROOT = Path(__file__).resolve().parents[2]
DECKS = {"undex": ROOT / "decks/underwater_explosion_axisymmetric_ale.yaml",
         "bird": ROOT / "decks/bird_strike_axisymmetric_plate_lagrangian.yaml"}
V_UNDEX = 28.84  # m/s, the ALE deck's measured peak plate-centre velocity
RHO_BIRD, V_BIRD, D_BIRD, L_BIRD = 1000.0, 100.0, 0.10, 0.20
SCENES = {
    # plate extent (r, z0, z1), shipped divisions, end time, centre point
    "undex": {"r": 0.15, "z": (0.0, 0.005), "div": (60, 4), "end": 1.0e-3, "centre": 0.0025, "h0": 0.0025},
    "bird": {"r": 0.25, "z": (-0.004, 0.0), "div": (100, 4), "end": 5.0e-3, "centre": -0.002, "h0": 0.0025},
}
FORMS = {"stiffness0.1": {"type": "stiffness", "coefficient": 0.1},
         "viscous0.1": {"type": "viscous", "coefficient": 0.1},
         "stiffness0.03": {"type": "stiffness", "coefficient": 0.03}}
PERMANENT = (3.5e-3, 5.0e-3)  # the bird study's window for the permanent deflection


def dry_deck(scene: str, level: float, form: str) -> dict:
    """The shipped deck's plate alone at `level` times its element count in r and in z, with the hourglass `form`."""
    spec = SCENES[scene]
    data = yaml.safe_load(DECKS[scene].read_text())
    steel = "steel" if scene == "undex" else "al2024"
    out = {"title": f"dry r-z plate, {scene}, level {level}, {form}", "units": data["units"],
           "dimension": "axisymmetric",
           "control": {"end_time": spec["end"], "timestep_scale": data["control"].get("timestep_scale", 0.9)},
           "materials": {steel: copy.deepcopy(data["materials"][steel])},
           "sections": {"plate": {"type": "solid", "hourglass": dict(FORMS[form])}}}
    z0, z1 = spec["z"]
    nr, nz = spec["div"]
    out["parts"] = {"plate": {"material": steel, "section": "plate",
                              "geometry": {"box": {"min": [0.0, z0], "max": [spec["r"], z1],
                                                   "divisions": [round(nr * level), round(nz * level)]}}}}
    out["sets"] = {"rim": {"type": "node", "part": "plate", "side": "right"}}
    out["boundaries"] = [{"type": "fixed", "set": "rim", "directions": ["x", "y"]}]
    if scene == "undex":
        out["sets"]["free"] = {"type": "node", "part": "plate",
                               "box": {"min": [-0.1, -0.1], "max": [spec["r"] - 1e-4, 0.1]}}
        out["initial"] = [{"type": "velocity", "set": "free", "velocity": [0.0, V_UNDEX]}]
    else:
        out["sets"]["footprint"] = {"type": "segment", "part": "plate",
                                    "box": {"min": [-0.1, z1 - 1e-6], "max": [D_BIRD / 2 + 1e-6, z1 + 1e-6]}}
        duration = L_BIRD / V_BIRD
        out["curves"] = {"pulse": {"points": [[0.0, 1.0], [duration, 1.0], [duration * (1 + 1e-6), 0.0]]}}
        out["loads"] = [{"type": "pressure", "set": "footprint", "value": RHO_BIRD * V_BIRD**2, "curve": "pulse"}]
    out["output"] = {"interval": 1.0, "history_interval": data["output"]["history_interval"], "fields": [],
                     "histories": [{"name": "centre", "point": [0.0, spec["centre"]],
                                    "quantities": ["displacement", "velocity"]}]}
    return out


def measure(folder: Path, scene: str) -> dict:
    hist = api.read_histories(folder)
    centre, glstat = hist["centre"], hist["glstat"]
    t, u = centre["time"], centre["displacement_y"]
    if scene == "bird":
        u = -u  # w positive away from the bird (down)
    i = int(np.argmax(u))
    share = glstat["hourglass"] / np.maximum(glstat["internal"] + glstat["hourglass"], 1e-300)
    j = int(np.argmin(np.abs(glstat["time"] - t[i])))
    row = {"u_max": float(u[i]), "t_max": float(t[i]), "u_end": float(u[-1]), "end": float(t[-1]),
           "hg_at_max": float(share[j]), "hg_end": float(share[-1]),
           "energy_error": float(np.max(np.abs(glstat["energy_ratio"] - 1.0)))}
    if scene == "bird":
        window = (t >= PERMANENT[0]) & (t <= PERMANENT[1])
        row["permanent"] = float(u[window].mean()) if window.any() else math.nan
    return row


def cases(levels: list[float], forms: list[str] | None = None) -> list[tuple[float, str]]:
    """Every level with both forms 0.1, and the stiffness form 0.03 at the shipped level; only `forms` where given."""
    every = ([(level, form) for level in levels for form in ("stiffness0.1", "viscous0.1")]
             + [(1, "stiffness0.03")] * (1 in levels))
    return [case for case in every if forms is None or case[1] in forms]


def run_case(scene: str, level: float, form: str, work: Path) -> dict:
    name = f"{scene}_L{level:g}_{form}"
    folder = work / name
    data = dry_deck(scene, level, form)
    cpu = time.process_time()
    result = api.run(data, folder, threads=1, overwrite=True, base_dir=ROOT)
    cpu = time.process_time() - cpu
    row = {"name": name, "scene": scene, "level": level, "form": form, "status": result.status,
           "steps": result.steps, "cpu": cpu, **measure(folder, scene)}
    (folder / "row.json").write_text(json.dumps(row, indent=1))
    return row


def table(rows: list[dict], scene: str) -> None:
    rows = [r for r in rows if r["scene"] == scene]
    if not rows:
        return
    spec = SCENES[scene]
    end_ms = spec["end"] * 1e3
    extra = " permanent (mm) |" if scene == "bird" else ""
    print(f"\n{scene}: | mesh (r x z) | form | u max (mm) | t max (ms) | u({end_ms:g} ms) (mm) |{extra} hourglass share at max / "
          f"end | energy error | steps | CPU s |")
    for r in sorted(rows, key=lambda r: (r["form"], r["level"])):
        nr, nz = spec["div"]
        perm = f" {r['permanent'] * 1e3:.3f} |" if scene == "bird" else ""
        print(f"| {round(nr * r['level'])} x {round(nz * r['level'])} | {r['form']} | {r['u_max'] * 1e3:.3f} | {r['t_max'] * 1e3:.3f} | "
              f"{r['u_end'] * 1e3:.3f} |{perm} {r['hg_at_max'] * 100:.2f} / {r['hg_end'] * 100:.2f} % | "
              f"{r['energy_error'] * 100:.2f} % | {r['steps']} | {r['cpu']:.1f} |")
    keys = ["u_max", "t_max", "u_end"] + (["permanent"] if scene == "bird" else [])
    for form in ("stiffness0.1", "viscous0.1"):
        series = {r["level"]: r for r in rows if r["form"] == form}
        if 1 not in series or len(series) < 3:
            continue
        ordered = sorted(series)
        for k in range(len(ordered) - 2):  # every three successive levels (ratio 2), the three finest last
            levels = ordered[k:k + 3]
            for key in keys:
                h = [spec["h0"] / level for level in levels]
                phi = [series[level][key] for level in levels]
                conv = three_grid(h, phi)
                shipped = series[1][key]
                if conv.monotone and math.isfinite(conv.extrapolated):
                    err = (shipped - conv.extrapolated) / conv.extrapolated
                    print(f"{scene} {form} {key} levels {levels}: {', '.join(f'{v * 1e3:.4f}' for v in phi)} -> order {conv.order:.2f}, "
                          f"extrapolated {conv.extrapolated * 1e3:.4f}, GCI fine {conv.gci_fine * 100:.2f} %, "
                          f"GCI medium {conv.gci_medium * 100:.2f} %, shipped level {err * 100:+.2f} % from the extrapolated")
                else:
                    print(f"{scene} {form} {key} levels {levels}: {', '.join(f'{v * 1e3:.4f}' for v in phi)} -> "
                          f"{'not monotone' if not conv.monotone else 'differences grow' if conv.diverging else 'no order'} "
                          f"(spread {(max(phi) - min(phi)) / phi[-1] * 100:.2f} % of the finest); "
                          f"shipped level {(shipped - phi[-1]) / phi[-1] * 100:+.2f} % from the finest")
    top = max(r["level"] for r in rows)
    finest = {r["form"]: r for r in rows if r["level"] == top}
    shipped = {r["form"]: r for r in rows if r["level"] == 1}
    for key in keys:
        for ref_form, ref in finest.items():
            for form, r in shipped.items():
                print(f"{scene} {key}: shipped-level {form} against finest {ref_form}: "
                      f"{(r[key] - ref[key]) / ref[key] * 100:+.2f} %")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scene", choices=["undex", "bird", "both"], default="both")
    parser.add_argument("--levels", type=float, nargs="*", default=[1, 2, 4],
                        help="element counts over the shipped mesh's, in r and in z (0.5 for the coarser level)")
    parser.add_argument("--forms", nargs="*", choices=sorted(FORMS), help="only these hourglass forms (default: all)")
    parser.add_argument("--table", action="store_true", help="only the table, from the runs in --work")
    parser.add_argument("--work", type=Path, default=Path("study_rz_plate_hourglass_dry"))
    args = parser.parse_args()
    args.work.mkdir(exist_ok=True)
    scenes = ["undex", "bird"] if args.scene == "both" else [args.scene]
    if not args.table:
        for scene in scenes:
            for level, form in cases(args.levels, args.forms):
                row = run_case(scene, level, form, args.work)
                print(f"{row['name']}: {row['status']} at {row['end'] * 1e3:.3f} ms, {row['steps']} steps, "
                      f"u_max {row['u_max'] * 1e3:.3f} mm at {row['t_max'] * 1e3:.3f} ms, u_end {row['u_end'] * 1e3:.3f} mm, "
                      f"hourglass share {row['hg_at_max'] * 100:.2f} / {row['hg_end'] * 100:.2f} %, "
                      f"energy error {row['energy_error'] * 100:.3f} %, CPU {row['cpu']:.1f} s", flush=True)
    rows = [json.loads(p.read_text()) for p in sorted(args.work.glob("*/row.json"))]
    for scene in scenes:
        table(rows, scene)


if __name__ == "__main__":
    main()
