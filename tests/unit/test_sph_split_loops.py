"""The split (vectorised) particle loops of the SPH step give the general loops' results bit for bit.

``eos._tait_state`` (one Tait material, 2D), ``integration._stable_time_step_2d`` and
``integration._advance_particles_2d`` (2D) compute the same operations in the same order as the
general loops, split into loops without calls or reductions (the first two vectorised by LLVM;
issue 17). Each test runs both on the same
state, among them inactive particles, NaN and inf entries, external forces, wall crossings and
particles leaving the domain, and asserts equality of every value and of the sign of every zero
(tolerance 0: observed 0 in every entry).
"""
from __future__ import annotations

import numpy as np
import pytest

from sphfem_cli.materials.slots import P_VISCOSITY
from sphfem_cli.sph import eos, integration, scenes

STATE = ("x", "v", "v_half", "rho", "rho_half", "e", "e_half", "acc", "drho", "de", "xsph", "f_ext", "m", "active")


def same_bits(a, b) -> bool:
    a, b = np.asarray(a), np.asarray(b)
    return bool(np.array_equal(a, b, equal_nan=True) and np.array_equal(np.signbit(a), np.signbit(b)))


@pytest.fixture(scope="module")
def dam():
    """A small 2D dam break after a few steps (ghost walls, gravity, domain box)."""
    ps = scenes.dam_break(a=1.0, dx=1.0 / 16, dim=2)
    for _ in range(3):
        ps.advance(0.9)
    ps.compute_rates()
    return ps


def perturbed(ps, seed, edge):
    """Copies of the particle state: jittered, 10 % inactive, external forces; ``edge`` adds NaN/inf entries."""
    rng = np.random.default_rng(seed)
    st = {k: getattr(ps, k).copy() for k in STATE}
    st["v"] += rng.normal(0.0, 30.0, st["v"].shape)  # some cross the walls or leave the domain in one step
    st["rho"] *= 1.0 + rng.normal(0.0, 0.01, ps.n)
    st["f_ext"] = rng.normal(0.0, 1.0, st["f_ext"].shape)
    st["xsph"] = rng.normal(0.0, 1e-3, st["xsph"].shape)
    st["active"] &= rng.random(ps.n) > 0.1
    st["x"][17] = ps._dom_hi[:2] + 0.5  # outside the domain box: deactivated by the step
    st["active"][17] = True
    if edge:
        st["v"][3] = np.nan
        st["acc"][5] = np.inf
        st["rho"][7] = np.nan
        st["drho"][9] = -np.inf
        st["v"][11] = 0.0
    return st


@pytest.mark.parametrize("seed,edge", [(0, False), (1, True)])
def test_tait_state_is_the_general_loop(dam, seed, edge):
    st = perturbed(dam, seed, edge)
    two = np.vstack([dam.params, dam.params])  # two rows: the general loop
    rng = np.random.default_rng(seed + 10)
    init = [rng.normal(0.0, 1.0, dam.n) for _ in range(3)]  # the inactive particles keep these
    out = []
    for params in (dam.params, two):
        p, c, h = (q.copy() for q in init)
        hmax = eos.update_particle_state(st["rho"], st["e"], st["m"], dam.mat, st["active"], params, 1.2, 2,
                                         0.0 if edge else -np.inf, p, c, h)
        out.append((hmax, p, c, h))
    for a, b in zip(out[0], out[1]):
        assert same_bits(a, b)


@pytest.mark.parametrize("seed,edge", [(0, False), (1, True)])
@pytest.mark.parametrize("viscous", [False, True])
def test_stable_time_step_2d_is_the_general_loop(dam, seed, edge, viscous):
    st = perturbed(dam, seed, edge)
    params = dam.params.copy()
    params[0, P_VISCOSITY] = 1e-3 if viscous else 0.0
    h, c = dam.h.copy(), dam.c.copy()
    if edge:
        h[13] = np.nan
        c[15] = -1e6  # c + |v| < 0: skipped
    dts = [integration.stable_time_step(h, c, st["v"], st["acc"], st["f_ext"], st["m"], st["rho"], dam.mat,
                                        st["active"], params, dam.gravity, 0.25, 0.25, 0.125, work)
           for work in (np.empty((3, dam.n)), np.zeros((0, 0)))]
    assert same_bits(dts[0], dts[1])
    assert (dts[0] == 0.0) if edge else (np.isfinite(dts[0]) and dts[0] > 0.0)  # edge: |a| = inf gives 0


@pytest.mark.parametrize("seed,edge", [(0, False), (1, True), (2, False)])
@pytest.mark.parametrize("dt_prev", [0.0, 1.5e-3])
def test_advance_particles_2d_is_the_general_loop(dam, seed, edge, dt_prev):
    runs = []
    for work in (np.empty(dam.n), np.zeros(0)):
        st = perturbed(dam, seed, edge)
        sums = integration.advance_particles(
            st["x"], st["v"], st["v_half"], st["rho"], st["rho_half"], st["e"], st["e_half"], st["acc"], st["drho"],
            st["de"], st["xsph"], st["f_ext"], st["m"], st["active"], dam.gravity, 2e-3, dt_prev, dam.walls,
            dam._dom_lo, dam._dom_hi, dam._use_domain, work)
        runs.append((sums, st))
    (s0, a), (s1, b) = runs
    assert s0[1] > 0 and s0[2] > 0  # some particles were mirrored back at a wall, some left the domain
    for k in STATE:
        assert same_bits(a[k], b[k]), k
    for u, w in zip(s0, s1):
        assert same_bits(u, w)
