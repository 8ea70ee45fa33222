"""The solver's time step against the true stability limit of the discrete system.

Central differences are stable for dt <= 2 / omega_max, omega_max the highest natural frequency
of the lumped-mass, one-point-element system (e.g. Belytschko, Liu & Moran, Nonlinear Finite
Elements for Continua and Structures, 2000, sec. 6.3). Here omega_max is computed exactly: the
stiffness is assembled column by column from the element kernel itself (finite differences of
the internal force for tiny velocities over a unit step), then the largest eigenvalue of
M^-1/2 K M^-1/2. The solver's first step (timestep_scale 0.9, element length V / largest face)
must not exceed 2 / omega_max.

Found by these tests (reported to the lead): the element length V / largest face, as in LS-DYNA,
gives the exact limit for elements surrounded by others, but not where an element can dilate
freely. An isolated hex8 has omega_max^2 = 8 (3 lambda + 2 mu) / (2 rho h^2), not
4 (lambda + 2 mu) / (rho h^2): its limit is 0.734 h/c at nu = 0.3 (quad4: 0.837 h/c). Meshes one
element thick in 3D inherit part of this: a 1 x 1 cross-section bar needs timestep_scale <= 0.81,
a plate one element thick <= 0.90, so at the default 0.9 they blow up (a 1 x 1 bar struck at
10 m/s inverts an element within 20 steps). The step now accounts for it: an element free to
dilate along k of its directions (both opposite faces exterior) takes sqrt((lambda + 2 mu) /
(k lambda + 2 mu)) of the usual step (model.build.free_dilatation_factor), the one-point element's
dilatation mode with lumped mass; these cases pass. Plane-stress quad4 (wave speed sqrt(E/((1 - nu^2) rho)),
lambda_bar = E nu/(1 - nu^2) in the factor) are checked the same way.
"""
from __future__ import annotations

import numpy as np
import pytest

from conftest import load_deck
from sphfem_cli.fem import kernels as fem
from sphfem_cli.materials.slots import NHIST
from sphfem_cli.solver.explicit import Simulation

pytestmark = pytest.mark.usefixtures("single_thread")

E, NU, RHO = 2.0e11, 0.3, 7850.0

def internal_force(model, x, v):
    """Nodal internal force after one unit step from a stress-free state, x = X + v."""
    n_elem, npe = model.connectivity.shape
    dim = model.dim
    f_elem = np.zeros((n_elem, npe, dim))
    fem.solid_element_forces(
        x, v, model.connectivity, model.element_active, model.element_material, model.element_section,
        model.material_type, model.material_param, model.section_param, model.volume0, 1.0,
        np.zeros((n_elem, 6)), np.zeros((n_elem, NHIST)), np.zeros(n_elem), np.zeros(n_elem),
        np.zeros((n_elem, 1 if dim == 2 else 4, dim)), f_elem, np.zeros(n_elem), np.zeros(n_elem),
        np.zeros(n_elem),
    )
    f = np.zeros_like(x)
    np.add.at(f, model.connectivity, f_elem)
    return f


def omega_max(model) -> float:
    X = model.coordinates
    n = X.size
    h = 1e-9 * np.abs(X).max()
    K = np.empty((n, n))
    for j in range(n):
        v = np.zeros(n)
        v[j] = h
        v = v.reshape(X.shape)
        K[:, j] = -internal_force(model, X + v, v).ravel() / h
    s = 1.0 / np.sqrt(np.repeat(model.mass, model.dim))
    A = s[:, None] * K * s[None, :]
    return float(np.sqrt(np.linalg.eigvalsh(0.5 * (A + A.T)).max()))


def deck(divisions: list[int], formulation: str = "plane_strain") -> str:
    dim = len(divisions)
    size = [0.01 * d for d in divisions]
    return f"""
dimension: {dim}
control: {{end_time: 1.0}}
materials:
  steel: {{type: elastic, density: {RHO}, youngs_modulus: {E}, poisson_ratio: {NU}}}
sections:
  solid: {{type: solid, formulation: {formulation}, hourglass: {{type: viscous, coefficient: 0.0}}}}
parts:
  block: {{material: steel, section: solid,
           geometry: {{box: {{min: {[0.0] * dim}, max: {size}, divisions: {divisions}}}}}}}
"""


@pytest.mark.parametrize("divisions", [
    [6, 6],
    [12, 1],
    [8, 2, 2],
    [3, 3, 3],
    [1, 1],
    [1, 1, 1],
    [12, 1, 1],
    [6, 4, 1],
], ids=lambda d: "x".join(map(str, d)))
def test_first_step_within_stability_limit(divisions, tmp_path):
    model = load_deck(tmp_path, deck(divisions))
    dt = Simulation(model).state.dt
    dt_crit = 2.0 / omega_max(model)
    print(f"\n{'x'.join(map(str, divisions))}: solver dt / critical dt = {dt / dt_crit:.3f} "
          f"(the critical timestep_scale is {0.9 * dt_crit / dt:.3f})")
    assert dt <= dt_crit


@pytest.mark.parametrize("divisions", [[6, 6], [12, 1], [1, 1]], ids=lambda d: "x".join(map(str, d)))
def test_plane_stress_first_step_within_stability_limit(divisions, tmp_path):
    model = load_deck(tmp_path, deck(divisions, "plane_stress"))
    dt = Simulation(model).state.dt
    dt_crit = 2.0 / omega_max(model)
    print(f"\nplane stress {'x'.join(map(str, divisions))}: solver dt / critical dt = {dt / dt_crit:.3f}")
    assert dt <= dt_crit
