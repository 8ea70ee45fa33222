"""Programmed burn of a high explosive (materials.burn; LS-DYNA *MAT_HIGH_EXPLOSIVE_BURN, BETA = 2).

TNT as in issue 5: rho0 = 1630, D = 6930 m/s, JWL A = 371.2 GPa, B = 3.231 GPa, R1 = 4.15, R2 = 0.95,
omega = 0.30, E0 = 7.0 GJ/m^3.
"""
from __future__ import annotations

import numpy as np
import pytest

from sphfem_cli.deck.schema import materials as sm
from sphfem_cli.materials import kernels as mk
from sphfem_cli.materials.burn import burn_fraction, lighting_time, quad_size
from sphfem_cli.materials.slots import P_DETONATION_VELOCITY
from sphfem_cli.materials.tables import pack_material

D = 6930.0
RHO0 = 1630.0
E0 = 7.0e9
JWL = sm.JWL(type="jwl", A=3.712e11, B=3.231e9, R1=4.15, R2=0.95, omega=0.30, e0=E0)
TNT = sm.HighExplosive(type="high_explosive", density=RHO0, detonation_velocity=D, eos="tnt")


def tnt_row() -> np.ndarray:
    kind, row = pack_material(TNT, JWL)
    assert kind == mk.FLUID and row[P_DETONATION_VELOCITY] == D
    return row


def p_jwl(row, v_rel, e):
    return float(mk.eos_pressure(mk.EOS_JWL, row[mk.EOS_OFFSET:], 1.0 / v_rel, e))


def test_lighting_time_and_fraction():
    pts = np.array([[0.0, 0.0], [3.0, 4.0], [10.0, 0.0]])
    t = lighting_time(pts, [([0.0, 0.0], 0.0), ([10.0, 0.0], 1.0)], 5.0)
    assert t == pytest.approx([0.0, 1.0, 1.0])
    assert lighting_time(pts, [], 5.0) == pytest.approx(0.0)  # no detonation point: all light at 0
    f = burn_fraction(np.array([0.0, 0.5, 1.0, 2.0]), 0.5, 3.0, 1.0)  # ramp over 1.5 delta / D = 0.5
    assert f == pytest.approx([0.0, 0.0, 1.0, 1.0])
    assert burn_fraction(0.75, 0.5, 3.0, 1.0) == pytest.approx(0.5)
    from sphfem_cli.model.mesh import box_mesh

    mesh = box_mesh([0, 0], [1.0, 0.5], divisions=[4, 1])
    assert quad_size(mesh.nodes, mesh.elements) == pytest.approx(0.25)  # area / longest edge = 0.125 / 0.5


def test_chapman_jouguet_point_of_the_jwl():
    """The JWL products' Hugoniot (E = E0 + p (1 - V) / 2 per unit initial volume) touched by the
    Rayleigh line p = rho0 D^2 (1 - V): the minimum of D^2 over V is the CJ state. For the TNT set
    it must give D_CJ = 6930 m/s (the deck's D) and p_CJ = 21 GPa (Dobratz & Crawford 1985)."""
    row = tnt_row()
    v = np.linspace(0.55, 0.95, 40001)
    cold = np.array([p_jwl(row, x, 0.0) for x in v])  # A, B terms
    w = JWL.omega
    p_h = (cold + w * E0 / v) / (1.0 - w * (1.0 - v) / (2.0 * v))
    d2 = p_h / (RHO0 * (1.0 - v))
    i = int(np.argmin(d2))
    assert np.sqrt(d2[i]) == pytest.approx(D, rel=2e-3)
    assert p_h[i] == pytest.approx(21.0e9, rel=0.02)
    assert 0.70 < v[i] < 0.76  # V_CJ = 0.73


def _strip(n=80, length=0.08, detonation=0.0):
    from sphfem_cli.ale.system import AleSystem
    from sphfem_cli.model.mesh import box_mesh

    h = length / n
    mesh = box_mesh([0.0, 0.0], [length, h], divisions=[n, 1])
    ale = AleSystem(mesh.nodes, mesh.elements, [tnt_row()], np.ones((n, 1)), [RHO0], energy=[E0 / RHO0])
    bottom = np.flatnonzero(np.isclose(mesh.nodes[:, 1], 0.0))
    top = np.flatnonzero(np.isclose(mesh.nodes[:, 1], h))
    ale.set_slip(bottom, (0.0, 1.0))
    ale.set_slip(top, (0.0, 1.0))
    ale.set_burn([0], [D], [([detonation, 0.5 * h], 0.0)])
    return ale, h


def test_unburnt_explosive_has_no_pressure_and_burnt_has_the_jwl_pressure():
    """At rest, F = 0 before t_L (p = 0) and F = 1 after the ramp: p = p_JWL(rho0, E0) exactly."""
    ale, h = _strip(n=10, length=0.01)
    p = ale.pressure()[:, 0]
    assert p[0] == 0.0 and np.all(p == 0.0)  # t = 0: the element at the point has t_L = h / (2D) > 0
    ale.time = 1.0  # every element burnt, state untouched
    p = ale.pressure()[:, 0]
    assert p == pytest.approx(p_jwl(tnt_row(), 1.0, E0), rel=1e-14)
    assert p[0] == pytest.approx(8.3837e9, rel=1e-4)


def test_detonation_front_in_an_ale_strip_arrives_at_r_over_d():
    """A strip of 80 elements of TNT lit at its left end: the time at which each element's pressure
    first exceeds p_JWL(rho0, E0) (the constant-volume burn pressure; the front compresses the
    unburnt explosive, so the pressure there rises above it) is its distance over D plus a fixed
    lag of the burn ramp; the fitted front speed is D within 2 %."""
    ale, h = _strip()
    n = ale.conn.shape[0]
    threshold = p_jwl(tnt_row(), 1.0, E0)
    arrival = np.full(n, np.nan)
    t_end = 0.08 / D
    while ale.time < t_end:
        dt = ale.stable_dt(0.5)
        ale.step(dt)
        p = ale.pressure()[:, 0]
        new = np.isnan(arrival) & (p >= threshold)
        arrival[new] = ale.time
    x = ale.centroids()[:, 0]
    sel = (x > 0.01) & (x < 0.07)
    assert not np.isnan(arrival[sel]).any()
    slope, offset = np.polyfit(x[sel], arrival[sel], 1)
    assert 1.0 / slope == pytest.approx(D, rel=0.02)
    lag = arrival[sel] - x[sel] / D
    assert np.all(np.abs(lag) < 1.5 * h / D + 2 * dt)  # within the ramp time of r/D


def test_detonation_front_on_a_line_of_sph_particles():
    """SPH particles in a channel three spacings high between slip walls (a plane flow along x), each row lit
    at x = 0 (a detonation point at the row's start: t_L = x / D): the burn fraction of each particle rises
    from 0 at t_L; its pressure becomes positive within one step of x / D and not before."""
    from sphfem_cli.sph import lattice
    from sphfem_cli.sph.options import SphOptions
    from sphfem_cli.sph.system import SphSystem
    from sphfem_cli.sph.walls import box_walls

    row = tnt_row()
    dx, n, rows = 1e-3, 60, 3
    x = lattice.box([0.0, 0.0], [n * dx, rows * dx], dx)  # x first: particle k is at column k // rows
    m = len(x)
    walls = box_walls([0.0, 0.0], [n * dx, rows * dx], ["bottom", "top"])
    ps = SphSystem(x, np.zeros_like(x), np.full(m, RHO0 * dx * dx), np.full(m, RHO0), np.zeros(m, dtype=np.int64),
                   (np.array([mk.FLUID]), row[None, :]), SphOptions(alpha=1.0, beta=2.0, walls=tuple(walls)))
    ps.set_burn([([0.0, (j + 0.5) * dx], 0.0) for j in range(rows)])
    assert np.all(ps.p == 0.0)
    first = np.full(m, np.nan)
    t_prev = 0.0
    while ps.time < 0.05 / D:
        ps.compute_rates()
        new = np.isnan(first[ps.ids]) & (ps.p > 0.0)
        first[ps.ids[new]] = ps.time
        dt = ps.stable_dt(0.5)
        t_prev = ps.time
        ps.step(dt)
    t_light = x[:, 0] / D
    lit = ~np.isnan(first)
    assert lit[: 40 * rows].all()
    assert np.all(first[lit] > t_light[lit])  # not before t_L
    assert np.all(first[lit] - t_light[lit] <= 1.5 * (ps.time - t_prev) + 1e-15)  # within a step of t_L
    ps.time = 1.0  # burnt, at rest
    ps._update_state()
    assert ps.p[np.argsort(ps.ids)][-1] == pytest.approx(p_jwl(row, 1.0, E0), rel=1e-3)


def test_deck_keywords():
    from sphfem_cli.deck.schema import Deck

    base = {
        "dimension": 2, "control": {"end_time": 1e-6},
        "equations_of_state": {"tnt": JWL.model_dump()},
        "materials": {"tnt": TNT.model_dump(), "void": {"type": "void"}},
        "sections": {"f": {"type": "ale_multi_material"}},
        "parts": {"t": {"material": "void", "section": "f",
                        "geometry": {"box": {"min": [0.0, 0.0], "max": [0.01, 0.01], "element_size": 0.001}},
                        "fill": [{"material": "tnt", "ball": {"center": [0.005, 0.005], "radius": 0.003}}]}},
        "detonations": [{"point": [0.005, 0.005]}],
    }
    deck = Deck.model_validate(base)
    assert deck.detonations[0].time == 0.0
    bad = dict(base, detonations=[{"point": [0.0, 0.0, 0.0]}])
    with pytest.raises(Exception, match="expected 2 values"):
        Deck.model_validate(bad)
