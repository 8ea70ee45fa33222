"""decks/dam_break_2d.yaml with physical settings (issue 18 items 2 and 3): is the compared front independent of
the artificial sound speed c0 and of the shock switch's floor alpha, what peak Mach number does the run reach, and
how does the front converge with the spacing (figures in docs/studies/dam_break_2d.md).

    python docs/studies/dam_break_2d.py N@C0@FLOOR[@WALLS] [...]    # runs go to ./study_dam_break_2d/
    python docs/studies/dam_break_2d.py --summary                    # the log, and Celik's three-grid table

A case is the shipped deck with a/dx = N (spacing a / N, a = 0.0572 m), the Tait sound speed C0 [m/s], the switch's
floor alpha FLOOR (Morris & Monaghan 1997, sphfem_cli/sph/switch.py: alpha_i between FLOOR and 1, decay 0.1, beta 0;
"fixed0.1" for the fixed Monaghan alpha 0.1 without the switch) and the walls' condition WALLS (default the deck's
wall_function; no_slip or slip). Each case runs on one thread (NUMBA_NUM_THREADS=1) and appends one JSON line to
study_dam_break_2d/log.jsonl: CPU seconds of the child process, the 1-minute load average, the number of steps,
the peak Mach number max|v| / C0 over the particle velocities written every T_END / 400 = 0.4 ms (a sampled
maximum), and the front Z = x_front / a at the times T = t sqrt(2 g / a) of Martin & Moyce's a = 2.25 in series
(../shared/reference/dambreak_front_martin_moyce_1952.csv), x_front the deck's probe (the largest particle x).

The three-grid table (``--summary``) is Celik et al. 2008 (J. Fluids Eng. 130, 078001;
``sphfem_cli.study.metrics.three_grid``) on Z at each of the four times, for each (C0, FLOOR, WALLS) run at three
values of N, with the spacing h = 1 / N.
"""
from __future__ import annotations

import copy
import json
import os
import resource
import subprocess
import sys
from collections import defaultdict
from pathlib import Path

import h5py
import numpy as np
import yaml

ROOT = Path(__file__).resolve().parents[2]
WORK = Path("study_dam_break_2d")
MM = ROOT.parent / "shared" / "reference" / "dambreak_front_martin_moyce_1952.csv"
A = 0.0572
G = 9.81
T_COMPARED = (0.832, 1.219, 1.997, 2.547)
SAMPLES = 400


def reference() -> tuple[np.ndarray, np.ndarray]:
    """Martin & Moyce's a = 2.25 in series: T and Z at the four compared times."""
    rows = [r.split(",") for r in MM.read_text().splitlines() if r.startswith("MM_a2.25in")]
    T = np.array([float(r[1]) for r in rows])
    Z = np.array([float(r[2]) for r in rows])
    keep = np.isin(T.round(3), T_COMPARED)
    return T[keep], Z[keep]


def variant(n: int, c0: float, floor: str, walls: str) -> dict:
    """The shipped deck with a/dx = n, sound speed c0, the viscosity FLOOR and the walls' condition."""
    d = copy.deepcopy(yaml.safe_load((ROOT / "decks" / "dam_break_2d.yaml").read_text()))
    d["equations_of_state"]["water"]["sound_speed"] = c0
    d["parts"]["column"]["spacing"] = A / n
    if floor.startswith("fixed"):
        d["sections"]["fluid"]["artificial_viscosity"] = {"alpha": float(floor[5:])}
    else:
        d["sections"]["fluid"]["artificial_viscosity"] = {"alpha": float(floor), "beta": 0.0,
                                                          "switch": {"alpha_max": 1.0, "decay": 0.1}}
    d["boundaries"][0]["condition"] = walls
    d["output"]["interval"] = d["control"]["end_time"] / SAMPLES
    d["output"]["fields"] = ["velocity"]
    d["output"].pop("references", None)
    return d


def peak_speed(h5: Path) -> float:
    """Largest particle speed over the field outputs of the column."""
    best = 0.0
    with h5py.File(h5, "r") as f:
        for name, step in f["column"].items():
            if name.startswith("step_"):
                best = max(best, float(np.linalg.norm(np.asarray(step["point"]["velocity"]), axis=1).max()))
    return best


def front(out: Path) -> list[float]:
    """Z = x_front / a at the compared times (linear in the history written every 2 ms)."""
    h = np.genfromtxt(out / "histories" / "front.csv", delimiter=",", names=True)
    T, _ = reference()
    return np.interp(T, h["time"] * np.sqrt(2 * G / A), h["front"] / A).round(4).tolist()


def run(case: str) -> dict:
    parts = case.split("@")
    n, c0, floor = int(parts[0]), float(parts[1]), parts[2]
    walls = parts[3] if len(parts) > 3 else "wall_function"
    folder = WORK / case.replace("@", "_")
    folder.mkdir(parents=True, exist_ok=True)
    deck = folder / "deck.yaml"
    deck.write_text(yaml.safe_dump(variant(n, c0, floor, walls), sort_keys=False))
    env = dict(os.environ, NUMBA_NUM_THREADS="1", PYTHONPATH=str(ROOT))
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    proc = subprocess.run([sys.executable, "-m", "sphfem_cli.cli", "run", str(deck), "-o", str(folder / "run"),
                           "--overwrite", "-q", "--threads", "1"], env=env, capture_output=True, text=True)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    row = {"case": case, "n": n, "c0": c0, "floor": floor, "walls": walls, "rc": proc.returncode,
           "cpu_s": round(after.ru_utime + after.ru_stime - before.ru_utime - before.ru_stime, 1),
           "load": round(os.getloadavg()[0], 2)}
    if proc.returncode != 0:
        row["error"] = (proc.stdout + proc.stderr)[-400:]
    else:
        h5 = folder / "run" / "results.h5"
        row["mach"] = round(peak_speed(h5) / c0, 4)
        row["Z"] = front(folder / "run")
        _, Z_ref = reference()
        row["err_pct"] = (100 * (np.array(row["Z"]) / Z_ref - 1)).round(1).tolist()
        g = np.genfromtxt(folder / "run" / "histories" / "glstat.csv", delimiter=",", names=True)
        log = (folder / "run" / "run.log").read_text().splitlines()
        row["steps"] = int(next(line.split(":")[1] for line in log if line.startswith("steps:")))
        row["energy_ratio"] = round(float(g["energy_ratio"][-1]), 5)
        h5.unlink()  # the velocities of 400 outputs are large at a/dx 80; the histories stay
    with open(WORK / "log.jsonl", "a") as log:
        log.write(json.dumps(row) + "\n")
    return row


def summary() -> None:
    from sphfem_cli.study.metrics import three_grid

    rows = [json.loads(line) for line in (WORK / "log.jsonl").read_text().splitlines()]
    for r in rows:
        print(json.dumps(r))
    groups = defaultdict(dict)
    for r in rows:
        if r.get("rc") == 0:
            groups[(r["c0"], r["floor"], r["walls"])][r["n"]] = r["Z"]
    _, Z_ref = reference()
    for key, by_n in sorted(groups.items()):
        ns = sorted(by_n)
        for k in range(len(ns) - 2):
            trio = ns[k:k + 3]
            print(f"\nc0 {key[0]:g}, floor {key[1]}, {key[2]}: a/dx = {trio}")
            # the probe's front (largest particle x) and the particles' edge, that front + dx / 2 (Z + 1 / (2 N))
            for label, shift in (("front", 0.0), ("front + dx/2", 0.5)):
                print(f" {label}:")
                for i, T in enumerate(T_COMPARED):
                    Z = [round(by_n[m][i] + shift / m, 4) for m in trio]
                    c = three_grid([1.0 / m for m in trio], Z)
                    kind = "diverging" if c.diverging else ("monotone" if c.monotone else "oscillating")
                    print(f"  T {T}: Z {Z} ({kind}), order {c.order:.2f}, Richardson {c.extrapolated:.4f} "
                          f"({100 * (c.extrapolated / Z_ref[i] - 1):+.1f} % vs exp), "
                          f"GCI fine {100 * c.gci_fine:.2f} %, "
                          f"GCI medium {100 * c.gci_medium:.2f} %, range {100 * (max(Z) / min(Z) - 1):.2f} %")


if __name__ == "__main__":
    if sys.argv[1:] == ["--summary"]:
        summary()
    else:
        WORK.mkdir(exist_ok=True)
        for arg in sys.argv[1:]:
            print(json.dumps(run(arg)), flush=True)
