"""Low-pass filters for probe histories, applied after the run to a copy of the raw series.

``butterworth`` (zero phase, the usual treatment of impact-pressure records): the digital
Butterworth filter of order n by the bilinear transform, run forward and then backward over the
series (no phase lag, so a filtered peak stays at its time). One pass has
|H(f)|² = 1 / (1 + (tan(π f/fs) / tan(π f_d/fs))^(2n)); the two passes square it, so the design
frequency f_d is set from the stated cutoff f_c by

    tan(π f_d/fs) = tan(π f_c/fs) / (√2 − 1)^(1/(2n)),

which puts the −3 dB point (|H| = 1/√2) of the whole forward–backward filter exactly at f_c
(Oppenheim & Schafer, Discrete-Time Signal Processing, §7.1 for the bilinear design; Gustafsson
1996, IEEE Trans. Signal Process. 44, for forward–backward filtering). The filter runs as cascaded
second-order sections (direct form II transposed), each started in its steady state for the first
(last) sample, after an odd reflection of 3·fs/f_c samples at each end (capped at the series' length),
so a series that starts at rest is not given a start-up transient.

``running_mean`` (causal): the mean of the series over the trailing window [t − T, t] (the
trapezoidal rule on the samples, the first T of the series averaged over what there is). It is what
a data logger's averaging channel reports; its amplitude response is |sin(π f T)/(π f T)|, −3 dB at
f ≈ 0.443/T.

History rows are written at the first step after each history time, so their spacing varies by up
to one step: both filters run on the series resampled linearly onto a uniform grid of the mean
spacing (fs = 1 / mean spacing), and the result is interpolated back onto the recorded times.
"""
from __future__ import annotations

import numpy as np

FILTERED = "_filtered"  # a probe's low-passed table is <probe>_filtered.csv, beside its raw table

KINDS = ("butterworth", "running_mean")
MAX_ORDER = 8


def _sections(cutoff_over_fs: float, order: int) -> list[tuple[np.ndarray, np.ndarray]]:
    """Second-order sections (b, a) of the digital Butterworth low-pass with the stated cutoff as the
    −3 dB point of the forward–backward pass (module docstring); unit gain at f = 0."""
    warped = np.tan(np.pi * cutoff_over_fs) / (np.sqrt(2.0) - 1.0) ** (1.0 / (2 * order))
    k = np.arange(order)
    s = np.exp(1j * np.pi * (2 * k + order + 1) / (2 * order))  # analog poles of |H|² = 1/(1 + Ω^2n), Ω_c = 1
    z = (1.0 + warped * s) / (1.0 - warped * s)  # bilinear map with the prewarped cutoff
    out = []
    for p in z[np.imag(z) > 1e-12]:
        a = np.array([1.0, -2.0 * p.real, abs(p) ** 2])
        out.append((np.array([1.0, 2.0, 1.0]) * a.sum() / 4.0, a))
    for p in z[np.abs(np.imag(z)) <= 1e-12]:
        a = np.array([1.0, -p.real, 0.0])
        out.append((np.array([1.0, 1.0, 0.0]) * a.sum() / 2.0, a))
    return out


def _run(b: np.ndarray, a: np.ndarray, x: np.ndarray) -> np.ndarray:
    """One section over x (direct form II transposed), started at rest at the value x[0]."""
    y = np.empty_like(x)
    z1 = (1.0 - b[0]) * x[0]
    z2 = (b[2] - a[2]) * x[0]
    for i, xi in enumerate(x):
        yi = b[0] * xi + z1
        z1 = b[1] * xi - a[1] * yi + z2
        z2 = b[2] * xi - a[2] * yi
        y[i] = yi
    return y


def butterworth(y: np.ndarray, cutoff_over_fs: float, order: int) -> np.ndarray:
    """Zero-phase Butterworth low-pass of a uniformly sampled series (module docstring)."""
    if not 0.0 < cutoff_over_fs < 0.5:
        raise ValueError(f"cutoff must lie below the Nyquist frequency (cutoff/fs = {cutoff_over_fs:g})")
    y = np.asarray(y, dtype=float)
    if y.size < 2:
        return y.copy()
    pad = int(min(y.size - 1, np.ceil(3.0 / cutoff_over_fs)))
    x = np.concatenate([2.0 * y[0] - y[pad:0:-1], y, 2.0 * y[-1] - y[-2:-pad - 2:-1]])
    sections = _sections(cutoff_over_fs, order)
    for b, a in sections:
        x = _run(b, a, x)
    x = x[::-1]
    for b, a in sections:
        x = _run(b, a, x)
    return x[::-1][pad:pad + y.size]


def running_mean(t: np.ndarray, y: np.ndarray, window: float) -> np.ndarray:
    """Causal mean over [t − window, t] of a series sampled at times t (trapezoidal rule)."""
    t, y = np.asarray(t, dtype=float), np.asarray(y, dtype=float)
    area = np.concatenate([[0.0], np.cumsum(0.5 * (y[1:] + y[:-1]) * np.diff(t))])
    start = np.maximum(t - window, t[0])
    area_start = np.interp(start, t, area)
    span = t - start
    out = y.copy()
    ok = span > 0.0
    out[ok] = (area[ok] - area_start[ok]) / span[ok]
    return out


def low_pass(t, y, kind: str, cutoff: float | None = None, order: int = 2, window: float | None = None) -> np.ndarray:
    """The filtered series at the recorded times `t` (module docstring); NaN samples are bridged by
    linear interpolation and stay NaN in the result."""
    t, y = np.asarray(t, dtype=float), np.asarray(y, dtype=float)
    if kind not in KINDS:
        raise ValueError(f"unknown filter kind {kind!r} (kinds: {', '.join(KINDS)})")
    good = np.isfinite(y)
    out = np.full_like(y, np.nan)
    if good.sum() < 2:
        out[good] = y[good]
        return out
    tg, yg = t[good], y[good]
    n = tg.size
    grid = np.linspace(tg[0], tg[-1], n)
    uniform = np.interp(grid, tg, yg)
    if kind == "butterworth":
        fs = (n - 1) / (tg[-1] - tg[0])
        filtered = butterworth(uniform, cutoff / fs, order)
    else:
        filtered = running_mean(grid, uniform, window)
    out[good] = np.interp(tg, grid, filtered)
    return out


def describe(kind: str, cutoff: float | None = None, order: int = 2, window: float | None = None) -> str:
    """One line naming the filter (the header of a filtered table)."""
    if kind == "butterworth":
        return f"zero-phase Butterworth low-pass, order {order}, -3 dB at {cutoff:g} [1/time]"
    return f"causal running mean over the trailing {window:g} [time]"
