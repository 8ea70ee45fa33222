"""Issue 18 item 1 on the underwater-explosion decks: the structure refined with the fluid fixed, the fluid
refined with the structure fixed (figures in docs/studies/underwater_explosion.md, "Structure-side convergence").

    python docs/studies/underwater_explosion_plate_convergence.py [CASE ...]   # run from the repository root

Each case writes a variant of decks/underwater_explosion_{ale,sph}.yaml into study_undex_plate/, runs it on one
thread and appends its CPU seconds to study_undex_plate/log.txt; `--summary` prints the plate centre's
maximum displacement, displacement at 0.1 and 0.5 ms, peak velocity and peak von Mises of every finished case.
The ALE coupling keeps the deck's rule L_c = n h / pfac = h / 2 (pfac = 2 n) with n = h / (segment / nquad) >= 1
coupling points per water element (docs/theory/coupling.md): nquad is raised where the plate's segment is
longer than the water's element.
"""
import copy, csv, math, os, resource, subprocess, sys, time
from pathlib import Path

import numpy as np
import yaml

ROOT = Path(__file__).resolve().parents[2]
WORK = Path("study_undex_plate")
CASES = {  # name: (deck, water element size or None, plate divisions)
    "ale_f2.5_p60x2": ("ale", 0.0025, [60, 2]), "ale_f2.5_p120x4": ("ale", 0.0025, [120, 4]),
    "ale_f2.5_p240x8": ("ale", 0.0025, [240, 8]), "ale_f5_p60x2": ("ale", 0.005, [60, 2]),
    "ale_f1.25_p60x2": ("ale", 0.00125, [60, 2]),
    "sph_p60x2": ("sph", None, [60, 2]), "sph_p120x4": ("sph", None, [120, 4]), "sph_p240x8": ("sph", None, [240, 8]),
}


def variant(name: str) -> Path:
    kind, h, div = CASES[name]
    d = copy.deepcopy(yaml.safe_load(open(ROOT / f"decks/underwater_explosion_{kind}.yaml")))
    d["parts"]["plate"]["geometry"]["box"]["divisions"] = div
    d["output"]["interval"] = 1.3e-4
    if kind == "ale":
        d["parts"]["tank"]["geometry"]["box"]["element_size"] = h
        segment = 0.30 / div[0]
        nquad = max(2, math.ceil(segment / h - 1e-9))
        d["couplings"][0].update(nquad=nquad, pfac=2.0 * h / (segment / nquad))
    path = WORK / f"{name}.yaml"
    yaml.safe_dump(d, open(path, "w"), sort_keys=False)
    return path


def run(name: str) -> None:
    path = variant(name)
    r0, t0 = resource.getrusage(resource.RUSAGE_CHILDREN), time.time()
    p = subprocess.run(["sphfem", "run", str(path), "-o", str(WORK / f"out_{name}"), "-q", "--overwrite",
                        "--threads", "1"], capture_output=True, text=True)
    r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = r1.ru_utime - r0.ru_utime + r1.ru_stime - r0.ru_stime
    with open(WORK / "log.txt", "a") as f:
        f.write(f"{name} rc={p.returncode} cpu={cpu:.1f} wall={time.time() - t0:.1f} "
                f"load={os.getloadavg()[0]:.1f} {p.stderr.strip()[-300:]}\n")


def summary() -> None:
    for name in CASES:
        f = WORK / f"out_{name}/histories/centre.csv"
        if not f.exists():
            continue
        rows = [r for r in csv.reader(open(f)) if r and not r[0].startswith("#")]
        t = dict(zip(rows[0], np.array(rows[1:], float).T))
        tt, uy, vy, vm = t["time"], t["displacement_y"], t["velocity_y"], t["von_mises"]
        print(f"{name:18s} umax {uy.max() * 1e3:7.3f} mm  u(0.1 ms) {np.interp(1e-4, tt, uy) * 1e3:6.3f}  "
              f"u(0.5 ms) {np.interp(5e-4, tt, uy) * 1e3:6.3f}  vmax {vy.max():6.1f} m/s  "
              f"von Mises {vm.max() / 1e6:6.1f} MPa")


if __name__ == "__main__":
    WORK.mkdir(exist_ok=True)
    if sys.argv[1:] == ["--summary"]:
        summary()
    else:
        for name in sys.argv[1:] or CASES:
            run(name)
