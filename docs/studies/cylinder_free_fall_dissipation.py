"""Issue 18 items 1-2: which numerical dissipation of the SPH free-fall decks sets their sound-speed dependence
and their slow order in the water's spacing (figures in docs/studies/cylinder_entry.md, "The free-fall SPH decks:
which dissipation").

    python /path/to/docs/studies/cylinder_free_fall_dissipation.py VARIANT C0 [MM] [rho1000]   # one run
    python /path/to/docs/studies/cylinder_free_fall_dissipation.py --constant VARIANT C0   # constant-speed deck
    python /path/to/docs/studies/cylinder_free_fall_dissipation.py --summary

Each run is the shipped deck decks/cylinder_free_fall{,_rho1000}_sph.yaml to its own end time (0.08 s, T = 0.74)
on one thread, with only the fluid section's dissipation (VARIANTS), the Tait sound speed c0 [m/s] and, if given,
the water's particle spacing [mm] changed. Run folders and one JSON per run go to study_free_fall_dissipation/
where the script is run.

The two dissipations in the SPH momentum and continuity equations (docs/theory/sph.md) both scale with c0:

- Monaghan's artificial viscosity Pi_ij = -alpha c mu_ij / rho for approaching pairs; in the continuum limit it
  acts as a viscosity nu_AV = alpha h c0 / (2 (d + 2)), alpha h c0 / 8 in 2D (Monaghan 2005, Rep. Prog. Phys. 68,
  1703; an estimate whose factor depends on the kernel, the one the deck headers quote);
- the delta-SPH density diffusion delta h c0 sum_j psi_ij . grad W V_j (Molteni & Colagrossi 2009), a diffusion
  of density with coefficient ~ delta h c0, which acts on the pressure, not on the velocity.

The shock switch (Morris & Monaghan 1997) keeps alpha_i at a floor and raises it only where the flow is
compressed (-div v > 0), so that the viscosity acts at the impact and the spray's collisions and not in the
shearing boundary layer. Compared: rigid_structure_refinement.freefall_quantities (penetration (y0 - y)/D at
T = 0.1/0.3/0.5/0.7, the speed at the end), the number of steps and the energy ratio at the end.

Two variants fix the contact's thickness at 1.25 mm instead of the default dx / 2 (the soft-constraint contact
holds the particles that far from the body's surface): with the spacing series they separate the contact layer's
share of the spacing dependence from the dissipation's.
"""
from __future__ import annotations

import json
import os
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from rigid_structure_refinement import freefall_quantities  # noqa: E402
from sphfem_cli import api  # noqa: E402
from sphfem_cli.study.metrics import describe, three_grid  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
WORK = Path("study_free_fall_dissipation")
SWITCH = {"alpha_max": 1.0, "decay": 0.1}  # Morris & Monaghan 1997's constants (the schema's defaults)
# name -> overrides of sections.fluid (the shipped deck: alpha 0.1, beta 0, delta 0.1, molteni_colagrossi)
VARIANTS = {
    "shipped": {},
    "a002": {"artificial_viscosity": {"alpha": 0.02}},
    "a0": {"artificial_viscosity": {"alpha": 0.0}},
    "sw001": {"artificial_viscosity": {"alpha": 0.01, "beta": 0.0, "switch": SWITCH}},
    "d005": {"density_diffusion": 0.05},
    "dplus": {"density_diffusion_form": "delta_plus"},
    # the switch with the contact's thickness fixed at 1.25 mm (the shipped rule is dx / 2, 2.5 mm at 5 mm):
    # how much of the spacing series is the contact layer's, which scales with dx
    "sw001_t125": {"artificial_viscosity": {"alpha": 0.01, "beta": 0.0, "switch": SWITCH},
                   "/contacts.0.thickness": 0.00125},
    "t125": {"/contacts.0.thickness": 0.00125},  # the shipped dissipation, the contact at 1.25 mm
    # the switch halved (floor and ceiling): switch.py's rate is linear in (alpha_i, alpha_min, alpha_max), so
    # alpha_i, and with beta 0 every pair's Pi_ij, is exactly half the shipped deck's at the same flow
    "sw_half": {"artificial_viscosity": {"alpha": 0.005, "beta": 0.0, "switch": {"alpha_max": 0.5, "decay": 0.1}}},
}
SERIES_MM = (10.0, 5.0, 2.5, 1.25)  # the water levels of cylinder_free_fall_fluid_series.py


def overrides(variant: str, c0: float, mm: float | None) -> dict:
    # keys with a leading "/" are paths from the deck's root, the others under sections.fluid
    out = {k[1:] if k.startswith("/") else f"sections.fluid.{k}": v for k, v in VARIANTS[variant].items()}
    out["equations_of_state.water.sound_speed"] = c0
    if mm is not None:
        out["parts.water.spacing"] = mm / 1000.0
    return out


def energy_ratio_end(result) -> float:
    """The glstat-type energy ratio at the end, if the run writes one (nan otherwise)."""
    for table in result.histories().values():
        if "energy_ratio" in table:
            return float(table["energy_ratio"][-1])
    return float("nan")


def run(variant: str, c0: float, mm: float | None, heavy: bool) -> dict:
    name = f"{variant}_c{c0:g}" + (f"_{mm:g}mm" if mm is not None else "") + ("_rho1000" if heavy else "")
    cpu = time.process_time()
    result = api.run(ROOT / f"decks/cylinder_free_fall{'_rho1000' if heavy else ''}_sph.yaml", WORK / name,
                     overrides(variant, c0, mm), threads=1, overwrite=True)
    cpu = time.process_time() - cpu
    out = {"status": result.status, "message": result.message, "time": result.time}
    if result.completed:
        out |= freefall_quantities(result.histories()["cylinder"])
        out["energy ratio"] = energy_ratio_end(result)
    out |= {"cpu_s": cpu, "steps": result.steps, "load": os.getloadavg()[0]}
    (WORK / f"{name}.json").write_text(json.dumps(out, indent=1))
    print(f"{name}: " + ", ".join(f"{k} {v:.4g}" if isinstance(v, float) else f"{k} {v}" for k, v in out.items()),
          flush=True)
    return out


def constant_speed(variant: str, c0: float) -> dict:
    """The same variants on decks/cylinder_entry_constant_speed_sph.yaml (V = 2.955 m/s prescribed, the bottom
    5 mm above the water at t = 0): the mean slamming coefficient Cs = F_y / (1/2 rho V^2 D) over the header's
    s/D windows 0.05-0.1 / 0.1-0.2 / 0.2-0.4 / 0.05-0.4, s = V t - 0.005 (mean of the 0.02 ms samples)."""
    import numpy as np

    name = f"constant_{variant}_c{c0:g}"
    cpu = time.process_time()
    result = api.run(ROOT / "decks/cylinder_entry_constant_speed_sph.yaml", WORK / name,
                     overrides(variant, c0, None), threads=1, overwrite=True)
    cpu = time.process_time() - cpu
    out = {"status": result.status, "message": result.message, "time": result.time}
    if result.completed:
        h = result.histories()["cylinder"]
        s_d = (2.955 * h["time"] - 0.005) / 0.11
        cs = h["contact_force_y"] / (0.5 * 1000.0 * 0.11 * 2.955 ** 2)
        for lo, hi in ((0.05, 0.1), (0.1, 0.2), (0.2, 0.4), (0.05, 0.4)):
            out[f"Cs {lo:g}-{hi:g}"] = float(np.mean(cs[(s_d >= lo) & (s_d < hi)]))
    out |= {"cpu_s": cpu, "steps": result.steps, "load": os.getloadavg()[0]}
    (WORK / f"{name}.json").write_text(json.dumps(out, indent=1))
    print(f"{name}: " + ", ".join(f"{k} {v:.4g}" if isinstance(v, float) else f"{k} {v}" for k, v in out.items()),
          flush=True)
    return out


def summary() -> None:
    keys = ("pen T=0.1", "pen T=0.3", "pen T=0.5", "pen T=0.7", "speed end")
    print("| run | " + " | ".join(keys) + " | energy ratio | steps | CPU s (load) |")
    print("|---|" + "---|" * (len(keys) + 3))
    for f in sorted(WORK.glob("*.json")):
        if f.stem.startswith("constant_"):
            continue
        r = json.loads(f.read_text())
        if r["status"] != "completed":
            print(f"| {f.stem} | {r['status']} at t = {r['time']:.4g}: {r['message']} |")
            continue
        print(f"| {f.stem} | " + " | ".join(f"{r[k]:.4f}" for k in keys)
              + f" | {r['energy ratio']:.4f} | {r['steps']} | {r['cpu_s']:.0f} ({r['load']:.1f}) |")
    # water series of a variant at c0 60 over every three consecutive SERIES_MM that ran (Celik, Fs 1.25; h the spacing)
    for variant in VARIANTS:
        for tail in ("", "_rho1000"):
            files = [WORK / f"{variant}_c60_{mm:g}mm{tail}.json" for mm in SERIES_MM]
            runs = [json.loads(f.read_text()) if f.exists() else None for f in files]
            runs = [r if r and r["status"] == "completed" else None for r in runs]
            if sum(r is not None for r in runs) < 2:
                continue
            print(f"\n{variant}{tail}, c0 60, " + " / ".join(f"{mm:g}" for mm in SERIES_MM) + " mm:")
            for k in keys:
                print(f"  {k}: " + " / ".join(f"{r[k]:.4f}" if r else "-" for r in runs))
                for i in range(len(SERIES_MM) - 2):
                    if not all(runs[i:i + 3]):
                        continue
                    c = three_grid(SERIES_MM[i:i + 3], [r[k] for r in runs[i:i + 3]])
                    line = f"    {' / '.join(f'{mm:g}' for mm in SERIES_MM[i:i + 3])} mm: {describe(c)}"
                    if c.monotone and not c.diverging and c.extrapolated == c.extrapolated:
                        five = runs[SERIES_MM.index(5.0)][k]
                        line += (f", Richardson {c.extrapolated:.4f}, "
                                 f"5 mm vs it {100 * (five / c.extrapolated - 1):+.2f} %")
                    print(line)
            print("  CPU s (load): " + " / ".join(f"{r['cpu_s']:.0f} ({r['load']:.1f})" if r else "-" for r in runs))


def main() -> None:
    WORK.mkdir(exist_ok=True)
    if sys.argv[1:] == ["--summary"]:
        summary()
        return
    if sys.argv[1] == "--constant":
        constant_speed(sys.argv[2], float(sys.argv[3]))
        return
    args = sys.argv[1:]
    heavy = "rho1000" in args
    args = [a for a in args if a != "rho1000"]
    variant, c0 = args[0], float(args[1])
    mm = float(args[2]) if len(args) > 2 else None
    run(variant, c0, mm, heavy)


if __name__ == "__main__":
    main()
