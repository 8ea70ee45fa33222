"""Fitted models of the mesh study: error against the ratio, cost and memory against the work,
and prediction intervals from the fits' residuals.

Errors and costs span decades, so every fit minimises *relative* residuals, sum ((m_i - y_i) / y_i)^2,
and an interval is relative too: with s^2 = that sum / (n - k) (k parameters) and the leverage
h0 = j0^T (J^T J)^-1 j0 of the prediction point (J the Jacobian of m_i / y_i in the parameters,
j0 that of m(x0) / m(x0)), the 95 % prediction interval is m(x0) (1 +- t_{n-k} s sqrt(1 + h0))
(the usual least-squares prediction interval, Montgomery & Runger, Applied Statistics, 11-6,
linearised for the nonlinear error model). With n = k the fit is exact and there is no interval.

- error: per quantity, e = e_inf + c r^-p (the floor: what refining the particles alone never beats)
  when at least four ratios support it, else e = c r^-p (see :func:`fit_error`); the worst over the
  quantities is the largest of those models (:class:`WorstError`), not one law fitted to the worst
  series;
- cost: cpu_s = a + c N steps (N particles or ALE elements), steps from the stable-step law;
- memory: peak_mib = m0 + m1 N.
"""
from __future__ import annotations

import math
from dataclasses import asdict, dataclass, field
from typing import Sequence

import numpy as np

# Two-sided 95 % quantiles of Student's t by degrees of freedom (1.96 beyond the table).
_T95 = [12.706, 4.303, 3.182, 2.776, 2.571, 2.447, 2.365, 2.306, 2.262, 2.228, 2.201, 2.179, 2.160, 2.145,
        2.131, 2.120, 2.110, 2.101, 2.093, 2.086, 2.080, 2.074, 2.069, 2.064, 2.060, 2.056, 2.052, 2.048,
        2.045, 2.042]


def t95(dof: int) -> float:
    return _T95[dof - 1] if dof <= len(_T95) else 1.96


def _finite_positive(x: Sequence[float], y: Sequence[float]) -> tuple[np.ndarray, np.ndarray]:
    x, y = np.asarray(x, dtype=float), np.asarray(y, dtype=float)
    ok = np.isfinite(x) & np.isfinite(y) & (x > 0) & (y > 0)
    return x[ok], y[ok]


def _interval(value: float, s: float | None, dof: int, jac: np.ndarray, j0: np.ndarray) -> list[float] | None:
    if s is None or dof < 1 or not math.isfinite(value):
        return None
    try:
        lev = float(j0 @ np.linalg.solve(jac.T @ jac, j0))
    except np.linalg.LinAlgError:
        return None
    half = t95(dof) * s * math.sqrt(1.0 + max(lev, 0.0))
    return [max(0.0, value * (1.0 - half)), value * (1.0 + half)]  # costs, memory and errors are >= 0


# ------------------------------------------------------------------------------------- linear


@dataclass
class LinearFit:
    """y = a + c x, relative least squares."""

    a: float
    c: float
    n: int
    s: float | None  # relative residual standard deviation (None: exact fit)
    x: list[float] = field(default_factory=list)
    y: list[float] = field(default_factory=list)

    def predict(self, x0: float) -> tuple[float, list[float] | None]:
        value = self.a + self.c * x0
        xs, ys = np.asarray(self.x), np.asarray(self.y)
        jac = np.stack([1.0 / ys, xs / ys], axis=1)
        j0 = np.array([1.0, x0]) / value if value != 0 else np.array([0.0, 0.0])
        return value, _interval(value, self.s, self.n - 2, jac, j0)

    def as_dict(self) -> dict:
        return asdict(self)


def linear_fit(x: Sequence[float], y: Sequence[float]) -> LinearFit | None:
    """(a, c) of y = a + c x minimising sum ((a + c x_i - y_i) / y_i)^2; None under two points.

    The intercept (a fixed cost) is kept >= 0: a negative one is refitted as y = c x."""
    x, y = _finite_positive(x, y)
    if len(x) < 2 or np.ptp(x) == 0:
        return None
    A = np.stack([1.0 / y, x / y], axis=1)
    (a, c), *_ = np.linalg.lstsq(A, np.ones_like(y), rcond=None)
    if a < 0:
        a, c = 0.0, float(np.sum(x / y) / np.sum((x / y) ** 2))
    res = (a + c * x - y) / y
    s = math.sqrt(float(np.sum(res**2)) / (len(x) - 2)) if len(x) > 2 else None
    return LinearFit(float(a), float(c), len(x), s, x.tolist(), y.tolist())


# -------------------------------------------------------------------------------------- error


@dataclass
class ErrorModel:
    """e(r) = floor + c r^-order; form "floor" or "power" (floor 0), and why."""

    form: str
    floor: float
    c: float
    order: float
    n: int
    s: float | None
    reason: str
    r: list[float] = field(default_factory=list)
    e: list[float] = field(default_factory=list)

    def __call__(self, r: float) -> float:
        return self.floor + self.c * r ** (-self.order)

    def _jac(self, r: np.ndarray) -> np.ndarray:
        rp = r ** (-self.order)
        cols = [rp, -self.c * rp * np.log(r)]
        if self.form == "floor":
            cols.insert(0, np.ones_like(r))
        return np.stack(cols, axis=1)

    def predict(self, r0: float) -> tuple[float, list[float] | None]:
        value = self(r0)
        r, e = np.asarray(self.r), np.asarray(self.e)
        k = 3 if self.form == "floor" else 2
        jac = self._jac(r) / e[:, None]
        j0 = self._jac(np.array([float(r0)]))[0] / value
        return value, _interval(value, self.s, self.n - k, jac, j0)

    def solve(self, tolerance: float) -> float | None:
        """The ratio at which e(r) = tolerance; None when the floor or a non-falling error forbids it."""
        if self.order <= 0 or self.c <= 0 or tolerance <= self.floor:
            return None
        return (self.c / (tolerance - self.floor)) ** (1.0 / self.order)

    def as_dict(self) -> dict:
        return asdict(self)


def _power(r: np.ndarray, e: np.ndarray) -> tuple[float, float, float]:
    """(c, p, relative SSR) of e = c r^-p, least squares in log-log."""
    slope, log_c = np.polyfit(np.log(r), np.log(e), 1)
    c, p = float(math.exp(log_c)), float(-slope)
    return c, p, float(np.sum(((c * r**-p) - e) ** 2 / e**2))


def _floor_at(r: np.ndarray, e: np.ndarray, p: float) -> tuple[float, float, float]:
    """(e_inf >= 0, c, relative SSR) of e = e_inf + c r^-p at a fixed p (linear least squares)."""
    rp = r**-p
    A = np.stack([1.0 / e, rp / e], axis=1)
    (e_inf, c), *_ = np.linalg.lstsq(A, np.ones_like(e), rcond=None)
    if e_inf < 0:
        e_inf, c = 0.0, float(np.sum(rp / e) / np.sum((rp / e) ** 2))
    return float(e_inf), float(c), float(np.sum(((e_inf + c * rp) - e) ** 2 / e**2))


def fit_floor(r: np.ndarray, e: np.ndarray, p_range: tuple[float, float] = (0.05, 8.0)) -> tuple[float, float, float, float]:
    """(e_inf, c, p, relative SSR) of e = e_inf + c r^-p: a scan over p, then golden-section refinement."""
    grid = np.geomspace(*p_range, 121)
    ssr = [_floor_at(r, e, p)[2] for p in grid]
    i = int(np.argmin(ssr))
    lo, hi = grid[max(i - 1, 0)], grid[min(i + 1, len(grid) - 1)]
    g = (math.sqrt(5.0) - 1.0) / 2.0
    a, b = lo, hi
    for _ in range(60):
        x1, x2 = b - g * (b - a), a + g * (b - a)
        if _floor_at(r, e, x1)[2] < _floor_at(r, e, x2)[2]:
            b = x2
        else:
            a = x1
    p = 0.5 * (a + b)
    e_inf, c, s = _floor_at(r, e, p)
    return e_inf, c, p, s


def fit_error(ratios: Sequence[float], errors: Sequence[float]) -> ErrorModel | None:
    """The error model of the data: the floor form where the data support it, else the power law.

    Supported means: at least four points (three parameters and one residual), a positive floor,
    an order inside the scan (0.05-8), and a smaller residual standard deviation than the power
    law's (each over its own degrees of freedom). None with fewer than two points."""
    r, e = _finite_positive(ratios, errors)
    if len(r) < 2 or np.ptp(r) == 0:
        return None
    n = len(r)
    c, p, ssr = _power(r, e)
    s_pow = math.sqrt(ssr / (n - 2)) if n > 2 else None
    power = ErrorModel("power", 0.0, c, p, n, s_pow, "", r.tolist(), e.tolist())
    if n < 4:
        power.reason = (f"{n} ratios: the floor form e_inf + c r^-p has three parameters and needs at least four "
                        "ratios to be checked, so the power law c r^-p is used")
        return power
    e_inf, cf, pf, ssr_f = fit_floor(r, e)
    s_floor = math.sqrt(ssr_f / (n - 3))
    floor = ErrorModel("floor", e_inf, cf, pf, n, s_floor, "", r.tolist(), e.tolist())
    if e_inf <= 0:
        power.reason = f"{n} ratios, but the best floor is 0: the power law c r^-p"
        return power
    if not 0.05 * 1.001 < pf < 8.0 * 0.999:
        power.reason = f"{n} ratios, but the floor fit's order {pf:.3g} sits at the edge of the scan: the power law"
        return power
    if s_pow is not None and s_floor >= s_pow:
        power.reason = (f"{n} ratios; the floor form's residual ({100 * s_floor:.2g} %) is not below the power "
                        f"law's ({100 * s_pow:.2g} %): the power law")
        return power
    floor.reason = (f"{n} ratios; the floor form fits with relative residual {100 * s_floor:.2g} % "
                    f"(power law: {100 * s_pow:.2g} %)")
    return floor


@dataclass
class WorstError:
    """The worst normalised L2 over the quantities, e(r) = max_q e_q(r), each quantity with its own
    model (:func:`fit_error`).

    Why not one law fitted to the worst series: the quantity that is worst changes with the ratio
    where the quantities converge at different orders (a point pressure at order 1 worst at coarse
    ratios, a stress at order 0.2 beyond), and the worst series then bends; a power law through it
    carries the fast quantity's order into the range where the slow one governs (measured on the
    underwater-explosion study: ratio 8 predicted at 4.7 %, docs/studies/underwater_explosion.md).

    A quantity whose error does not fall with the ratio (order <= 0: already at the level of the
    reference's own noise, or diverging) is not extrapolated along its fitted trend; it counts as
    constant at the largest error measured, a floor.
    """

    models: dict[str, ErrorModel]

    @staticmethod
    def falls(m: ErrorModel) -> bool:
        return m.order > 0 and m.c > 0

    def value(self, q: str, r: float) -> float:
        m = self.models[q]
        return m(r) if self.falls(m) else max(m.e)

    def governing(self, r: float) -> str:
        """The quantity whose model is the largest at ratio r."""
        return max(self.models, key=lambda q: self.value(q, r))

    def __call__(self, r: float) -> float:
        return max(self.value(q, r) for q in self.models)

    def predict(self, r0: float) -> tuple[float, list[float] | None]:
        """The governing quantity's prediction and interval at r0 (a non-falling one: its largest
        measured error, within the range measured)."""
        m = self.models[self.governing(r0)]
        return m.predict(r0) if self.falls(m) else (max(m.e), [min(m.e), max(m.e)])

    def solve(self, tolerance: float) -> tuple[float | None, str | None]:
        """(r, None): the smallest ratio >= 1 at which every quantity's model is within the tolerance;
        (None, q): none exists, q the quantity that forbids it (its floor, or an error that does not
        fall and is beyond the tolerance)."""
        r = 1.0
        for q, m in self.models.items():
            if not self.falls(m):
                if max(m.e) > tolerance:
                    return None, q
            elif tolerance <= m.floor:
                return None, q
            else:
                r = max(r, (m.c / (tolerance - m.floor)) ** (1.0 / m.order))
        return r, None

    def summary(self, r: float) -> dict:
        """The governing quantity's model at ratio r, for the report."""
        q = self.governing(r)
        m = self.models[q]
        return {"form": m.form, "floor": m.floor, "order": m.order, "c": m.c, "residual": m.s, "points": m.n,
                "reason": m.reason, "governing": q}


# --------------------------------------------------------------------------------------- steps


def steps_at(dt0_ref: dict, steps_ref: float, ratio_ref: float, ratio: float, fluid: str) -> float:
    """Steps of a case at ``ratio`` from a measured one at ``ratio_ref`` by the stable-step law.

    The fluid's stable step is proportional to its spacing (CFL: dt = C h / c, h / dx fixed), so
    dt_fluid(r) = dt_fluid(r_ref) r_ref / r; the other domains' (the structure's, the contact's)
    do not change with the fluid's spacing. steps(r) = steps_ref dt0(r_ref) / dt0(r), dt0 the
    smallest first step over the domains."""
    vals = {k: v for k, v in (dt0_ref or {}).items() if v}
    if fluid not in vals:
        return steps_ref * ratio / ratio_ref
    now = min(vals.values())
    scaled = dict(vals, **{fluid: vals[fluid] * ratio_ref / ratio})
    return steps_ref * now / min(scaled.values())
