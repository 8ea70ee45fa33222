"""Issue 18 A1: the fluid-side error of decks/bird_strike_axisymmetric_{sph,ale}.yaml on the late load.

    python docs/studies/bird_strike_force_window.py --method sph   # dx 10 / 5 / 2.5 / 1.25 mm
    python docs/studies/bird_strike_force_window.py --method ale   # h 10 / 5 / 2.5 / 1.25 mm

Runs what docs/studies/bird_strike.py runs (its `overrides`: the SPH spacing; the ALE element size with
L_c = h / 2), into the same folders (study_bird_strike/<method>_<size>mm), and reuses a folder that holds
a finished run of the deck with those overrides (bird_strike.py's own runs). From the target's contact
force F(t) / (rho A v^2), every 2 us:

- `window mean`: the plain mean over 1.0-1.8 ms, the quantity of bird_strike.md and the deck headers;
- `Hann mean`: the same window, weighted by w(t) = sin^2(pi (t - 1.0 ms) / 0.8 ms). A Hann-weighted mean
  equals the plain mean on a constant and on a straight line (the weight is symmetric about the window's
  centre), so it measures the same load level as the plain mean. Its weight falls to zero with zero
  slope at the window's ends: an oscillation of frequency f leaks into it as 1 / (f T)^3, where the plain
  mean's leak is 1 / (f T). That leak is what the ALE coupling's ringing (the penalty spring's own
  oscillation) and the SPH contact's chatter put into a mean whose window starts and ends at arbitrary
  phases of it;
- `late impulse`: the impulse after 1.0 ms over m v, the momentum the bird still delivers once the cavity
  on the axis has closed (the quantity the window samples, without a window end: it runs to 3 ms);
- `impulse`: the whole run's over m v, as bird_strike.py;
- `shock impulse`: the impulse over the first 50 us (the window of bird_strike.py's centre peak) over
  P_H A 50 us. In Wilbeck's shock phase the whole face carries P_H until the release from the rim
  reaches it, (D / 2) / c0 = 34 us on the axis; the force's integral over that phase is the shock
  load summed over the face and over time, where the centre peak is one sample of one ring.

Order / GCI: sphfem_cli.study.metrics.three_grid on each consecutive triple, Fs 1.25; the shipped level's
error against the finest triple's Richardson value where that triple has an order.
"""
from __future__ import annotations

import argparse
import math
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import bird_strike  # noqa: E402  (its decks, overrides, WORK and constants)
from sphfem_cli import api  # noqa: E402
from sphfem_cli.api import read_histories  # noqa: E402
from sphfem_cli.study.metrics import describe, three_grid  # noqa: E402

SHIPPED = {"sph": 0.005, "ale": 0.0025}
T0, T1 = bird_strike.WINDOW
KEYS = ("window mean", "Hann mean", "late impulse", "impulse", "shock impulse")
SHOCK = 5.0e-5  # s: the centre peak's window in bird_strike.py


def hugoniot_force() -> float:
    """P_H A: the Hugoniot pressure over the bird's face, the shock phase's force (Wilbeck 1978)."""
    return bird_strike.hugoniot_pressure() * math.pi * bird_strike.RADIUS ** 2


def folder(method: str, size: float) -> Path:
    return bird_strike.WORK / f"{method}_{size * 1e3:g}mm"


def finished(path: Path) -> bool:
    try:
        hist = read_histories(path)["target"]
    except Exception:  # noqa: BLE001  (no folder, or no table yet)
        return False
    return bool(len(hist["time"])) and float(hist["time"][-1]) >= 3.0e-3 - 1e-9


def run(method: str, size: float) -> float | None:
    """CPU s of a new run, None where a finished one was reused."""
    path = folder(method, size)
    if finished(path):
        return None
    cpu = time.process_time()
    result = api.run(bird_strike.DECKS[method], path, bird_strike.overrides(method, size), threads=1, overwrite=True)
    assert result.completed, result.message
    return time.process_time() - cpu


def quantities(method: str, size: float) -> dict:
    hist = read_histories(folder(method, size))["target"]
    t, force = hist["time"], -hist["contact_force_y"]
    area = math.pi * bird_strike.RADIUS ** 2
    steady = bird_strike.RHO * area * bird_strike.SPEED ** 2
    mv = bird_strike.RHO * area * bird_strike.LENGTH * bird_strike.SPEED
    win = (t >= T0) & (t <= T1)
    w = np.sin(math.pi * (t[win] - T0) / (T1 - T0)) ** 2
    late = t >= T0
    return {"window mean": float(force[win].mean()) / steady,
            "Hann mean": float(np.trapezoid(w * force[win], t[win]) / np.trapezoid(w, t[win])) / steady,
            "late impulse": float(np.trapezoid(force[late], t[late])) / mv,
            "impulse": float(np.trapezoid(force, t)) / mv,
            "shock impulse": float(np.trapezoid(force[t <= SHOCK], t[t <= SHOCK])) / (hugoniot_force() * SHOCK)}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--method", choices=("sph", "ale"), default="sph")
    parser.add_argument("--sizes", type=float, nargs="*", default=[0.01, 0.005, 0.0025, 0.00125],
                        help="coarse to fine, ratio 2 (m)")
    args = parser.parse_args()
    bird_strike.WORK.mkdir(exist_ok=True)
    sizes = args.sizes
    rows = []
    for size in sizes:
        cpu = run(args.method, size)
        rows.append(quantities(args.method, size))
        print(f"{args.method} {size * 1e3:g} mm ({'reused' if cpu is None else f'{cpu:.1f} s CPU'}): "
              + ", ".join(f"{k} {rows[-1][k]:.4f}" for k in KEYS), flush=True)
    for key in KEYS:
        parts = []
        for i in range(len(sizes) - 2):
            conv = three_grid(sizes[i:i + 3], [r[key] for r in rows[i:i + 3]])
            text = describe(conv)
            if math.isfinite(conv.extrapolated):
                text += f", Richardson {conv.extrapolated:.4f}"
                if SHIPPED[args.method] in sizes[i:i + 3]:
                    shipped = rows[sizes.index(SHIPPED[args.method])][key]
                    text += f", shipped {100 * (shipped / conv.extrapolated - 1):+.2f} %"
            parts.append(f"{' / '.join(f'{s * 1e3:g}' for s in sizes[i:i + 3])} mm: {text}")
        print(f"{key}: " + "; ".join(parts))


if __name__ == "__main__":
    main()
