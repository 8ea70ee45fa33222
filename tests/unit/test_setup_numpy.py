"""The model set-up's numpy passes against the kernels they replaced (issue 17: no kernel to compile before the
first step): the same numbers bit for bit (np.array_equal), on small distorted meshes.

References: the former numba kernels, which meshes above 262144 quad4 still take (``ale.topology``'s face maps and
dual node lines, ``build_topology(kernel=True)``; ``ale.fill._quad_samples``), the quad4 sample points' loop run as
plain Python on scalars (``ale.fill``), the kernels' own Python bodies (``py_func``) of
``fem.geometry.hex8_gradient_rows`` (equal to ``hex8_gradient`` bit for bit, tests/unit/test_fem_kernels.py),
``fem.geometry.quad4_gradient`` and ``materials.kernels.eos_state``; the EOS is also checked against its compiled
kernel, the r-z ALE ring volumes against ``ale.axisymmetric.ring_volumes`` and the hydrostatic fill against its
former loop over elements with the compiled ``eos_pressure`` and ``eos_sound_speed``.
"""
from __future__ import annotations

import numpy as np
import pytest

from sphfem_cli.ale.fill import quad_sample_points
from sphfem_cli.ale.topology import build_topology
from sphfem_cli.model.mesh import hex8_volumes, ring_volumes


def _quad_mesh(nx=5, ny=4, seed=3):
    """A distorted nx x ny quad4 mesh, elements shuffled and each element's corner list rotated (still
    counter-clockwise): the maps must not lean on a structured numbering."""
    rng = np.random.default_rng(seed)
    gx, gy = np.meshgrid(np.linspace(0.0, 1.0, nx + 1), np.linspace(0.0, 0.8, ny + 1), indexing="ij")
    nodes = np.stack([gx.ravel(), gy.ravel()], axis=1) + rng.uniform(-0.03, 0.03, ((nx + 1) * (ny + 1), 2))
    nodes[:, 0] += 0.2  # x = r > 0 for the ring volumes
    node = np.arange((nx + 1) * (ny + 1)).reshape(nx + 1, ny + 1)
    conn = np.array([[node[i, j], node[i + 1, j], node[i + 1, j + 1], node[i, j + 1]]
                     for i in range(nx) for j in range(ny)], dtype=np.int64)
    conn = conn[rng.permutation(len(conn))]
    shift = rng.integers(0, 4, len(conn))
    return nodes, np.array([np.roll(c, -s) for c, s in zip(conn, shift)], dtype=np.int64)


@pytest.mark.parametrize("collapse", [False, True])
def test_quad_topology_maps_are_the_former_kernels(collapse):
    nodes, conn = _quad_mesh()
    if collapse:  # merge two corners of an element on the boundary: a triangle written as a quad, and its neighbours
        corner = conn[np.flatnonzero((conn == 0).any(axis=1))[0]]
        conn = np.where(conn == corner[(list(corner).index(0) + 1) % 4], 0, conn)
    topo = build_topology(conn, len(nodes))
    assert topo["node_line"].dtype == np.int32
    large = build_topology(conn, len(nodes), kernel=True)  # the former kernels, which large meshes still take
    for name, value in topo.items():
        for got, want in zip(large[name], value) if name == "faces_by_dir" else [(large[name], value)]:
            got, want = np.asarray(got), np.asarray(want)
            assert got.dtype == want.dtype and np.array_equal(got, want), name
    if not collapse:
        assert (topo["elem_nbr"] >= 0).sum() == 2 * (5 * 3 + 4 * 4)  # interior faces, each seen from both sides


def test_quad_topology_rejects_a_face_of_three_elements():
    conn = np.array([[0, 1, 2, 3], [1, 0, 4, 5], [0, 1, 6, 7]], dtype=np.int64)
    for kernel in (False, True):
        with pytest.raises(ValueError, match="more than two"):
            build_topology(conn, 8, kernel=kernel)


def test_quad_sample_points_are_the_former_kernel():
    nodes, conn = _quad_mesh()
    px, py, jac, jac_sum = quad_sample_points(nodes, conn, 3)
    t = (np.arange(3) + 0.5) / 3 * 2.0 - 1.0
    xi, eta = (g.ravel() for g in np.meshgrid(t, t, indexing="ij"))
    sn = np.array([[-1, -1], [1, -1], [1, 1], [-1, 1]], dtype=float)
    shape = 0.25 * (1 + np.outer(xi, sn[:, 0])) * (1 + np.outer(eta, sn[:, 1]))
    dxi = 0.25 * sn[:, 0][None, :] * (1 + np.outer(eta, sn[:, 1]))
    deta = 0.25 * sn[:, 1][None, :] * (1 + np.outer(xi, sn[:, 0]))
    for e in range(len(conn)):
        for s in range(9):
            xa, ya = nodes[conn[e], 0], nodes[conn[e], 1]
            x, y = shape[s, 0] * xa[0], shape[s, 0] * ya[0]
            x_xi, y_xi, x_eta, y_eta = dxi[s, 0] * xa[0], dxi[s, 0] * ya[0], deta[s, 0] * xa[0], deta[s, 0] * ya[0]
            for a in range(1, 4):
                x += shape[s, a] * xa[a]
                y += shape[s, a] * ya[a]
                x_xi += dxi[s, a] * xa[a]
                y_xi += dxi[s, a] * ya[a]
                x_eta += deta[s, a] * xa[a]
                y_eta += deta[s, a] * ya[a]
            assert (px[e, s], py[e, s], jac[e, s]) == (x, y, x_xi * y_eta - x_eta * y_xi)
    assert np.array_equal(jac_sum, jac.sum(axis=1))
    for got, ref in zip(quad_sample_points(nodes, conn, 3, kernel=True), (px, py, jac, jac_sum)):  # large meshes'
        assert np.array_equal(got, ref)


def test_ring_volumes_are_the_kernels():
    from sphfem_cli.fem.geometry import quad4_gradient

    nodes, conn = _quad_mesh()
    got = ring_volumes(nodes, conn)
    b = np.empty((2, 4))
    for e in range(len(conn)):
        xe = nodes[conn[e]]
        rc = 0.0
        for a in range(4):
            rc += 0.25 * xe[a, 0]
        assert got[e] == 2.0 * np.pi * rc * quad4_gradient.py_func(xe, b)


def test_hex8_volumes_are_the_kernels():
    from sphfem_cli.fem.geometry import hex8_gradient_rows

    rng = np.random.default_rng(7)
    cube = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1]], float)
    nodes = np.concatenate([cube * [0.3, 0.5, 0.7] + rng.uniform(-0.05, 0.05, (8, 3)) + 10.0 * i for i in range(12)])
    conn = np.arange(len(nodes), dtype=np.int64).reshape(-1, 8)
    got = hex8_volumes(nodes, conn)
    b = np.empty((3, 8))
    ref = np.array([hex8_gradient_rows.py_func(nodes[c], b) for c in conn])
    assert np.array_equal(got, ref)
    assert np.allclose(got, 0.3 * 0.5 * 0.7, rtol=0.3)  # a sanity check of the scale: boxes distorted by <= 0.05


@pytest.mark.parametrize("eos, q, states", [
    ("EOS_LINEAR_POLYNOMIAL", [1000.0, 0.0, 1.0, 0.0, 2.2e9, 9.5e9, 1.45e10, 0.28, 0.28, 0.0], [0.95, 1.0, 1.07]),
    ("EOS_GRUNEISEN", [2700.0, 0.0, 1.0, 5386.0, 1.339, 0.0, 0.0, 1.97, 0.48], [0.9, 1.0, 1.2]),
    ("EOS_TAIT", [1000.0, 0.0, 1.0, 1000.0, 30.0, 7.0, 1.0e5, 1000.0 * 30.0 ** 2 / 7.0], [0.99, 1.0, 1.013]),
    ("EOS_IDEAL_GAS", [1.2, 2.5e5, 1.0, 1.4], [0.5, 1.0, 3.0]),
    ("EOS_STIFFENED_GAS", [1000.0, 0.0, 1.0, 4.4, 6.0e8], [0.98, 1.0, 1.05]),
    ("EOS_JWL", [1630.0, 7.0e9, 1.0, 3.712e11, 3.231e9, 4.15, 0.95, 0.30], [0.4, 1.0, 1.3]),
])
def test_eos_at_set_up_is_the_kernel(eos, q, states):
    from sphfem_cli.materials import kernels as mk
    from sphfem_cli.materials.slots import NQ
    from sphfem_cli.materials.tables import eos_sound_speed_set_up, eos_state_set_up

    row = np.zeros(NQ)
    row[:len(q)] = q
    eos_id = getattr(mk, eos)
    for r in states:
        for e in (0.0, row[1], 3.0e5):
            assert eos_state_set_up(eos_id, row, r, e) == mk.eos_state(eos_id, row, r, e)
            assert eos_sound_speed_set_up(eos_id, row, r, e) == mk.eos_sound_speed(eos_id, row, r, e)


@pytest.mark.parametrize("npe", [4, 8])
def test_nodal_mass_at_set_up_is_the_kernel(npe):
    """``ale.system.node_sums_set_up`` (numpy, the ALE system's set-up) gives ``nodal_mass``'s bits: three
    materials of unrelated magnitudes on a shuffled mesh, nodes in up to four (quad4) or eight (hex8) elements."""
    from sphfem_cli.ale.remap_nodes import nodal_mass
    from sphfem_cli.ale.system import node_sums_set_up

    rng = np.random.default_rng(7)
    if npe == 4:
        _, conn = _quad_mesh()
    else:  # a 3 x 3 x 3 hex8 block, elements shuffled
        node = np.arange(64).reshape(4, 4, 4)
        conn = np.array([[node[i + a, j + b, k + c] for a, b, c in
                          ((0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1))]
                         for i in range(3) for j in range(3) for k in range(3)], dtype=np.int64)
        conn = conn[rng.permutation(len(conn))]
    n_nodes = int(conn.max()) + 1
    mass_m = rng.uniform(0.0, 1.0, (len(conn), 3)) * np.array([1e3, 1.0, 1e-9])
    mass_m[::5, 1] = 0.0
    topo = build_topology(conn, n_nodes) if npe == 4 else None
    if npe == 4:
        ptr, idx = topo["node_elem_ptr"], topo["node_elem_idx"]
    else:
        a = conn.ravel()
        idx = np.argsort(a, kind="stable").astype(np.int64)
        ptr = np.zeros(n_nodes + 1, dtype=np.int64)
        ptr[1:] = np.cumsum(np.bincount(a, minlength=n_nodes))
    kernel = np.empty(n_nodes)
    nodal_mass(mass_m, ptr, idx, npe, kernel)
    got = node_sums_set_up((1.0 / npe) * mass_m, ptr, idx, npe)
    assert np.array_equal(got.view(np.int64), kernel.view(np.int64))


def test_ale_ring_volumes_are_the_kernel():
    """``ale.system.ring_volumes_set_up`` (numpy, the r-z ALE system's initial volumes) gives the bits of the kernel
    ``ale.axisymmetric.ring_volumes`` (the exact ring volume (pi / 3) S), on the shuffled, rotated mesh, and near
    the axis (a column of nodes at r = 0: rings that touch it)."""
    from sphfem_cli.ale.axisymmetric import ring_volumes as ring_volumes_kernel
    from sphfem_cli.ale.system import ring_volumes_set_up

    nodes, conn = _quad_mesh()
    on_axis = nodes.copy()
    on_axis[:, 0] -= 0.2
    on_axis[on_axis[:, 0] < 0.05, 0] = 0.0  # the first column of nodes on the axis
    for x in (nodes, on_axis):
        kernel = np.empty(len(conn))
        ring_volumes_kernel(x, conn, kernel)
        got = ring_volumes_set_up(x, conn)
        assert np.array_equal(got.view(np.int64), kernel.view(np.int64))
    assert np.all(got > 0.0)


def _hydrostatic_loop(eos, q, rho0, p):
    """The former per-element Newton of ``model.ale_build.hydrostatic_fill`` with the compiled EOS kernels."""
    from sphfem_cli.materials.kernels import eos_pressure, eos_sound_speed
    from sphfem_cli.materials.slots import Q_E0

    out = np.empty(len(p))
    for i, pi in enumerate(p):
        rho = rho0
        for _ in range(50):
            r = rho / rho0
            c = eos_sound_speed(eos, q, r, q[Q_E0])
            step = (eos_pressure(eos, q, r, q[Q_E0]) - pi) / (c * c)
            rho -= step
            if abs(step) <= 1e-14 * rho:
                break
        out[i] = rho
    return out


@pytest.mark.parametrize("eos, q", [
    ("EOS_LINEAR_POLYNOMIAL", [1000.0, 0.0, 1.0, 0.0, 2.2e9, 9.5e9, 1.45e10, 0.28, 0.28, 0.0]),
    ("EOS_GRUNEISEN", [1000.0, 0.0, 1.0, 1480.0, 1.92, -0.096, 0.0, 0.35, 0.0]),
    ("EOS_TAIT", [1000.0, 0.0, 1.0, 1000.0, 30.0, 7.0, 0.0, 1000.0 * 30.0 ** 2 / 7.0]),
    ("EOS_STIFFENED_GAS", [1000.0, (1.0e5 + 4.4 * 6.0e8) / 3.4, 1.0, 4.4, 6.0e8]),  # E0: p = 1 bar at rho0
])
def test_hydrostatic_fill_is_the_former_kernel_loop(eos, q):
    """``model.ale_build.hydrostatic_fill`` (all elements at once in numpy) gives the densities the former loop over
    elements with the compiled ``eos_pressure`` / ``eos_sound_speed`` gave, bit for bit: a 6 x 8 water column under
    g = 9.81 m/s^2 down, a partly filled top row (each element stops its Newton at its own step)."""
    from types import SimpleNamespace

    from sphfem_cli.deck.schema import Gravity
    from sphfem_cli.materials import kernels as mk
    from sphfem_cli.materials.slots import EOS_OFFSET, NPARAM, P_EOS_TYPE, P_RHO0
    from sphfem_cli.model.ale_build import hydrostatic_fill
    from sphfem_cli.model.mesh import box_mesh

    mesh = box_mesh([0.0, 0.0], [0.6, 4.0], divisions=[6, 8])
    nodes, conn = mesh.nodes, mesh.elements
    f = np.clip((3.3 - nodes[conn, 1].min(axis=1)) / 0.5, 0.0, 1.0)
    row = np.zeros(NPARAM)
    row[P_RHO0], row[P_EOS_TYPE] = q[0], getattr(mk, eos)
    row[EOS_OFFSET:EOS_OFFSET + len(q)] = q
    deck = SimpleNamespace(loads=[Gravity(type="gravity", acceleration=[0.0, -9.81])])
    model = SimpleNamespace(material_param=row[None, :])
    density, pressure = np.zeros(len(conn)), np.zeros(len(conn))
    hydrostatic_fill(model, deck, "tank", 0, nodes, conn, f, 0, density, pressure)
    hit = np.flatnonzero(f > 0)
    deep = density[hit][np.argsort(pressure[hit])]
    assert np.all(pressure[hit] > 0.0) and np.all(np.diff(deep) >= 0.0) and deep[-1] > deep[0]  # denser deeper
    ref = _hydrostatic_loop(int(row[P_EOS_TYPE]), np.ascontiguousarray(row[EOS_OFFSET:]), q[0], pressure[hit])
    assert np.array_equal(density[hit], ref)
    assert np.all(density[f == 0] == 0.0)


def test_ale_hex8_volumes_are_the_kernel():
    """``ale.system.hex8_volumes_set_up`` (numpy, the 3D ALE system's initial volumes) gives the bits of the kernel
    ``ale.energy.element_volumes_3d`` on distorted, shuffled hex8 boxes far from the origin."""
    from sphfem_cli.ale.energy import element_volumes_3d
    from sphfem_cli.ale.system import hex8_volumes_set_up

    rng = np.random.default_rng(11)
    cube = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1]], float)
    nodes = np.concatenate([cube * [0.3, 0.5, 0.7] + rng.uniform(-0.05, 0.05, (8, 3)) + [10.0 * i, 3.0, -7.0]
                            for i in range(20)])
    conn = rng.permutation(np.arange(len(nodes), dtype=np.int64).reshape(-1, 8))
    kernel = np.empty(len(conn))
    element_volumes_3d(nodes, conn, kernel)
    got = hex8_volumes_set_up(nodes, conn)
    assert np.array_equal(got.view(np.int64), kernel.view(np.int64))
    assert np.allclose(got, 0.3 * 0.5 * 0.7, rtol=0.3)  # the scale: boxes distorted by <= 0.05


@pytest.mark.parametrize("nquad", [1, 3])
def test_coupling_face_shares_are_the_kernel(nquad):
    """``contact.coupling.face_shares_set_up`` (numpy, the 3D coupling's set-up) gives the bits of the kernel
    ``coupling_kernels_3d.face_shares`` on warped quad faces; the shares of a face sum to its area (plane faces)."""
    from sphfem_cli.contact.coupling import face_shares_set_up
    from sphfem_cli.contact.coupling_kernels_3d import face_shares

    rng = np.random.default_rng(5)
    square = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], float)
    xs = np.concatenate([square * [0.4, 0.6, 0.0] + rng.uniform(-0.05, 0.05, (4, 3)) + [i, 0.0, 2.0] for i in range(7)])
    faces = np.arange(len(xs), dtype=np.int64).reshape(-1, 4)
    kernel = np.empty(len(faces) * nquad * nquad)
    face_shares(xs, faces, nquad, kernel)
    got = face_shares_set_up(xs, faces, nquad)
    assert np.array_equal(got.view(np.int64), kernel.view(np.int64))
    plane = np.concatenate([square * [0.4, 0.6, 0.0] + [i, 0.0, 2.0] for i in range(3)])
    assert np.allclose(face_shares_set_up(plane, faces[:3], nquad).reshape(3, -1).sum(axis=1), 0.24, rtol=1e-12)


def test_set_up_pages_turns_numpy_huge_page_advice_off_and_back():
    """``model.pages.set_up_pages`` (around the ALE set-up): numpy's madvise of huge pages off inside the block, and
    the former setting back after it, also when the block raises."""
    multiarray = pytest.importorskip("numpy._core.multiarray")
    from sphfem_cli.model.pages import set_up_pages

    switch = multiarray._set_madvise_hugepage  # returns the setting it replaces
    former = switch(True)
    try:
        with set_up_pages():
            assert switch(False) is False
        assert switch(True) is True
        with pytest.raises(RuntimeError), set_up_pages():
            raise RuntimeError
        assert switch(True) is True
    finally:
        switch(former)
