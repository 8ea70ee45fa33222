"""Patch test of the one-point quad4 / hex8 elements on distorted meshes.

A linear velocity field v = L x + c must give every element, whatever its shape, the exact
velocity gradient, hence one and the same stress; a uniform stress must then be self-equilibrated,
so the internal force vanishes at every interior node; and the Flanagan-Belytschko hourglass
shape vectors are orthogonal to linear fields, so the hourglass forces vanish too (Irons & Razzaque
1972 for the patch test; Flanagan & Belytschko 1981, Int. J. Numer. Meth. Eng. 17, 679-706,
eqs. 12-18 and 45-52 for the mean gradient and the hourglass vectors).

Tolerance 1e-10 relative: everything here is exact up to round-off.
"""
from __future__ import annotations

import numpy as np
import pytest

from conftest import load_deck
from sphfem_cli.deck.schema.materials import Elastic
from sphfem_cli.fem import kernels as fem
from sphfem_cli.fem.geometry import hex8_gradient, quad4_gradient
from sphfem_cli.materials.slots import NHIST
from sphfem_cli.materials.tables import pack_material
from sphfem_cli.model.mesh import box_mesh
from sphfem_cli.solver.explicit import Simulation

pytestmark = pytest.mark.usefixtures("single_thread")

RTOL = 1e-10
E, NU, RHO = 2.0e11, 0.3, 7850.0
LAM = E * NU / ((1 + NU) * (1 - 2 * NU))
G = E / (2 * (1 + NU))


def distorted_patch(dim: int, n: int, seed: int):
    """An n^dim patch of unit cells with every node moved by up to 0.2 cell in each direction.

    Returns nodes, connectivity and the mask of interior nodes. Boundary nodes move too, so the
    hex8 faces are warped: the test is then stricter than with flat faces.
    """
    mesh = box_mesh([0.0] * dim, [float(n)] * dim, divisions=n)
    rng = np.random.default_rng(seed)
    x = mesh.nodes + rng.uniform(-0.2, 0.2, mesh.nodes.shape)
    grid = np.rint(mesh.nodes).astype(int)
    interior = np.all((grid > 0) & (grid < n), axis=1)
    return x, mesh.elements, interior


def gradient_and_pre_stress(dim: int, seed: int):
    rng = np.random.default_rng(seed)
    L = rng.uniform(-1.0, 1.0, (dim, dim))  # [1/s]
    c = rng.uniform(-1.0, 1.0, dim)  # [m/s]
    s0 = rng.uniform(-1e8, 1e8, 6)  # [Pa], xx yy zz xy yz zx
    if dim == 2:
        s0[4:] = 0.0
    return L, c, s0


def tensor(s):
    return np.array([[s[0], s[3], s[5]], [s[3], s[1], s[4]], [s[5], s[4], s[2]]])


def exact_stress(L, dt, s0):
    """Stress after one step of the hypoelastic Jaumann update driven by v = L X + c.

    The element kernel differentiates at the mid-step configuration x^{n+1/2} = (I + dt/2 L) X + ...,
    where the same field has the gradient Lm = L (I + dt/2 L)^-1. With D, W its symmetric and skew
    parts: sigma = R s0 R^T + lambda tr(D dt) I + 2 G D dt, R = (I - dt/2 W)^-1 (I + dt/2 W)
    (Hughes & Winget 1980).
    """
    dim = L.shape[0]
    Lm = np.zeros((3, 3))
    Lm[:dim, :dim] = L @ np.linalg.inv(np.eye(dim) + 0.5 * dt * L)
    D = 0.5 * (Lm + Lm.T)
    W = 0.5 * (Lm - Lm.T)
    S = 0.5 * dt * W
    R = np.linalg.solve(np.eye(3) - S, np.eye(3) + S)
    sig = R @ tensor(s0) @ R.T + LAM * np.trace(D) * dt * np.eye(3) + 2 * G * D * dt
    return np.array([sig[0, 0], sig[1, 1], sig[2, 2], sig[0, 1], sig[1, 2], sig[2, 0]])


def element_pass(x, v, conn, dt, s0, hg_type, hg_coef):
    """One call of the element kernel on a single-material patch; returns stress, element forces,
    hourglass resultants and hourglass energy."""
    n_elem, npe = conn.shape
    dim = x.shape[1]
    mtype, row = pack_material(Elastic(type="elastic", density=RHO, youngs_modulus=E, poisson_ratio=NU))
    # Bulk viscosity off: q is an artificial viscous pressure scaled by each element's own length,
    # so by design it is not uniform over a distorted patch.
    sec = np.zeros((1, fem.NSEC))
    sec[0, fem.SEC_HG_TYPE], sec[0, fem.SEC_HG_COEF] = hg_type, hg_coef
    stress = np.tile(s0, (n_elem, 1))
    hist = np.zeros((n_elem, NHIST))
    energy = np.zeros(n_elem)
    hg_energy = np.zeros(n_elem)
    hg_force = np.zeros((n_elem, 1 if dim == 2 else 4, dim))
    f_elem = np.zeros((n_elem, npe, dim))
    dt_elem = np.zeros(n_elem)
    vol = np.zeros(n_elem)
    q = np.zeros(n_elem)
    x0 = x - dt * v
    b = np.empty((dim, npe))
    grad = quad4_gradient if dim == 2 else hex8_gradient
    vol0 = np.array([grad(np.ascontiguousarray(x0[c]), b) for c in conn])
    fem.solid_element_forces(
        x, v, conn, np.ones(n_elem, dtype=np.bool_), np.zeros(n_elem, dtype=np.int64),
        np.zeros(n_elem, dtype=np.int64), np.array([mtype]), row[None, :], sec, vol0, dt,
        stress, hist, energy, hg_energy, hg_force, f_elem, dt_elem, vol, q,
    )
    assert np.all(dt_elem > 0.0)
    return stress, f_elem, hg_force, hg_energy


def nodal(f_elem, conn, n_nodes):
    out = np.zeros((n_nodes, f_elem.shape[2]))
    np.add.at(out, conn, f_elem)
    return out


@pytest.mark.parametrize("dim, n", [(2, 3), (3, 3)], ids=["quad4", "hex8"])
@pytest.mark.parametrize("hg", [(fem.HG_VISCOUS, 0.1), (fem.HG_STIFFNESS, 0.1)], ids=["viscous", "stiffness"])
def test_linear_field_gives_exact_uniform_stress(dim, n, hg):
    X, conn, interior = distorted_patch(dim, n, seed=dim)
    L, c, s0 = gradient_and_pre_stress(dim, seed=10 + dim)
    dt = 1e-3
    v = X @ L.T + c  # v = L X + c at every node; x^{n+1} = X + dt v
    x = X + dt * v

    stress, f_elem, hg_force, hg_energy = element_pass(x, v, conn, dt, s0, *hg)
    expected = exact_stress(L, dt, s0)
    scale = np.abs(expected).max()
    f = nodal(f_elem, conn, len(x))
    print(f"\n{dim}D patch: stress error {np.abs(stress - expected).max() / scale:.1e}, interior force "
          f"{np.linalg.norm(f[interior], axis=1).max() / np.linalg.norm(f[~interior], axis=1).max():.1e} "
          f"of the boundary forces")
    # Every element, however distorted, has the exact stress.
    assert np.abs(stress - expected).max() <= RTOL * scale

    # Hourglass forces vanish for a linear field: identical forces with and without control.
    _, f_plain, _, _ = element_pass(x, v, conn, dt, s0, hg[0], 0.0)
    f_scale = np.abs(f_plain).max()
    assert np.abs(f_elem - f_plain).max() <= RTOL * f_scale
    assert np.abs(hg_force).max() <= RTOL * scale
    assert np.abs(hg_energy).max() <= RTOL * scale * dt

    # A uniform stress is self-equilibrated: no internal force at interior nodes.
    f = nodal(f_elem, conn, len(x))
    boundary_scale = np.linalg.norm(f[~interior], axis=1).max()
    assert interior.sum() >= 4
    assert np.linalg.norm(f[interior], axis=1).max() <= RTOL * boundary_scale


@pytest.mark.parametrize("dim, n", [(2, 3), (3, 2)], ids=["quad4", "hex8"])
def test_patch_through_the_solver(dim, n, tmp_path):
    """The same patch, read from a mesh file through a deck and run by the explicit solver.

    The boundary nodes are driven with v = L X (constant in time, so x(t) = (I + t L) X stays a
    linear map of X); the interior nodes start on the same field and are free. If the interior
    forces vanish exactly, they stay on the linear field: after 50 steps their velocities must
    still be L X, every element must carry the same stress, and no hourglass energy may appear.
    """
    import meshio

    X, conn, interior = distorted_patch(dim, n, seed=20 + dim)
    points = X if dim == 3 else np.column_stack([X, np.zeros(len(X))])
    meshio.write(tmp_path / "patch.vtu", meshio.Mesh(points, [("quad" if dim == 2 else "hexahedron", conn)]))
    deck = f"""
title: distorted patch
dimension: {dim}
control: {{end_time: 1.0}}
materials:
  steel: {{type: elastic, density: {RHO}, youngs_modulus: {E}, poisson_ratio: {NU}}}
sections:
  solid: {{type: solid, hourglass: {{type: stiffness, coefficient: 0.1}},
           bulk_viscosity: {{q1: 0.0, q2: 0.0}}}}
parts:
  patch: {{material: steel, section: solid, geometry: {{file: {{file: patch.vtu}}}}}}
"""
    model = load_deck(tmp_path, deck)
    assert np.allclose(model.coordinates, X)
    sim = Simulation(model)
    L, _, _ = gradient_and_pre_stress(dim, seed=30 + dim)
    v_exact = X @ L.T
    sim.state.v[:] = v_exact
    sim.constraints.free[~interior] = False
    sim.constraints.v_prescribed[~interior] = v_exact[~interior]
    f_max = 0.0
    for _ in range(50):
        sim.step()
        f_max = max(f_max, np.linalg.norm(sim.state.f_int[~interior], axis=1).max())
    st = sim.state
    f_interior = np.linalg.norm(st.f_int[interior], axis=1).max()
    assert f_interior <= RTOL * f_max
    assert np.abs(st.v[interior] - v_exact[interior]).max() <= RTOL * np.abs(v_exact).max()
    s_scale = np.abs(st.stress).max()
    assert s_scale > 1e5  # the patch is loaded (strain ~ t |L| ~ 1e-5 to 1e-4)
    assert np.abs(st.stress - st.stress.mean(axis=0)).max() <= RTOL * s_scale
    assert np.abs(st.hg_energy).max() <= RTOL * np.abs(st.energy).max()
