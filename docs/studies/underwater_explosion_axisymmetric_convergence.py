"""Issue 18 item 1 / issue 15 on decks/underwater_explosion_axisymmetric_ale.yaml: the water refined with
the plate fixed (60 x 4), three levels h = 2.5 / 1.25 / 0.625 mm, to 0.2 ms (the free-field peaks at 30 and
62 us, the plate centre's peak velocity near 0.2 ms).

    python docs/studies/underwater_explosion_axisymmetric_convergence.py   # from the repository root

The coupling keeps the deck's rule L_c = n h / pfac = h / 2 (pfac = 2 n), n = h / (segment / nquad) coupling
points per water element, nquad raised where the plate's 2.5 mm segment is longer than the water element
(docs/theory/coupling.md, "Stiffness"). Prints, per level, the charge as filled, the probes' peaks, the plate
centre's peak velocity and displacement at the end, the CPU seconds, then the observed order and the GCI
(Roache, safety factor 1.25, refinement ratio 2) of each quantity on the three levels.
"""
import math
import sys
import time
from pathlib import Path

import numpy as np

from sphfem_cli import api
from sphfem_cli.model.mesh import ring_volumes
from sphfem_cli.study.metrics import describe, three_grid

ROOT = Path(__file__).resolve().parents[2]
DECK = ROOT / "decks/underwater_explosion_axisymmetric_ale.yaml"
WORK = Path("study_undex_axisymmetric")
SEGMENT = 0.15 / 60  # the plate's segment length, m
LEVELS = (0.0025, 0.00125, 0.000625)


def overrides(h: float) -> dict:
    nquad = max(2, math.ceil(SEGMENT / h - 1e-9))
    n = h / (SEGMENT / nquad)
    return {"parts.tank.geometry.box.element_size": h, "couplings.0.nquad": nquad, "couplings.0.pfac": 2.0 * n,
            "control.end_time": 2.0e-4, "output.interval": 1.0e-4}


def charge_mass(loaded) -> float:
    model, ale = loaded.model, loaded.model.ale
    vol = ring_volumes(np.ascontiguousarray(ale.nodes), np.ascontiguousarray(ale.elements))
    j = [model.material_names[k] for k in ale.materials].index("tnt")
    return float((ale.fractions[:, j] * vol * ale.density[:, j]).sum())


def level(h: float) -> dict:
    loaded = api.load(DECK, overrides(h))
    cpu = time.process_time()
    result = api.run(loaded, WORK / f"h{h * 1e3:g}mm", threads=1, overwrite=True)
    cpu = time.process_time() - cpu
    assert result.completed, result.message
    hist = result.histories()
    out = {"charge_kg": charge_mass(loaded), "cpu_s": cpu, "steps": result.steps}
    for probe in ("half_pressure", "standoff_pressure", "plate_pressure"):
        out[f"{probe}_MPa"] = float(hist[probe]["pressure"].max()) / 1e6
    out["centre_peak_velocity"] = float(np.abs(hist["centre"]["velocity_y"]).max())
    out["centre_displacement_end_mm"] = float(hist["centre"]["displacement_y"][-1]) * 1e3
    return out


def main() -> None:
    WORK.mkdir(exist_ok=True)
    runs = [level(h) for h in LEVELS]
    for h, run in zip(LEVELS, runs):
        print(f"h = {h * 1e3:g} mm: " + ", ".join(f"{k} {v:.4g}" for k, v in run.items()))
    for key in runs[0]:
        if key in ("cpu_s", "steps"):
            continue
        conv = three_grid(LEVELS, [run[key] for run in runs])
        print(f"{key}: {' / '.join(f'{run[key]:.4g}' for run in runs)}; {describe(conv)}")


if __name__ == "__main__":
    sys.exit(main())
