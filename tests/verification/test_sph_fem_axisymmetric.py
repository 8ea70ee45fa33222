"""SPH -> FEM penalty contact in an axisymmetric deck: segments sweep rings (contact.system, kernels).

* Conservation: an SPH ball (meridian half-disc on the axis) flying axially into a free elastic FEM
  disc, no gravity, no walls. Particle and node masses are full rings, the contact force on a
  particle is the full ring's and its reaction goes to the segment's ring nodes. The axial momentum
  budget is taken apart per step (dt_avg = (dt_prev + dt)/2, the kick of both integrators):
    - the contact's axial forces on particles and nodes sum to round-off (measured 1.1e-13 N);
    - the solid's own axial impulse, sum M dv_z - dt_avg sum f_contact,z over the nodes, is round-off
      (measured 7.6e-17 of sum m |v_z| for 1.8 N s of contact impulse): the axisymmetric quad's internal and
      hourglass forces sum to zero along the axis;
    - the SPH's own axial impulse, sum m dv_z - dt_avg sum f_contact,z over the particles, is NOT
      round-off: 6.0e-3 of sum m |v_z| (1.6e-2 N s) over the impact, all of the total drift. It is the
      formulation's (sph/axisymmetric.py, "Conservation"): the axis images carry the signed radius
      s_j = -1, so the axial forces of the image of j on i and of the image of i on j are both
      -m_i m_j (Q_j - Q_i) F_ij' (z_i - z_j), equal, not opposite. With the images' s_j set to +1 (the
      even mirror, a diagnostic edit of _pair_terms, not in the code) the same scene's total drift
      is 3.3e-16 of sum m |v_z|; the ball into a resting water slab (SPH alone, no disc) drifts
      1.0e-3. Since issue 15's corner fix the hoop term has an axial component p kappa_z/(rho r), a
      force on one particle, nonzero where the support is cut in z, here at the disc (contact floor)
      during the impact: the drift is 1.26e-2 of sum m |v_z| with it (6.0e-3 with the radial kappa
      alone). Asserted below 2e-2 (dx = 0.01).
  No particle crosses the axis; glstat's energy ratio (the contact's work included) stays near 1.
* Hydrostatics: a water column (R 0.1 m, H 0.2 m, dx 0.01, slip ghost wall at r = R, no ghost floor)
  rests on a clamped elastic disc through the contact; the contact force on the particles carries the
  weight rho g H pi R^2 (the midpoint lattice's ring masses sum to it exactly). Measured over
  0.05-0.15 s, alpha 0.1: mean 0.9985 of the weight; asserted within 1 %. The same column is NOT
  at rest longer (the strict xfail below), for two causes:
    - fixed (issue 15): the hoop term's renormalisation had only its radial component; at a floor
      without ghosts the images' odd term leaves an axial force first order in a particle's radial
      offset and growing as 1/r, and the particles at the corner of the axis and the floor blew up
      (max |v| at 0.3 s: 1.14 m/s at dx 0.01, 12.5 m/s at dx 0.005). With the vector kappa of
      sph/axisymmetric.py: 0.34 and 0.19 m/s (test_sph_axisymmetric_uniform_pressure checks the term);
    - left: the second row above a floor without ghosts pairs into the first (a zig-zag of v_z along
      the row, largest next to the axis). It is not axisymmetric: the plane 2D twin (a ghost wall at
      x = 0 instead of the axis) does the same once seeded with 1 mm/s random velocities (0.20 m/s at
      0.2 s); unseeded it has no perturbation along x and keeps 0.005 m/s to 0.3 s. The axisymmetric
      column on a ghost floor is stable (test_sph_axisymmetric). A cure needs kernel support below a
      contact floor (ghosts or boundary particles on the master surface), in 2D as well.
"""
from __future__ import annotations

import numpy as np
import pytest


def _ball_into_disc(end_time: float) -> dict:
    return {
        "title": "SPH ball into a free FEM disc, axisymmetric, no gravity",
        "dimension": "axisymmetric",
        "control": {"end_time": end_time, "timestep_scale": 0.9},
        "equations_of_state": {"water": {"type": "tait", "reference_density": 1000.0, "sound_speed": 50.0,
                                         "gamma": 7.0}},
        "materials": {
            "water": {"type": "fluid", "density": 1000.0, "eos": "water"},
            "disc": {"type": "elastic", "density": 2000.0, "youngs_modulus": 2.0e7, "poisson_ratio": 0.3},
        },
        "sections": {"fluid": {"type": "sph", "artificial_viscosity": {"alpha": 0.1}}, "solid": {"type": "solid"}},
        "parts": {
            "ball": {"material": "water", "section": "fluid", "spacing": 0.01,
                     "geometry": {"ball": {"center": [0.0, 0.07], "radius": 0.05}}},
            "disc": {"material": "disc", "section": "solid",
                     "geometry": {"box": {"min": [0.0, 0.0], "max": [0.12, 0.02], "divisions": [12, 2]}}},
        },
        "initial": [{"type": "velocity", "part": "ball", "velocity": [0.0, -5.0]}],
        "contacts": [{"type": "nodes_to_surface", "nodes": "ball", "surface": "disc"}],
    }


def _axial_momentum(sim) -> tuple[float, float, float, float]:
    """(sum m v_z of the particles, of the nodes, and their sums of m |v_z|) at v^{n+1/2}."""
    ps = sim.particles.system
    vp = ps.v_half if ps.nsteps else ps.v
    a = ps.active
    return (float((ps.m[a] * vp[a, 1]).sum()), float((sim.model.mass * sim.state.v[:, 1]).sum()),
            float((ps.m[a] * np.abs(vp[a, 1])).sum()), float((sim.model.mass * np.abs(sim.state.v[:, 1])).sum()))


def test_ball_into_free_disc_conserves_axial_momentum(sim_from_deck, single_thread):
    end_time = 0.012
    sim = sim_from_deck(_ball_into_disc(end_time))
    ps = sim.particles.system
    p_p, p_n, s_p, s_n = _axial_momentum(sim)
    scale = s_p + s_n
    p0 = p_p + p_n
    worst, touched, closest, ratio_worst, pair_worst, impulse = 0.0, 0, float(ps.x[:, 0].min()), 0.0, 0.0, 0.0
    own_sph = own_solid = 0.0
    dt_prev = 0.0
    while sim.state.time < end_time * (1 - 1e-12):
        sim.step()
        dt_avg = 0.5 * (dt_prev + sim.state.dt_prev)  # both integrators' kick of this step
        dt_prev = sim.state.dt_prev
        c = sim.interactions[0]
        on_points, on_nodes = c._f_point[:, 1], c._f_master[:, 1]
        pair_worst = max(pair_worst, abs(float(on_points.sum() + on_nodes.sum())))
        impulse += float(np.abs(on_points).sum()) * dt_avg
        q_p, q_n, _, _ = _axial_momentum(sim)
        own_sph += (q_p - p_p) - float(on_points.sum()) * dt_avg
        own_solid += (q_n - p_n) - float(on_nodes.sum()) * dt_avg
        p_p, p_n = q_p, q_n
        worst = max(worst, abs(q_p + q_n - p0))
        touched = max(touched, int((c._seg_of >= 0).sum()))
        closest = min(closest, float(ps.x[ps.active, 0].min()))
        ratio_worst = max(ratio_worst, abs(sim.energy_row().ratio - 1.0))
    disc_v = float((sim.model.mass * sim.state.v[:, 1]).sum() / sim.model.mass.sum())
    print(f"pair sum worst {pair_worst:.3e} N, contact impulse {impulse:.4g} N s, touched {touched}, "
          f"momentum drift {worst / scale:.3e} (SPH own {own_sph / scale:.3e}, solid own {own_solid / scale:.3e}), "
          f"closest r {closest:.4g}, energy ratio worst {ratio_worst:.3e}, disc v {disc_v:.4g}")
    assert touched >= 5, "the ball never met the disc"
    assert pair_worst <= 1e-12 * impulse / end_time, pair_worst
    assert abs(own_solid) <= 1e-12 * scale, own_solid
    assert abs(own_sph) < 2e-2 * scale, own_sph  # axis images, axial hoop term (module docstring): 1.26e-2
    assert closest > 0.0
    assert disc_v < -0.05  # the disc took axial momentum from the ball
    assert ratio_worst < 0.05, ratio_worst


R_COLUMN, H_COLUMN, G = 0.1, 0.2, 9.81


def _column_on_disc(end_time: float) -> dict:
    """Water at rest (hydrostatic start, Tait c0 = 14 m/s = 10 sqrt(g H)) on a clamped disc of the column's
    radius; the contact is the only floor, a slip ghost wall the side r = R."""
    return {
        "title": "water column on a clamped FEM disc, axisymmetric",
        "dimension": "axisymmetric",
        "control": {"end_time": end_time, "timestep_scale": 1.0},
        "equations_of_state": {"water": {"type": "tait", "reference_density": 1000.0, "sound_speed": 14.0,
                                         "gamma": 7.0}},
        "materials": {
            "water": {"type": "fluid", "density": 1000.0, "eos": "water"},
            "disc": {"type": "elastic", "density": 1000.0, "youngs_modulus": 1.0e7, "poisson_ratio": 0.3},
        },
        "sections": {"fluid": {"type": "sph", "kernel": "cubic_spline", "smoothing_ratio": 1.2,
                               "density_diffusion": 0.1, "artificial_viscosity": {"alpha": 0.1}},
                     "solid": {"type": "solid"}},
        "parts": {
            "column": {"material": "water", "section": "fluid", "spacing": 0.01, "hydrostatic": True,
                       "geometry": {"box": {"min": [0.0, 0.0], "max": [R_COLUMN, H_COLUMN]}}},
            "disc": {"material": "disc", "section": "solid",
                     "geometry": {"box": {"min": [0.0, -0.02], "max": [R_COLUMN, 0.0], "divisions": [10, 2]}}},
        },
        "boundaries": [{"type": "fixed", "part": "disc"},
                       {"type": "wall", "min": [0.0, -0.02], "max": [R_COLUMN, 1.5 * H_COLUMN], "sides": ["right"]}],
        "loads": [{"type": "gravity", "acceleration": [0.0, -G]}],
        "contacts": [{"type": "nodes_to_surface", "nodes": "column", "surface": "disc"}],
    }


def _run_column(sim_from_deck, end_time: float):
    sim = sim_from_deck(_column_on_disc(end_time))
    t, force = [], []
    while sim.state.time < end_time * (1 - 1e-12):
        sim.step()
        t.append(sim.state.time)
        force.append(float(sim.interactions[0]._f_point[:, 1].sum()))  # the floor's push on the water
    return sim, np.array(t), np.array(force)


def test_column_on_clamped_disc_carries_its_weight(sim_from_deck, single_thread):
    sim, t, force = _run_column(sim_from_deck, 0.15)
    ps = sim.particles.system
    weight = 1000.0 * G * H_COLUMN * np.pi * R_COLUMN ** 2
    assert abs(float(ps.m[ps.active].sum()) * G - weight) < 1e-12 * weight  # ring masses: pi R^2 H rho
    settled = t > 0.05  # past three and a half sound transits of the depth (H / c0 = 0.014 s)
    mean = float(force[settled].mean())
    print(f"contact force / rho g H pi R^2 over 0.05-0.15 s: mean {mean / weight:.5f}, "
          f"min {force[settled].min() / weight:.4f}, max {force[settled].max() / weight:.4f}")
    assert abs(mean - weight) < 0.01 * weight, mean / weight
    assert ps.x[ps.active, 0].min() > 0.0


@pytest.mark.xfail(strict=True, reason="the second row above a contact floor (no floor ghosts) pairs into the "
                   "first: max |v| 0.34 m/s at 0.3 s (1.14 before the vector hoop term; the seeded plane 2D twin "
                   "does the same); module docstring")
def test_column_on_clamped_disc_stays_at_rest(sim_from_deck, single_thread):
    sim, _, _ = _run_column(sim_from_deck, 0.3)
    ps = sim.particles.system
    vmax = float(np.linalg.norm(ps.v[ps.active], axis=1).max())
    print(f"max |v| at 0.3 s: {vmax:.4g} m/s")
    assert vmax < 0.05, vmax
