"""SPH -> FEM penalty contact in an axisymmetric deck: segments sweep rings (contact.system, kernels).

* Conservation: an SPH ball (meridian half-disc on the axis) flying axially into a free elastic FEM
  disc, no gravity, no walls. Particle and node masses are full rings, the contact force on a
  particle is the full ring's and its reaction goes to the segment's ring nodes: each step the
  contact's axial forces on particles and nodes sum to round-off. The total axial momentum
  (particles + nodes) is only reported: the SPH axis images conserve it to truncation error, not
  round-off (sph/axisymmetric.py). No particle crosses the axis; glstat's energy ratio (the
  contact's work included) stays near 1.
"""
from __future__ import annotations

import numpy as np


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


def _axial_momentum(sim) -> tuple[float, float]:
    ps = sim.particles.system
    p = float((sim.model.mass * sim.state.v[:, 1]).sum() + (ps.m * ps.v_half[:, 1])[ps.active].sum())
    scale = float((sim.model.mass * np.abs(sim.state.v[:, 1])).sum() + (ps.m * np.abs(ps.v_half[:, 1]))[ps.active].sum())
    return p, scale


def test_ball_into_free_disc_conserves_axial_momentum(sim_from_deck, single_thread):
    end_time = 0.012
    sim = sim_from_deck(_ball_into_disc(end_time))
    ps = sim.particles.system
    p0, scale0 = _axial_momentum(sim)
    worst, touched, closest, ratio_worst, pair_worst, impulse = 0.0, 0, float(ps.x[:, 0].min()), 0.0, 0.0, 0.0
    while sim.state.time < end_time * (1 - 1e-12):
        sim.step()
        c = sim.interactions[0]
        on_points, on_nodes = c._f_point[:, 1], c._f_master[:, 1]
        pair_worst = max(pair_worst, abs(float(on_points.sum() + on_nodes.sum())))
        impulse += float(np.abs(on_points).sum()) * sim.state.dt_prev
        worst = max(worst, abs(_axial_momentum(sim)[0] - p0))
        touched = max(touched, int((sim.interactions[0]._seg_of >= 0).sum()))
        closest = min(closest, float(ps.x[ps.active, 0].min()))
        ratio_worst = max(ratio_worst, abs(sim.energy_row().ratio - 1.0))
    disc_v = float((sim.model.mass * sim.state.v[:, 1]).sum() / sim.model.mass.sum())
    print(f"pair sum worst {pair_worst:.3e} N, contact impulse {impulse:.4g} N s, "
          f"touched {touched} momentum drift {worst / scale0:.3e} closest r {closest:.4g} "
          f"energy ratio worst {ratio_worst:.3e} disc v {disc_v:.4g}")
    assert touched >= 5, "the ball never met the disc"
    assert pair_worst <= 1e-12 * impulse / end_time, pair_worst
    assert closest > 0.0
    assert disc_v < -0.05  # the disc took axial momentum from the ball
    assert ratio_worst < 0.05, ratio_worst
