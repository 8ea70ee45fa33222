"""Issue 18 acceptance A1 on decks/elastic_gate_{sph,ale}.yaml: the gate refined with the water fixed, the water
refined with the gate fixed (figures in docs/studies/elastic_gate.md).

    python docs/studies/elastic_gate_convergence.py run CASE [CASE ...]   # from the repository root, one at a time
    python docs/studies/elastic_gate_convergence.py summary

Variants are the shipped decks loaded in memory with dotted overrides (sphfem_cli.api.run), on one thread; each
run's figures and CPU seconds (time.process_time of this process, numba's cached kernels loaded before the clock
starts) go to study_elastic_gate/CASE.json, with the 1-minute load average at its end.

Cases (``sph_g<NT>x<NL>_dx<MM>``, ``ale_g<NT>x<NL>_h<MM>``: gate divisions through the thickness x along the length,
SPH water spacing or ALE element size in mm):
- structure side, the water at the shipped size: gate 2 x 16 / 4 x 32 (shipped) / 8 x 64;
- fluid side, the gate at 4 x 32: SPH spacing 5 / 2.5 (shipped) / 1.25 mm; ALE elements 10 / 5 (shipped) / 2.5 mm,
  and 1.25 mm (the 10 mm level has the 5 mm gate inside one element column).
The end time is WINDOW (0.16 s: the opening and the peak near 0.118 s), or 0.4 s (the decks' own) for a case
suffixed ``_full``. The history interval is 0.5 ms instead of the deck's 2 ms (an output setting: the same run).

ALE coupling rule, the deck's (its header, "pfac"): the penalty is an extra water layer L_c = n h / pfac
(docs/theory/coupling.md, "Stiffness"), n = h / l the coupling points per water-element face (l = segment /
nquad; nquad 2, and 4 on the holder at 1.25 mm so that n stays >= 1 there). The deck ships pfac = 2 n rounded
1 % up (gate 8.1 for n = 4.05, holder 4.1 for n = 2.04), i.e. L_c = h / 2. n scales as h, as nquad and as the
gate's divisions along its length, so each level keeps L_c = h / 2 with pfac_gate = 8.1 (NL / 32) (h / 5 mm)
and pfac_holder = 4.1 (h / 5 mm) (nquad / 2); `sphfem check` prints L_c = 0.5 h (gate), 0.497 h (holder) at
every level. `pfac: auto` (2 n, the median n) is the same rule without the 1 %.

Compared (history gate_tip: the node at the middle of the free end, x = 0.1025, y = 0.0025): the maxima of the x
and y displacement and their times (the vertex of the parabola through the largest sample and its two
neighbours), and x at 0.05 / 0.10 s (linear interpolation). Order / GCI: sphfem_cli.study.metrics.three_grid
(Celik et al. 2008, Fs 1.25) with h = 1 / divisions or the water size.
"""
from __future__ import annotations

import json
import os
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))
from sphfem_cli import api  # noqa: E402
from sphfem_cli.study.metrics import three_grid  # noqa: E402

WORK = Path("study_elastic_gate")
WINDOW = 0.16  # s
SHIPPED = {"sph": 0.0025, "ale": 0.005}  # the water's size in the decks [m]
PFAC_GATE, PFAC_HOLDER, NL0 = 8.1, 4.1, 32  # the ALE deck's couplings and gate divisions along the length
CASES = {  # name: (method, gate divisions [through, along], water size [m])
    "sph_g2x16_dx2.5": ("sph", [2, 16], 0.0025), "sph_g4x32_dx2.5": ("sph", [4, 32], 0.0025),
    "sph_g8x64_dx2.5": ("sph", [8, 64], 0.0025), "sph_g4x32_dx5": ("sph", [4, 32], 0.005),
    "sph_g4x32_dx1.25": ("sph", [4, 32], 0.00125),
    "ale_g2x16_h5": ("ale", [2, 16], 0.005), "ale_g4x32_h5": ("ale", [4, 32], 0.005),
    "ale_g8x64_h5": ("ale", [8, 64], 0.005), "ale_g4x32_h10": ("ale", [4, 32], 0.01),
    "ale_g4x32_h2.5": ("ale", [4, 32], 0.0025), "ale_g4x32_h1.25": ("ale", [4, 32], 0.00125),
}
SERIES = {  # label: the three cases, fine to coarse, and their relative sizes
    "SPH gate 8x64 / 4x32 / 2x16 (water 2.5 mm)":
        (["sph_g8x64_dx2.5", "sph_g4x32_dx2.5", "sph_g2x16_dx2.5"], [1, 2, 4]),
    "SPH water 1.25 / 2.5 / 5 mm (gate 4x32)": (["sph_g4x32_dx1.25", "sph_g4x32_dx2.5", "sph_g4x32_dx5"], [1, 2, 4]),
    "ALE gate 8x64 / 4x32 / 2x16 (water 5 mm)": (["ale_g8x64_h5", "ale_g4x32_h5", "ale_g2x16_h5"], [1, 2, 4]),
    "ALE water 2.5 / 5 / 10 mm (gate 4x32)": (["ale_g4x32_h2.5", "ale_g4x32_h5", "ale_g4x32_h10"], [1, 2, 4]),
    "ALE water 1.25 / 2.5 / 5 mm (gate 4x32)": (["ale_g4x32_h1.25", "ale_g4x32_h2.5", "ale_g4x32_h5"], [1, 2, 4]),
}
QUANTITIES = ("x max [mm]", "t x max [s]", "y max [mm]", "t y max [s]", "x(0.05) [mm]", "x(0.10) [mm]")


def overrides(name: str) -> dict:
    """The dotted overrides of a case (module docstring)."""
    method, div, size = CASES[name.removesuffix("_full")]
    out = {"parts.gate.geometry.box.divisions": div, "output.history_interval": 5.0e-4,
           "control.end_time": 0.4 if name.endswith("_full") else WINDOW}
    if method == "sph":
        out["parts.water.spacing"] = size
    else:
        scale = size / SHIPPED["ale"]
        nquad_holder = 2 if size >= 0.0025 else 4  # keeps n >= 1 on the holder's 4.9 mm segments
        out.update({"parts.tank.geometry.box.element_size": size,
                    "couplings.0.pfac": round(PFAC_GATE * div[1] / NL0 * scale, 4),
                    "couplings.1.nquad": nquad_holder,
                    "couplings.1.pfac": round(PFAC_HOLDER * scale * nquad_holder / 2, 4)})
    return out


def peak(t: np.ndarray, q: np.ndarray) -> tuple[float, float]:
    """(value, time) of the maximum: the vertex of the parabola through the largest sample and its neighbours."""
    i = int(np.argmax(q))
    if i == 0 or i == len(q) - 1:
        return float(q[i]), float(t[i])
    a, b, c = q[i - 1], q[i], q[i + 1]
    den = a - 2.0 * b + c
    s = 0.5 * (a - c) / den if den != 0.0 else 0.0
    dt = t[i + 1] - t[i]
    return float(b - 0.25 * (a - c) * s), float(t[i] + s * dt)


def figures(histories: dict) -> dict:
    h = histories["gate_tip"]
    t, ux, uy = h["time"], h["displacement_x"], h["displacement_y"]
    xm, txm = peak(t, ux)
    ym, tym = peak(t, uy)
    out = {"x max [mm]": 1e3 * xm, "t x max [s]": txm, "y max [mm]": 1e3 * ym, "t y max [s]": tym,
           "x(0.05) [mm]": 1e3 * float(np.interp(0.05, t, ux)), "x(0.10) [mm]": 1e3 * float(np.interp(0.10, t, ux))}
    for tt in (0.15, 0.2, 0.25, 0.3, 0.4):  # the headers' later times, where the run reaches them
        if t[-1] >= tt - 1e-9:
            out[f"x({tt:.2f}) [mm]"] = 1e3 * float(np.interp(tt, t, ux))
    if t[-1] >= 0.4 - 1e-9:  # the closing: the smallest x after the peak (the negative of the maximum of -x)
        later = t > txm
        xmin, txmin = peak(t[later], -ux[later])
        out.update({"x min after peak [mm]": -1e3 * xmin, "t x min [s]": txmin})
    return out


def run(name: str) -> dict:
    method = CASES[name.removesuffix("_full")][0]
    deck = ROOT / f"decks/elastic_gate_{method}.yaml"
    ov = overrides(name)
    loaded = api.load(deck, ov)  # parse and build before the clock starts
    cpu = time.process_time()
    result = api.run(loaded, WORK / f"out_{name}", overwrite=True, threads=1)
    cpu = time.process_time() - cpu
    assert result.completed, result.message
    out = {"case": name, "overrides": ov, "steps": result.steps, "cpu_s": round(cpu, 1),
           "load_1min": round(os.getloadavg()[0], 2), **figures(result.histories())}
    (WORK / f"{name}.json").write_text(json.dumps(out, indent=1))
    return out


def summary() -> None:
    done = {p.stem: json.loads(p.read_text()) for p in WORK.glob("*.json")}
    print("| case | steps | CPU s | load | " + " | ".join(QUANTITIES) + " |")
    print("|---" * (4 + len(QUANTITIES)) + "|")
    for name, r in sorted(done.items()):
        if name.endswith("_full"):
            continue
        print(f"| {name} | {r['steps']} | {r['cpu_s']:.0f} | {r['load_1min']:.1f} | "
              + " | ".join(f"{r[q]:.4f}" if "[s]" in q else f"{r[q]:.3f}" for q in QUANTITIES) + " |")
    late = [n for n in sorted(done) if n.endswith("_full")]
    if late:
        cols = [k for k in done[late[0]] if k.startswith("x(0.") or k in ("x min after peak [mm]", "t x min [s]")]
        print("\nTo 0.4 s\n| case | CPU s | load | x max [mm] | " + " | ".join(cols) + " |\n" + "|---" * (4 + len(cols))
              + "|")
        for n in late:
            r = done[n]
            print(f"| {n} | {r['cpu_s']:.0f} | {r['load_1min']:.1f} | {r['x max [mm]']:.3f} | "
                  + " | ".join(f"{r[k]:.4f}" if "[s]" in k else f"{r[k]:.3f}" for k in cols) + " |")
    for label, (names, h) in SERIES.items():
        if not all(n in done for n in names):
            continue
        print(f"\n{label}\n| quantity | fine / medium / coarse | order | Richardson | GCI fine | GCI medium "
              "| medium - Richardson |\n|---|---|---|---|---|---|---|")  # medium: the shipped level
        for q in QUANTITIES:
            v = [done[n][q] for n in names]
            c = three_grid(h, v)
            vals = " / ".join(f"{x:.4f}" for x in v)
            if c.monotone and not c.diverging and np.isfinite(c.order):
                err = v[1] - c.extrapolated
                print(f"| {q} | {vals} | {c.order:.2f} | {c.extrapolated:.4f} | {100 * c.gci_fine:.2f} % | "
                      f"{100 * c.gci_medium:.2f} % | {err:+.4f} ({100 * err / c.extrapolated:+.2f} %) |")
            else:
                why = "differences grow" if c.monotone else "not monotone"
                print(f"| {q} | {vals} | {why} | spread {max(v) - min(v):.4f} | | | |")


if __name__ == "__main__":
    WORK.mkdir(exist_ok=True)
    if sys.argv[1:2] == ["summary"]:
        summary()
    elif sys.argv[1:2] == ["run"]:
        for case in sys.argv[2:]:
            print(json.dumps(run(case)), flush=True)
    else:
        sys.exit(__doc__)
