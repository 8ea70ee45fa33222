"""Decks and helpers of the axisymmetric verification tests (test_axisymmetric.py).

Quasi-static cases are solved by viscous dynamic relaxation through the ordinary explicit loop: after
every step the half-step velocities are scaled by (1 - 2 omega_1 dt), critical damping of the lowest
mode, omega_1 ~ c_p / (outer radius). (Kinetic damping, zeroing v at each kinetic-energy peak, was
tried first: with resets on every other step it amplifies the highest mode once omega dt > 1, which
it reached at timestep_scale 0.9.) The loads are small (strains ~1e-7) so that the small-strain
elastic solutions apply to well below the tolerances.
"""
from __future__ import annotations

import numpy as np

E, NU, RHO = 2.0e11, 0.3, 7850.0
CP = float(np.sqrt(E * (1 - NU) / ((1 + NU) * (1 - 2 * NU) * RHO)))  # dilatational wave speed
C0 = float(np.sqrt(E / RHO))  # bar speed of a thin rod
PRESSURE = 1.0e4
INNER, OUTER = 1.0, 2.0


def _deck(title: str, geometry: str, sets: str, boundaries: str, loads: str, hourglass: str,
          control: str = "end_time: 1.0, energy_band: null, timestep_scale: 0.5") -> str:
    return f"""
title: {title}
dimension: axisymmetric
control: {{{control}}}
materials:
  steel: {{type: elastic, density: {RHO}, youngs_modulus: {E}, poisson_ratio: {NU}}}
sections:
  solid: {{type: solid, hourglass: {{{hourglass}}}}}
parts:
  body: {{material: steel, section: solid, geometry: {geometry}}}
sets:
{sets}
boundaries:
{boundaries}
loads:
{loads}
"""


def lame_cylinder_deck(n: int) -> str:
    """Thick cylinder a <= r <= b, one element high, u_z = 0 everywhere (plane strain), p inside."""
    h = (OUTER - INNER) / n
    return _deck("Lame cylinder", f"{{box: {{min: [{INNER}, 0.0], max: [{OUTER}, {h}], divisions: [{n}, 1]}}}}",
                 "  inner: {type: segment, part: body, side: left}",
                 "  - {type: fixed, part: body, directions: [y]}",
                 f"  - {{type: pressure, set: inner, value: {PRESSURE}}}", "type: viscous, coefficient: 0.0")


def lame_cylinder_exact(r: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """u_r and sigma_tt of the plane-strain thick cylinder (Timoshenko & Goodier, Theory of Elasticity, sect. 28)."""
    k = PRESSURE * INNER ** 2 / (OUTER ** 2 - INNER ** 2)
    u = k / E * ((1 + NU) * (1 - 2 * NU) * r + (1 + NU) * OUTER ** 2 / r)
    return u, k * (1 + OUTER ** 2 / r ** 2)


def spherical_shell_mesh(path, n: int) -> None:
    """Meridian quarter annulus a <= R <= b, 0 <= phi <= pi/2 (r = R sin phi, z = R cos phi): n x 2n quad4."""
    import meshio

    radius = np.linspace(INNER, OUTER, n + 1)
    phi = np.linspace(0.0, 0.5 * np.pi, 2 * n + 1)
    rr, pp = np.meshgrid(radius, phi, indexing="ij")
    pts = np.stack([rr * np.sin(pp), rr * np.cos(pp)], axis=-1).reshape(-1, 2)
    pts[np.abs(pts) < 1e-14] = 0.0
    idx = np.arange(pts.shape[0]).reshape(n + 1, 2 * n + 1)
    cells = np.stack([idx[:-1, :-1], idx[1:, :-1], idx[1:, 1:], idx[:-1, 1:]], axis=-1).reshape(-1, 4)
    x = pts[cells]
    area = (x[:, 2, 0] - x[:, 0, 0]) * (x[:, 3, 1] - x[:, 1, 1]) + (x[:, 1, 0] - x[:, 3, 0]) * (x[:, 2, 1] - x[:, 0, 1])
    cells[area < 0] = cells[area < 0][:, ::-1]
    meshio.write(path, meshio.Mesh(np.hstack([pts, np.zeros((len(pts), 1))]), [("quad", cells)]))


def spherical_shell_deck(mesh_file: str) -> str:
    """Thick sphere a <= R <= b, p inside; the axis is free in z (u_r = 0 by itself), the equator z = 0 symmetric."""
    return _deck("thick spherical shell", f"{{file: {{file: {mesh_file}}}}}",
                 f"  inner: {{type: segment, part: body, sphere: {{center: [0.0, 0.0], radius: {INNER}}}}}\n"
                 "  equator: {type: node, part: body, side: bottom}",
                 "  - {type: symmetry, set: equator, normal: y}",
                 f"  - {{type: pressure, set: inner, value: {PRESSURE}}}", "type: stiffness, coefficient: 0.05")


def spherical_shell_exact(radius: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """u_R and sigma_tt of the thick sphere (Timoshenko & Goodier, Theory of Elasticity, sect. 141)."""
    k = PRESSURE * INNER ** 3 / (OUTER ** 3 - INNER ** 3)
    u = k / E * ((1 - 2 * NU) * radius + (1 + NU) * OUTER ** 3 / (2 * radius ** 2))
    return u, k * (1 + OUTER ** 3 / (2 * radius ** 3))


def hydrostatic_cylinder_deck(n: int) -> str:
    """Solid cylinder 0 <= r, z <= 1 (the axis included), p on its side and top, z = 0 symmetric."""
    return _deck("hydrostatic patch", f"{{box: {{min: [0.0, 0.0], max: [1.0, 1.0], divisions: [{n}, {n}]}}}}",
                 "  side: {type: segment, part: body, side: right}\n  top: {type: segment, part: body, side: top}\n"
                 "  bottom: {type: node, part: body, side: bottom}",
                 "  - {type: symmetry, set: bottom, normal: y}",
                 f"  - {{type: pressure, set: side, value: {PRESSURE}}}\n  - {{type: pressure, set: top, value: {PRESSURE}}}",
                 "type: stiffness, coefficient: 0.05")


def relax(sim, omega1: float, transit: float, max_steps: int = 50000, tol: float = 1e-9) -> int:
    """Viscous dynamic relaxation to rest; the steps taken (-1: not at rest after max_steps).

    At rest: max |v| times a wave transit time below tol times the largest displacement.
    """
    st = sim.state
    x0 = sim.model.coordinates
    for i in range(max_steps):
        sim.step()
        st.v *= 1.0 - 2.0 * omega1 * st.dt_prev
        if i > 10 and np.abs(st.v).max() * transit < tol * np.abs(st.x - x0).max():
            return i
    return -1


def observed_order(sizes, errors) -> float:
    """Least-squares slope of log(error) against log(size)."""
    return float(np.polyfit(np.log(sizes), np.log(errors), 1)[0])


ROD_RADIUS, ROD_LENGTH = 0.01, 1.0


def rod_wave_deck(radial: int, along: int) -> str:
    """A free thin rod (R/L = 0.01) on the axis, its end z = 0 driven at 1 m/s along the axis from t = 0."""
    stations = "".join(f"\n  station{i}: {{type: node, part: body, plane: {{point: [0.0, {z}], normal: [0.0, 1.0]}}}}"
                       for i, z in ((1, 0.25 * ROD_LENGTH), (2, 0.75 * ROD_LENGTH)))
    return _deck("thin rod, step velocity at one end",
                 f"{{box: {{min: [0.0, 0.0], max: [{ROD_RADIUS}, {ROD_LENGTH}], divisions: [{radial}, {along}]}}}}",
                 "  struck: {type: node, part: body, side: bottom}" + stations,
                 "  - {type: prescribed_velocity, set: struck, velocity: [null, 1.0]}", "  []",
                 "type: viscous, coefficient: 0.1", control=f"end_time: {0.9 * ROD_LENGTH / C0:.6e}")


def rod_impact_deck(end_time: float, timestep_scale: float = 0.9, impact: bool = True) -> str:
    """A free rod (R = 10 mm, L = 100 mm, axis included) whose upper half moves at -20 m/s into its
    resting lower half: an internal impact with no boundary condition but the axis. Without `impact`
    the rod starts at rest and without the energy guard (the caller sets its velocities)."""
    return _deck("free rod, internal impact",
                 "{box: {min: [0.0, 0.0], max: [0.01, 0.1], divisions: [4, 40]}}",
                 "  upper: {type: node, part: body, box: {min: [0.0, 0.0501], max: [0.011, 0.11]}}",
                 "  []", "  []", "type: stiffness, coefficient: 0.1",
                 control=f"end_time: {end_time:.6e}, timestep_scale: {timestep_scale}"
                 + ("" if impact else ", energy_band: null")) + \
        ("initial:\n  - {type: velocity, set: upper, velocity: [0.0, -20.0]}\n" if impact else "")
