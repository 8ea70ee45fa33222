"""Mesh-study metrics on manufactured histories with known error: L2, peak, time of peak,
observed order, Richardson extrapolation and GCI."""
from __future__ import annotations

import math

import numpy as np
import pytest

from sphfem_cli.study import metrics


def _write(path, columns, rows):
    path.write_text(",".join(columns) + "\n" + "\n".join(",".join(f"{v:.15e}" for v in r) for r in rows) + "\n")


def test_l2_and_peak_of_a_scaled_history():
    t = np.linspace(0.0, 1.0, 2001)
    ref = np.sin(np.pi * t)
    err = metrics.history_error(t, 1.03 * ref, t, ref)
    assert err.l2 == pytest.approx(0.03, rel=1e-9)  # ||0.03 r|| / ||r||
    assert err.peak == pytest.approx(0.03, rel=1e-9)
    assert err.peak_time == pytest.approx(0.0, abs=1e-12)
    assert err.reference_peak == pytest.approx(1.0, rel=1e-6)


def test_interpolation_onto_reference_times_and_time_of_peak():
    t_ref = np.linspace(0.0, 2.0, 4001)
    ref = np.exp(-((t_ref - 1.0) / 0.2) ** 2)
    t = np.linspace(0.0, 2.0, 1601)  # other times, peak shifted by 0.05
    q = np.exp(-((t - 1.05) / 0.2) ** 2)
    err = metrics.history_error(t, q, t_ref, ref)
    assert err.peak_time == pytest.approx(0.05, abs=1e-3)
    assert err.peak_time_rel == pytest.approx(0.025, abs=1e-3)
    # ||g(t - a) - g(t)||^2 / ||g||^2 = 2 (1 - exp(-a^2 / (2 s^2))) for a Gaussian g of width s
    expected = math.sqrt(2.0 * (1.0 - math.exp(-0.05**2 / (2 * 0.2**2))))
    assert err.l2 == pytest.approx(expected, rel=1e-3)


def test_only_the_common_time_range_counts():
    t_ref = np.linspace(0.0, 2.0, 201)
    ref = np.ones_like(t_ref)
    t = np.linspace(0.0, 1.0, 101)  # a run that stopped half way, exact while it ran
    err = metrics.history_error(t, np.ones_like(t), t_ref, ref)
    assert err.l2 == pytest.approx(0.0, abs=1e-14)


@pytest.mark.parametrize("p, hs", [(2.0, (0.01, 0.02, 0.04)), (1.0, (1 / 3, 1 / 2, 1.0)), (1.7, (0.1, 0.15, 0.3))])
def test_three_grid_recovers_order_and_exact_value(p, hs):
    exact, c = 2.5, 0.8
    phi = [exact + c * h**p for h in hs]
    conv = metrics.three_grid(hs, phi)
    assert conv.order == pytest.approx(p, rel=1e-8)
    assert conv.extrapolated == pytest.approx(exact, rel=1e-10)
    r21 = hs[1] / hs[0]
    ea = abs((phi[0] - phi[1]) / phi[0])
    assert conv.gci_fine == pytest.approx(1.25 * ea / (r21**p - 1), rel=1e-8)
    # in the asymptotic range GCI_medium = r21^p GCI_fine, up to the relative errors' phi1/phi2
    assert conv.asymptotic == pytest.approx(phi[0] / phi[1], rel=1e-8)
    assert conv.monotone


def test_three_grid_input_order_does_not_matter():
    hs, phi = (0.04, 0.01, 0.02), [1.0 + 3.0 * h**2 for h in (0.04, 0.01, 0.02)]
    assert metrics.three_grid(hs, phi).order == pytest.approx(2.0, rel=1e-8)


def test_three_grid_oscillating_is_not_monotone():
    conv = metrics.three_grid((0.01, 0.02, 0.04), (1.0, 1.1, 1.0 + 0.1 - 0.3))
    assert not conv.monotone


def test_manufactured_histories_through_the_files(tmp_path):
    """A history whose amplitude error is C h^p: peak values give p and the exact peak back."""
    t = np.linspace(0.0, 1e-3, 501)
    exact_peak, c, p = 0.002, 0.5, 2.0
    runs = {}
    for h in (0.01, 0.02, 0.04):
        d = tmp_path / f"h{h}"
        d.mkdir()
        amp = exact_peak * (1.0 + c * h**p)
        _write(d / "plate.csv", ["time", "displacement_x", "displacement_y"],
               np.stack([t, 0.6 * amp * np.sin(np.pi * t / 1e-3), 0.8 * amp * np.sin(np.pi * t / 1e-3)], axis=1))
        runs[h] = d
    ref_dir = tmp_path / "ref"
    ref_dir.mkdir()
    _write(ref_dir / "plate.csv", ["time", "displacement_x", "displacement_y"],
           np.stack([t, 0.6 * exact_peak * np.sin(np.pi * t / 1e-3), 0.8 * exact_peak * np.sin(np.pi * t / 1e-3)], axis=1))
    assert metrics.default_quantities(ref_dir) == ["plate.displacement"]
    ref = metrics.quantity_series(ref_dir, "plate.displacement")
    peaks, l2 = [], []
    for h, d in runs.items():
        e = metrics.history_error(*metrics.quantity_series(d, "plate.displacement"), *ref)
        peaks.append(e.peak_value)
        l2.append(e.l2)
        assert e.l2 == pytest.approx(c * h**p, rel=1e-9)
        assert e.peak == pytest.approx(c * h**p, rel=1e-6)
    conv = metrics.three_grid(list(runs), peaks)
    assert conv.order == pytest.approx(p, rel=1e-6)
    assert conv.extrapolated == pytest.approx(exact_peak, rel=1e-8)
    fit = metrics.power_fit(list(runs), l2)
    assert fit[1] == pytest.approx(p, rel=1e-9) and fit[0] == pytest.approx(c, rel=1e-9)


def test_quantity_names_a_missing_column(tmp_path):
    _write(tmp_path / "plate.csv", ["time", "von_mises"], [[0.0, 1.0], [1.0, 2.0]])
    with pytest.raises(KeyError, match="no column or family 'velocity'"):
        metrics.quantity_series(tmp_path, "plate.velocity")


def test_three_grid_refuses_an_order_to_a_growing_change():
    """0.813 / 0.822 / 0.836 at h 4 / 2 / 1 (the r-z ALE bird's window force): the change grows as h
    halves, which no positive order gives; Celik's |ln| would have said p = 0.64 and extrapolated 0.861."""
    conv = metrics.three_grid((1.0, 2.0, 4.0), (0.836, 0.822, 0.813))
    assert conv.monotone and conv.diverging
    assert math.isnan(conv.order) and math.isnan(conv.extrapolated) and math.isnan(conv.gci_fine)
    converging = metrics.three_grid((1.0, 2.0, 4.0), (0.836, 0.830, 0.813))
    assert not converging.diverging and converging.order == pytest.approx(math.log2(17 / 6), rel=1e-12)
