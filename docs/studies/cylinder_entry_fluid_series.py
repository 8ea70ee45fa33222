"""Issue 18 acceptance A1, gap 5 of docs/studies/fsi_convergence_audit.md: the constant-speed cylinder entry's
fluid refined on the shipped decks, over the whole compared window s/D 0.05-0.4, the structure fixed.

    python docs/studies/cylinder_entry_fluid_series.py run ale 0.01      # one level into WORK/ale_0.01/level.json
    python docs/studies/cylinder_entry_fluid_series.py run sph 0.0025
    python docs/studies/cylinder_entry_fluid_series.py report            # orders / GCI on the levels present

Decks: decks/cylinder_entry_constant_speed_{ale,sph}.yaml as shipped (1.2 x 0.6 m water, c0 60, 64-segment
disc, histories every 0.02 ms) with only the water's size changed (ALE parts.tank.geometry.box.element_size,
SPH parts.water.spacing) and control.end_time cut to 0.017 s (s/D 0.41; the window ends at t = 16.6 ms and an
explicit run's history before its end does not depend on it). Run one level per process, one thread.

ALE coupling rule kept: the penalty layer L_c / h = n / pfac = 1.85 / 4 = 0.46, the deck's (64 segments of 5.40 mm,
nquad 2, h 5 mm: n = h / (segment / nquad) = 1.85; docs/theory/coupling.md, "Stiffness"). n is held too with
nquad 1 / 2 / 4 at h 10 / 5 / 2.5 mm (pfac 4), but the schema then capped nquad at 5 (16 since 12b37b3; NQUAD_MAX
keeps the recorded run's 5): at 1.25 mm nquad 5, n = 1.16 and pfac 2.5 (L_c / h still 0.46). SPH: the
contact thickness (dx / 2), the soft-constraint stiffness (0.1 m / dt0^2) and h = 1.2 dx follow dx by the deck's
own rules; nothing else changes.

Compared (the validation tests' analysis, tests/validation/test_fsi_scenes_{sph,ale}.py, by
rigid_structure_refinement.cylinder_quantities): Cs = contact_force_y / (1/2 rho D V^2), s/D = V (t - 0.005 / V) / D,
the mean of the raw 0.02 ms samples over s/D 0.05-0.1 / 0.1-0.2 / 0.2-0.4 and the window 0.05-0.4 (bounds
included), and the peak of the centred 1 ms running mean. Order / GCI: sphfem_cli.study.metrics.three_grid on the finest three
levels present (h = the element size / spacing, Fs 1.25).

Status (8 December 2026; one thread, load 1.2-4.5; `report uniform`): ALE h 10 / 5 / 2.5 / 1.25 mm window mean
1.658 / 1.554 / 1.593 / 1.562, 1 ms peak 5.90 / 4.18 / 4.51 / 4.21 (CPU 120 with compilation / 20 / 154 / 1352 s);
no compared quantity has an order on 5 / 2.5 / 1.25 mm. SPH dx 10 / 5 / 2.5 mm window 1.654 / 1.627 / 1.567, 1 ms
peak 6.95 / 5.58 / 4.91 (order 1.02, GCI 16.6 %), bins not monotone or diverging (CPU 30 / 18 / 122 s); SPH
1.25 mm not run. Tables: docs/studies/cylinder_entry.md "The water refined on the shipped decks".
"""
from __future__ import annotations

import json
import os
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from rigid_structure_refinement import D, GAP, V, cylinder_quantities  # noqa: E402
from sphfem_cli import api  # noqa: E402
from sphfem_cli.study.metrics import describe, history_columns, three_grid  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
WORK = Path(os.environ.get("CYL_FLUID_WORK", "study_cylinder_fluid"))
SHIPPED_H, SHIPPED_NQUAD, PFAC = 0.005, 2, 4.0  # the ALE deck's water element, points per segment, pfac
NQUAD_MAX = 5  # the schema's bound when the series ran (16 since 12b37b3): the recorded 1.25 mm level used 5
END_TIME = 0.017
COST = ("cpu_s", "steps", "load")


def overrides(method: str, h: float) -> dict:
    """The deck's overrides at water size h [m]: ALE nquad ~ 1 / h (n = 1.85 kept), pfac 4; SPH the spacing."""
    out: dict = {"control.end_time": END_TIME}
    if method == "ale":
        nquad = min(NQUAD_MAX, int(round(SHIPPED_NQUAD * SHIPPED_H / h)))
        pfac = PFAC * nquad * h / (SHIPPED_NQUAD * SHIPPED_H)  # n / pfac, i.e. L_c / h, kept
        out.update({"parts.tank.geometry.box.element_size": h, "couplings.0.nquad": nquad, "couplings.0.pfac": pfac})
    else:
        out["parts.water.spacing"] = h
    return out


def run_level(method: str, h: float) -> dict:
    folder = WORK / f"{method}_{h:g}"
    ov = overrides(method, h)
    cpu = time.process_time()
    result = api.run(ROOT / f"decks/cylinder_entry_constant_speed_{method}.yaml", folder / "run", ov, threads=1,
                     overwrite=True)
    cpu = time.process_time() - cpu
    assert result.completed, result.message
    out = cylinder_quantities(result.histories()["cylinder"]) | {"h": h, "cpu_s": cpu, "steps": result.steps,
                                                         "load": os.getloadavg()[0], "overrides": ov}
    (folder / "level.json").write_text(json.dumps(out, indent=1))
    return out


def analysed(folder: Path, uniform: bool) -> dict:
    """A level's quantities from its history (also one stopped before its end) with its cost from level.json."""
    hist = history_columns(folder / "run" / "histories" / "cylinder.csv")
    out = cylinder_quantities(hist, uniform) | {"h": float(folder.name.split("_")[1])}
    if (folder / "level.json").exists():
        out |= {k: v for k, v in json.loads((folder / "level.json").read_text()).items() if k in COST}
    else:
        out["unfinished at s/D"] = float(V * (hist["time"][-1] - GAP / V) / D)
    return out


def report(uniform: bool) -> None:
    print("force on a uniform 0.02 ms grid" if uniform else "raw history rows (the validation tests' analysis)")
    for method in ("ale", "sph"):
        runs = sorted((analysed(f, uniform) for f in WORK.glob(f"{method}_*")), key=lambda r: -r["h"])
        for run in runs:
            print(f"{method} h {run['h'] * 1e3:g} mm: " + ", ".join(
                f"{k} {v:.4g}" for k, v in run.items() if k != "h"), flush=True)
        for key in ("Cs 0.05-0.1", "Cs 0.1-0.2", "Cs 0.2-0.4", "Cs 0.05-0.4", "1 ms peak"):  # the compared ones
            have = [r for r in runs if key in r]
            shipped = next((r[key] for r in have if abs(r["h"] - SHIPPED_H) < 1e-9), float("nan"))
            for start in range(len(have) - 2):  # every consecutive triple, coarsest first
                triple = have[start:start + 3]
                c = three_grid([r["h"] for r in triple], [r[key] for r in triple])
                levels = " / ".join(f"{r['h'] * 1e3:g}" for r in triple)
                line = f"  {method} {key} on {levels} mm: {describe(c)}"
                if c.monotone and np.isfinite(c.extrapolated):  # no Richardson value of an oscillating triple
                    line += (f"; GCI(medium) {100 * c.gci_medium:.2f} %, Richardson {c.extrapolated:.4g}, shipped 5 mm "
                             f"{100 * (shipped - c.extrapolated) / c.extrapolated:+.1f} %")
                print(line, flush=True)


def main() -> None:
    WORK.mkdir(parents=True, exist_ok=True)
    if sys.argv[1] == "run":
        print(json.dumps(run_level(sys.argv[2], float(sys.argv[3]))), flush=True)
    else:
        report(uniform=sys.argv[2:] == ["uniform"])


if __name__ == "__main__":
    main()
