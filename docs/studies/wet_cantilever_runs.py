"""Runs of docs/studies/wet_cantilever.md: decks/wet_cantilever_{ale,sph}.yaml at other fluid sizes and
plate meshes (and the plate alone, in vacuum), each run's wet frequency from its tip history.

    python docs/studies/wet_cantilever_runs.py OUT CASE [CASE ...]
    python docs/studies/wet_cantilever_runs.py OUT --gci CASE_FINE CASE_MEDIUM CASE_COARSE

CASE is METHOD:FLUID_SIZE_MM:PLATE_THROUGH[:ALPHA] (e.g. ale:10:2, sph:5:4, dry:0:8, sph:5:4:0.02: the
SPH artificial viscosity's alpha); the plate has
PLATE_THROUGH elements through its 10 mm thickness and 12 times as many along its 120 mm (squares).
One line of JSON per case is appended to OUT/results.jsonl (frequency, decay, steps, CPU seconds).
"""
from __future__ import annotations

import copy
import json
import os
import resource
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import yaml

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tests" / "verification"))
import wet_cantilever_reference as ref  # noqa: E402

RELEASE = 0.051  # s, the end of the decks' push curve


def variant(method: str, size_mm: float, through: int, alpha: float | None = None) -> dict:
    """The deck of one case as a dict (``alpha``: the SPH artificial viscosity's, default the deck's)."""
    base = "sph" if method == "sph" else "ale"
    d = yaml.safe_load((ROOT / "decks" / f"wet_cantilever_{base}.yaml").read_text())
    d = copy.deepcopy(d)
    d["parts"]["plate"]["geometry"]["box"]["divisions"] = [through, 12 * through]
    if method == "dry":
        d["parts"] = {"plate": d["parts"]["plate"]}
        d.pop("couplings", None)
        d["boundaries"] = [b for b in d["boundaries"] if b["type"] == "fixed"]
        d["materials"] = {"polymer": d["materials"]["polymer"]}
        d.pop("equations_of_state", None)
        d["sections"] = {"plate": d["sections"]["plate"]}
        return d
    h = size_mm / 1000.0
    if method == "ale":
        d["parts"]["tank"]["geometry"]["box"]["element_size"] = h
    else:
        for p in ("left", "right"):
            d["parts"][p]["spacing"] = h
        if alpha is not None:
            d["sections"]["fluid"]["artificial_viscosity"]["alpha"] = alpha
    return d


def run(out: Path, case: str) -> dict:
    method, size, through, *extra = case.split(":")
    d = variant(method, float(size), int(through), float(extra[0]) if extra else None)
    folder = out / case.replace(":", "_")
    folder.mkdir(parents=True, exist_ok=True)
    deck = folder / "deck.yaml"
    deck.write_text(yaml.safe_dump(d, sort_keys=False))
    env = dict(os.environ, NUMBA_NUM_THREADS="1")
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.time()
    proc = subprocess.run([sys.executable, "-m", "sphfem_cli.cli", "run", str(deck), "-o", str(folder / "run"),
                           "--overwrite", "-q", "--threads", "1"], env=env, capture_output=True, text=True)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    row = {"case": case, "rc": proc.returncode, "wall_s": round(time.time() - t0, 1),
           "cpu_s": round(after.ru_utime + after.ru_stime - before.ru_utime - before.ru_stime, 1)}
    if proc.returncode != 0:
        row["error"] = (proc.stdout + proc.stderr)[-400:]
        return row
    tip = np.genfromtxt(folder / "run" / "histories" / "tip.csv", delimiter=",", names=True)
    r = ref.ringing(tip["time"], tip["displacement_x"], RELEASE + 0.004)
    row.update(frequency=round(r.frequency, 4), zeta=round(r.zeta, 4), crossings=round(r.crossings, 4),
               periods=round(r.periods, 2), residual=round(r.residual, 4),
               amplitude_mm=round(1e3 * float(np.abs(tip["displacement_x"][tip["time"] > RELEASE]).max()), 4))
    glstat = folder / "run" / "histories" / "glstat.csv"
    if glstat.exists():
        g = np.genfromtxt(glstat, delimiter=",", names=True)
        row["dt_mean"] = float(np.mean(g["dt"][1:]))
    return row


def gci(f1: float, f2: float, f3: float, r: float = 2.0) -> dict:
    """Observed order, Richardson extrapolation and fine-grid GCI (safety factor 1.25) of a
    fine / medium / coarse series with refinement ratio r (Celik et al. 2008, J. Fluids Eng. 130)."""
    e21, e32 = f2 - f1, f3 - f2
    if e21 * e32 <= 0:
        return {"monotone": False}
    p = np.log(e32 / e21) / np.log(r)
    ext = f1 + (f1 - f2) / (r ** p - 1)
    return {"monotone": True, "order": round(float(p), 3), "extrapolated": round(float(ext), 4),
            "gci_fine": round(float(1.25 * abs(f1 - f2) / (r ** p - 1) / abs(f1)), 5)}


def main(argv: list[str]) -> None:
    out = Path(argv[0])
    if len(argv) > 1 and argv[1] == "--gci":
        rows = {}
        for line in (out / "results.jsonl").read_text().splitlines():
            row = json.loads(line)
            rows[row["case"]] = row
        f = [rows[c]["frequency"] for c in argv[2:5]]
        print(json.dumps({"cases": argv[2:5], "frequency": f, **gci(*f)}))
        return
    out.mkdir(parents=True, exist_ok=True)
    for case in argv[1:]:
        row = run(out, case)
        print(json.dumps(row), flush=True)
        with open(out / "results.jsonl", "a") as f:
            f.write(json.dumps(row) + "\n")


if __name__ == "__main__":
    main(sys.argv[1:])
