"""Issue 18 acceptance A1, gap 8 of docs/studies/fsi_convergence_audit.md: the free-fall decks' fluid refined, the
cylinder's polygon fixed (figures in docs/studies/cylinder_entry.md, "The free-fall decks: the water refined").

    python /path/to/docs/studies/cylinder_free_fall_fluid_series.py sph|ale [rho1000] [MM ...]   # run levels
    python /path/to/docs/studies/cylinder_free_fall_fluid_series.py --summary

Run folders and one JSON per level go to study_free_fall_fluid/ where the script is run. Levels are the water's
particle spacing (SPH) or element size (ALE) in mm: 10 / 5 / 2.5 (x2, the shipped x1, x1/2); each level is
one run of the shipped deck (decks/cylinder_free_fall{,_rho1000}_{sph,ale}.yaml) to its own end time (0.08 s,
T = 0.74) on one thread, with only the fluid's size changed:

- SPH: ``parts.water.spacing``. The start (the cylinder's bottom 5 mm above the water's box at 2.9384 m/s,
  contact at t_c = 1.69 ms with 2.955 m/s) is the scene's and stays; the contact's thickness, the smoothing
  length and the sound speed follow the deck's own rules (dx / 2, 1.2 dx, c0 = 60 m/s).
- ALE: ``parts.tank.geometry.box.element_size``, with the coupling points per water element held at the shipped
  deck's n = h / (segment / nquad) = 1.85 (64 segments of 5.40 mm; nquad 1 / 2 / 4 at 10 / 5 / 2.5 mm) and pfac 4
  kept, so that the penalty layer L_c = n h / pfac = 0.46 h is the same fraction of the element at every level
  (docs/theory/coupling.md, "Stiffness"). The structure series (rigid_structure_refinement.py) showed that
  changing n at a fixed layer moves the slamming force by a few per cent, so n is held.

Compared: the decks' penetration (y0 - y) / D at T = (t - t_c) sqrt(g / D) = 0.1 / 0.3 / 0.5 / 0.7 and the speed
at the end (rigid_structure_refinement.freefall_quantities). Order and GCI: Celik et al. 2008 through
sphfem_cli.study.metrics.three_grid (h the fluid size, Fs 1.25); the shipped level's estimated error is
(phi_5mm - phi_ext) / phi_ext where an order exists. An observed order far below the schemes' (SPH about 1-2,
the ALE's van Leer advection 1-2) says the three levels are not yet in the asymptotic range, and the Richardson
value is then an extrapolation far beyond the finest level, not an estimate.
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
WORK = Path("study_free_fall_fluid")
LEVELS_MM = (10.0, 5.0, 2.5)
SHIPPED_MM, SHIPPED_NQUAD, SHIPPED_PFAC = 5.0, 2, 4.0  # the ALE decks' water element, coupling points, pfac
DECKS = ("sph", "sph_rho1000", "ale", "ale_rho1000")


def overrides(method: str, mm: float) -> dict:
    """The deck overrides of one fluid level (see the module docstring)."""
    if method == "sph":
        return {"parts.water.spacing": mm / 1000.0}
    nquad = SHIPPED_NQUAD * SHIPPED_MM / mm  # the coupling points per water element n held
    if abs(nquad - round(nquad)) > 1e-9 or round(nquad) < 1:
        raise ValueError(f"ALE level {mm} mm: nquad {nquad} is not a whole number >= 1")
    return {"parts.tank.geometry.box.element_size": mm / 1000.0, "couplings.0.nquad": int(round(nquad)),
            "couplings.0.pfac": SHIPPED_PFAC}


def level(method: str, heavy: bool, mm: float) -> dict:
    name = f"{method}{'_rho1000' if heavy else ''}"
    cpu = time.process_time()
    result = api.run(ROOT / f"decks/cylinder_free_fall{'_rho1000' if heavy else ''}_{method}.yaml",
                     WORK / f"{name}_{mm:g}mm", overrides(method, mm), threads=1, overwrite=True)
    cpu = time.process_time() - cpu
    assert result.completed, result.message
    out = freefall_quantities(result.histories()["cylinder"]) | {
        "cpu_s": cpu, "steps": result.steps, "load": os.getloadavg()[0]}
    (WORK / f"{name}_{mm:g}mm.json").write_text(json.dumps(out, indent=1))
    print(f"{name} {mm:g} mm: " + ", ".join(f"{k} {v:.4g}" for k, v in out.items()), flush=True)
    return out


def summary() -> None:
    for name in DECKS:
        files = [WORK / f"{name}_{mm:g}mm.json" for mm in LEVELS_MM]
        runs = [json.loads(f.read_text()) if f.exists() else None for f in files]
        if not any(runs):
            continue
        print(f"\n{name}: " + " / ".join(f"{mm:g}" for mm in LEVELS_MM) + " mm")
        for key in [k for k in (next(r for r in runs if r)) if k not in ("cpu_s", "steps", "load")]:
            vals = [r[key] if r else float("nan") for r in runs]
            line = f"  {key}: " + " / ".join(f"{v:.4f}" for v in vals)
            if all(runs):
                c = three_grid([mm for mm in LEVELS_MM], vals)
                line += f"; {describe(c)}"
                if c.monotone and not c.diverging and c.extrapolated == c.extrapolated:
                    shipped = vals[LEVELS_MM.index(SHIPPED_MM)]
                    line += (f", Richardson {c.extrapolated:.4f}, GCI(5 mm) {100 * c.gci_medium:.2f} %, "
                             f"5 mm vs Richardson {100 * (shipped / c.extrapolated - 1):+.2f} %")
            print(line)
        print("  CPU s: " + " / ".join(f"{r['cpu_s']:.0f} (load {r['load']:.1f}, {r['steps']} steps)" if r else "-"
                                       for r in runs))


def main() -> None:
    WORK.mkdir(exist_ok=True)
    if sys.argv[1:] == ["--summary"]:
        summary()
        return
    method, rest = sys.argv[1], sys.argv[2:]
    heavy = bool(rest) and rest[0] == "rho1000"
    levels = [float(a) for a in rest[heavy:]] or list(LEVELS_MM)
    for mm in levels:
        level(method, heavy, mm)


if __name__ == "__main__":
    main()
