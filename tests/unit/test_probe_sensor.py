"""Sensor-sized probes and their low-pass filters (issue 18 item 4).

- The sensor's quadrature (model/sensors.py) averages linear and quadratic fields exactly over a
  wall face (segment in 2D, disc in 3D), a disc and a ball: the exact means are worked out by hand
  (mean of s² over a segment of half-length R is R²/3, of r² over a disc R²/2, over a ball 3R²/5).
- The zero-phase Butterworth passes a steady signal unchanged, puts its -3 dB point at the stated
  cutoff (|H| = 1/√2 within 0.5 %, orders 1, 2, 4) and shifts no peak; the running mean's response
  is the sinc |sin(π f T)/(π f T)| within 1 %.
- A run writes the raw probe table and, for a probe with a filter, <name>_filtered beside it.
- Bad sensor and filter settings are one-line deck errors with file:line:col.
"""
from __future__ import annotations

import re
import textwrap

import numpy as np
import pytest
from click.testing import CliRunner

from sphfem_cli.cli import main
from sphfem_cli.driver import DeckProblem as DeckError
from sphfem_cli.driver import load_model
from sphfem_cli.model.sensors import sensor_mean, sensor_points
from sphfem_cli.output.filters import butterworth, low_pass, running_mean


def _quadratic(x):
    """A full quadratic in 2 or 3 coordinates: 1 + Σ a_i x_i + Σ b_ij x_i x_j."""
    a = np.array([0.7, -1.3, 0.4])[: x.shape[1]]
    b = np.array([[2.0, 0.5, -0.3], [0.5, -1.0, 0.8], [-0.3, 0.8, 1.5]])[: x.shape[1], : x.shape[1]]
    return 1.0 + x @ a + np.einsum("pi,ij,pj->p", x, b, x)


def _exact_mean(c, radius, second_moment):
    """Mean of _quadratic over a region centred at c with ∫(x−c)(x−c)ᵀ / |region| = second_moment."""
    dim = len(c)
    b = np.array([[2.0, 0.5, -0.3], [0.5, -1.0, 0.8], [-0.3, 0.8, 1.5]])[:dim, :dim]
    return _quadratic(c[None, :])[0] + float(np.sum(b * second_moment))


@pytest.mark.parametrize("centre, normal, moment", [
    ((0.3, -0.2), (-1.0, 0.0), lambda r, n: r * r / 3.0 * np.outer([0, 1], [0, 1])),           # face in a wall x = const
    ((0.3, -0.2), (0.6, 0.8), lambda r, n: r * r / 3.0 * np.outer([-0.8, 0.6], [-0.8, 0.6])),  # inclined wall
    ((0.3, -0.2), None, lambda r, n: r * r / 4.0 * np.eye(2)),                                  # disc
    ((0.3, -0.2, 0.5), (0.0, 0.0, 1.0), lambda r, n: r * r / 4.0 * np.diag([1.0, 1.0, 0.0])),   # face disc in 3D
    ((0.3, -0.2, 0.5), None, lambda r, n: r * r / 5.0 * np.eye(3)),                             # ball
])
def test_sensor_mean_of_linear_and_quadratic_fields_is_exact(centre, normal, moment):
    c = np.array(centre)
    diameter = 0.05
    points, weights = sensor_points(c, diameter, normal)
    assert weights.sum() == pytest.approx(1.0, abs=1e-14)
    linear = 2.0 + points @ np.arange(1.0, len(c) + 1.0)
    assert sensor_mean(linear, weights) == pytest.approx(2.0 + c @ np.arange(1.0, len(c) + 1.0), rel=1e-13)
    expected = _exact_mean(c, 0.5 * diameter, moment(0.5 * diameter, normal))
    assert sensor_mean(_quadratic(points), weights) == pytest.approx(expected, rel=1e-13)
    if normal is not None:  # the face lies in the wall: no sample point off the plane through c
        n = np.array(normal) / np.linalg.norm(normal)
        assert np.max(np.abs((points - c) @ n)) < 1e-15
    assert np.max(np.linalg.norm(points - c, axis=1)) <= 0.5 * diameter * (1 + 1e-12)


def test_a_dry_sample_point_reads_zero_and_no_sensor_is_the_point():
    points, weights = sensor_points((0.0, 0.0), 0.0)
    assert points.shape == (1, 2) and weights.tolist() == [1.0]
    p, w = sensor_points((0.0, 0.0), 0.1, (1.0, 0.0))
    values = np.where(p[:, 1] > 0.0, np.nan, 100.0)  # upper half of the face above the free surface
    assert sensor_mean(values, w) == pytest.approx(50.0, rel=1e-12)


@pytest.mark.parametrize("order", [1, 2, 4])
def test_butterworth_minus_3_db_at_the_cutoff_and_zero_phase(order):
    fs, fc = 20000.0, 800.0
    t = np.arange(0.0, 0.5, 1.0 / fs)
    mid = slice(len(t) // 4, 3 * len(t) // 4)  # away from the ends
    for f, low, high in ((fc, 1 / np.sqrt(2) * 0.995, 1 / np.sqrt(2) * 1.005), (0.1 * fc, 0.99, 1.0 + 1e-9)):
        y = np.sin(2.0 * np.pi * f * t)
        out = butterworth(y, fc / fs, order)
        gain = np.sqrt(2.0 * np.mean(out[mid] ** 2))
        assert low <= gain <= high, (f, gain)
        lag = np.argmax(np.correlate(out[mid], y[mid], "full")) - (len(y[mid]) - 1)
        assert lag == 0  # no phase lag
    steady = butterworth(np.full(400, 3.25), fc / fs, order)
    assert np.allclose(steady, 3.25, rtol=1e-12)  # unit gain at f = 0, no start-up transient
    pulse = np.exp(-(((t - 0.2) / 2e-3) ** 2))
    assert t[np.argmax(butterworth(pulse, fc / fs, order))] == pytest.approx(0.2, abs=1.0 / fs)
    with pytest.raises(ValueError, match="Nyquist"):
        butterworth(pulse, 0.5, order)


def test_running_mean_is_causal_with_the_sinc_response():
    fs, window = 10000.0, 2e-3
    t = np.arange(0.0, 0.4, 1.0 / fs)
    for f in (50.0, 221.5, 400.0):  # 221.5 Hz = 0.443 / window: -3 dB
        out = running_mean(t, np.sin(2.0 * np.pi * f * t), window)
        gain = np.sqrt(2.0 * np.mean(out[len(t) // 4:] ** 2))
        x = np.pi * f * window
        assert gain == pytest.approx(abs(np.sin(x) / x), rel=0.01)
    step = np.where(t >= 0.1, 1.0, 0.0)
    out = running_mean(t, step, window)
    assert np.all(out[t < 0.1] == 0.0)  # causal: nothing before the step
    assert out[np.searchsorted(t, 0.1 + window) + 1] == pytest.approx(1.0)


def test_low_pass_on_uneven_rows_and_gaps():
    rng = np.random.default_rng(3)
    t = np.cumsum(1e-4 * (1.0 + 0.2 * rng.random(4000)))  # rows at the first step after each history time
    y = 2.0 + np.sin(2.0 * np.pi * 10.0 * t)
    y[100] = np.nan
    out = low_pass(t, y, "butterworth", cutoff=500.0, order=2)
    assert np.isnan(out[100]) and np.all(np.isfinite(np.delete(out, 100)))
    assert np.max(np.abs(out[200:-200] - y[200:-200])[np.isfinite(y[200:-200])]) < 2e-3  # 10 Hz passes


BASE = """\
title: probe deck
dimension: 2
control: {end_time: 0.004}
equations_of_state:
  water: {type: tait, reference_density: 1000.0, sound_speed: 20.0}
materials:
  water: {type: fluid, density: 1000.0, eos: water}
sections:
  fluid: {type: sph}
parts:
  pool: {material: water, section: fluid, geometry: {box: {min: [0.0, 0.0], max: [0.1, 0.05]}}, spacing: 0.005,
         hydrostatic: true}
boundaries:
  - {type: wall, min: [0.0, 0.0], max: [0.1, 0.1], sides: [left, right, bottom], condition: slip}
loads:
  - {type: gravity, acceleration: [0.0, -9.81]}
output:
  history_interval: 0.0001
  probes:
"""


@pytest.mark.parametrize("probe, line, message", [
    ("{name: a, type: front, sensor: {diameter: 0.01}}", 20, "only a pressure probe takes a sensor"),
    ("{name: a, type: pressure, point: [0.1, 0.01], sensor: {diameter: 0.0}}", 20, "must be > 0"),
    ("{name: a, type: pressure, point: [0.1, 0.01], sensor: {diameter: 0.01, normal: [0.0, 0.0]}}", 20,
     "zero vector"),
    ("{name: a, type: pressure, point: [0.1, 0.01], sensor: {diameter: 0.01, normal: [1.0, 0.0, 0.0]}}", 20, "2"),
    ("{name: a, type: pressure, point: [0.1, 0.01], filter: {kind: butterworth}}", 20, "needs 'cutoff'"),
    ("{name: a, type: pressure, point: [0.1, 0.01], filter: {kind: butterworth, cutoff: 5000.0}}", 20,
     "Nyquist frequency 5000"),
    ("{name: a, type: pressure, point: [0.1, 0.01], filter: {kind: butterworth, cutoff: 100.0, order: 9}}", 20,
     "must be <= 8"),
    ("{name: a, type: pressure, point: [0.1, 0.01], filter: {kind: running_mean, window: 1.0e-5}}", 20,
     "shorter than the history_interval"),
    ("{name: a, type: pressure, point: [0.1, 0.01], filter: {kind: running_mean, cutoff: 10.0, window: 0.001}}",
     20, "'cutoff' is for butterworth"),
    ("{name: a, type: pressure, point: [0.1, 0.01], filter: {kind: lowpass, cutoff: 10.0}}", 20, "butterworth"),
])
def test_bad_sensor_and_filter_settings_are_one_line_deck_errors(tmp_path, probe, line, message):
    deck = tmp_path / "bad.yaml"
    deck.write_text(BASE + f"    - {probe}\n")
    with pytest.raises(DeckError) as info:
        load_model(deck)
    text = str(info.value)
    assert "\n" not in text and re.match(rf"^{re.escape(str(deck))}:{line}:\d+: \S+: .+", text), text
    assert message in text, text
    result = CliRunner().invoke(main, ["check", str(deck)])
    assert result.exit_code == 65 and "Traceback" not in result.output


def test_filtered_table_clashing_with_another_history_is_a_deck_error(tmp_path):
    deck = tmp_path / "bad.yaml"
    deck.write_text(BASE + "    - {name: a, type: pressure, point: [0.1, 0.01], filter: {kind: running_mean, "
                    "window: 0.001}}\n    - {name: a_filtered, type: front}\n")
    with pytest.raises(DeckError, match="'a_filtered' is another history's name"):
        load_model(deck)


def test_a_run_keeps_the_raw_table_and_writes_the_filtered_one(tmp_path):
    deck = tmp_path / "pool.yaml"
    deck.write_text(BASE + textwrap.indent(textwrap.dedent("""\
        - {name: wall, type: pressure, point: [0.1, 0.01], sensor: {diameter: 0.01, normal: [-1.0, 0.0]},
           filter: {kind: butterworth, cutoff: 1000.0, order: 2}}
        - {name: centre, type: pressure, point: [0.1, 0.01]}
        - {name: mean, type: pressure, point: [0.1, 0.01], filter: {kind: running_mean, window: 0.001}}
        """), "    "))
    out = tmp_path / "run"
    result = CliRunner().invoke(main, ["run", str(deck), "-o", str(out), "--quiet"])
    assert result.exit_code == 0, result.output
    hist = out / "histories"
    raw = np.loadtxt(hist / "wall.csv", delimiter=",", skiprows=1)
    filtered = np.loadtxt(hist / "wall_filtered.csv", delimiter=",", skiprows=1)
    centre = np.loadtxt(hist / "centre.csv", delimiter=",", skiprows=1)
    assert (hist / "wall_filtered.csv").read_text().splitlines()[0] == "time,pressure"
    assert np.array_equal(raw[:, 0], filtered[:, 0]) and len(raw) >= 40
    # a hydrostatic pool at rest: the pressure is linear in y, so the face's mean is the centre's value
    # (up to the interpolation's own error, 2 % of rho g h here)
    assert np.allclose(raw[:, 1], centre[:, 1], rtol=0.02, atol=0.02 * 1000 * 9.81 * 0.05)
    assert not (hist / "centre_filtered.csv").exists() and (hist / "mean_filtered.csv").exists()
    assert np.allclose(filtered[:, 1], low_pass(raw[:, 0], raw[:, 1], "butterworth", cutoff=1000.0, order=2))
    import h5py

    with h5py.File(out / "results.h5", "r") as f:
        assert np.allclose(f["histories/wall_filtered"][()], filtered)


def test_saved_run_probe_with_a_sensor_and_a_filter(tmp_path):
    from sphfem_cli.output import GridStep, XdmfWriter
    from sphfem_cli.output.probe import probe

    run = tmp_path / "saved"
    run.mkdir()
    (run / "deck.effective.yaml").write_text("sections: {fluid: {type: sph, kernel: cubic_spline}}\n")
    g = np.arange(-6, 7) * 0.1
    px, py = np.meshgrid(g, g, indexing="ij")
    particles = np.column_stack([px.ravel(), py.ravel()])
    times = np.linspace(0.0, 0.1, 201)
    with XdmfWriter(run) as w:
        w.add_grid("water", "Polyvertex", None, len(particles))
        for t in times:
            w.write_step(t, {"water": GridStep(particles, {
                "pressure": 5.0 + np.sin(2 * np.pi * 20.0 * t) + np.full(len(particles), 0.0),
                "mass": np.full(len(particles), 10.0), "density": np.full(len(particles), 1000.0),
                "smoothing_length": np.full(len(particles), 0.12)})})
    table = probe(run, (0.0, 0.0), "pressure", sensor=0.2, normal=(1.0, 0.0),
                  filtering={"kind": "butterworth", "cutoff": 500.0, "order": 2})
    assert table.columns == ["time", "pressure", "pressure_filtered"]
    assert np.allclose(table.rows[:, 1], 5.0 + np.sin(2 * np.pi * 20.0 * times), rtol=1e-12)  # uniform field
    result = CliRunner().invoke(main, ["probe", str(run), "--point", "0,0", "--quantity", "pressure",
                                       "--sensor-diameter", "0.2", "--normal", "1,0", "--filter", "running_mean:0.01"])
    assert result.exit_code == 0, result.output
    result = CliRunner().invoke(main, ["probe", str(run), "--point", "0,0", "--quantity", "pressure",
                                       "--filter", "butterworth:-3"])
    assert result.exit_code == 2 and "butterworth:CUTOFF" in result.output
