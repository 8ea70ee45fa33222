"""Error metrics and grid convergence (Richardson, Roache's GCI) of the mesh study (the fitted
models are in ``models``).

Quantities are named ``TABLE.COLUMN`` after the history CSVs of a run (``histories/TABLE.csv``):
``COLUMN`` is a column (``displacement_y``, ``von_mises``) or a vector family (``displacement``: the
magnitude of ``displacement_x``, ``displacement_y`` [, ``displacement_z``]).

Errors of a history q(t) against a reference r(t) (q interpolated onto the reference's times, over
the times both cover):

- normalised L2: sqrt(int (q - r)^2 dt / int r^2 dt), trapezoidal rule;
- peak error: (max|q| - max|r|) / max|r|;
- time-of-peak error: t(max|q|) - t(max|r|), and that over the reference's duration.

A quantity may be compared as a low-passed series (the study's ``filters``, docs/mesh-study.md):
the same filter (``output.filters.low_pass``: zero-phase Butterworth or causal running mean) is
applied to the case's and the reference's own series before the errors; raw samples otherwise.

Convergence over three grids h1 < h2 < h3 (Celik et al. 2008, J. Fluids Eng. 130, 078001): observed
order p from the fixed point p = |ln|e32/e21| + q(p)| / ln r21, q(p) = ln((r21^p - s)/(r32^p - s)),
s = sign(e32/e21); Richardson value phi_ext = (r21^p phi1 - phi2)/(r21^p - 1); GCI_fine =
Fs |(phi1 - phi2)/phi1| / (r21^p - 1) with Fs = 1.25.
"""
from __future__ import annotations

import math
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Sequence

import numpy as np

VECTOR_AXES = ("x", "y", "z")


def read_history(path: Path) -> tuple[list[str], np.ndarray]:
    """(column names, rows) of a history CSV; an empty table gives a (0, columns) array."""
    with Path(path).open() as f:
        columns = f.readline().strip().split(",")
    data = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)
    if data.size == 0:
        data = np.zeros((0, len(columns)))
    return columns, data


def history_columns(path: Path) -> dict[str, np.ndarray]:
    """A history CSV as {column name: values}."""
    columns, data = read_history(path)
    return {c: data[:, i] for i, c in enumerate(columns)}


def quantity_series(histories: Path, quantity: str) -> tuple[np.ndarray, np.ndarray]:
    """(t, q) of ``TABLE.COLUMN`` from a run's histories folder."""
    table, _, column = quantity.partition(".")
    if not column:
        raise KeyError(f"quantity '{quantity}': name it TABLE.COLUMN (e.g. plate.displacement)")
    path = Path(histories) / f"{table}.csv"
    if not path.exists():
        raise KeyError(f"quantity '{quantity}': no history table {path}")
    columns, data = read_history(path)
    t = data[:, columns.index("time")] if "time" in columns else data[:, 0]
    if column in columns:
        return t, data[:, columns.index(column)]
    parts = [f"{column}_{a}" for a in VECTOR_AXES if f"{column}_{a}" in columns]
    if not parts:
        raise KeyError(f"quantity '{quantity}': table {table} has no column or family '{column}' "
                       f"(columns: {', '.join(columns)})")
    comps = np.stack([data[:, columns.index(c)] for c in parts], axis=1)
    return t, np.sqrt(np.sum(comps**2, axis=1))


def compared_series(histories: Path, quantity: str, settings: dict | None = None) -> tuple[np.ndarray, np.ndarray]:
    """(t, q) of ``TABLE.COLUMN`` as the study compares it: raw, or low-passed with ``settings``
    (``output.filters.low_pass`` keywords: kind, cutoff and order, or window) on its own times."""
    t, q = quantity_series(histories, quantity)
    if settings is None or len(t) < 2:
        return t, q
    from ..output.filters import low_pass

    return t, low_pass(t, q, **settings)


def default_quantities(histories: Path) -> list[str]:
    """Every requested history's quantities (vector families as magnitudes); glstat kinetic if none.

    The tables every run writes (glstat, matsum, and ale_materials of ALE runs, which SPH runs lack)
    are not requested histories.
    """
    out: list[str] = []
    for path in sorted(Path(histories).glob("*.csv")):
        if path.stem in ("glstat", "matsum", "ale_materials"):
            continue
        columns, _ = read_history(path)
        seen: list[str] = []
        for c in columns[1:]:
            head, _, tail = c.rpartition("_")
            name = head if head and tail in VECTOR_AXES else c  # stress_xx etc. stay columns
            if name not in seen:
                seen.append(name)
        out += [f"{path.stem}.{n}" for n in seen]
    return out or ["glstat.kinetic"]


@dataclass
class HistoryError:
    l2: float  # normalised L2 over the common time range
    peak: float  # relative peak-value error (signed)
    peak_time: float  # time-of-peak error [time] (signed)
    peak_time_rel: float  # over the reference's duration
    peak_value: float  # max |q|
    reference_peak: float  # max |r|

    def as_dict(self) -> dict:
        return asdict(self)


def _trapezoid(y: np.ndarray, t: np.ndarray) -> float:
    return float(np.sum(0.5 * (y[1:] + y[:-1]) * np.diff(t))) if len(t) > 1 else 0.0


def history_error(t: np.ndarray, q: np.ndarray, t_ref: np.ndarray, r: np.ndarray) -> HistoryError:
    """Errors of q(t) against r(t_ref); q is interpolated onto the reference times it covers."""
    t, q, t_ref, r = (np.asarray(a, dtype=float) for a in (t, q, t_ref, r))
    if len(t) == 0 or len(t_ref) == 0:
        nan = float("nan")
        return HistoryError(nan, nan, nan, nan, nan, nan)
    keep = (t_ref >= t[0] - 1e-12 * max(1.0, abs(t[0]))) & (t_ref <= t[-1] + 1e-12 * max(1.0, abs(t[-1])))
    tr, rr = t_ref[keep], r[keep]
    qi = np.interp(tr, t, q)
    den = _trapezoid(rr**2, tr)
    l2 = math.sqrt(_trapezoid((qi - rr) ** 2, tr) / den) if den > 0 else float("nan")
    iq, ir = int(np.argmax(np.abs(q))), int(np.argmax(np.abs(r)))
    pq, pr = float(abs(q[iq])), float(abs(r[ir]))
    peak = (pq - pr) / pr if pr > 0 else float("nan")
    duration = float(t_ref[-1] - t_ref[0])
    dt_peak = float(t[iq] - t_ref[ir])
    return HistoryError(l2, peak, dt_peak, dt_peak / duration if duration > 0 else float("nan"), pq, pr)


# ----------------------------------------------------------------------------------- convergence


@dataclass
class Convergence:
    """Three-grid study of one scalar (h1 finest)."""

    h: tuple[float, float, float]
    phi: tuple[float, float, float]
    order: float  # observed order p (nan when the solutions do not converge monotonically)
    extrapolated: float  # Richardson value
    gci_fine: float  # relative, Fs = 1.25
    gci_medium: float
    asymptotic: float  # GCI_medium / (r21^p GCI_fine), near 1 in the asymptotic range
    monotone: bool
    diverging: bool = False  # monotone, but the change grows with refinement: no order, no extrapolation

    def as_dict(self) -> dict:
        return asdict(self)


def three_grid(h: Sequence[float], phi: Sequence[float], fs: float = 1.25, tol: float = 1e-12,
               max_iter: int = 500) -> Convergence:
    """Observed order, Richardson extrapolation and GCI from three grids (any order of the input).

    Celik et al. 2008 (J. Fluids Eng. 130, 078001): p = |ln|e32/e21| + q(p)| / ln r21, q(p) = ln((r21^p - s) /
    (r32^p - s)), s = sign(e32/e21); extrapolated (r21^p f1 - f2) / (r21^p - 1); GCI = Fs e_a / (r^p - 1).
    Their absolute value would give a positive order to a monotone series whose change grows with
    refinement (|e21| >= |e32| with r32 >= r21, which no p > 0 produces): such a series is reported
    ``diverging``, without order, extrapolation or GCI.
    """
    order_idx = np.argsort(np.asarray(h, dtype=float))
    h1, h2, h3 = (float(h[i]) for i in order_idx)
    f1, f2, f3 = (float(phi[i]) for i in order_idx)
    r21, r32 = h2 / h1, h3 / h2
    e21, e32 = f2 - f1, f3 - f2
    nan = float("nan")
    if e21 == 0.0 or e32 == 0.0 or r21 <= 1.0 or r32 <= 1.0:
        return Convergence((h1, h2, h3), (f1, f2, f3), nan, f1 if e21 == 0.0 else nan, 0.0 if e21 == 0.0 else nan,
                           nan, nan, e21 == 0.0 and e32 == 0.0)
    ratio = e32 / e21
    s = 1.0 if ratio > 0 else -1.0
    if s > 0 and r32 >= r21 and abs(e32) <= abs(e21):
        return Convergence((h1, h2, h3), (f1, f2, f3), nan, nan, nan, nan, nan, True, True)
    p = abs(math.log(abs(ratio))) / math.log(r21)
    for _ in range(max_iter):
        try:
            qp = math.log((r21**p - s) / (r32**p - s))
        except (ValueError, ZeroDivisionError, OverflowError):
            p = nan
            break
        p_new = abs(math.log(abs(ratio)) + qp) / math.log(r21)
        if abs(p_new - p) < tol * max(1.0, abs(p)):
            p = p_new
            break
        p = p_new
    if not math.isfinite(p) or p <= 0:
        return Convergence((h1, h2, h3), (f1, f2, f3), nan, nan, nan, nan, nan, s > 0)
    r21p, r32p = r21**p, r32**p
    extrapolated = (r21p * f1 - f2) / (r21p - 1.0)
    ea21 = abs((f1 - f2) / f1) if f1 != 0 else nan
    ea32 = abs((f2 - f3) / f2) if f2 != 0 else nan
    gci_fine = fs * ea21 / (r21p - 1.0)
    gci_medium = fs * ea32 / (r32p - 1.0)
    asym = gci_medium / (r21p * gci_fine) if gci_fine > 0 else nan
    return Convergence((h1, h2, h3), (f1, f2, f3), p, extrapolated, gci_fine, gci_medium, asym, s > 0)


def describe(conv: Convergence) -> str:
    """One line for a study script: "order p, GCI g %", or why there is none."""
    if not conv.monotone:
        return "not monotone"
    if conv.diverging:
        return "differences grow"
    if not math.isfinite(conv.order):
        return "no order"
    return f"order {conv.order:.2f}, GCI {100 * conv.gci_fine:.2f} %"


# ------------------------------------------------------------------------------------ power laws


def power_fit(x: Sequence[float], y: Sequence[float]) -> tuple[float, float] | None:
    """(a, k) of y = a x^k by least squares in log-log; None with fewer than two usable points."""
    x, y = np.asarray(x, dtype=float), np.asarray(y, dtype=float)
    ok = np.isfinite(x) & np.isfinite(y) & (x > 0) & (y > 0)
    if np.count_nonzero(ok) < 2 or np.ptp(np.log(x[ok])) == 0:
        return None
    k, log_a = np.polyfit(np.log(x[ok]), np.log(y[ok]), 1)
    return float(math.exp(log_a)), float(k)
