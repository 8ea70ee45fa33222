"""Element kernels against short NumPy references on small random inputs."""
from __future__ import annotations

import numpy as np
import pytest

from sphfem_cli.fem.geometry import (hex8_gradient, hex8_gradient_faces, hex8_gradient_rows, hex8_volume,
                                     hex8_volume_origin, quad4_gradient)
from sphfem_cli.fem.kernels import rotate_stress
from sphfem_cli.fem.tables import HEX_DV, HEX_FACES

HEX_SIGNS = np.array([(-1, -1, -1), (1, -1, -1), (1, 1, -1), (-1, 1, -1),
                      (-1, -1, 1), (1, -1, 1), (1, 1, 1), (-1, 1, 1)], dtype=float)


def hex_volume_and_dvdx(x):
    """Reference: V = sum over 2x2x2 Gauss points of det J (exact for trilinear maps), and
    dV/dx_I = sum_g det J_g dN_I/dx (g), the Flanagan-Belytschko uniform gradient times V."""
    g = 1.0 / np.sqrt(3.0)
    volume, dvdx = 0.0, np.zeros((3, 8))
    for xi in (-g, g):
        for eta in (-g, g):
            for zeta in (-g, g):
                p = np.array([xi, eta, zeta])
                dn = np.empty((8, 3))  # dN/dxi
                for i, s in enumerate(HEX_SIGNS):
                    dn[i, 0] = s[0] / 8.0 * (1 + s[1] * p[1]) * (1 + s[2] * p[2])
                    dn[i, 1] = s[1] / 8.0 * (1 + s[0] * p[0]) * (1 + s[2] * p[2])
                    dn[i, 2] = s[2] / 8.0 * (1 + s[0] * p[0]) * (1 + s[1] * p[1])
                jac = x.T @ dn  # dx/dxi
                det = np.linalg.det(jac)
                volume += det
                dvdx += det * np.linalg.solve(jac.T, dn.T)
    return volume, dvdx


def distorted_hex(rng):
    x = (HEX_SIGNS + 1.0) / 2.0 * np.array([1.0, 0.7, 1.3])
    return x + 0.12 * rng.uniform(-1, 1, size=(8, 3))


def test_hex8_gradient_equals_dv_dx():
    rng = np.random.default_rng(3)
    b = np.empty((3, 8))
    for _ in range(20):
        x = distorted_hex(rng)
        volume = hex8_gradient(x, b)
        ref_v, ref_dvdx = hex_volume_and_dvdx(x)
        assert volume == pytest.approx(ref_v, rel=1e-13)
        assert np.allclose(b * volume, ref_dvdx, rtol=0, atol=1e-13)
        # A linear field's gradient is exact: sum_I x_I (x) b_I = identity.
        assert np.allclose(x.T @ b.T, np.eye(3), atol=1e-13)


def test_hex8_gradient_written_out_is_the_table_sum_bit_for_bit():
    """The written-out gradient and the HEX_DV row loop: the same bits (valid, inverted, far from the origin)."""
    rng = np.random.default_rng(6)
    b, b_rows = np.empty((3, 8)), np.empty((3, 8))
    for i in range(200):
        x = distorted_hex(rng) * rng.uniform(1e-3, 1e3) + rng.normal(0.0, 50.0, 3)
        if i % 5 == 0:
            x = rng.normal(size=(8, 3))  # often inverted: b is zero, the volume is still returned
        volume, volume_rows = hex8_gradient(x, b), hex8_gradient_rows(x, b_rows)
        assert np.float64(volume).tobytes() == np.float64(volume_rows).tobytes()
        assert b.tobytes() == b_rows.tobytes()


def test_hex8_gradient_faces_grouping_is_the_table():
    """Each node's nine HEX_DV rows are, face by face, +([a, b] + [a, c] + [b, c]) with a, b, c the
    face's corners after the node in HEX_FACES's order: the identity hex8_gradient_faces is built on."""
    for node in range(8):
        rows = {(int(j), int(k)): int(s) for i, j, k, s in HEX_DV if i == node}
        grouped = {}
        for face in HEX_FACES.tolist():
            if node in face:
                p = face.index(node)
                a, b, c = face[(p + 1) % 4], face[(p + 2) % 4], face[(p + 3) % 4]
                for j, k in ((a, b), (a, c), (b, c)):
                    grouped[(j, k) if j < k else (k, j)] = 1 if j < k else -1
        assert grouped == rows


def test_hex8_gradient_faces_is_the_table_form_to_round_off():
    """The factored gradient: hex8_gradient's numbers to round-off, the Gauss reference, a linear field's
    exact gradient, at scales 1e-3..1e3; an inverted hex gives a negative volume and b = 0."""
    rng = np.random.default_rng(7)
    b, b_ref = np.empty((3, 8)), np.empty((3, 8))
    for i in range(200):
        scale = rng.uniform(1e-3, 1e3)
        x = distorted_hex(rng) * scale
        volume, volume_ref = hex8_gradient_faces(x, b), hex8_gradient(x, b_ref)
        assert volume == pytest.approx(volume_ref, rel=1e-13)
        assert np.allclose(b * scale, b_ref * scale, rtol=0, atol=1e-13)
        assert np.allclose(x.T @ b.T, np.eye(3), atol=1e-13)
        if i < 20:
            ref_v, ref_dvdx = hex_volume_and_dvdx(x / scale)
            assert volume / scale**3 == pytest.approx(ref_v, rel=1e-13)
            assert np.allclose(b * scale * ref_v, ref_dvdx, rtol=0, atol=1e-13)
    inverted = distorted_hex(rng)[[4, 5, 6, 7, 0, 1, 2, 3]]
    assert hex8_gradient_faces(inverted, b) < 0.0
    assert not b.any()


def test_quad4_gradient():
    rng = np.random.default_rng(4)
    b = np.empty((2, 4))
    for _ in range(20):
        x = np.array([[0, 0], [1, 0], [1.2, 0.9], [-0.1, 1.0]]) + 0.1 * rng.uniform(-1, 1, size=(4, 2))
        area = quad4_gradient(x, b)
        shoelace = 0.5 * np.sum(x[:, 0] * np.roll(x[:, 1], -1) - np.roll(x[:, 0], -1) * x[:, 1])
        assert area == pytest.approx(shoelace, rel=1e-13)
        assert np.allclose(x.T @ b.T, np.eye(2), atol=1e-13)
        assert np.allclose(b.sum(axis=1), 0.0, atol=1e-13)


def test_rotate_stress_is_the_cayley_rotation():
    rng = np.random.default_rng(5)
    for _ in range(20):
        w_xy, w_yz, w_zx, dt = rng.normal(size=4)
        s = rng.normal(size=6)
        t = np.array([[s[0], s[3], s[5]], [s[3], s[1], s[4]], [s[5], s[4], s[2]]])
        spin = np.array([[0, w_xy, -w_zx], [-w_xy, 0, w_yz], [w_zx, -w_yz, 0]])
        half = 0.5 * dt * spin
        r = np.linalg.solve(np.eye(3) - half, np.eye(3) + half)
        expected = r @ t @ r.T
        rotate_stress(s, w_xy, w_yz, w_zx, dt)
        got = np.array([[s[0], s[3], s[5]], [s[3], s[1], s[4]], [s[5], s[4], s[2]]])
        assert np.allclose(got, expected, atol=1e-13)
        assert np.allclose(r @ r.T, np.eye(3), atol=1e-13)


def test_hex8_volume_origin_is_hex8_volume_bit_for_bit():
    """The written-out volume of corners relative to corner 0: the bits of the table form (hex8_volume)."""
    rng = np.random.default_rng(11)
    for i in range(500):
        x = distorted_hex(rng) * rng.uniform(1e-3, 1e3) + rng.uniform(-5, 5, size=3)
        if i % 5 == 0:  # a swept hexahedron: the top a small move of the bottom (the ALE face sweep)
            x[4:] = x[:4] + rng.uniform(-1e-3, 1e-3, size=(4, 3)) * (i % 2)
        p = x - x[0]
        assert hex8_volume_origin(*p[1:].ravel()) == hex8_volume(p)
