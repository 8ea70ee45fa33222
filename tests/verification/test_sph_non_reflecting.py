"""Non-reflecting open sides of SPH water (``Wall(condition="non_reflecting")``, deck ``wall`` with
``condition: non_reflecting``; sph/open_sides.py, docs/theory/sph.md "Non-reflecting open sides").

Tait water (rho0 1000, c 1480 m/s, gamma 7), cubic spline, h/dx 1.2, Monaghan alpha 0.1 (the
underwater-explosion decks' viscosity). What comes back from a side is measured as the pressure
difference to the same run in a column or box long enough that nothing returns from its far end in the
time measured (same lattice, same particles), over the incident amplitude. Measured (1 thread):

* plane pulse (Gaussian p' = rho c u, half-width 0.05 m, 1e5 Pa, moving right) through the right end of
  a 1 m column, left over at t c = 0.95 m. The column is a plane 2D channel three spacings high between
  slip walls (``_column``; the pulse stays plane: |v_y| < 3e-12 m/s): non-reflecting -1.34 / -1.28 /
  -1.11 % at 200 / 400 / 800 particles per metre, a free end -95.3 / -98.4 / -99.3 %, a slip wall +94.2 /
  +97.7 / +98.9 % (7 December 2026). Until then it was a 1D column (the 1D SPH mode, removed as no deck
  can reach it), which gave -1.60 / -1.52 / -1.29 %, -94.4 / -98.0 / -99.1 %, +93.1 / +97.2 / +98.6 %
  (with the mirror images about the fixed plane of before -1.53 / -1.40 / -1.10 %); the reflection falls
  with the spacing, slower than first order (measured in 1D with the mirror images: the artificial
  viscosity's share, with alpha 0.02 2.9 / 0.6 / 0.26 %, with alpha 0 -6.9 / +3.2 / -1.5 %, first order);
* the same pulse at 30 MPa (the underwater-explosion deck's shock at its sides): -4.96 / -5.89 / -6.06 % at
  200 / 400 / 800 particles per metre (1D: -4.63 / -5.56 / -5.79 %; the mirror images sent back +12.4 /
  +17.5 / -58.5 %, 1D);
* water at rest at p_far = 1e5 Pa in a box open on every side: |v| < 1e-14 m/s after two crossing
  times; hydrostatic water (c 20 m/s, free top) open at the bottom and sides: |v| 2.6e-3 m/s after two
  crossing times (slip walls: 0.9e-3 m/s), 0.2 % of sqrt(g H);
* a cylindrical pulse (Gaussian p', half-width 0.03 m, at rest, from (0.15, 0.10) in a 0.4 x 0.32 m box
  open on all four sides; the nearest side 0.10 m away, the corners at oblique incidence), at 0.42 m / c:
  largest / rms left 7.6 / 1.76 % (dx 5 mm) and 2.0 / 0.68 % (2.5 mm) with ``source``, 14.7 / 3.5 % and
  12.0 / 3.2 % without, a free surface 128 / 42 % and 150 / 41 % (``test_cylindrical_pulse``).
"""
from __future__ import annotations

import numpy as np
import pytest

from sphfem_cli.sph import lattice
from sphfem_cli.sph.scenes import water
from sphfem_cli.sph.options import SphOptions
from sphfem_cli.sph.system import SphSystem
from sphfem_cli.sph.walls import box_walls

C, RHO, GAMMA = 1480.0, 1000.0, 7.0
Z = RHO * C


def _density(dp):
    """Tait density of the pressure dp: p = (rho0 c^2 / gamma) ((rho/rho0)^gamma - 1)."""
    return RHO * (1.0 + GAMMA * dp / (RHO * C * C)) ** (1.0 / GAMMA)


ROWS = 3  # the channel's height in spacings: wider than 2 h = 2.4 dx, so single wall images suffice


def _column(n: int, right: str, length: float = 1.0, amp: float = 1e5, width: float = 0.05) -> SphSystem:
    """Water column [0, length] at spacing dx = 1/n as a plane 2D channel ``ROWS`` spacings high between slip
    walls at y = 0 and y = ROWS dx (the lattice continued by the wall images on both sides: a plane flow along
    x), slip wall at x = 0, ``right`` at x = length ("free": nothing, the particles crossing it deactivated; a
    non_reflecting side moves with the water and deletes nothing), a right-moving Gaussian pulse centred at 0.5."""
    dx = 1.0 / n
    height = ROWS * dx
    x = lattice.box([0.0, 0.0], [length, height], dx)
    m = len(x)
    dp = amp * np.exp(-(((x[:, 0] - 0.5) / width) ** 2))
    walls = box_walls([0.0, 0.0], [length, height], ["left", "bottom", "top"])
    if right != "free":
        walls += box_walls([0.0, 0.0], [length, height], ["right"], right)
    domain = ([-1.0, -1.0], [length, height + 1.0]) if right == "free" else None
    opt = SphOptions(walls=tuple(walls), domain=domain, alpha=0.1)
    v = np.zeros_like(x)
    v[:, 0] = dp / Z
    return SphSystem(x, v, np.full(m, RHO * dx * dx), _density(dp), np.zeros(m, dtype=np.int64), water(C), opt)


def _pressure(ps: SphSystem) -> np.ndarray:
    """Pressure in the original particle order (the system reorders its arrays)."""
    return ps.p[np.argsort(ps.ids)]


def _plane_echo(n: int) -> dict[str, float]:
    """Signed largest pressure difference to the long column at t c = 0.95 m over the incident amplitude
    (the long column's peak at t c = 0.2 m), for each right end."""
    ref = _column(n, "slip", length=2.0)
    ref.run(0.2 / C, 0.5)
    incident = np.abs(ref.p).max()
    ref.run(0.95 / C, 0.5)
    p_ref = _pressure(ref)[: ROWS * n]  # lattice.box orders x first: the particles of [0, 1]
    out = {}
    for right in ("non_reflecting", "free", "slip"):
        ps = _column(n, right)
        ps.run(0.95 / C, 0.5)
        assert ps.lost == 0
        d = _pressure(ps) - p_ref
        out[right] = float(d[np.argmax(np.abs(d))] / incident)
    return out


def _assert_echoes(n: int, e: dict[str, float]) -> None:
    """Non-reflecting |R| < 2 %; the free end inverts (R < -90 %), the wall does not (R > 90 %)."""
    assert abs(e["non_reflecting"]) < 0.02, (n, e)
    assert e["free"] < -0.90, (n, e)
    assert e["slip"] > 0.90, (n, e)


def test_plane_pulse_reflection():
    """What a non-reflecting end sends back, against a free end and a slip wall, at 200 particles per metre.

    Tolerances as ``test_plane_pulse_reflection_falls_with_the_spacing`` (measured -1.34 %, -95.3 %, +94.2 %):
    the non-reflecting end sends back 70 times less than either. About 6 s CPU.
    """
    _assert_echoes(200, _plane_echo(200))


@pytest.mark.validation
def test_plane_pulse_reflection_falls_with_the_spacing():
    """What a non-reflecting end sends back, against a free end and a slip wall, at three spacings.

    Tolerances: non-reflecting |R| < 2 % at every spacing (measured 1.34 / 1.28 / 1.11 % at 200 / 400 / 800
    particles per metre) and falling with the spacing; the free end inverts (R < -90 %, measured -95.3 ... -99.3 %),
    the wall does not (R > 90 %, measured 94.2 ... 98.9 %). About 60 s CPU (the 800 level 45 s).
    """
    echoes = {n: _plane_echo(n) for n in (200, 400, 800)}
    for n, e in echoes.items():
        _assert_echoes(n, e)
    r = [abs(echoes[n]["non_reflecting"]) for n in (200, 400, 800)]
    assert r[0] > r[1] > r[2], r


def test_plane_pulse_energy_leaves():
    """The energy the non-reflecting end books as radiated (``energies()["open"]``) closes the balance.

    The Tait water's internal energy is set to 0 at the start whatever its density (it does not enter its
    pressure), so the pulse starts with its kinetic energy K0 only and its compression energy, equal to K0
    in a simple wave, appears as internal energy going negative as the water relaxes behind it. At
    t c = 0.95 m (400 particles per metre): kinetic + internal + radiated = K0 within 1e-4 K0 (measured
    7.7e-6 K0: the open side's power is the ghosts' pair work, ``open_sides.open_side_power``), and the
    radiated energy is 2 K0, the pulse's acoustic energy, within 3 % (measured 98.9 %: the echo and the
    artificial viscosity keep the rest).
    """
    ps = _column(400, "non_reflecting")
    e0 = ps.energies()
    start = e0["kinetic"] + e0["internal"]
    ps.run(0.95 / C, 0.5)
    e = ps.energies()
    assert abs(e["kinetic"] + e["internal"] + e["open"] - start) < 1e-4 * start, (e, start)
    assert 0.97 < e["open"] / (2.0 * e0["kinetic"]) <= 1.0, (e["open"], e0["kinetic"])


@pytest.mark.parametrize("gravity", [0.0, -9.81])
def test_rest_stays_at_rest(gravity):
    """Water at rest at its far pressure stays at rest beside open sides.

    Without gravity, at p_far = 1e5 Pa, open on all four sides: |v| < 1e-9 m/s and p within 1e-9 of
    p_far after two crossing times (measured 6e-15 m/s). Hydrostatic water (c 20 m/s, depth 0.2 m, free
    top, gravity -9.81) open at the bottom and on both sides: |v| < 1 % of sqrt(g H) = 1.4 m/s (measured
    2.6e-3 m/s, 2.5e-3 with the mirror images of before; the same tank with slip walls 0.9e-3 m/s); no
    particle leaves.
    """
    dx, depth = 0.01, 0.2
    x = lattice.box((0.0, 0.0), (depth, depth), dx)
    mat = np.zeros(len(x), dtype=np.int64)
    if gravity == 0.0:
        c0, p_far, sides = C, 1e5, ["left", "right", "bottom", "top"]
        rho = np.full(len(x), _density(p_far))
    else:
        c0, p_far, sides = 20.0, None, ["left", "right", "bottom"]
        rho = lattice.hydrostatic_density(x, water(c0)[1], mat, [0.0, gravity], [0.0, depth])
    opt = SphOptions(walls=tuple(box_walls((0.0, 0.0), (depth, depth), sides, "non_reflecting")), alpha=0.1,
                     gravity=[0.0, gravity])
    ps = SphSystem(x, np.zeros_like(x), np.full(len(x), RHO * dx * dx), rho, mat, water(c0), opt)
    ps.run(2.0 * depth / c0, 0.5)
    assert ps.lost == 0
    speed = float(np.abs(ps.v).max())
    if gravity == 0.0:
        assert speed < 1e-9
        assert np.allclose(ps.p, p_far, rtol=1e-9, atol=0.0)
    else:
        assert speed < 0.01 * np.sqrt(-gravity * depth), speed


SRC = (0.15, 0.10)
BOX_LO, BOX_HI = (0.0, 0.0), (0.4, 0.32)


def _box(dx: float, lo, hi, condition: str, source=None, width: float = 0.03) -> SphSystem:
    """A Gaussian pressure bump at rest at SRC in the box [lo, hi], its four sides ``condition``."""
    x = lattice.box(lo, hi, dx)
    dp = 1e5 * np.exp(-((x - np.array(SRC)) ** 2).sum(axis=1) / width**2)
    walls = () if condition == "free" else tuple(box_walls(lo, hi, ["left", "right", "bottom", "top"], condition,
                                                           source))
    opt = SphOptions(walls=walls, domain=(list(lo), list(hi)) if condition == "free" else None, alpha=0.1)
    return SphSystem(x, np.zeros_like(x), np.full(len(x), RHO * dx * dx), _density(dp),
                     np.zeros(len(x), dtype=np.int64), water(C), opt)


# heavy (11 s): the plane pulses below and above check the same open sides in the default suite
@pytest.mark.heavy
def test_cylindrical_pulse():
    """A cylindrical pulse from a point leaves a box open on all sides, at oblique incidence on most of them.

    Against the same lattice in a box 0.24 m larger each way (slip walls, whose echo has not come back by
    then), at t = 0.42 m / c, dx = 5 mm, over the incident peak at the nearest side (the larger box's
    largest |p| within a spacing of it, when the pulse's peak reaches it). Largest / rms difference,
    measured at dx = 5 mm (this test) and 2.5 mm: the non-reflecting sides with the source 7.6 / 1.76 % and
    2.0 / 0.68 % (converging), without the source (the plane-wave condition, wrong at oblique incidence and
    for the cylindrical wave's tail) 14.7 / 3.5 % and 12.0 / 3.2 %, a free surface 128 / 42 % and 150 / 41 %.
    Tolerances: with the source below 10 % / 2.5 %, its rms below the plane condition's, the free surface's
    largest above 100 %. (Remeasured with the images that follow their particles, 6 December 2026: the same
    to the digits given.)
    """
    dx, margin = 0.005, 0.24
    ref = _box(dx, (BOX_LO[0] - margin, BOX_LO[1] - margin), (BOX_HI[0] + margin, BOX_HI[1] + margin), "slip")
    inside = np.all((ref.x >= BOX_LO) & (ref.x <= BOX_HI), axis=1)  # original order (not yet reordered)
    ref.run((SRC[1] - BOX_LO[1]) / C, 0.5)
    near = inside[ref.ids] & (ref.x[:, 1] - BOX_LO[1] < dx)
    incident = np.abs(ref.p[near]).max()
    t_end = 0.42 / C
    ref.run(t_end, 0.5)
    p_ref = _pressure(ref)[inside]
    out = {}
    for name, condition, source in (("source", "non_reflecting", SRC), ("plane", "non_reflecting", None),
                                    ("free", "free", None)):
        ps = _box(dx, BOX_LO, BOX_HI, condition, source)
        ps.run(t_end, 0.5)
        d = (_pressure(ps) - p_ref)[ps.active[np.argsort(ps.ids)]]
        out[name] = (np.abs(d).max() / incident, np.sqrt(np.mean(d**2)) / incident)
    assert out["source"][0] < 0.10 and out["source"][1] < 0.025, out
    assert out["source"][1] < out["plane"][1], out
    assert out["free"][0] > 1.0, out


def _strong_echo(n: int) -> float:
    """``_plane_echo``'s non-reflecting end at 3e7 Pa: the largest |p| difference over the incident peak."""
    col = _column(n, "slip", length=2.0, amp=3e7)
    col.run(0.2 / C, 0.5)
    incident = np.abs(col.p).max()
    col.run(0.95 / C, 0.5)
    ps = _column(n, "non_reflecting", amp=3e7)
    ps.run(0.95 / C, 0.5)
    assert ps.lost == 0
    d = _pressure(ps) - _pressure(col)[: ROWS * n]
    return float(np.abs(d).max() / incident)


def test_strong_plane_pulse_reflection():
    """A 30 MPa plane pulse (the shock's strength at the underwater-explosion deck's sides) leaves as the
    linear one does, at 200 particles per metre (measured -4.96 %). Tolerance |R| < 7 %; no particle
    leaves. About 3 s CPU. The three spacings: ``test_strong_plane_pulse_reflection_at_three_spacings``.
    """
    r = _strong_echo(200)
    assert r < 0.07, r


@pytest.mark.validation
def test_strong_plane_pulse_reflection_at_three_spacings():
    """A 30 MPa plane pulse leaves as the linear one does, at three spacings.

    The plane pulse of ``test_plane_pulse_reflection`` at 3e7 Pa. The side's images follow their
    particles (x_g = x_i + 2 d0_i n, sph/open_sides.py): the side sends back -4.96 / -5.89 / -6.06 % at
    200 / 400 / 800 particles per metre (measured in the 2D channel; in the 1D column of before -4.63 /
    -5.56 / -5.79 %), not growing with the resolution as it did with mirror images about the fixed plane
    (+12.4 / +17.5 / -58.5 %, 1D: the particles closed on their own images; docs/studies/underwater_explosion.md,
    "3a."). What is left is second order in the amplitude (1D, 400 per metre: -1.5 % at 0.1 MPa, -11.3 % at
    100 MPa: the layer's compression, the impedance). Tolerance |R| < 7 % at each spacing; no particle
    leaves. About 42 s CPU (the 800 level 31 s).
    """
    for n in (200, 400, 800):
        r = _strong_echo(n)
        assert r < 0.07, (n, r)
