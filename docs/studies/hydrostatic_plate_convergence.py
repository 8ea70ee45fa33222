"""Issue 18 item 1 on decks/hydrostatic_plate_{ale,sph}.yaml: the plate mesh refined with the load fixed, and the
plate mesh and the fluid refined with the other fixed (figures in docs/studies/hydrostatic_plate_convergence.md).

    python /path/to/docs/studies/hydrostatic_plate_convergence.py [CASE ...]   # run folders go where it is run
    python /path/to/docs/studies/hydrostatic_plate_convergence.py --summary

The compared quantity is the decks' own: the plate's static mid-span deflection, against
w = q L^4 / (384 D), D = E t^3 / (12 (1 - nu^2)), q = g (rho_f H + rho_s t) = -6.86e-5 m (the decks' headers).

Case kinds (each a variant of the deck written into study_hydro_plate/, run on one thread, its CPU seconds
appended to study_hydro_plate/log.txt):
- ``dry_<deck>_p<NX>x<NY>``: the deck's plate alone, the water replaced by the load it carries at equilibrium
  (the hydrostatic pressure rho_f g H on the plate's top face; the SPH deck's plate_load history measures
  19 624 N/m against this 19 620 N/m), the plate's own weight kept; both ramped up over RAMP (5.5 periods of the
  dry plate's first mode, 270 Hz) and held. Static deflection: the mid-span mean over whole periods of the
  residual ringing in the hold (between the first and the last upward crossing of the hold's mean).
- ``ale_f<MM>_p<NX>x<NY>`` / ``sph_dx<MM>_p<NX>x<NY>``: the deck itself at that water size and plate mesh, to its
  own end time; the deflection is the deck's tail mean (ALE: the last half; SPH: t >= 0.04 s, the validation
  tests' windows at the time of those runs, the ALE deck then at pfac 1 to 0.05 s).
- ``ale_auto_f<MM>_p<NX>x<NY>`` (``ale_pfac1_...``: pfac 1, the deck's before December 2026): the ALE deck at that water size and plate mesh with the coupling's ``pfac: auto``
  (pfac = 2 n, so the penalty layer L_c = n h / pfac = h/2 at every level, docs/theory/coupling.md "Stiffness")
  run to PERIOD_END; the deflection is the mean over PERIOD_WINDOW, two whole periods of the column's acoustic
  ringing 4 H / c0 = 8 / 200 = 0.04 s (a window of whole periods averages the ringing out; the plate's own
  270 Hz ringing is 10 of its periods per 0.04 s).
"""
import copy, csv, os, resource, subprocess, sys, time
from pathlib import Path

import numpy as np
import yaml

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))
from sphfem_cli.study.metrics import describe, three_grid  # noqa: E402

WORK = Path("study_hydro_plate")
W_PLATE = -6.86e-5  # m, the headers' plate formula
RHO_F, G, H = 1000.0, 9.81, 2.0
RAMP, HOLD = 0.02, 0.02  # s
C0 = 200.0  # m/s, the decks' water sound speed
PERIOD = 4.0 * H / C0  # s, the column's quarter-wave acoustic period (0.04 s)
PERIOD_WINDOW = (PERIOD, 3.0 * PERIOD)  # s, two whole periods after the first
PERIOD_END = 3.0 * PERIOD  # s
CASES = {  # name: (kind, deck, fluid size [m] or None, plate divisions)
    "dry_ale_p40x2": ("dry", "ale", None, [40, 2]), "dry_ale_p80x4": ("dry", "ale", None, [80, 4]),
    "dry_ale_p160x8": ("dry", "ale", None, [160, 8]),
    "dry_sph_p20x2": ("dry", "sph", None, [20, 2]), "dry_sph_p40x4": ("dry", "sph", None, [40, 4]),
    "dry_sph_p80x8": ("dry", "sph", None, [80, 8]),
    "ale_f50_p40x2": ("wet", "ale", 0.05, [40, 2]), "ale_f50_p80x4": ("wet", "ale", 0.05, [80, 4]),
    "ale_f50_p160x8": ("wet", "ale", 0.05, [160, 8]), "ale_f100_p80x4": ("wet", "ale", 0.10, [80, 4]),
    "ale_f25_p80x4": ("wet", "ale", 0.025, [80, 4]),
    "sph_dx25_p20x2": ("wet", "sph", 0.025, [20, 2]), "sph_dx25_p40x4": ("wet", "sph", 0.025, [40, 4]),
    "sph_dx25_p80x8": ("wet", "sph", 0.025, [80, 8]), "sph_dx50_p40x4": ("wet", "sph", 0.05, [40, 4]),
    "sph_dx12.5_p40x4": ("wet", "sph", 0.0125, [40, 4]),
    "ale_auto_f100_p80x4": ("period", "ale", 0.10, [80, 4]), "ale_auto_f50_p80x4": ("period", "ale", 0.05, [80, 4]),
    "ale_auto_f25_p80x4": ("period", "ale", 0.025, [80, 4]),
    "ale_auto_f12.5_p80x4": ("period", "ale", 0.0125, [80, 4]),
    "ale_auto_f100_p160x8": ("period", "ale", 0.10, [160, 8]),
    "ale_auto_f50_p160x8": ("period", "ale", 0.05, [160, 8]),
    "ale_auto_f25_p160x8": ("period", "ale", 0.025, [160, 8]),
    "ale_pfac1_f50_p80x4": ("period", "ale", 0.05, [80, 4]),  # the old pfac 1 over the whole-period window
}
PFAC = {"ale_pfac1_f50_p80x4": 1.0}  # period cases' pfac where not auto
SERIES = {  # three-level series (fine, medium, coarse) and the size that is refined
    "ALE deck's plate alone, 160x8 / 80x4 / 40x2": (["dry_ale_p160x8", "dry_ale_p80x4", "dry_ale_p40x2"], [1, 2, 4]),
    "SPH deck's plate alone, 80x8 / 40x4 / 20x2": (["dry_sph_p80x8", "dry_sph_p40x4", "dry_sph_p20x2"], [1, 2, 4]),
    "ALE 50 mm, plate 160x8 / 80x4 / 40x2": (["ale_f50_p160x8", "ale_f50_p80x4", "ale_f50_p40x2"], [1, 2, 4]),
    "ALE plate 80x4, water 25 / 50 / 100 mm": (["ale_f25_p80x4", "ale_f50_p80x4", "ale_f100_p80x4"], [1, 2, 4]),
    "SPH 25 mm, plate 80x8 / 40x4 / 20x2": (["sph_dx25_p80x8", "sph_dx25_p40x4", "sph_dx25_p20x2"], [1, 2, 4]),
    "SPH plate 40x4, water 12.5 / 25 / 50 mm": (["sph_dx12.5_p40x4", "sph_dx25_p40x4", "sph_dx50_p40x4"], [1, 2, 4]),
    "ALE plate 80x4, pfac auto, water 25 / 50 / 100 mm": (
        ["ale_auto_f25_p80x4", "ale_auto_f50_p80x4", "ale_auto_f100_p80x4"], [1, 2, 4]),
    "ALE plate 80x4, pfac auto, water 12.5 / 25 / 50 mm": (
        ["ale_auto_f12.5_p80x4", "ale_auto_f25_p80x4", "ale_auto_f50_p80x4"], [1, 2, 4]),
    "ALE plate 160x8, pfac auto, water 25 / 50 / 100 mm": (
        ["ale_auto_f25_p160x8", "ale_auto_f50_p160x8", "ale_auto_f100_p160x8"], [1, 2, 4]),
}


def variant(name: str) -> Path:
    kind, deck, size, div = CASES[name]
    d = copy.deepcopy(yaml.safe_load(open(ROOT / f"decks/hydrostatic_plate_{deck}.yaml")))
    d["parts"]["plate"]["geometry"]["box"]["divisions"] = div
    if kind == "dry":
        d["parts"] = {"plate": d["parts"]["plate"]}
        d["sets"]["plate_top"] = {"type": "segment", "part": "plate", "side": "top"}
        d["boundaries"] = [b for b in d["boundaries"] if b["type"] == "fixed"]
        d.pop("couplings", None)
        d.pop("contacts", None)
        d["curves"] = {"ramp": {"points": [[0.0, 0.0], [RAMP, 1.0], [RAMP + HOLD, 1.0]]}}
        d["loads"] = [{"type": "gravity", "acceleration": [0.0, -G], "curve": "ramp"},
                      {"type": "pressure", "set": "plate_top", "value": RHO_F * G * H, "curve": "ramp"}]
        d["control"]["end_time"] = RAMP + HOLD
        d["output"]["histories"] = [h for h in d["output"]["histories"] if h["name"] == "midspan"]
        d["output"]["history_interval"] = 2.0e-5
        d["output"]["fields"] = ["displacement"]
        d["output"]["interval"] = RAMP + HOLD
        d["materials"] = {"aluminium": d["materials"]["aluminium"]}
        d.pop("equations_of_state", None)
        d["sections"] = {"plate": d["sections"]["plate"]}
    elif deck == "ale":
        d["parts"]["tank"]["geometry"]["box"]["element_size"] = size
        d["parts"]["tank"]["geometry"]["box"]["min"][1] = -size  # the bottom row overlaps the plate
        if kind == "period":
            d["couplings"][0]["pfac"] = PFAC.get(name, "auto")
            d["control"]["end_time"] = PERIOD_END
    else:
        d["parts"]["water"]["spacing"] = size
    path = WORK / f"{name}.yaml"
    yaml.safe_dump(d, open(path, "w"), sort_keys=False)
    return path


def run(name: str) -> None:
    path = variant(name)
    r0, t0 = resource.getrusage(resource.RUSAGE_CHILDREN), time.time()
    env = dict(os.environ, NUMBA_NUM_THREADS="1", PYTHONPATH=str(ROOT))
    p = subprocess.run([sys.executable, "-m", "sphfem_cli.cli", "run", str(path), "-o", str(WORK / f"out_{name}"),
                        "-q", "--overwrite", "--threads", "1"], capture_output=True, text=True, env=env)
    r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = r1.ru_utime - r0.ru_utime + r1.ru_stime - r0.ru_stime
    with open(WORK / "log.txt", "a") as f:
        f.write(f"{name} rc={p.returncode} cpu={cpu:.1f} wall={time.time() - t0:.1f} "
                f"load={os.getloadavg()[0]:.1f} {p.stderr.strip()[-300:]}\n")


def deflection(name: str) -> float | None:
    """The case's static mid-span deflection [m] (see the module docstring), None when it has not run."""
    f = WORK / f"out_{name}/histories/midspan.csv"
    if not f.exists():
        return None
    rows = [r for r in csv.reader(open(f)) if r and not r[0].startswith("#")]
    t = dict(zip(rows[0], np.array(rows[1:], float).T))
    tt, uy = t["time"], t["displacement_y"]
    kind, deck = CASES[name][:2]
    if kind == "period":
        w = (tt >= PERIOD_WINDOW[0]) & (tt <= PERIOD_WINDOW[1])
        return float(np.trapezoid(uy[w], tt[w]) / (tt[w][-1] - tt[w][0]))
    if kind == "wet":
        return float(uy[tt > 0.5 * tt[-1]].mean() if deck == "ale" else uy[tt >= 0.04].mean())
    hold = tt >= RAMP
    th, uh = tt[hold], uy[hold]
    s = uh - uh.mean()
    up = np.flatnonzero((s[:-1] < 0.0) & (s[1:] >= 0.0))
    if len(up) < 2:
        return float(uh.mean())
    i0, i1 = up[0], up[-1]
    return float(np.trapezoid(uh[i0:i1 + 1], th[i0:i1 + 1]) / (th[i1] - th[i0]))


def summary() -> None:
    print("| case | mid-span deflection [m] | vs plate formula |\n|---|---|---|")
    for name in CASES:
        w = deflection(name)
        if w is not None:
            print(f"| {name} | {w:.5e} | {100 * (w / W_PLATE - 1):+.2f} % |")
    print("\n| series | fine / medium / coarse [m] | observed order | Richardson [m] | GCI fine | GCI medium |\n"
          "|---|---|---|---|---|---|")
    for label, (names, h) in SERIES.items():
        w = [deflection(n) for n in names]
        if None in w:
            continue
        c = three_grid(h, w)
        if not c.monotone or c.diverging:  # no order: the spread of the three levels instead
            print(f"| {label} | {w[0]:.5e} / {w[1]:.5e} / {w[2]:.5e} | {describe(c)} | - | spread "
                  f"{100 * (max(w) - min(w)) / abs(np.mean(w)):.3f} % | - |")
            continue
        print(f"| {label} | {w[0]:.5e} / {w[1]:.5e} / {w[2]:.5e} | {c.order:.2f} | {c.extrapolated:.5e} | "
              f"{100 * c.gci_fine:.2f} % | {100 * c.gci_medium:.2f} % |")


if __name__ == "__main__":
    WORK.mkdir(exist_ok=True)
    if sys.argv[1:] == ["--summary"]:
        summary()
    else:
        for name in sys.argv[1:] or CASES:
            run(name)
