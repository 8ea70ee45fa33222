"""Issue 15, scene 2 (deformable target): decks/bird_strike_axisymmetric_plate_{sph,ale,lagrangian}.yaml refined on
the structure side (plate through the thickness and along the radius) and on the fluid side (SPH spacing, ALE
element size, the Lagrangian bird's element), the three birds against each other, and against a rigid-plastic
membrane estimate.

    python docs/studies/bird_strike_plate.py --method sph --plates 1 2 4          # plate series, SPH dx 5 mm
    python docs/studies/bird_strike_plate.py --method sph --sizes 0.005 0.0025 0.00125   # fluid series, plate level 2
    python docs/studies/bird_strike_plate.py --method ale --sizes 0.005 0.0025 --end-time 2e-3
    python docs/studies/bird_strike_plate.py --method ale --sizes 0.00125 --end-time 2e-3   # peak only
    python docs/studies/bird_strike_plate.py --method lagrangian --sizes 0.005 0.0025 0.00125
    python docs/studies/bird_strike_plate.py --table       # every run under WORK, from its files
    python docs/studies/bird_strike_plate.py --series ale_5mm_p2_5ms ale_2.5mm_p2_5ms ale_1.25mm_p2_2ms
    python docs/studies/bird_strike_plate.py --plot docs/studies/bird_strike_plate_deflection.png

Plate level k is k x 50 elements along the radius and 2 k through the 4 mm thickness (k = 2 is the shipped
100 x 4). Runs land in WORK/<method>_<fluid size>mm_p<k>_<end ms>ms and are reused when their run.log
says completed (--fresh runs them again).

Measured per run: the centre deflection w (mid-thickness node on the axis, positive away from the bird):
its peak and time of peak, and the permanent deflection = mean of w over PERMANENT (the bird has gone by
then, the plate rings elastically about its deformed shape); the force of the bird on the plate (contact or
coupling) and its impulse over the run, over m v; the centre's equivalent plastic strain at the end; the
largest energy ratio error (glstat); CPU seconds (time.process_time of the run) and steps.
"""
from __future__ import annotations

import argparse
import json
import math
import time
from pathlib import Path

import numpy as np

from sphfem_cli import api
from sphfem_cli.api import read_histories
from sphfem_cli.study.metrics import describe, three_grid

ROOT = Path(__file__).resolve().parents[2]
DECKS = {"sph": ROOT / "decks/bird_strike_axisymmetric_plate_sph.yaml",
         "ale": ROOT / "decks/bird_strike_axisymmetric_plate_ale.yaml",
         "lagrangian": ROOT / "decks/bird_strike_axisymmetric_plate_lagrangian.yaml"}
SHIPPED = {"sph": 0.005, "ale": 0.0025, "lagrangian": 0.0025}
WORK = Path("study_bird_strike_plate")
RHO, SPEED, RADIUS, LENGTH = 1000.0, 100.0, 0.05, 0.2  # the bird (the decks')
PLATE_R, PLATE_H, PLATE_RHO = 0.25, 0.004, 2770.0  # the plate (the decks')
FLOW_STRESSES = (3.69e8, 4.14e8, 4.96e8)  # Pa: JC A; (yield + ultimate) / 2 of 2024-T3; JC at 10 % strain
PERMANENT = (3.5e-3, 5.0e-3)  # s: the force is below 1 % of rho A v^2 from about 3.4 ms in every run
MOMENTUM = RHO * math.pi * RADIUS ** 2 * LENGTH * SPEED
STYLES = {"sph": ("-", 1.0, 2), "ale": ("--", 1.6, 3), "lagrangian": (":", 1.8, 4)}  # line, width, z-order


def overrides(method: str, size: float, plate: int, end_time: float) -> dict:
    """Fluid size, plate level and end time. ALE keeps the shipped coupling rule L_c = h / 2: pfac = 2 n with
    n = h / (segment / nquad) coupling points per water element (as docs/studies/bird_strike.py)."""
    out = {"parts.plate.geometry.box.divisions": [50 * plate, 2 * plate], "control.end_time": end_time}
    if method == "sph":
        out["parts.bird.spacing"] = size
        return out
    if method == "lagrangian":
        out["parts.bird.geometry.box.divisions"] = [round(RADIUS / size), round(LENGTH / size)]
        return out
    segment = PLATE_R / (50 * plate)
    nquad = max(2, math.ceil(segment / size - 1e-9))
    out.update({"parts.air.geometry.box.element_size": size, "couplings.0.nquad": nquad,
                "couplings.0.pfac": 2.0 * size / (segment / nquad)})
    return out


def folder(method: str, size: float, plate: int, end_time: float) -> Path:
    return WORK / f"{method}_{size * 1e3:g}mm_p{plate}_{end_time * 1e3:g}ms"


def run(method: str, size: float, plate: int, end_time: float, fresh: bool) -> Path:
    out = folder(method, size, plate, end_time)
    log = out / "run.log"
    if not fresh and log.exists() and "status: completed" in log.read_text():
        return out
    cpu = time.process_time()
    result = api.run(DECKS[method], out, overrides(method, size, plate, end_time), threads=1, overwrite=True)
    cpu = time.process_time() - cpu
    assert result.completed, result.message
    (out / "study.json").write_text(json.dumps({"cpu_s": cpu, "steps": result.steps}))
    return out


def measure(out: Path) -> dict:
    """The figures of one run folder (module docstring)."""
    hist = read_histories(out)
    t, w = hist["centre"]["time"], -hist["centre"]["displacement_y"]
    tf, force = hist["plate"]["time"], -hist["plate"]["contact_force_y"]
    glstat = hist["glstat"]
    late = (t >= PERMANENT[0]) & (t <= PERMANENT[1])
    info = json.loads((out / "study.json").read_text()) if (out / "study.json").exists() else {}
    return {"peak_mm": 1e3 * float(w.max()), "t_peak_ms": 1e3 * float(t[w.argmax()]),
            "permanent_mm": 1e3 * float(w[late].mean()) if late.sum() > 10 else float("nan"),
            "impulse/mv": float(np.trapezoid(force, tf)) / MOMENTUM,
            "eps_p_centre": float(hist["centre"]["plastic_strain"][-1]),
            "energy_err": float(np.abs(glstat["energy_ratio"] - 1.0).max()),
            "cpu_s": info.get("cpu_s", float("nan")), "steps": info.get("steps", -1)}


def membrane_estimate(flow_stress: float) -> dict:
    """Rigid-perfectly plastic membrane under the bird's steady force (docs/studies/bird_strike_plate.md,
    "Independent estimate"). Once W exceeds a few H the plate carries the load as a membrane (Jones 1989,
    "Structural Impact", ch. 7); at yield the radial membrane force is N0 = sigma0 H everywhere, so vertical
    equilibrium of the disc inside radius r, 2 pi r N0 w'(r) = -F(r), gives for a load F spread evenly over
    the bird's radius a:
        w(r) = F / (2 pi N0) [ln(R / a) + (1 - r^2 / a^2) / 2]  (r <= a),  F / (2 pi N0) ln(R / r)  (r >= a),
    centre W = F (1/2 + ln(R / a)) / (2 pi N0). With F = rho A v^2 (the jet's momentum flux, the force of
    the rigid-target study's steady phase) this is the quasi-static deflection W_qs. Dynamics in one mode
    (that shape, phi = w / W): generalised mass m_g = rho_p H int phi^2 dA, generalised force F phi_a
    (phi_a the mean of phi over the loaded disc), resistance K W with K = F phi_a / W_qs; F applied suddenly
    for the bird's squash time L / v (impulse m v): W peaks at 2 W_qs if L / v >= pi / omega, omega^2 =
    K / m_g, and stays there (rigid-plastic: no spring-back). Bound: the bird's whole kinetic energy
    dissipated in that mode, 1/2 K W^2 = m v^2 / 2."""
    n0 = flow_stress * PLATE_H
    a, big_r = RADIUS, PLATE_R
    steady = RHO * math.pi * a ** 2 * SPEED ** 2
    scale = 0.5 + math.log(big_r / a)
    r = np.linspace(0.0, big_r, 20001)
    phi = (np.log(big_r / np.maximum(r, a)) + 0.5 * np.clip(1.0 - (r / a) ** 2, 0.0, None)) / scale
    m_g = PLATE_RHO * PLATE_H * float(np.trapezoid(phi ** 2 * 2.0 * math.pi * r, r))
    inner = r <= a
    phi_a = float(np.trapezoid(phi[inner] * 2.0 * math.pi * r[inner], r[inner])) / (math.pi * a ** 2)
    w_qs = steady * scale / (2.0 * math.pi * n0)
    stiffness = steady * phi_a / w_qs
    omega = math.sqrt(stiffness / m_g)
    duration = LENGTH / SPEED
    dynamic = 2.0 * w_qs if duration * omega >= math.pi else w_qs * (1.0 - math.cos(omega * duration))
    kinetic = 0.5 * MOMENTUM * SPEED
    return {"flow_stress_MPa": flow_stress / 1e6, "W_qs_mm": 1e3 * w_qs, "W_dyn_mm": 1e3 * dynamic,
            "t_dyn_peak_ms": 1e3 * math.pi / omega, "m_g_kg": m_g, "phi_a": phi_a,
            "W_energy_bound_mm": 1e3 * math.sqrt(2.0 * kinetic / stiffness)}


def series(runs: list[tuple[float, dict]], label: str) -> None:
    for size, row in runs:
        print(f"  {label} {size:g}: " + ", ".join(f"{k} {v:.4g}" for k, v in row.items()))
    if len(runs) >= 3:
        h = [s for s, _ in runs[-3:]]
        for key in ("peak_mm", "permanent_mm", "impulse/mv"):
            print(f"  {key}: {describe(three_grid(h, [r[key] for _, r in runs[-3:]]))}")


def named_series(names: list[str]) -> None:
    """Order and GCI over three run folders under WORK, coarse to fine (sizes from their names: the fluid size,
    or the plate's element through the thickness where the fluid sizes agree)."""
    parts = [name.split("_") for name in names]
    fluid = [float(p[1][:-2]) * 1e-3 for p in parts]
    sizes = fluid if len(set(fluid)) > 1 else [PLATE_H / (2 * int(p[2][1:])) for p in parts]
    rows = [measure(WORK / name) for name in names]
    for key in ("peak_mm", "t_peak_ms", "permanent_mm", "impulse/mv"):
        values = [r[key] for r in rows]
        if all(math.isfinite(v) for v in values):
            print(f"{key} {' / '.join(f'{v:.4g}' for v in values)}: {describe(three_grid(sizes, values))}")


def table() -> None:
    for out in sorted(WORK.iterdir()):
        if (out / "histories").exists():
            print(out.name + ": " + ", ".join(f"{k} {v:.4g}" for k, v in measure(out).items()))


def plot(path: Path) -> None:
    """Centre deflection against time for every run under WORK: SPH solid, ALE dashed, Lagrangian dotted."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(8, 4.6))
    for out in sorted(WORK.iterdir()):
        if not (out / "histories").exists():
            continue
        method, size, plate, _ = out.name.split("_")
        hist = read_histories(out)["centre"]
        style, width, order = STYLES[method]
        ax.plot(hist["time"] * 1e3, -hist["displacement_y"] * 1e3, style, lw=width, zorder=order,
                label=f"{method.upper()} bird {size[:-2]} mm, plate {50 * int(plate[1:])} x {2 * int(plate[1:])}")
    ax.set_xlabel("time (ms)")
    ax.set_ylabel("plate centre deflection (mm)")
    ax.set_title("Bird strike (1.57 kg water, 100 m/s) on a clamped 4 mm 2024-T3 plate, r-z")
    ax.axvspan(PERMANENT[0] * 1e3, PERMANENT[1] * 1e3, color="0.9", zorder=0, label="permanent-deflection window")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7, loc="lower right")
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    print(f"wrote {path}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--method", choices=sorted(DECKS), default="sph")
    parser.add_argument("--sizes", type=float, nargs="*", help="fluid sizes, coarse to fine, ratio 2 (m)")
    parser.add_argument("--plates", type=int, nargs="*", help="plate levels k, coarse to fine (1 2 4)")
    parser.add_argument("--end-time", type=float, default=5.0e-3)
    parser.add_argument("--fresh", action="store_true", help="run again even where a completed run exists")
    parser.add_argument("--table", action="store_true", help="only measure the runs under WORK")
    parser.add_argument("--series", nargs=3, help="only: order and GCI over three run folders, coarse to fine")
    parser.add_argument("--plot", type=Path, help="only plot the runs under WORK into this PNG")
    args = parser.parse_args()
    if args.plot:
        plot(args.plot)
        return
    if args.series:
        named_series(args.series)
        return
    if args.table:
        table()
        for sigma in FLOW_STRESSES:
            print("membrane estimate:", ", ".join(f"{k} {v:.4g}" for k, v in membrane_estimate(sigma).items()))
        return
    WORK.mkdir(exist_ok=True)
    sizes = args.sizes or [SHIPPED[args.method]]
    plates = args.plates or [2]
    if len(plates) > 1:
        series([(PLATE_H / (2 * k), measure(run(args.method, sizes[0], k, args.end_time, args.fresh)))
                for k in plates], f"{args.method} fluid {sizes[0] * 1e3:g} mm, plate element through thickness (m)")
    else:
        series([(s, measure(run(args.method, s, plates[0], args.end_time, args.fresh))) for s in sizes],
               f"{args.method} plate level {plates[0]}, fluid size (m)")


if __name__ == "__main__":
    main()
