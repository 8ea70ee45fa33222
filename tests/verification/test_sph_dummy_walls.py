"""Dummy wall particles from the deck (`boundaries: [{type: dummy_wall, ...}]`, Adami et al. 2012).

Two modes: layers outside sides of a box (a tank), and a region filled with wall particles (a wall
of any shape: here a disc the water falls onto). The walls' pressure is extrapolated from the
fluid with gravity; their share of the fluid-wall pair work is counted in the energy balance
(sph.rates.fluid_rates ``wall_power``).

Still tank: H = 0.4 m, dx = 0.02 m (H/dx = 20), c0 = 10 sqrt(g H); exact floor pressure
rho g (H - y). Measured: at y = 2 dx the mean over the last 0.16 s (two acoustic periods
4 H / c0) is +2.6 % above rho g (H - y); energies balance to about 2e-4 J out of 0.1 J.

The energy guard is switched off in these decks: a tank at rest under gravity starts with internal
and kinetic energies of 1e-4 J against a reference (the work of gravity) of 1e-5 J, and the ratio
of such small numbers says nothing in the first tens of steps.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

G, H, DX = 9.81, 0.4, 0.02


def _tank(boundaries: list, end_time: float, water: dict, probes: list | None = None) -> dict:
    return {
        "dimension": 2,
        "control": {"end_time": end_time, "energy_band": None},
        "equations_of_state": {"water": {"type": "tait", "reference_density": 1000.0,
                                         "sound_speed": round(10 * math.sqrt(G * H), 2), "gamma": 7.0}},
        "materials": {"water": {"type": "fluid", "density": 1000.0, "eos": "water"}},
        "sections": {"fluid": {"type": "sph", "artificial_viscosity": {"alpha": 0.05}, "density_diffusion": 0.1}},
        "parts": {"water": {"material": "water", "section": "fluid", "geometry": {"box": water}, "spacing": DX,
                            "hydrostatic": True}},
        "boundaries": boundaries,
        "loads": [{"type": "gravity", "acceleration": [0.0, -G]}],
        "output": {"probes": probes or []},
    }


def test_still_tank_between_dummy_walls(sim_from_deck, single_thread):
    sim = sim_from_deck(_tank([{"type": "dummy_wall", "min": [0.0, 0.0], "max": [0.4, 1.0],
                                "sides": ["left", "right", "bottom"]}], 0.3, {"min": [0.0, 0.0], "max": [0.4, H]}))
    ps = sim.particles.system
    assert len(ps.wall_x) == 3 * (20 + 3 + 3) + 2 * 3 * 50  # floor incl. corners, two side walls up to y = 1
    window = 2 * 4 * H / (10 * math.sqrt(G * H))
    p, rows = [], []
    while sim.state.time < 0.3 * (1 - 1e-12):
        sim.step()
        if sim.state.time > 0.3 - window:
            p.append(ps.interpolate([[0.2, 2 * DX]], include_walls=False)[0])
        rows.append(sim.energy_row())
    assert np.mean(p) == pytest.approx(1000.0 * G * (H - 2 * DX), rel=0.05)
    assert ps.x[:, 1].min() > 0.0 and ps.x[:, 0].min() > 0.0 and ps.x[:, 0].max() < 0.4
    assert np.abs(ps.v).max() < 0.05 * math.sqrt(G * H)
    imbalance = max(abs(r.total - r.total / r.ratio) for r in rows[20:])
    assert imbalance < 1e-3, imbalance  # J, against energies of about 0.1 J


def test_water_falls_onto_a_disc_of_wall_particles(sim_from_deck, single_thread):
    disc = {"center": [0.2, 0.15], "radius": 0.06}
    deck = _tank([{"type": "dummy_wall", "min": [0.0, 0.0], "max": [0.4, 1.0], "sides": ["left", "right", "bottom"]},
                  {"type": "dummy_wall", "region": {"ball": disc}}], 0.25, {"min": [0.1, 0.3], "max": [0.3, 0.5]})
    deck["parts"]["water"]["hydrostatic"] = False
    sim = sim_from_deck(deck)
    ps = sim.particles.system
    inside_min = np.inf
    while sim.state.time < 0.25 * (1 - 1e-12):
        sim.step()
        r = np.linalg.norm(ps.x - np.array(disc["center"]), axis=1)
        inside_min = min(inside_min, float(r.min()))
    # The water has reached the disc (it started 0.09 m above it) and stays out of it: no particle
    # centre comes closer than half a spacing beyond the disc's wall particles' own edge.
    assert ps.x[:, 1].min() < 0.15
    assert inside_min > disc["radius"] - 0.5 * DX
