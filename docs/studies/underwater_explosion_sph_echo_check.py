"""Echo check of the SPH underwater-explosion twin's non-reflecting sides (issue 18 A3).

Derives the SPH deck (study.derive.sph_variant at ratio 1, as decks/underwater_explosion_sph.yaml is made)
from the ALE deck as shipped and from the ALE deck with `extra` metres more water on the left, right and
bottom (the enlargement of underwater_explosion_echo_check.py: mesh and fill enlarged, element size
unchanged, the plate extended with every node beyond the clamped ends fixed), runs both to `end` and
prints the plate centre's peaks and their differences. docs/studies/fsi_convergence_audit.md gives the
figures ("The SPH twin with non-reflecting sides").

    PYTHONPATH=. NUMBA_NUM_THREADS=1 python docs/studies/underwater_explosion_sph_echo_check.py 0.3 1.3e-3 /tmp/echo
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


def sph_deck(extra: float, end: float) -> dict:
    d = sph_variant(echo.deck("plane", round(SHIPPED_EXTRA + extra, 6), end), 1).data
    d["control"]["max_lost_fraction"] = 0.9  # as the shipped deck
    d["output"]["interval"] = 1e-4
    return d


def peaks(h) -> dict:
    return {"maximum [mm]": 1e3 * h["displacement_y"].max(), "peak velocity [m/s]": h["velocity_y"].max(),
            "peak von Mises [MPa]": 1e-6 * h["von_mises"].max()}


def main():
    extra, end, out = float(sys.argv[1]), float(sys.argv[2]), Path(sys.argv[3])
    runs = {}
    for tag, e in (("ship", 0.0), ("big", extra)):
        r = api.run(sph_deck(e, end), out / f"sph_{tag}", overwrite=True, threads=1)
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
