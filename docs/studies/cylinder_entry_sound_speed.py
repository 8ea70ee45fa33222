"""Issue 18 item 2 on decks/cylinder_entry_constant_speed_sph.yaml: does the slamming coefficient move with the
artificial sound speed c0 under the deck's fixed Monaghan alpha 0.1, and with the shock switch instead? Figures in
docs/studies/cylinder_entry.md ("The SPH deck's sound speed and viscosity").

    python docs/studies/cylinder_entry_sound_speed.py cylinder_sph@FACTOR@KIND [...]   # from the repository root
    python docs/studies/cylinder_entry_sound_speed.py --summary

FACTOR multiplies the deck's c0 = 60 m/s, KIND is "fixed" (alpha 0.1, the deck) or "switch" (Morris & Monaghan 1997,
alpha between 0.01 and 1, decay 0.1, beta 0). The runs go through docs/studies/sph_sound_speed_decks.py (its
``run``: one thread, CPU s, load, peak Mach over 100 field outputs) into study_c0/.

Compared, as the deck's header and tests/validation/test_fsi_scenes_sph.py: Cs = F_y / (1/2 rho D V^2) against
s/D, s = V (t - t_contact) (D 0.11 m, V 2.955 m/s, first contact after the 5 mm gap); the means of the raw Cs over
s/D 0.05-0.1 / 0.1-0.2 / 0.2-0.4 and over the window 0.05-0.4, and the peak of the centred 1 ms running mean.
"""
from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import sph_sound_speed_decks as c0study  # noqa: E402

D, V, RHO, GAP = 0.11, 2.955, 1000.0, 0.005
BINS = ((0.05, 0.1), (0.1, 0.2), (0.2, 0.4), (0.05, 0.4))


def _cylinder(out: Path) -> dict:
    h = np.genfromtxt(out / "histories" / "cylinder.csv", delimiter=",", names=True)
    s = V * (h["time"] - GAP / V) / D
    cs = h["contact_force_y"] / (0.5 * RHO * D * V * V)
    n = int(round(1.0e-3 / float(h["time"][2] - h["time"][1])))
    smooth = np.convolve(cs, np.ones(n) / n, mode="same")
    k = int(np.argmax(smooth))
    return {"bins": [round(float(cs[(s >= lo) & (s <= hi)].mean()), 3) for lo, hi in BINS],
            "peak_1ms": round(float(smooth[k]), 3), "peak_s_over_d": round(float(s[k]), 4)}


c0study.CASES["cylinder_sph"] = ("cylinder_entry_constant_speed_sph", 60.0, 0.1, None, {}, _cylinder)

if __name__ == "__main__":
    if sys.argv[1:] == ["--summary"]:
        c0study.summary()
    else:
        c0study.WORK.mkdir(exist_ok=True)
        for arg in sys.argv[1:]:
            print(c0study.json.dumps(c0study.run(arg)), flush=True)
