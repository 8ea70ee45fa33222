"""The r-z SPH free field against the 1D spherical reference and the r-z ALE at equal spacing (issue 15;
docs/studies/underwater_explosion.md, "Axisymmetric SPH free field").

Both are derived from decks/underwater_explosion_free_field_axisymmetric_ale.yaml by the mesh study's rules
(sphfem_cli/study/derive.py): the ALE deck meshed at h (``ale_variant``) and its SPH twin with particles at
the sub-centres of that mesh (``sph_variant`` at ratio 10 mm / h), as the shipped
decks/underwater_explosion_free_field_axisymmetric_sph.yaml (ratio 2). Histories at every step (1e-8 s). Per
run: the peak pressure at the four probes (R = 0.06 ... 0.18 m), its time, the impulse to 0.12 ms, the share
of the charge's internal energy left in the products at 0.12 ms, and the CPU seconds of the run (process
time, compilation included on the first run of each method: run a small level first).

    PYTHONPATH=. NUMBA_NUM_THREADS=1 python docs/studies/underwater_explosion_axisymmetric_sph.py \
        --levels 0.005 0.0025 0.00125 [--methods sph ale] [--viscosity 0.1 0] [--plane] [--plain] [-o /tmp/rz_sph]

The SPH runs with the artificial viscosity of decks/underwater_explosion_free_field_axisymmetric_sph.yaml
(Monaghan alpha 1, beta 2; the derivation's own default is alpha 0.1, beta 0); ``--viscosity ALPHA BETA``
overrides it (``--viscosity 0.1 0``: the runs before the change). ``--plane`` runs the same scene as a plane
2D deck (dimension 2, the axis a slip ghost wall: an infinite TNT cylinder lit along its axis) against the 1D
cylindrical reference. ``--plain`` (r-z only) runs the SPH without the products' renormalised continuity (the plain
areal sum), for the comparison in the study page. Then the observed order p = ln(e21/e32)/ln 2 and Roache's
GCI on the finest (Fs 1.25) of every monotone triple, per method and probe, and the 1D Lagrangian reference
(tests/verification/spherical_blast_reference.py, spherical or cylindrical, dr 0.5 / 0.25 / 0.125 mm,
Richardson-extrapolated) with each SPH level's ratio to it.
"""
from __future__ import annotations

import argparse
import math
import time
from pathlib import Path

import numpy as np
import yaml

from sphfem_cli import api
from sphfem_cli.study import derive
from sphfem_cli.study.study import load_deck_data

ROOT = Path(__file__).resolve().parents[2]
DECK = ROOT / "decks" / "underwater_explosion_free_field_axisymmetric_ale.yaml"
SPH_DECK = ROOT / "decks" / "underwater_explosion_free_field_axisymmetric_sph.yaml"
PROBES = ("p_r060", "p_r100", "p_r140", "p_r180")
RADII = (0.06, 0.10, 0.14, 0.18)  # the probes' distances from the charge centre, m


def run_level(method: str, h: float, out: Path, plain: bool = False, viscosity: tuple | None = None,
              plane: bool = False) -> dict:
    """Run one level; its probe peaks (MPa), peak times (us), impulses (Pa s), products' energy share, CPU s.
    ``viscosity`` (alpha, beta) of the SPH, default the shipped SPH deck's; ``plane``: the plane 2D twin."""
    data = load_deck_data(DECK)
    deck = derive.sph_variant(data, round(0.01 / h)).data if method == "sph" else derive.ale_variant(data, h).data
    if method == "sph":
        shipped = yaml.safe_load(SPH_DECK.read_text())["sections"]["sph"]["artificial_viscosity"]
        av = dict(shipped) if viscosity is None else {"alpha": viscosity[0], "beta": viscosity[1]}
        deck["sections"]["sph"]["artificial_viscosity"] = av
        if plane:  # the axis becomes a slip ghost wall: a TNT cylinder of radius 20 mm lit along its axis
            deck["dimension"] = 2
            deck["boundaries"][0]["sides"] = ["bottom", "left"]
    if plain:
        from sphfem_cli.sph import axisymmetric

        axisymmetric.renormalise_ring_continuity = lambda *args: 0  # the plain areal sum for the products
    t0 = time.process_time()
    result = api.run(deck, out, {"output.history_interval": 1.0e-8, "output.interval": 1.0}, overwrite=True,
                     threads=1)
    cpu = time.process_time() - t0
    assert result.completed, result.message
    hist = result.histories()
    peaks, times, impulses = [], [], []
    for p in PROBES:
        t, pr = hist[p]["time"], np.nan_to_num(hist[p]["pressure"])
        i = int(np.argmax(pr))
        peaks.append(pr[i] / 1e6)
        times.append(t[i] * 1e6)
        impulses.append(float(np.trapezoid(pr, t)))
    if method == "sph":
        e = hist["matsum"]["pool_fill0_internal"]
    else:
        e = hist["ale_materials"]["internal_tnt"]
    return {"peaks": peaks, "times": times, "impulses": impulses, "products": float(e[-1] / e[0]), "cpu": cpu,
            "steps": len(hist["glstat"]["time"]) - 1}


def order_and_gci(f: list[float]) -> tuple[float, float] | None:
    """Observed order and GCI (fine level, Fs 1.25) of three levels at ratio 2, coarse to fine; None unless monotone."""
    e21, e32 = f[1] - f[0], f[2] - f[1]
    if e21 == 0.0 or e32 == 0.0 or e21 * e32 < 0.0:
        return None
    p = math.log(abs(e21 / e32)) / math.log(2.0)
    return p, 1.25 * abs(e32 / f[2]) / (2.0 ** p - 1.0) if p > 0 else float("inf")


def reference_1d(geometry: str) -> list[float]:
    """The 1D Lagrangian reference's peaks (MPa) at RADII, Richardson-extrapolated from dr 0.5 / 0.25 / 0.125 mm."""
    import sys

    sys.path.insert(0, str(ROOT))
    from sphfem_cli.study.metrics import three_grid
    from tests.verification.spherical_blast_reference import blast, peaks, setup_from_deck

    drs = (5e-4, 2.5e-4, 1.25e-4)
    setup = setup_from_deck(DECK)
    pk = np.array([peaks(blast(setup, dr, np.array(RADII), t_end=1.2e-4, geometry=geometry))["peak"] for dr in drs])
    return [three_grid(drs, pk[:, k]).extrapolated / 1e6 for k in range(len(RADII))]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--levels", type=float, nargs="+", default=[0.005, 0.0025, 0.00125])
    ap.add_argument("--methods", nargs="+", default=["sph", "ale"])
    ap.add_argument("--plain", action="store_true")
    ap.add_argument("--plane", action="store_true")
    ap.add_argument("--viscosity", type=float, nargs=2, default=None, metavar=("ALPHA", "BETA"))
    ap.add_argument("-o", type=Path, default=Path("rz_sph_free_field"))
    args = ap.parse_args()
    methods = ["sph"] if args.plane else args.methods  # the plane twin is an SPH deck only
    geometry = "cylindrical" if args.plane else "spherical"
    ref = reference_1d(geometry)
    print(f"1D {geometry} reference (extrapolated) {np.round(ref, 1)} MPa", flush=True)
    for method in methods:
        rows = []
        for h in args.levels:
            r = run_level(method, h, args.o / f"{method}_{h:g}", plain=args.plain and method == "sph",
                          viscosity=args.viscosity, plane=args.plane)
            rows.append(r)
            print(f"{method} h {h * 1000:g} mm: peaks {np.round(r['peaks'], 1)} MPa at {np.round(r['times'], 1)} us; "
                  f"impulse {np.round(r['impulses'], 0)} Pa s; products keep {r['products']:.3f}; "
                  f"{r['steps']} steps, {r['cpu']:.1f} s CPU", flush=True)
        for h, r in zip(args.levels, rows):
            print(f"  {method} h {h * 1000:g} mm / 1D: {np.round(np.array(r['peaks']) / ref, 3)}")
        for k in range(len(rows) - 2):
            for j, p in enumerate(PROBES):
                og = order_and_gci([rows[k + i]["peaks"][j] for i in range(3)])
                print(f"  {method} {p} levels {k}-{k + 2}: " + ("not monotone" if og is None else
                                                             f"order {og[0]:.2f}, GCI {100 * og[1]:.1f} %"))


if __name__ == "__main__":
    main()
