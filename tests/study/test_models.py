"""Mesh-study models on manufactured data: the error model with a floor and when the data support
it, the linear cost/memory fits and their prediction intervals, the stable-step law, and units."""
from __future__ import annotations

import numpy as np
import pytest

from sphfem_cli.study import models
from sphfem_cli.study.units import unit_of


def test_floor_model_recovers_floor_and_order():
    r = np.array([1.0, 2.0, 3.0, 4.0, 6.0])
    e = 0.17 + 0.3 * r**-1.5
    m = models.fit_error(r, e)
    assert m.form == "floor"
    assert m.floor == pytest.approx(0.17, rel=1e-4) and m.order == pytest.approx(1.5, rel=1e-3)
    assert m.solve(0.10) is None  # below the floor: not reachable
    assert m.solve(0.2) == pytest.approx((0.3 / 0.03) ** (1 / 1.5), rel=1e-3)


def test_power_law_when_three_points_or_no_floor():
    r = np.array([1.0, 2.0, 3.0])
    m = models.fit_error(r, 0.2 + 0.1 * r**-2)
    assert m.form == "power" and "at least four" in m.reason
    pure = np.array([1.0, 2.0, 3.0, 4.0])
    m = models.fit_error(pure, 0.2 * pure**-1.2)
    assert m.form == "power" and m.floor == 0.0
    assert m.order == pytest.approx(1.2, rel=1e-9) and m.c == pytest.approx(0.2, rel=1e-9)
    assert m.solve(0.05) == pytest.approx(4.0 ** (1 / 1.2), rel=1e-9)
    rising = models.fit_error(r, 0.1 * r**0.5)
    assert rising.order < 0 and rising.solve(0.01) is None


def test_worst_error_is_the_largest_per_quantity_model():
    """A fast quantity (order 1.2) worst at coarse ratios, a slow one (order 0.2) beyond: the worst
    series bends, and the envelope of the two models follows it where one law through it cannot."""
    r = np.array([1.0, 2.0, 3.0])
    fast, slow = 0.5 * r**-1.2, 0.15 * r**-0.2
    worst = models.WorstError({"p": models.fit_error(r, fast), "vm": models.fit_error(r, slow)})
    assert worst.governing(1.0) == "p" and worst.governing(8.0) == "vm"
    assert worst(8.0) == pytest.approx(0.15 * 8.0**-0.2, rel=1e-9)
    assert worst.predict(8.0)[0] == pytest.approx(worst(8.0), rel=1e-12)
    single = models.fit_error(r, np.maximum(fast, slow))
    assert single(8.0) < 0.85 * worst(8.0)  # one law through the worst series: 58 % low at ratio 8
    # every quantity within 10 %: the slow one decides, (0.15 / 0.1)^(1 / 0.2)
    assert worst.solve(0.10) == (pytest.approx(1.5**5, rel=1e-9), None)
    # a floor above the tolerance forbids it, and names the quantity
    floored = models.WorstError({"p": models.fit_error(r, fast),
                                 "vm": models.ErrorModel("floor", 0.12, 0.1, 1.0, 4, 0.0, "")})
    assert floored.solve(0.10) == (None, "vm")
    # an error that does not fall counts as its largest measured value: binding only above the tolerance
    rising = models.fit_error(r, np.array([0.010, 0.006, 0.017]))
    assert rising.order < 0
    both = models.WorstError({"p": models.fit_error(r, fast), "u": rising})
    assert both(1e3) == pytest.approx(0.017) and both.governing(1e3) == "u"
    assert both.solve(0.10)[1] is None and both.solve(0.012) == (None, "u")


def test_prediction_interval_from_residuals():
    rng = np.random.default_rng(3)
    x = np.linspace(1e4, 1e6, 12)
    noise = 1.0 + 0.02 * rng.standard_normal(len(x))
    y = (2.0 + 3e-5 * x) * noise
    fit = models.linear_fit(x, y)
    assert fit.a == pytest.approx(2.0, rel=0.2) and fit.c == pytest.approx(3e-5, rel=0.05)
    assert fit.s == pytest.approx(0.02, rel=0.6)
    value, (lo, hi) = fit.predict(2e6)  # extrapolated: a wider interval than inside the data
    _, (lo_in, hi_in) = fit.predict(5e5)
    assert lo < value < hi and (hi - lo) / value > (hi_in - lo_in) / fit.predict(5e5)[0]
    exact = models.linear_fit([1.0, 2.0], [3.0, 5.0])
    assert exact.a == pytest.approx(1.0) and exact.c == pytest.approx(2.0)
    assert exact.predict(3.0) == (pytest.approx(7.0), None)  # two points: no residuals, no interval


def test_interval_covers_the_truth_for_the_error_model():
    r = np.array([1.0, 2.0, 3.0, 4.0, 5.0, 6.0])
    rng = np.random.default_rng(11)
    e = (0.05 + 0.4 * r**-1.3) * (1.0 + 0.01 * rng.standard_normal(len(r)))
    m = models.fit_error(r, e)
    value, (lo, hi) = m.predict(9.0)
    assert lo < 0.05 + 0.4 * 9.0**-1.3 < hi


def test_stable_step_law():
    dt0 = {"solid": 0.71e-6, "sph": 0.61e-6, "contact": 5e-6}
    # at ratio 3 the particles set the step; at 6 their step halves
    assert models.steps_at(dt0, 4918, 3, 6, "sph") == pytest.approx(2 * 4918)
    dt0 = {"solid": 0.71e-6, "sph": 1.83e-6}
    # the solid sets the step until the particles' falls below it (ratio 1 -> 3: 1.83/3 = 0.61 us)
    assert models.steps_at(dt0, 4392, 1, 2, "sph") == pytest.approx(4392)
    assert models.steps_at(dt0, 4392, 1, 3, "sph") == pytest.approx(4392 * 0.71 / 0.61, rel=1e-12)


@pytest.mark.parametrize("column, units, dim, expected", [
    ("mid.displacement", {"length": "m", "mass": "kg", "time": "s"}, 2, "m"),
    ("mid.velocity_x", {"length": "mm", "mass": "t", "time": "s"}, 2, "mm/s"),
    ("clamp.von_mises", {"length": "mm", "mass": "t", "time": "s"}, 3, "MPa"),
    ("glstat.kinetic", {"length": "m", "mass": "kg", "time": "s"}, 2, "J/m"),
    ("glstat.kinetic", {"length": "m", "mass": "kg", "time": "s"}, 3, "J"),
    ("glstat.energy_ratio", None, 2, "-"),
    ("time", {"length": "mm", "mass": "kg", "time": "ms"}, 2, "ms"),
    ("ale_materials.mass_water", None, 2, "kg/m"),
    ("plate.contact_force_y", None, 3, "N"),
])
def test_units_of_history_columns(column, units, dim, expected):
    assert unit_of(column, units, dim) == expected
