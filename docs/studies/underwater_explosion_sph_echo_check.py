"""Echo check of the SPH underwater-explosion twin's non-reflecting sides (issue 18 A3).

Derives the SPH deck (study.derive.sph_variant at ratio 1, as decks/underwater_explosion_sph.yaml is made)
from the ALE deck as shipped and from the ALE deck with `extra` metres more water on the left, right and
bottom (the enlargement of underwater_explosion_echo_check.py: mesh and fill enlarged, element size
unchanged, the plate extended with every node beyond the clamped ends fixed), runs both to `end` and
prints the plate centre's peaks and their differences. docs/studies/fsi_convergence_audit.md gives the
figures ("The SPH twin with non-reflecting sides").

    PYTHONPATH=. NUMBA_NUM_THREADS=1 python docs/studies/underwater_explosion_sph_echo_check.py 0.3 1.3e-3 /tmp/echo

A fourth argument, a run folder of the shipped deck (decks/underwater_explosion_sph.yaml run to `end`),
takes the shipped tank's histories from there instead of running the derived one; the larger tank then
gets the shipped deck's output interval (2e-5 s), the only setting besides the title in which the derived
deck differs from it (the steps land on the field output times, so both runs land on the same ones).
"""
import sys
import types
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))
import underwater_explosion_echo_check as echo  # noqa: E402

from sphfem_cli import api  # noqa: E402
from sphfem_cli.deck.loader import loads  # noqa: E402
from sphfem_cli.study.derive import sph_variant  # noqa: E402

echo.yaml = types.SimpleNamespace(safe_load=lambda text: loads(text)[0])  # the deck loader's number rules
SHIPPED_EXTRA = 0.15  # the shipped ALE tank is the echo script's original one with 0.15 m more water


def sph_deck(extra: float, end: float, interval: float = 1e-4) -> dict:
    d = sph_variant(echo.deck("plane", round(SHIPPED_EXTRA + extra, 6), end), 1).data
    d["output"]["interval"] = interval
    return d


def peaks(h) -> dict:
    return {"maximum [mm]": 1e3 * h["displacement_y"].max(), "peak velocity [m/s]": h["velocity_y"].max(),
            "peak von Mises [MPa]": 1e-6 * h["von_mises"].max()}


def main():
    extra, end, out = float(sys.argv[1]), float(sys.argv[2]), Path(sys.argv[3])
    runs = {}
    cases = (("ship", 0.0), ("big", extra))
    interval = 1e-4
    if len(sys.argv) > 4:  # the shipped deck's run
        runs["ship"] = api.read_histories(sys.argv[4])["centre"]
        cases, interval = cases[1:], 2e-5
    for tag, e in cases:
        r = api.run(sph_deck(e, end, interval), out / f"sph_{tag}", overwrite=True, threads=1)
        print(tag, r.status, r.time, r.steps, flush=True)
        runs[tag] = r.histories()["centre"]
    a, b = peaks(runs["ship"]), peaks(runs["big"])
    for k in a:
        print(f"{k}: {a[k]:.4g} / {b[k]:.4g} ({100 * (a[k] - b[k]) / b[k]:+.2f} %)")
    t = np.arange(0.0, min(runs["ship"]["time"][-1], runs["big"]["time"][-1]), 1e-6)
    for k in ("displacement_y", "velocity_y", "von_mises"):
        x, y = (np.interp(t, h["time"], h[k]) for h in (runs["ship"], runs["big"]))
        i = int(np.argmax(np.abs(x - y)))
        print(f"{k}: largest difference {abs(x[i] - y[i]):.4g} at {t[i] * 1e3:.3f} ms")


if __name__ == "__main__":
    main()
