"""``sph_boundary``'s ``extrapolation: mdbc`` (sph/structure_walls.py ``wall_state_mdbc``, English et al. 2022):
the boundary particles' density extrapolated to first order from ghost nodes mirrored through the plate's faces, or
through its convex vertices for the particles behind a corner.

- a lattice of water at rest round a plate 20 x 10 mm with a uniform density and with a linear density field: the
  first-order system reproduces a linear field exactly (Taylor's expansion is exact for it), so every boundary
  particle, those mirrored through the plate's four convex corners included, takes the field's value at its own
  position to round-off, and (linear EOS) the pressure there; the Adami default (a Shepard mean of the one-sided
  fluid) does not, which shows the test discriminates;
- the free plate moving through water (tests/unit/test_sph_boundary.py's scene) with mdbc: fluid + plate momentum is
  conserved to round-off and the energy table closes.
"""
from __future__ import annotations

import numpy as np
import pytest

from sphfem_cli.driver import load_model
from sphfem_cli.solver.explicit import Simulation
from sphfem_cli.sph.structure_walls import W_GX, W_GY, W_P, W_RHO, W_X, W_Y

from test_sph_boundary import AT_REST, FREE_PLATE, _momentum

RHO0, C0, C1 = 1000.0, 1.0e6, 2.2e9  # the decks' water: linear_polynomial p = C0 + C1 (rho / rho0 - 1)


def _sim(tmp_path, text: str, extrapolation: str) -> Simulation:
    deck = tmp_path / "deck.yaml"
    deck.write_text(text.replace("fluid: water}", f"fluid: water, extrapolation: {extrapolation}}}"))
    return Simulation(load_model(str(deck)).model)


def _density(x: np.ndarray, kind: str) -> np.ndarray:
    """The imposed field: uniform 1.0005 rho0, or linear with 0.004 / 0.006 % of rho0 per 10 mm in x / y (the
    pressure 1.1-3.3 MPa over the 100 mm box, above the cut-off everywhere)."""
    if kind == "uniform":
        return np.full(len(x), 1.0005 * RHO0)
    return RHO0 * (1.0005 + 0.004 * (x[:, 0] - 0.05) + 0.006 * (x[:, 1] - 0.05))


def _extrapolate(tmp_path, extrapolation: str, kind: str):
    sim = _sim(tmp_path, AT_REST, extrapolation)
    ps, coupling = sim.particles.system, sim.interactions[0]
    ps.rho[:] = _density(ps.x[:, :2], kind)
    ps.compute_rates()  # the sorted point set with these densities
    coupling.forces(sim.state)
    return coupling


@pytest.mark.parametrize("kind", ["uniform", "linear"])
def test_mdbc_reproduces_linear_density_at_boundary_particles(tmp_path, kind):
    coupling = _extrapolate(tmp_path, "mdbc", kind)
    ws = coupling.ws
    xw = ws[:, [W_X, W_Y]]
    corner = coupling.vertex >= 0
    # the four convex corners' squares: every particle that coincides with another face's is mirrored through its
    # nearest corner (the plate is 2 particles thick and 4 long, so the squares of 3 layers cover most of it)
    twins = np.array([(coupling._coincident(coupling.particles())[w] >= 0).any() for w in range(len(ws))])
    assert corner.sum() > 8 and np.array_equal(corner, twins), (corner.sum(), twins.sum())
    ghost = ws[:, [W_GX, W_GY]]
    outside = (ghost[:, 0] < 0.04) | (ghost[:, 0] > 0.06) | (ghost[:, 1] < 0.045) | (ghost[:, 1] > 0.055)
    assert outside.all()  # every ghost node lies in the water
    diagonal = ((ghost[corner, 0] < 0.04) | (ghost[corner, 0] > 0.06)) & (
        (ghost[corner, 1] < 0.045) | (ghost[corner, 1] > 0.055))
    assert diagonal.all()  # the vertex ghosts lie in the quadrant diagonal to their corner
    assert np.all(coupling.mdbc_order == 1)  # every particle's system was regular (no Shepard fallback)
    exact = _density(xw, kind)
    np.testing.assert_allclose(ws[:, W_RHO], exact, rtol=1e-12, atol=0.0)
    np.testing.assert_allclose(ws[:, W_P], C0 + C1 * (exact / RHO0 - 1.0), rtol=1e-9, atol=0.0)


def test_adami_does_not_reproduce_linear_density(tmp_path):
    """The control: the Adami pressure (g = 0: the Shepard mean of the one-sided fluid's pressure) of the same
    particles misses the linear field by about its change over two spacings (measured: 132 kPa at most, the
    field's change over 10 mm in y; mdbc: 2e-6 Pa), far above round-off."""
    coupling = _extrapolate(tmp_path, "adami", "linear")
    ws = coupling.ws
    exact = C0 + C1 * (_density(ws[:, [W_X, W_Y]], "linear") / RHO0 - 1.0)
    seen = ws[:, W_P] != 0.0
    error = np.abs(ws[seen, W_P] - exact[seen]).max()
    assert error > 0.1 * C1 * 0.006 * 0.01, error  # a tenth of the pressure's change over 10 mm in y


def test_free_plate_conserves_momentum_with_mdbc(tmp_path):
    sim = _sim(tmp_path, FREE_PLATE, "mdbc")
    p0 = _momentum(sim)
    for _ in range(40):
        sim.step()
    assert np.abs(sim.state.v).max() > 0.05
    np.testing.assert_allclose(_momentum(sim), p0, rtol=0.0, atol=1e-12 * np.linalg.norm(p0))
    row = sim.energy_row()
    assert abs(row.ratio - 1.0) < 1e-3, row
