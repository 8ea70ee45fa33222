"""Issue 15, scene 4: decks/cylinder_entry_end_on_axisymmetric_{sph,ale}.yaml (a flat-ended rigid cylinder, free,
hitting calm water end-on at V0) refined, against the acoustic and impulsive exact results and a linear-acoustics
reference computed here.

    python docs/studies/cylinder_entry_end_on.py --reference          # the linear-acoustics reference (tests/data)
    python docs/studies/cylinder_entry_end_on.py                      # SPH, R/dx = 10 / 20 / 40
    python docs/studies/cylinder_entry_end_on.py --method ale         # ALE, R/h = 10 / 20 / 40
    python docs/studies/cylinder_entry_end_on.py --method sph --levels 40 --face 20   # body face alone (20/40/80)
    python docs/studies/cylinder_entry_end_on.py --method sph --levels 40 --gap 0.000625   # force before contact
    python docs/studies/cylinder_entry_end_on.py --plot docs/studies/cylinder_entry_end_on.png   # runs above

Exact results (docs/studies/cylinder_entry_end_on.md, tests/data/cylinder_entry_end_on.md):

- acoustic phase (von Karman 1929; Verhagen 1967, J. Ship Res. 11, 211): the face meets the water at V0 and the
  pressure on it is rho c V0; a point of the face at radius r keeps the one-dimensional (piston) pressure
  rho c V(t) until the relief from the rim reaches it, at t = (R - r) / c; so the centre pressure is rho c V(t)
  for t < R / c and the force starts at rho c V0 pi R^2;
- impulsive (incompressible) limit (Batchelor 1967, section 6.10; Glasheen & McMahon 1996): the impulse given to
  the water is m_a V with m_a = 4/3 rho R^3 (half the 8/3 rho R^3 of a disc in unbounded fluid), so a free body of
  mass M leaves the impact at V1 = V0 M / (M + m_a). In compressible water this is the final value of the linear
  acoustic problem only if the face can pull the water (the pressure on the face goes below zero once the rim's
  relief has reached the axis, t ~ R / c); the deck's contact and coupling push only, so the body leaves the
  water earlier, slower than V1.

The linear-acoustics reference (`reference`): the same linear problem solved by finite differences (staggered
pressure and velocities in r-z, the face's velocity from the body's equation M dV/dt = -F, p = 0 on the free
surface, rigid walls 6 R away, no echo before t = 10 R / c), with the face either bonded to the water (tension
allowed: its final velocity must be V1, a check of the solver) or unilateral (a face cell lets go when its
pressure would go negative and takes hold again when the gap closes: the deck's contact). Three grids, R / d =
20 / 40 / 80, give the reference and its discretisation error.

Prints per level: the body's velocity at t = 2 R / c and at the end over V0 (against the unilateral reference),
the centre pressure over rho c V(t) averaged over 0.2-0.8 R / c (exact 1), the peak force over rho c V0 pi R^2,
the force's first sample time, the CPU seconds; then the observed order and GCI on three levels.
"""
from __future__ import annotations

import argparse
import csv
import math
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
DECKS = {m: ROOT / f"decks/cylinder_entry_end_on_axisymmetric_{m}.yaml" for m in ("sph", "ale")}
DATA = ROOT / "tests/data/cylinder_entry_end_on_reference.csv"
WORK = Path("study_cylinder_entry_end_on")
RHO, C0, V0, RADIUS, LENGTH, BODY_DENSITY = 1000.0, 1480.0, 3.0, 0.05, 0.1, 500.0  # the decks'
MASS = BODY_DENSITY * math.pi * RADIUS ** 2 * LENGTH
ADDED_MASS = 4.0 / 3.0 * RHO * RADIUS ** 3
V1 = V0 * MASS / (MASS + ADDED_MASS)
FORCE0 = RHO * C0 * V0 * math.pi * RADIUS ** 2
T_ACOUSTIC = RADIUS / C0  # s


# ------------------------------------------------------------------ linear-acoustics reference


def reference(per_radius: int, unilateral: bool, mass: float | None = MASS, extent: float = 6.0,
              t_end: float = 10.0, courant: float = 0.5) -> dict[str, np.ndarray]:
    """Linear acoustics in r-z below the plane z = 0 (z up); the face r < R moves down at V(t), the rest of the
    plane is a free surface (p = 0, by an odd ghost); rigid walls at r = z = -extent R. Staggered grid of
    spacing d = R / per_radius: p at cell centres, u_r on the radial faces, u_z on the axial ones; leapfrog in
    time. mass None: V = V0 held (constant speed). Returns the times over R / c, the force on the face, the body
    velocity, the pressure of the cell at the centre of the face (r = z = -d/2) and the lowest face pressure.
    """
    d = RADIUS / per_radius
    n = int(round(extent * per_radius))
    p = np.zeros((n, n))  # p[i, j] at r = (i + 1/2) d, z = -(j + 1/2) d
    ur = np.zeros((n + 1, n))  # at r = i d; ur[0] = 0 (axis), ur[n] = 0 (wall)
    uz = np.zeros((n, n + 1))  # at z = -j d; uz[:, 0] on the surface, uz[:, n] = 0 (floor)
    rc = (np.arange(n) + 0.5) * d
    rf = np.arange(n + 1) * d
    face = rc < RADIUS
    ring = 2.0 * math.pi * rc[face] * d  # the face cells' ring areas
    bulk = RHO * C0 ** 2
    dt = courant * d / C0 / math.sqrt(2.0)
    steps = int(math.ceil(t_end * T_ACOUSTIC / dt))
    touching = np.ones(face.sum(), dtype=bool)
    gap = np.zeros(face.sum())
    speed = V0
    out = np.zeros((steps, 5))
    for k in range(steps):
        ur[1:n] -= dt / RHO * (p[1:] - p[:-1]) / d
        uz[:, 1:n] -= dt / RHO * (p[:, :-1] - p[:, 1:]) / d
        free = ~face
        if unilateral:
            free = free.copy()
            free[face] = ~touching
        uz[free, 0] -= dt / RHO * (-2.0 * p[free, 0]) / d
        loads = p[face, 0] * ring
        force = float(loads[touching].sum()) if unilateral else float(loads.sum())
        if mass is not None:
            speed -= dt * force / mass
        if unilateral:  # a released cell's gap grows while its water runs ahead of the face
            gap[~touching] += dt * (-uz[face, 0][~touching] - speed)
            closed = ~touching & (gap <= 0.0)
            gap[closed] = 0.0
            touching |= closed
            uz[face, 0] = np.where(touching, -speed, uz[face, 0])
        else:
            uz[face, 0] = -speed
        div = ((rf[1:, None] * ur[1:] - rf[:-1, None] * ur[:-1]) / (rc[:, None] * d)
               + (uz[:, :-1] - uz[:, 1:]) / d)
        p -= dt * bulk * div
        if unilateral:
            touching &= ~(p[face, 0] < 0.0)
        out[k] = ((k + 1) * dt / T_ACOUSTIC, force, speed, p[0, 0], p[face, 0].min())
    return {"tau": out[:, 0], "force": out[:, 1], "velocity": out[:, 2], "centre": out[:, 3], "min_face": out[:, 4]}


def write_reference(grids=(20, 40, 80)) -> None:
    """tests/data/cylinder_entry_end_on_reference.csv: V / V0 and F / (rho c V0 pi R^2) of the free body at
    tau = t c / R = 0, 0.05, ..., 4 on the three grids, unilateral face (the decks' contact), and the bonded face."""
    taus = np.round(np.arange(0.0, 4.0001, 0.05), 2)
    columns = {"tau": taus}
    for g in grids:
        for name, uni in (("unilateral", True), ("bonded", False)):
            cpu = time.process_time()
            r = reference(g, uni)
            tau = np.concatenate([[0.0], r["tau"]])
            columns[f"V_over_V0_{name}_{g}"] = np.interp(taus, tau, np.concatenate([[V0], r["velocity"]])) / V0
            columns[f"F_over_F0_{name}_{g}"] = np.interp(taus, tau, np.concatenate([[0.0], r["force"]])) / FORCE0
            end = r["velocity"][-1]
            print(f"R/d {g:3d} {name:10s}: V(2 R/c) / V0 {np.interp(2.0, tau[1:], r['velocity']) / V0:.5f}, "
                  f"V(4 R/c) / V0 {np.interp(4.0, tau[1:], r['velocity']) / V0:.5f}, V(10 R/c) / V1 {end / V1:.5f}, "
                  f"first face tension at t c/R = {r['tau'][np.argmax(r['min_face'] < 0)]:.3f}, "
                  f"{time.process_time() - cpu:.1f} s CPU")
    DATA.parent.mkdir(parents=True, exist_ok=True)
    with DATA.open("w", newline="") as f:
        w = csv.writer(f)
        w.writerow(list(columns))
        for row in zip(*columns.values()):
            w.writerow([f"{v:.6g}" for v in row])
    print(f"wrote {DATA}")


# ------------------------------------------------------------------ deck levels


def overrides(method: str, per_radius: int, face: int | None = None, gap: float = 0.0) -> dict:
    """The fluid at spacing (element size) R / per_radius, the body's face in `face` segments (default matched),
    the centre probe in the first particle's (element's) place; `gap` lifts the body's face above the surface
    (the run is made longer by the flight gap / V0)."""
    size = RADIUS / per_radius
    segments = face or per_radius
    out = {"parts.cylinder.geometry.box.divisions": [segments, 2 * segments],
           "output.probes.0.point": [size / 2.0, -size / 2.0]}
    if gap:
        out["parts.cylinder.geometry.box.min"] = [0.0, gap]
        out["parts.cylinder.geometry.box.max"] = [RADIUS, LENGTH + gap]
        out["control.end_time"] = gap / V0 + 2.0 * T_ACOUSTIC
    if method == "sph":
        out["parts.water.spacing"] = size
    else:  # the deck's coupling rule L_c = h / 2: pfac = 2 n, n = nquad h / segment coupling points per element face
        out["parts.tank.geometry.box.element_size"] = size
        out["parts.tank.geometry.box.max"] = [0.2, 4.0 * size]
        out["couplings.0.pfac"] = 2.0 * 2 * size / (RADIUS / segments)
    return out


def level(method: str, per_radius: int, face: int | None = None, gap: float = 0.0) -> dict:
    from sphfem_cli import api

    tag = f"{method}_R{per_radius}" + (f"_face{face}" if face else "") + (f"_gap{gap * 1e3:g}mm" if gap else "")
    cpu = time.process_time()
    result = api.run(DECKS[method], WORK / tag, overrides(method, per_radius, face, gap), threads=1, overwrite=True)
    cpu = time.process_time() - cpu
    assert result.completed, result.message
    if gap:  # the force before the face reaches the surface (t < gap / V0): none expected
        hist = result.histories()
        t, f = hist["cylinder"]["time"], hist["cylinder"]["contact_force_y"]
        before = t < gap / V0
        first = t[np.argmax(np.abs(f) > 0)] if (np.abs(f) > 0).any() else float("nan")
        print(f"{tag}: contact at t = gap / V0 = {gap / V0 * 1e6:.2f} us; largest |force| before it "
              f"{np.abs(f[before]).max():.3g} N; impulse before it {np.trapezoid(f[before], t[before]):.3g} N s; "
              f"first nonzero force at {first * 1e6:.2f} us ({(first - gap / V0) / T_ACOUSTIC:+.3f} R/c); "
              f"{cpu:.1f} s CPU")
        return {"tag": tag}
    return measure(result.histories()) | {"cpu_s": cpu, "steps": result.steps, "tag": tag}


def measure(hist: dict) -> dict:
    """The compared quantities of a run's histories (cylinder, centre)."""
    t = hist["cylinder"]["time"]
    tau = t / T_ACOUSTIC
    v = -hist["cylinder"]["velocity_y"]
    f = hist["cylinder"]["contact_force_y"]
    tc, pc = hist["centre"]["time"] / T_ACOUSTIC, np.nan_to_num(hist["centre"]["pressure"])
    window = (tc >= 0.2) & (tc <= 0.8)
    return {"V(2R/c)/V0": float(np.interp(2.0, tau, v)) / V0,
            "V(end)/V0": float(v[-1]) / V0,
            "centre/(rho c V)": float(np.mean(pc[window] / (RHO * C0 * np.interp(tc[window], tau, v)))),
            "peak F/F0": float(f.max()) / FORCE0,
            "first force tau": float(tau[np.argmax(f > 0)]) if (f > 0).any() else float("nan"),
            "t": t, "v": v, "f": f}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--method", choices=("sph", "ale"), default="sph")
    ap.add_argument("--levels", type=int, nargs="+", default=[10, 20, 40], help="R / dx (R / h)")
    ap.add_argument("--face", type=int, default=None, help="the body face's segments (default R / dx)")
    ap.add_argument("--gap", type=float, default=0.0, help="start the face this far above the surface (m): "
                    "prints the force before contact")
    ap.add_argument("--reference", action="store_true", help="write tests/data/cylinder_entry_end_on_reference.csv")
    ap.add_argument("--plot", type=Path, default=None)
    args = ap.parse_args()
    if args.reference:
        write_reference()
        return
    if args.plot:
        plot(args.plot)
        return
    if args.gap:
        for n in args.levels:
            level(args.method, n, args.face, args.gap)
        return
    from sphfem_cli.study.metrics import describe, three_grid

    ref = np.loadtxt(DATA, delimiter=",", skiprows=1)
    names = DATA.read_text().splitlines()[0].split(",")
    v2_ref = float(np.interp(2.0, ref[:, 0], ref[:, names.index("V_over_V0_unilateral_80")]))
    v4_ref = float(np.interp(4.0, ref[:, 0], ref[:, names.index("V_over_V0_unilateral_80")]))
    print(f"{args.method}: V0 {V0} m/s, M {MASS:.4f} kg, m_a {ADDED_MASS:.4f} kg, V1/V0 {V1 / V0:.4f}; "
          f"unilateral linear reference V(2R/c)/V0 {v2_ref:.4f}, V(4R/c)/V0 {v4_ref:.4f}")
    rows = []
    for n in args.levels:
        r = level(args.method, n, args.face)
        rows.append(r)
        print(f"R/dx {n:3d} face {args.face or n:3d}: V(2R/c)/V0 {r['V(2R/c)/V0']:.4f} "
              f"({100 * (r['V(2R/c)/V0'] / v2_ref - 1):+.2f} %), V(end)/V0 {r['V(end)/V0']:.4f} "
              f"({100 * (r['V(end)/V0'] / v4_ref - 1):+.2f} %; / V1 {r['V(end)/V0'] * V0 / V1:.4f}), "
              f"centre/(rho c V) {r['centre/(rho c V)']:.4f}, peak F/F0 {r['peak F/F0']:.4f}, "
              f"first force at tau {r['first force tau']:.3f}, {r['steps']} steps, {r['cpu_s']:.1f} s CPU", flush=True)
        np.savetxt(WORK / f"{r['tag']}.csv", np.column_stack([r["t"], r["v"], r["f"]]), delimiter=",",
                   header="time,velocity_down,contact_force_y", comments="")
    if len(rows) >= 3:
        h = [RADIUS / n for n in args.levels[-3:]]
        for key in ("V(2R/c)/V0", "V(end)/V0", "centre/(rho c V)", "peak F/F0"):
            conv = three_grid(h, [r[key] for r in rows[-3:]])
            extra = f", extrapolated {conv.extrapolated:.4f}" if math.isfinite(conv.extrapolated) else ""
            print(f"  {key}: {describe(conv)}{extra}")


def plot(path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    ref = np.loadtxt(DATA, delimiter=",", skiprows=1)
    names = DATA.read_text().splitlines()[0].split(",")
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 4.2))
    for col, style, label in (("unilateral_80", "k-", "linear acoustics, face lets go (R/d 80)"),
                              ("bonded_80", "k:", "linear acoustics, face bonded (R/d 80)")):
        ax1.plot(ref[:, 0], ref[:, names.index(f"V_over_V0_{col}")], style, lw=2, label=label)
        ax2.plot(ref[:, 0], ref[:, names.index(f"F_over_F0_{col}")], style, lw=2, label=label)
    ax1.axhline(V1 / V0, color="grey", lw=0.8)
    ax1.text(3.0, V1 / V0 + 0.01, "V1 = V0 M / (M + m_a)", color="grey")
    for f in sorted(WORK.glob("*_R*.csv")):
        if "face" in f.stem or "gap" in f.stem:
            continue
        d = np.loadtxt(f, delimiter=",", skiprows=1, ndmin=2)
        ls = "--" if f.stem.startswith("ale") else "-"
        ax1.plot(d[:, 0] / T_ACOUSTIC, d[:, 1] / V0, ls, lw=1, label=f.stem)
        ax2.plot(d[:, 0] / T_ACOUSTIC, d[:, 2] / FORCE0, ls, lw=1, label=f.stem)
    ax1.set(xlabel="t c / R", ylabel="V / V0", xlim=(0, 4))
    ax2.set(xlabel="t c / R", ylabel="F / (rho c V0 pi R^2)", xlim=(0, 2))
    ax1.legend(fontsize=7)
    ax2.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    print(f"wrote {path}")


if __name__ == "__main__":
    main()
