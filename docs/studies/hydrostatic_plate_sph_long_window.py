"""Issue 18 item 2 on decks/hydrostatic_plate_sph.yaml: is the mean mid-span deflection independent of the artificial
sound speed once the averaging window holds enough of the column's ringing? Figures in
docs/studies/sph_sound_speed_decks.md ("Hydrostatic plate").

    python docs/studies/hydrostatic_plate_sph_long_window.py hp_long@1@fixed hp_long@2@fixed   # from the repository root
    python docs/studies/hydrostatic_plate_sph_long_window.py --windows hp_long_1_fixed hp_long_2_fixed

The shipped deck run to 0.32 s (instead of 0.12 s) at c0 200 (factor 1) and 400 (factor 2) m/s with its alpha 0.1,
through docs/studies/sph_sound_speed_decks.py (one thread, CPU s, load) into study_c0/. ``--windows`` prints, per
window, the mean deflection against the plate formula's static w = -6.86e-5 m (the deck's header) with the band it
swings in, and the mean load the plate carries against the water's weight 19 620 N/m: a window whose mean load is
the weight has averaged the ringing out (the check of the deck's validation test).
"""
from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import sph_sound_speed_decks as c0study  # noqa: E402

W_STATIC, WEIGHT = -6.86e-5, 19620.0
WINDOWS = ((0.04, 0.12), (0.12, 0.20), (0.20, 0.28), (0.24, 0.32), (0.12, 0.32), (0.04, 0.32))

c0study.CASES["hp_long"] = ("hydrostatic_plate_sph", 200.0, 0.1, 0.32, {}, lambda out: {})


def windows(case: str) -> None:
    run = c0study.WORK / case / "run" / "histories"
    h = np.genfromtxt(run / "midspan.csv", delimiter=",", names=True)
    load = np.genfromtxt(run / "plate_load.csv", delimiter=",", names=True)
    print(case)
    for lo, hi in WINDOWS:
        w = h["displacement_y"][(h["time"] >= lo) & (h["time"] <= hi)]
        f = abs(load["contact_force_y"][(load["time"] >= lo) & (load["time"] <= hi)].mean())
        print(f"  {lo:.2f}-{hi:.2f} s: w mean {w.mean():.5e} m ({100 * (w.mean() / W_STATIC - 1):+.2f} %), band "
              f"{100 * (w.min() / W_STATIC - 1):+.1f} .. {100 * (w.max() / W_STATIC - 1):+.1f} %, load mean {f:.0f} N/m "
              f"({100 * (f / WEIGHT - 1):+.2f} %)")


if __name__ == "__main__":
    if sys.argv[1:2] == ["--windows"]:
        for name in sys.argv[2:]:
            windows(name)
    else:
        c0study.WORK.mkdir(exist_ok=True)
        for arg in sys.argv[1:]:
            print(c0study.json.dumps(c0study.run(arg)), flush=True)
