"""Issue 18, gap 1 of docs/studies/fsi_convergence_audit.md: the rigid / fixed structures refined, the fluid fixed.

    python docs/studies/rigid_structure_refinement.py cylinder sph     # elements_around 32 / 64 / 128
    python docs/studies/rigid_structure_refinement.py cylinder ale
    python docs/studies/rigid_structure_refinement.py cylinder ale fixed   # nquad 4 / 2 / 1, pfac 4: n = 1.85 kept
    python docs/studies/rigid_structure_refinement.py bird sph         # target divisions x1 / x2 / x4
    python docs/studies/rigid_structure_refinement.py bird ale
    python docs/studies/rigid_structure_refinement.py freefall sph [rho1000]   # elements_around 32 / 64 / 128
    python docs/studies/rigid_structure_refinement.py freefall ale [rho1000]   # nquad 4 / 2 / 1, pfac 4 kept

Cylinder entry at constant speed (decks/cylinder_entry_constant_speed_{sph,ale}.yaml, shipped tank, 5 mm
water): the polygon of the rigid disc with 32 / 64 / 128 segments, elements_through 2 kept. The analysis is
the validation tests' (tests/validation/test_fsi_scenes_{sph,ale}.py), the one behind the decks' "Measured"
figures: Cs = contact_force_y / (1/2 rho D V^2), s/D = V (t - 0.005 / V) / D, the mean of the raw
0.02 ms samples over s/D 0.05-0.1 / 0.1-0.2 / 0.2-0.4 and 0.05-0.4 (bounds included), and the peak of the
centred 1 ms running mean (np.convolve(..., mode="same")). end_time is cut to 0.018 s (s/D 0.44): the
window ends at t = 16.6 ms, and an explicit run's history before its end does not depend on it.
ALE coupling: nquad the smallest >= 2 giving n = h / (segment / nquad) >= 1 (docs/studies/bird_strike.py's
rule), pfac scaled so that the penalty layer L_c = n h / pfac stays the shipped one (n = 1.85, pfac 4:
L_c = 0.46 h; docs/theory/coupling.md, "Stiffness"). With "fixed": nquad 4 / 2 / 1 and pfac 4 at every level,
so that the coupling points per water element (n = 1.85) and the layer are the shipped deck's and only the
polygon changes.

Bird strike (decks/bird_strike_axisymmetric_{sph,ale}.yaml, the bird at the shipped 5 mm / 2.5 mm): the
fixed steel disc's divisions x1 / x2 / x4 in both directions; the quantities and analysis are
docs/studies/bird_strike.py's `level` (imported). ALE coupling: bird_strike.py's rule with the target's
segment 0.25 m / divisions: nquad max(2, ceil(segment / h)), pfac = 2 n (L_c = h / 2, as shipped).

Free fall (decks/cylinder_free_fall{,_rho1000}_{sph,ale}.yaml, shipped tank and water): the polygon 32 / 64 / 128
segments as for the constant-speed entry (ALE with the coupling points per water element and the layer held:
nquad 4 / 2 / 1, pfac 4), the decks' own end time (0.08 s, T = 0.74). Compared: the headers' penetration
(y0 - y) / D = (-0.005 - displacement_y) / D at T = (t - t_c) sqrt(g / D) = 0.1 / 0.3 / 0.5 / 0.7, t_c = 1.69 ms
(linear interpolation of the history), and the speed at the end.

Order / GCI: sphfem_cli.study.metrics.three_grid with h = 1 / (segments), Fs 1.25.
"""
from __future__ import annotations

import json
import math
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import bird_strike  # noqa: E402  (its `level` and `hugoniot_pressure`)
from sphfem_cli import api  # noqa: E402
from sphfem_cli.study.metrics import describe, three_grid  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
WORK = Path("study_rigid_refinement")
D, V, RHO, GAP = 0.11, 2.955, 1000.0, 0.005
CYL_H, CYL_SEGMENTS, CYL_PFAC = 0.005, 64, 4.0  # the ALE deck's water element, polygon and pfac
BINS = {"0.05-0.1": (0.05, 0.1), "0.1-0.2": (0.1, 0.2), "0.2-0.4": (0.2, 0.4), "0.05-0.4": (0.05, 0.4)}
SAMPLE = 2.0e-5  # the cylinder decks' history_interval [s]


FIXED_POINTS = False


def cylinder_overrides(method: str, around: int) -> dict:
    out = {"parts.cylinder.geometry.ring.elements_around": around, "control.end_time": 0.018}
    if method == "ale" and FIXED_POINTS:
        out.update({"couplings.0.nquad": max(1, 2 * CYL_SEGMENTS // around), "couplings.0.pfac": CYL_PFAC})
    elif method == "ale":
        segment = 2.0 * math.pi * 0.055 / around
        nquad = max(2, math.ceil(segment / CYL_H - 1e-9))
        n = CYL_H / (segment / nquad)
        n0 = CYL_H / (2.0 * math.pi * 0.055 / CYL_SEGMENTS / 2)
        out.update({"couplings.0.nquad": nquad, "couplings.0.pfac": CYL_PFAC * n / n0})
    return out


def cylinder_quantities(hist: dict, uniform: bool = False) -> dict:
    """The compared quantities of a constant-speed entry's ``cylinder`` history (module docstring): the bin means
    of Cs (only the bins a run has finished), the peak of the centred 1 ms running mean and its s/D, the raw peak.
    ``uniform``: the force first interpolated linearly onto a SAMPLE grid, so that a bin mean is a time mean and
    the running mean spans 1 ms at every level (the history holds one row per step where the step exceeds SAMPLE)."""
    t, force = hist["time"], hist["contact_force_y"]
    if uniform:
        grid = np.arange(0.0, t[-1] + 1e-12, SAMPLE)
        t, force = grid, np.interp(grid, t, force)
    s_over_d = V * (t - GAP / V) / D
    cs = force / (0.5 * RHO * D * V * V)
    n = int(round(1.0e-3 / float(t[2] - t[1])))
    smooth = np.convolve(cs, np.ones(n) / n, mode="same")
    peak = int(np.argmax(smooth))
    out = {f"Cs {k}": float(cs[(s_over_d >= lo) & (s_over_d <= hi)].mean())
           for k, (lo, hi) in BINS.items() if s_over_d[-1] >= hi}
    out.update({"1 ms peak": float(smooth[peak]), "peak s/D": float(s_over_d[peak]), "raw peak": float(cs.max())})
    return out


def cylinder_level(method: str, around: int) -> dict:
    ov = cylinder_overrides(method, around)
    cpu = time.process_time()
    result = api.run(ROOT / f"decks/cylinder_entry_constant_speed_{method}.yaml",
                     WORK / f"cyl_{method}_{around}", ov, threads=1, overwrite=True)
    cpu = time.process_time() - cpu
    assert result.completed, result.message
    out = cylinder_quantities(result.histories()["cylinder"]) | {"cpu_s": cpu, "steps": result.steps}
    if method == "ale":
        out.update({"nquad": ov["couplings.0.nquad"], "pfac": ov["couplings.0.pfac"]})
    return out


T_C, G = (2.955 - 2.9384) / 9.81, 9.81  # the free-fall decks' contact time and gravity


def freefall_level(method: str, around: int, heavy: bool) -> dict:
    ov = {"parts.cylinder.geometry.ring.elements_around": around}
    if method == "ale":
        ov.update({"couplings.0.nquad": max(1, 2 * CYL_SEGMENTS // around), "couplings.0.pfac": CYL_PFAC})
    deck = f"decks/cylinder_free_fall{'_rho1000' if heavy else ''}_{method}.yaml"
    cpu = time.process_time()
    result = api.run(ROOT / deck, WORK / f"fall_{method}{'_rho1000' if heavy else ''}_{around}", ov, threads=1,
                     overwrite=True)
    cpu = time.process_time() - cpu
    assert result.completed, result.message
    return freefall_quantities(result.histories()["cylinder"]) | {"cpu_s": cpu, "steps": result.steps}


def freefall_quantities(h) -> dict:
    """The free-fall decks' compared quantities from their ``cylinder`` history: the penetration
    (y0 - y) / D = (-0.005 - displacement_y) / D at T = (t - t_c) sqrt(g / D) = 0.1 / 0.3 / 0.5 / 0.7 (linear
    interpolation) and the speed at the end [m/s]."""
    big_t = (h["time"] - T_C) * math.sqrt(G / D)
    depth = (-0.005 - h["displacement_y"]) / D
    out = {f"pen T={t:.1f}": float(np.interp(t, big_t, depth)) for t in (0.1, 0.3, 0.5, 0.7)}
    out["speed end"] = float(-h["velocity_y"][-1])
    return out


def bird_level(method: str, factor: int) -> dict:
    base = {"sph": (50, 2), "ale": (100, 4)}[method]
    div = [base[0] * factor, base[1] * factor]
    ov = {"parts.target.geometry.box.divisions": div}
    if method == "ale":
        size, segment = 0.0025, 0.25 / div[0]
        nquad = max(2, math.ceil(segment / size - 1e-9))
        ov.update({"couplings.0.nquad": nquad, "couplings.0.pfac": 2.0 * size / (segment / nquad)})
    bird_strike.WORK = WORK / f"bird_target_x{factor}"
    bird_strike.WORK.mkdir(parents=True, exist_ok=True)
    original = bird_strike.overrides
    bird_strike.overrides = lambda m, s: ov  # the fluid at the shipped size: only the target changes
    try:
        out = bird_strike.level(method, {"sph": 0.005, "ale": 0.0025}[method])
    finally:
        bird_strike.overrides = original
    if method == "ale":
        out.update({"nquad": ov["couplings.0.nquad"], "pfac": ov["couplings.0.pfac"]})
    return out


def main() -> None:
    global WORK, FIXED_POINTS
    scene, method = sys.argv[1], sys.argv[2]
    FIXED_POINTS = sys.argv[3:] == ["fixed"]
    heavy = sys.argv[3:] == ["rho1000"]
    if FIXED_POINTS:
        WORK = WORK / "ale_fixed_points"
    WORK.mkdir(parents=True, exist_ok=True)
    if scene == "cylinder":
        levels = [32, 64, 128]
        runs = [cylinder_level(method, a) for a in levels]
        hs = [1.0 / a for a in levels]
    elif scene == "freefall":
        levels = [32, 64, 128]
        runs = [freefall_level(method, a, heavy) for a in levels]
        hs = [1.0 / a for a in levels]
        scene += "_rho1000" if heavy else ""
    else:
        levels = [1, 2, 4]
        runs = [bird_level(method, f) for f in levels]
        hs = [1.0 / f for f in levels]
    for lev, run in zip(levels, runs):
        print(f"{scene} {method} {lev}: " + ", ".join(f"{k} {v:.4g}" for k, v in run.items()), flush=True)
    conv = {}
    for key in runs[0]:
        if key in ("cpu_s", "steps", "nquad", "pfac", "peak s/D"):
            continue
        c = three_grid(hs, [run[key] for run in runs])
        conv[key] = c.as_dict() | {"describe": describe(c)}
        print(f"{key}: {describe(c)}; extrapolated {c.extrapolated:.4g}, asymptotic {c.asymptotic:.3g}")
    (WORK / f"{scene}_{method}.json").write_text(json.dumps({"levels": levels, "runs": runs, "conv": conv}, indent=1))


if __name__ == "__main__":
    main()
