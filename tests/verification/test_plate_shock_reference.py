"""Checks of tests/verification/plate_shock_reference.py against Taylor's (1941) closed forms."""
import numpy as np
import pytest

from tests.verification.plate_shock_reference import (
    M_PLATE, RHO_W, C_W, column_plate, hugoniot_velocity, observed_order, taylor_exponential, taylor_plate)

P0, THETA = 2.0e6, 2.0e-5   # small amplitude: Taylor's linear acoustics holds (u/c ~ 1e-3)


def test_closed_forms_consistent():
    cf = taylor_exponential(P0, THETA)
    beta = RHO_W * C_W * THETA / M_PLATE
    assert cf["beta"] == pytest.approx(beta)
    # the face pressure 2 p_i - rho c v vanishes at t_cav, and v peaks there
    tc = cf["t_cav"]
    assert 2 * P0 * np.exp(-tc / THETA) - RHO_W * C_W * cf["v"](tc) == pytest.approx(0.0, abs=1e-6 * P0)
    assert cf["v_max"] == pytest.approx(float(cf["v"](tc)), rel=1e-12)
    assert cf["impulse_fraction"] == pytest.approx(M_PLATE * cf["v_max"] / (2 * P0 * THETA), rel=1e-12)
    # beta -> 0 (heavy plate) keeps the whole rigid-wall impulse
    assert taylor_exponential(P0, THETA, m=1e6)["impulse_fraction"] > 0.999


def test_taylor_ode_matches_closed_form():
    cf = taylor_exponential(P0, THETA)
    t = np.linspace(0.0, 6e-5, 601)
    v = taylor_plate(t, P0 * np.exp(-t / THETA), p_cav=0.0)
    assert v.max() == pytest.approx(cf["v_max"], rel=5e-4)   # sampled every 0.1 us
    assert t[v.argmax()] == pytest.approx(cf["t_cav"], abs=1.5e-6)
    assert v[100] == pytest.approx(float(cf["v"](t[100])), rel=5e-4)


def test_column_acoustic_limit_is_taylor():
    cf = taylor_exponential(P0, THETA)
    t = np.linspace(0.0, 1e-4, 2001)
    r = column_plate(t, P0 * np.exp(-t / THETA), 4e-5, 2e-4, length=0.01, eos="acoustic", p_cav=-1e15,
                     t_out=np.array([1e-5, cf["t_cav"]]))
    assert r["v"][0] == pytest.approx(float(cf["v"](1e-5)), rel=2e-3)
    assert r["v"][1] == pytest.approx(cf["v_max"], rel=2e-3)


def test_column_without_plate_carries_the_incident_wave():
    t = np.linspace(0.0, 1e-4, 2001)
    p = P0 * np.exp(-t / THETA)
    r = column_plate(t, p, 4e-5, 1e-4, length=0.01, eos="acoustic", plate=False)
    # the water's velocity at x = 0 is the incident wave's p/(rho c)
    assert np.interp(2e-5, r["t"], r["v"]) == pytest.approx(P0 * np.exp(-1.0) / (RHO_W * C_W), rel=1e-2)


def test_column_gruneisen_converges():
    t = np.linspace(0.0, 1e-4, 2001)
    p = 2e8 * np.exp(-t / THETA)
    vs = [column_plate(t, p, 4e-5, dx, length=0.01, t_out=np.array([4e-5]))["v"][0] for dx in (4e-4, 2e-4, 1e-4)]
    order, ext = observed_order(*vs)
    assert order > 0.3
    # water's Hugoniot stiffens the radiation load: below Taylor's linear plate
    assert ext < taylor_exponential(2e8, THETA)["v_max"]
    assert abs(vs[-1] - ext) < 0.01 * ext


def test_hugoniot_velocity():
    up = float(hugoniot_velocity(2e8))
    assert 2e8 == pytest.approx(RHO_W * (C_W + 1.92 * up) * up, rel=1e-12)
    assert float(hugoniot_velocity(-1e5)) == pytest.approx(-1e5 / (RHO_W * C_W))


def test_strip_plate_2d_plane_limits():
    from tests.verification.plate_shock_reference import strip_plate_2d
    t = np.linspace(0.0, 1e-4, 2001)
    p = np.where(t > 1e-5, P0 * np.exp(-(t - 1e-5) / THETA), 0.0)
    plane = strip_plate_2d(t, p, 6e-5, dx=4e-3, dt=1e-6, plane=True)
    vt = taylor_plate(t, p)
    assert np.interp(5e-5, plane["t"], plane["v_centre"]) == pytest.approx(np.interp(5e-5, t, vt), rel=5e-3)
    # a plane incident wave (line source far away) on the finite strip plate: the centre moves as the
    # infinite plate until the edges' signal arrives (half_span / c = 100 us)
    far = strip_plate_2d(t, p, 6e-5, standoff=1e4, dx=4e-3, dt=1e-6)
    assert np.interp(5e-5, far["t"], far["v_centre"]) == pytest.approx(
        np.interp(5e-5, plane["t"], plane["v_centre"]), rel=2e-3)
    # the cylindrical wave of the 2D charge (R = 0.1 m) loads the centre's neighbours later and
    # the centre's radiation load is relieved: it moves faster than the plane-wave plate
    near = strip_plate_2d(t, p, 6e-5, dx=4e-3, dt=1e-6)
    assert np.interp(5e-5, near["t"], near["v_centre"]) > np.interp(5e-5, plane["t"], plane["v_centre"])
