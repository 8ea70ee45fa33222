"""Issue 12's last two SPH wall candidates (docs/studies/structure_in_water.md, "mDBC's velocity and a first-order
pressure gradient"), study code in docs/studies, checked on test_sph_boundary.py's plate in a lattice of water at rest
(plate 20 x 10 mm, dx 5 mm, cubic spline h/dx 1.2, 1 MPa ambient):

- structure_in_water_mdbc_velocity.py: the fluid's velocity at mDBC's ghost nodes solves the same first-order system
  as the density, so for a linear velocity field it is exact at every ghost, those mirrored through the plate's four
  convex corners included, and the boundary particles take 2 v_wall - v(x_g) (no-slip) or v(x_g) with its normal
  part relative to the wall reversed (slip) to round-off;
- structure_in_water_kgc.py: the correction matrix L_i = M_i^-T of every water point that sees the plate makes
  sum_j V_j (f_j - f_i) L_i grad_i W_ij (water and boundary particles, a corner's coincident group counted once)
  exact for a linear f, and the corrected pair terms it adds conserve the momentum of water + boundary particles and
  the pair energy (work of the added forces + the water's added internal energy + the boundary's half of its pairs'
  work = 0) to round-off.
"""
from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

from sphfem_cli.driver import load_model
from sphfem_cli.solver.explicit import Simulation
from sphfem_cli.sph import structure_walls as sw
from sphfem_cli.sph.kernel_functions import kernel_f
from sphfem_cli.sph.slots import SI_KERNEL

from test_sph_boundary import AT_REST

# study code, not shipped, and about 50 s of CPU (its own kernels compiled): behind -m validation (README)
pytestmark = pytest.mark.validation

# the study modules imported by name from docs/studies (numba's cache needs a module it can find again)
sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "docs" / "studies"))
import structure_in_water_kgc as kgc  # noqa: E402
import structure_in_water_mdbc_velocity as mvel  # noqa: E402


def _ready(tmp_path, extrapolation: str, v_field=None, rho_field=None):
    deck = tmp_path / "deck.yaml"
    deck.write_text(AT_REST.replace("fluid: water}", f"fluid: water, extrapolation: {extrapolation}}}"))
    sim = Simulation(load_model(str(deck)).model)
    ps, coupling = sim.particles.system, sim.interactions[0]
    if v_field is not None:
        ps.v[:, :2] = v_field(ps.x[:, :2])
    if rho_field is not None:
        ps.rho[:] = rho_field(ps.x[:, :2])
    ps.compute_rates()
    coupling.forces(sim.state)  # places the boundary particles, their density and pressure, the plain wall pairs
    pts = ps._sorted
    mine = np.zeros(pts["sx"].shape[1], dtype=np.bool_)  # as the coupling builds it: every particle is its water
    mine[np.flatnonzero(pts["perm"] < ps.n)] = True
    return sim, ps, coupling, pts, mine


def _linear_v(x: np.ndarray) -> np.ndarray:
    """A linear velocity field, m/s (x in m)."""
    return np.stack([0.3 + 20.0 * (x[:, 0] - 0.05) - 10.0 * (x[:, 1] - 0.05),
                     -0.2 + 5.0 * (x[:, 0] - 0.05) + 30.0 * (x[:, 1] - 0.05)], axis=1)


@pytest.mark.parametrize("mode", ["no_slip", "slip"])
def test_ghost_velocity_exact_for_linear_field(tmp_path, mode):
    sim, ps, coupling, pts, mine = _ready(tmp_path, "mdbc", v_field=_linear_v)
    ws = coupling.ws
    wall = ws[:, [sw.W_VX, sw.W_VY]].copy()
    assert np.all(wall == 0.0)  # the plate at rest
    order = np.zeros(len(ws), dtype=np.int64)
    mvel.ghost_velocity(ws, coupling.side2, pts["sx"], pts["sd"], mine, pts["cell_start"], ps.settings_i,
                        pts["grid_f"], pts["grid_i"], mvel.MODES[mode], order)
    assert np.all(order == 1)  # every ghost's system regular: the first-order value everywhere
    vg = _linear_v(ws[:, [sw.W_GX, sw.W_GY]])
    if mode == "no_slip":
        expected = 2.0 * wall - vg
    else:
        n = ws[:, [sw.W_NX, sw.W_NY]]
        expected = vg - 2.0 * np.sum(vg * n, axis=1)[:, None] * n
    assert (coupling.vertex >= 0).sum() > 8  # the corners' vertex ghosts are among them
    np.testing.assert_allclose(ws[:, [sw.W_VX, sw.W_VY]], expected, rtol=0.0, atol=1e-12)


def _sum_gradient(ps, pts, coupling, lmat, k, f_fluid_slots, f_wall):
    """sum_j V_j (f_j - f_k) L_k grad_k W_kj over the water slots and the boundary particles the slot k sees."""
    sx, sd = pts["sx"], pts["sd"]
    kernel = int(ps.settings_i[SI_KERNEL])
    xi, hi = sx[:2, k], sx[3, k]
    total = np.zeros(2)
    water = np.flatnonzero(pts["perm"] < ps.n)
    for j in water:
        d = xi - sx[:2, j]
        r, hij = np.linalg.norm(d), 0.5 * (hi + sx[3, j])
        if j == k or r >= 2.0 * hij:
            continue
        total += sd[4, j] * (f_fluid_slots[j] - f_fluid_slots[k]) * kernel_f(kernel, 2, r, hij) * d
    ws = coupling.ws
    for w in range(len(ws)):
        if not sw._on_side(ws, w, xi[0], xi[1], 0.0):
            continue
        d = xi - ws[w, [sw.W_X, sw.W_Y]]
        r, hij = np.linalg.norm(d), 0.5 * (hi + ws[w, sw.W_H])
        if r >= 2.0 * hij:
            continue
        vol = ws[w, sw.W_M] / ws[w, sw.W_RHO] * kgc._seen(ws, coupling.twins, w, xi[0], xi[1])
        total += vol * (f_wall[w] - f_fluid_slots[k]) * kernel_f(kernel, 2, r, hij) * d
    return (lmat[k] + np.eye(2)) @ total


@pytest.mark.parametrize("everywhere", [False, True])
def test_kgc_gradient_exact_for_linear_field(tmp_path, everywhere):
    sim, ps, coupling, pts, mine = _ready(tmp_path, "adami")
    lmat = np.zeros((pts["sx"].shape[1], 2, 2))
    count, fallback = kgc.correction_matrices(coupling.ws, coupling.twins, pts["sx"], pts["sd"], mine,
                                              pts["cell_start"], ps.settings_i, pts["grid_f"], pts["grid_i"], lmat,
                                              everywhere)
    if everywhere:  # every water point; those at the blob's free edges (a truncated support) keep L = I
        assert count == ps.n and 0 < fallback < count - 36, (count, fallback)
    else:  # the two layers round the plate (12 + 12 + 4 x 3), all with full supports
        assert count == 36 and fallback == 0, (count, fallback)
    grad = np.array([3.0e5, -7.0e5])  # f = 1e6 + grad . x
    f_slots = 1.0e6 + pts["sx"][:2].T @ grad
    f_wall = 1.0e6 + coupling.ws[:, [sw.W_X, sw.W_Y]] @ grad
    flagged = np.flatnonzero(np.abs(lmat).sum(axis=(1, 2)) > 0.0)
    corrections = [np.abs(lmat[k]).max() for k in flagged]
    assert max(corrections) > 1e-2  # the plate's corners: the boundary's lattice is not the water's there
    for k in flagged:
        np.testing.assert_allclose(_sum_gradient(ps, pts, coupling, lmat, k, f_slots, f_wall), grad, rtol=1e-10)


@pytest.mark.parametrize("walls", [True, False])
def test_kgc_pairs_conserve_momentum_and_energy(tmp_path, walls):
    rng = np.random.default_rng(3)

    def rho(x):  # densities (so pressures) varying from particle to particle
        return 1000.0 * (1.0 + 2e-4 * rng.standard_normal(len(x)))

    def vel(x):
        return rng.standard_normal((len(x), 2))

    sim, ps, coupling, pts, mine = _ready(tmp_path, "adami", v_field=vel, rho_field=rho)
    ws = coupling.ws
    ws[:, [sw.W_VX, sw.W_VY]] = rng.standard_normal((len(ws), 2))  # a moving wall
    lmat = np.zeros((pts["sx"].shape[1], 2, 2))
    kgc.correction_matrices(ws, coupling.twins, pts["sx"], pts["sd"], mine, pts["cell_start"], ps.settings_i,
                            pts["grid_f"], pts["grid_i"], lmat)
    acc, f_fluid = np.zeros((ps.n, 2)), np.zeros((ps.n, 2))
    drho, de, f_wall = np.zeros(ps.n), np.zeros(ps.n), np.zeros((len(ws), 3))
    power = kgc.add_correction(ws, coupling.twins, pts["sx"], pts["sd"], mine, pts["perm"], pts["cell_start"],
                               ps.settings_i, pts["grid_f"], pts["grid_i"], lmat, acc, f_fluid, drho, de, f_wall, walls)
    m = ps.m[:, None]
    force = m * acc + f_fluid
    scale = np.abs(force).sum()
    assert scale > 0.0
    np.testing.assert_allclose(force.sum(axis=0) + f_wall[:, :2].sum(axis=0), 0.0, atol=1e-12 * scale)
    v = ps.v[:, :2]
    work = np.sum(force * v) + np.sum(f_wall[:, :2] * ws[:, [sw.W_VX, sw.W_VY]])
    heat = np.sum(ps.m * de)
    # a water pair's work goes to the two points' internal energy; of a boundary pair's the water keeps half (its de,
    # summed in ``power``) and the boundary absorbs the other half, as in wall_pairs (booked as contact energy)
    if walls:
        assert abs(power) > 0.0
    else:  # the boundary pairs keep the plain gradient: nothing on the boundary particles
        assert power == 0.0 and not f_wall.any() and not f_fluid.any()
    assert abs(work + heat + power) < 1e-12 * np.sum(np.abs(force * v)), (work, heat, power)
