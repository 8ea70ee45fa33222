"""Issue 18 item 2 on decks/dam_break_wall_pressure_sph.yaml: does the answer depend on the artificial sound speed,
and which numerical dissipation makes it? (figures in docs/studies/dam_break_wall_pressure.md).

    python docs/studies/dam_break_wall_pressure_dissipation.py CASE@DX [CASE@DX ...]   # from the repository root
    python docs/studies/dam_break_wall_pressure_dissipation.py --summary

A case is the shipped deck with the Tait sound speed c0 and the artificial viscosity of VARIANTS and the particle
spacing DX (m; the deck's 0.005 is H/dx 60); it runs on one thread into study_dbwp/<case>_<dx>/ and appends its
CPU seconds and the validation test's measures (tests/validation/test_dam_break_wall_pressure.py: first impact
time, the T at which the 100 Hz low-passed P first exceeds 0.1, and the plateau, the mean low-passed P over
T 3.5-5.5, each against Lobovsky et al. 2014's record) to study_dbwp/log.txt.

Kinds: "c<c0>" Monaghan's viscosity with the deck's fixed alpha 0.1 (an effective kinematic viscosity
alpha h c0 / 8 in 2D, Monaghan 2005, Rep. Prog. Phys. 68, 1703, sec. 4.2: it grows with c0); "c<c0>sw" the
shock switch of Morris & Monaghan 1997 (alpha_i between a floor of 0.01 and 1, decay 0.1, beta 0;
sphfem_cli/sph/switch.py), which keeps alpha at its floor where the water is not compressed.
"""
import os
import resource
import subprocess
import sys
from pathlib import Path

import numpy as np
import yaml

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))
from sphfem_cli.output.filters import low_pass  # noqa: E402

WORK = Path("study_dbwp")
DATA = ROOT / "tests" / "data" / "lobovsky_2014" / "wall_pressure_H300_event5.csv"
H, G, RHO = 0.3, 9.81, 1000.0
T_SCALE, P_SCALE = np.sqrt(H / G), RHO * G * H
SWITCH = {"alpha": 0.01, "beta": 0.0, "switch": {"alpha_max": 1.0, "decay": 0.1}}
VARIANTS = {f"c{c0}": (float(c0), {"alpha": 0.1}) for c0 in (30, 40, 60, 120)}
VARIANTS.update({f"c{c0}sw": (float(c0), SWITCH) for c0 in (30, 40, 60, 120)})


def metrics(T: np.ndarray, P: np.ndarray) -> dict[str, float]:
    """First impact time and plateau of one sensor's dimensionless series, as the validation test."""
    Pf = low_pass(T * T_SCALE, P, "butterworth", cutoff=100.0, order=2)
    return {"impact": float(T[np.argmax(Pf > 0.1)]), "plateau": float(Pf[(T >= 3.5) & (T <= 5.5)].mean())}


def variant(kind: str, dx: float) -> Path:
    d = yaml.safe_load(open(ROOT / "decks" / "dam_break_wall_pressure_sph.yaml"))
    c0, viscosity = VARIANTS[kind]
    d["equations_of_state"]["water"]["sound_speed"] = c0
    d["sections"]["fluid"]["artificial_viscosity"] = dict(viscosity)
    d["parts"]["column"]["spacing"] = dx
    for ref in d["output"].get("references", []):
        ref["file"] = str(DATA)
    WORK.mkdir(exist_ok=True)
    path = WORK / f"{kind}_{dx}.yaml"
    yaml.safe_dump(d, open(path, "w"), sort_keys=False)
    return path


def run(kind: str, dx: float) -> None:
    deck, out = variant(kind, dx), WORK / f"{kind}_{dx}"
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    subprocess.run(["sphfem", "run", str(deck), "-o", str(out), "-q", "--overwrite", "--threads", "1"], check=True)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = after.ru_utime + after.ru_stime - before.ru_utime - before.ru_stime
    with open(WORK / "log.txt", "a") as log:
        log.write(f"{kind}_{dx} cpu {cpu:.0f} s load {os.getloadavg()[0]:.1f}\n")


def summary() -> None:
    measured = np.loadtxt(DATA, delimiter=",", comments="#", skiprows=8)
    exp = [metrics(measured[:, 0], measured[:, k]) for k in range(1, 5)]
    print("case | impact T - measured, sensors 1-4 | plateau / measured - 1, sensors 1-4")
    for out in sorted(p for p in WORK.glob("*_*") if p.is_dir()):
        if not (out / "histories" / "p4.csv").exists():
            continue
        dt, dp = [], []
        for k in range(1, 5):
            raw = np.loadtxt(out / "histories" / f"p{k}.csv", delimiter=",", skiprows=1)
            sim = metrics(raw[:, 0] / T_SCALE, raw[:, 1] / P_SCALE)
            dt.append(f"{sim['impact'] - exp[k - 1]['impact']:+.3f}")
            dp.append(f"{sim['plateau']:.3f} ({100 * (sim['plateau'] / exp[k - 1]['plateau'] - 1):+.0f} %)")
        print(f"{out.name} | {' / '.join(dt)} | {' / '.join(dp)}")


if __name__ == "__main__":
    if sys.argv[1:] == ["--summary"]:
        summary()
    else:
        for arg in sys.argv[1:]:
            kind, dx = arg.split("@")
            run(kind, float(dx))
