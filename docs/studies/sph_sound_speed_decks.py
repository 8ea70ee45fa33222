"""Issue 18 item 2 on the SPH decks with an artificial sound speed and a fixed Monaghan alpha: does the compared
answer move with c0, what peak Mach number does the run reach, and does the shock switch make the answer
independent of c0? (figures in docs/studies/sph_sound_speed_decks.md).

    python docs/studies/sph_sound_speed_decks.py DECK@FACTOR@KIND [...]   # from the repository root
    python docs/studies/sph_sound_speed_decks.py --summary

DECK is a key of CASES, FACTOR multiplies the sound speed c0 the deck had before this study (CASES; Tait
``sound_speed``; for the linear polynomial EOS C1 = rho0 c0^2 is multiplied by FACTOR^2), KIND is "fixed" (the
fixed Monaghan alpha the deck had before this study, an effective kinematic viscosity alpha h c0 / 8 in 2D:
Monaghan 2005, Rep. Prog. Phys. 68, 1703, sec. 4.2, so it grows with c0) or "switch" (Morris & Monaghan
1997's switch as in decks/dam_break_wall_pressure_sph.yaml: alpha_i between a floor 0.01 and 1, decay 0.1, beta 0;
sphfem_cli/sph/switch.py). Each case runs on one thread (NUMBA_NUM_THREADS=1) into study_c0/<case>/ and appends
one JSON line to study_c0/log.jsonl: CPU seconds of the child process, the 1-minute load average, the peak Mach
number max|v|/c0 over the SPH particles of the field outputs (written every window/100 for this), and the
deck's compared quantities (the ones its header and validation test compare).
"""
from __future__ import annotations

import copy
import json
import os
import resource
import subprocess
import sys
from pathlib import Path

import h5py
import numpy as np
import yaml

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tests" / "verification"))
WORK = Path("study_c0")
SWITCH = {"alpha": 0.01, "beta": 0.0, "switch": {"alpha_max": 1.0, "decay": 0.1}}
MM = ROOT.parent / "shared" / "reference" / "dambreak_front_martin_moyce_1952.csv"


def _dam_break_2d(out: Path, a: float = 0.0572) -> dict:
    """Front Z = x_front / a at the times T = t sqrt(2 g / a) of Martin & Moyce's a = 2.25 in series, T <= 3,
    and its relative error there (a: the column's width, 0.0572 m in dam_break_2d, 0.1 m in dam_break_3d)."""
    g = 9.81
    h = np.genfromtxt(out / "histories" / "front.csv", delimiter=",", names=True)
    rows = [r.split(",") for r in MM.read_text().splitlines() if r.startswith("MM_a2.25in")]
    T_ref = np.array([float(r[1]) for r in rows])
    Z_ref = np.array([float(r[2]) for r in rows])
    keep = T_ref <= 3.0
    Z = np.interp(T_ref[keep], h["time"] * np.sqrt(2 * g / a), h["front"] / a)
    return {"T": T_ref[keep].round(3).tolist(), "Z": Z.round(3).tolist(),
            "err_pct": (100 * (Z / Z_ref[keep] - 1)).round(1).tolist()}


def _elastic_gate(out: Path) -> dict:
    """The free end's largest x displacement, its time, and its y displacement maximum (decks header)."""
    h = np.genfromtxt(out / "histories" / "gate_tip.csv", delimiter=",", names=True)
    i = int(np.argmax(h["displacement_x"]))
    return {"ux_max_mm": round(1e3 * h["displacement_x"][i], 2), "t_max": round(float(h["time"][i]), 3),
            "uy_max_mm": round(1e3 * float(h["displacement_y"].max()), 2),
            "ux_at_mm": {str(t): round(1e3 * float(np.interp(t, h["time"], h["displacement_x"])), 2)
                         for t in (0.05, 0.10, 0.15)}}


def _water_column(out: Path) -> dict:
    """Floor probes' pressure over the last 0.1 s against rho g (H - z) (H = 0.2 m, z = 0.02 m): mean, lowest
    and highest (the column's acoustic mode rings about the hydrostatic state)."""
    exact = 1000.0 * 9.81 * (0.2 - 0.02)
    res = {}
    for name in ("floor_axis", "floor_mid"):
        h = np.genfromtxt(out / "histories" / f"{name}.csv", delimiter=",", names=True)
        late = h["time"] >= h["time"][-1] - 0.1
        p = h[[c for c in h.dtype.names if c != "time"][0]][late] / exact - 1
        res[name + "_pct"] = [round(100 * float(q), 2) for q in (p.mean(), p.min(), p.max())]
    return res


def _dam_break_3d(out: Path) -> dict:
    return _dam_break_2d(out, a=0.1)


def _hydrostatic_plate(out: Path) -> dict:
    """Mid-span deflection's mean over 0.04-0.12 s (the deck's validation window) against the plate formula's
    static w = -6.86e-5 m (the deck's header)."""
    h = np.genfromtxt(out / "histories" / "midspan.csv", delimiter=",", names=True)
    m = (h["time"] >= 0.04) & (h["time"] <= 0.12)
    w = float(h["displacement_y"][m].mean())
    return {"w_mean": float(f"{w:.5g}"), "w_pct": round(100 * (w / -6.86e-5 - 1), 2)}


def _wet_cantilever(out: Path) -> dict:
    """Wet first frequency and damping ratio fitted to the tip's free ringing after the release (0.051 s + 4 ms),
    as docs/studies/wet_cantilever_runs.py."""
    import wet_cantilever_reference as ref

    tip = np.genfromtxt(out / "histories" / "tip.csv", delimiter=",", names=True)
    r = ref.ringing(tip["time"], tip["displacement_x"], 0.055)
    return {"frequency": round(r.frequency, 3), "zeta": round(r.zeta, 4), "periods": round(r.periods, 2)}


# deck, c0 and fixed alpha before this study (the "@1@fixed" case is the deck as it was), the window run (None: the
# deck's end_time), overrides (path -> value) and the measures
CASES = {
    # dam_break_2d: the deck changed on 7 December 2026 (wall-function walls, water viscosity, switch, c0 30;
    # docs/studies/dam_break_2d.py): its tables in the .md were run on the deck before (git show cb4274c:decks/dam_break_2d.yaml)
    "dam_break_2d": ("dam_break_2d", 15.0, 0.1, None, {}, _dam_break_2d),
    # a/dx = 40 (the deck: 20), the resolution of the validation test of the SPH scene (test_sph_dambreak.py)
    "dam_break_2d_a40": ("dam_break_2d", 15.0, 0.1, None, {"parts.column.spacing": 0.00143}, _dam_break_2d),
    "elastic_gate": ("elastic_gate_sph", 20.0, 0.1, 0.16, {}, _elastic_gate),
    "dam_break_3d": ("dam_break_3d", 20.0, 0.1, None, {}, _dam_break_3d),
    "hydrostatic_plate": ("hydrostatic_plate_sph", 200.0, 0.1, None, {}, _hydrostatic_plate),
    "water_column": ("water_column_axisymmetric_sph", 14.0, 0.02, None, {}, _water_column),
    "wet_cantilever": ("wet_cantilever_sph", 100.0, 0.1, None, {}, _wet_cantilever),
    # the wet cantilever at the resolution it shipped with before issue 18 (5 mm water, 4 x 48 plate; 1/5 of the
    # shipped one's CPU time)
    "wet_cantilever_5mm": ("wet_cantilever_sph", 100.0, 0.1, None,
                           {"parts.left.spacing": 0.005, "parts.right.spacing": 0.005,
                            "parts.plate.geometry.box.divisions": [4, 48]}, _wet_cantilever),
}


def _set(d: dict, path: str, value) -> None:
    keys = path.split(".")
    for k in keys[:-1]:
        d = d[k]
    d[keys[-1]] = value


def variant(key: str, factor: float, kind: str) -> tuple[dict, float, float]:
    """The case's deck as a dict, its sound speed and its end time."""
    name, c0, alpha, window, overrides, _ = CASES[key]
    d = copy.deepcopy(yaml.safe_load((ROOT / "decks" / f"{name}.yaml").read_text()))
    eos = d["equations_of_state"]["water"]
    if eos["type"] == "tait":
        eos["sound_speed"] = c0 * factor
    else:  # linear polynomial: p = C1 (rho / rho0 - 1), C1 = rho0 c0^2
        eos["c1"] = float(eos["c1"]) * factor ** 2  # PyYAML reads "1.0e7" (no exponent sign) as a string
    d["sections"]["fluid"]["artificial_viscosity"] = dict(SWITCH) if kind == "switch" else {"alpha": alpha}
    for path, value in overrides.items():
        _set(d, path, value)
    end = window or d["control"]["end_time"]
    d["control"]["end_time"] = end
    d["output"]["interval"] = end / 100
    d["output"].pop("references", None)
    return d, c0 * factor, end


def peak_mach(h5: Path, c0: float, interval: float) -> tuple[float, float]:
    """Largest particle speed over the SPH parts' field outputs, divided by c0, and the time of that output
    (output k is written at k * interval)."""
    best, when = 0.0, 0.0
    with h5py.File(h5, "r") as f:
        for part in f.values():
            if not isinstance(part, h5py.Group):
                continue
            for name, step in part.items():
                if not name.startswith("step_") or "smoothing_length" not in step.get("point", {}):  # SPH parts only
                    continue
                v = np.asarray(step["point"]["velocity"])
                active = np.asarray(step["point"]["active"]).astype(bool) if "active" in step["point"] else slice(None)
                s = float(np.linalg.norm(v[active], axis=1).max())
                if s > best:
                    best, when = s, round(int(name[5:]) * interval, 5)
    return best / c0, when


def run(case: str) -> dict:
    key, factor, kind = case.split("@")
    d, c0, end = variant(key, float(factor), kind)
    folder = WORK / case.replace("@", "_")
    folder.mkdir(parents=True, exist_ok=True)
    deck = folder / "deck.yaml"
    deck.write_text(yaml.safe_dump(d, sort_keys=False))
    env = dict(os.environ, NUMBA_NUM_THREADS="1", PYTHONPATH=str(ROOT))
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    proc = subprocess.run([sys.executable, "-m", "sphfem_cli.cli", "run", str(deck), "-o", str(folder / "run"),
                           "--overwrite", "-q", "--threads", "1"], env=env, capture_output=True, text=True)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    row = {"case": case, "c0": c0, "end": end, "rc": proc.returncode,
           "cpu_s": round(after.ru_utime + after.ru_stime - before.ru_utime - before.ru_stime, 1),
           "load": round(os.getloadavg()[0], 2)}
    if proc.returncode != 0:
        row["error"] = (proc.stdout + proc.stderr)[-400:]
    else:
        mach, t = peak_mach(folder / "run" / "results.h5", c0, end / 100)
        row.update(mach=round(mach, 4), mach_t=t, **CASES[key][5](folder / "run"))
    with open(WORK / "log.jsonl", "a") as log:
        log.write(json.dumps(row) + "\n")
    return row


def summary() -> None:
    for line in (WORK / "log.jsonl").read_text().splitlines():
        print(line)


if __name__ == "__main__":
    if sys.argv[1:] == ["--summary"]:
        summary()
    else:
        WORK.mkdir(exist_ok=True)
        for arg in sys.argv[1:]:
            print(json.dumps(run(arg)), flush=True)
