"""Where the images of a non-reflecting open side lie and which of them are open (sph/open_sides.py,
sph/walls.py; docs/theory/sph.md "Non-reflecting open sides").

An open side's image of particle i lies at x_i - 2 s d0_i e_axis (d0_i its distance from the side at t = 0),
so it follows the particle; across a wall the image is the mirror image about the wall's plane. The
impedance pressure goes to the images across an open side, told by the planes each image is the image
across, not by where it lies.
"""
from __future__ import annotations

import numpy as np
import pytest

from sphfem_cli.sph import open_sides, walls
from sphfem_cli.sph.options import SphOptions
from sphfem_cli.sph.scenes import water
from sphfem_cli.sph.system import SphSystem
from sphfem_cli.sph.walls import Wall

RHO, C = 1000.0, 1480.0


def _planes():
    """A slip wall x = 0 (fluid at x > 0, plane 0) and an open side y = 0 (fluid at y > 0, plane 1)."""
    return open_sides.ghost_planes([Wall(0, 0.0, 1, "slip"), Wall(1, 0.0, 1, "non_reflecting")], 2)


def test_images_follow_their_particle_and_the_corner_mixes_mirror_and_offset():
    """A particle that started 4 mm above the open side and has moved to y = 10 mm, 3 mm from the wall.

    Expected (exact, same floating-point operations): across the wall (-3, 10) mm with the normal velocity
    reversed; across the open side (3, 10 - 8) = (3, 2) mm with the velocity copied, on the fluid's side of
    the side's plane; at the corner (-3, 2) mm, x velocity reversed. The open side's images and only they
    get the impedance pressure p_far + rho c v.n (n = -e_y): the image at y = 2 mm too.
    """
    planes = _planes()
    x = np.array([[0.003, 0.010]])
    v = np.array([[0.5, -2.0]])
    rho, c = np.array([RHO]), np.array([C])
    d0 = np.array([[0.003, 0.004]])  # distances at t = 0 from plane 0 (unused: a wall) and plane 1
    valid = np.array([False, True, True, True])
    gpos, gvel, gflip, gsrc, gsub, gdp, gdr = walls.make_ghosts(x, v, rho, c, d0, np.ones(1, dtype=np.bool_),
                                                                planes, valid, 0.02, np.zeros(3), False)
    images = {int(s): (gpos[k, :2], gvel[k, :2]) for k, s in enumerate(gsub)}
    assert sorted(images) == [1, 2, 3] and np.all(gsrc == 0)
    assert np.array_equal(images[1][0], [-0.003, 0.010]) and np.array_equal(images[1][1], [-0.5, -2.0])
    assert np.array_equal(images[2][0], [0.003, 0.010 - 2.0 * 0.004]) and np.array_equal(images[2][1], [0.5, -2.0])
    assert np.array_equal(images[3][0], [-0.003, 0.010 - 2.0 * 0.004]) and np.array_equal(images[3][1], [-0.5, -2.0])

    p, p_far = np.array([2e5]), np.array([1e5])
    is_open = np.zeros(len(gsrc), dtype=np.bool_)
    open_sides.open_ghost_state(x, p, rho, c, p_far, np.zeros(1), gpos, gvel, gsrc, gsub, gdp, gdr, planes, 0.5,
                                np.zeros(3), -1e5, is_open)
    assert [bool(is_open[list(gsub).index(s)]) for s in (1, 2, 3)] == [False, True, True]
    k = list(gsub).index(2)
    assert gdp[k] == pytest.approx(1e5 + RHO * C * 2.0 - 2e5, rel=1e-14)  # v.n = (-2)(-1) = 2 m/s outwards


def test_a_particle_beyond_an_open_side_at_the_start_is_refused():
    with pytest.raises(ValueError, match="beyond a non_reflecting side"):
        open_sides.initial_distances(np.array([[0.01, 0.02], [0.01, -0.001]]), _planes())
    assert open_sides.initial_distances(np.array([[0.01, 0.02]]), _planes()[:1]).shape == (1, 0)  # walls only


def test_initial_distances_travel_with_the_particles_and_nothing_leaves():
    """A water block (c 20 m/s, 40 x 40 mm, free elsewhere) moving down at 5 m/s onto an open bottom,
    reordered every 5 evaluations: after 60 steps (0.61 ms) open_d0 still holds each particle's own
    distance at t = 0 (exactly), the lowest particles have moved past the bottom's plane of t = 0
    (measured 0.94 mm; the side moves with the water) and none was deactivated."""
    dx = 0.002
    g = np.mgrid[0:20, 0:20].reshape(2, -1).T
    x0 = (g + 0.5) * dx
    opt = SphOptions(walls=(Wall(1, 0.0, 1, "non_reflecting"),), alpha=0.1, reorder_every=5)
    ps = SphSystem(x0, np.tile([0.0, -5.0], (len(x0), 1)), np.full(len(x0), RHO * dx * dx), np.full(len(x0), RHO),
                   np.zeros(len(x0), dtype=np.int64), water(20.0), opt)
    for _ in range(60):
        ps.advance(0.5)
    assert not np.array_equal(ps.ids, np.arange(len(x0)))  # reordered
    assert np.array_equal(ps.open_d0[:, 0], x0[ps.ids, 1])
    assert ps.x[:, 1].min() < 0.0 and ps.lost == 0 and ps.active.all()
