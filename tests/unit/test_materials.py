"""Unit tests of the material kernels, the EOSs, the parameter tables and the deck schema."""
from __future__ import annotations

import math

import numpy as np
import pytest
from pydantic import TypeAdapter, ValidationError

from sphfem_cli.deck.schema.materials import EquationOfState, Material
from sphfem_cli.materials import kernels as k
from sphfem_cli.materials import slots as ms
from sphfem_cli.materials.tables import pack_eos, pack_material

MAT = TypeAdapter(Material)
EOS = TypeAdapter(EquationOfState)

E, NU, SY, ET, RHO = 200e9, 0.3, 250e6, 2e9, 7850.0


def material(**kw):
    eos = kw.pop("_eos", None)
    t, p = pack_material(MAT.validate_python(kw), EOS.validate_python(eos) if eos else None)
    return t, p


def bilinear(beta=1.0):
    return material(type="elastic_plastic", density=RHO, youngs_modulus=E, poisson_ratio=NU,
                    yield_stress=SY, tangent_modulus=ET, hardening_beta=beta)


def uniaxial_step(t, p, sig, hist, dexx, dt=1e-6):
    """One increment of uniaxial stress: find the lateral strain that keeps sigma_yy = sigma_zz = 0."""

    def trial(lat):
        s, h = sig.copy(), hist.copy()
        k.update_stress(t, p, s, h, np.array([dexx, lat, lat, 0.0, 0.0, 0.0]), dt, 1.0, 0.0)
        return s, h

    x0, x1 = -NU * dexx, -0.5 * dexx
    f0, f1 = trial(x0)[0][1], trial(x1)[0][1]
    for _ in range(60):
        if f1 == f0 or abs(f1) < 1e-9 * max(1.0, abs(trial(x1)[0][0])):
            break
        x0, x1, f0 = x1, x1 - f1 * (x1 - x0) / (f1 - f0), f1
        f1 = trial(x1)[0][1]
    s, h = trial(x1)
    sig[:], hist[:] = s, h
    return s[0]


def drive(t, p, strains, steps_per_unit=2e5, dt=1e-6):
    """Drive uniaxial stress through the total strains in `strains`; return (strain, stress) pairs."""
    sig, hist = np.zeros(6), np.zeros(ms.NHIST)
    eps, out = 0.0, []
    for target in strains:
        n = max(1, int(abs(target - eps) * steps_per_unit))
        for de in np.full(n, (target - eps) / n):
            s = uniaxial_step(t, p, sig, hist, de, dt)
            eps += de
            out.append((eps, s, hist.copy()))
    return out, sig, hist


# ----------------------------------------------------------------------------------- elastic


def test_elastic_shear_and_volume():
    t, p = material(type="elastic", density=RHO, youngs_modulus=E, poisson_ratio=NU)
    g, kb = E / (2 * (1 + NU)), E / (3 * (1 - 2 * NU))
    sig, hist = np.zeros(6), np.zeros(ms.NHIST)
    gam = 1e-4  # tensor shear strain eps_xy
    assert k.update_stress(t, p, sig, hist, np.array([0, 0, 0, gam, 0, 0.0]), 1e-6, 1.0, 0.0) == 0.0
    assert sig[3] == pytest.approx(2 * g * gam, rel=1e-14)
    assert np.all(sig[[0, 1, 2, 4, 5]] == 0.0)
    sig[:] = 0.0
    ev = 1e-4
    k.update_stress(t, p, sig, hist, np.full(6, ev) * [1, 1, 1, 0, 0, 0], 1e-6, 1.0, 0.0)
    assert sig[:3] == pytest.approx(np.full(3, 3 * kb * ev), rel=1e-14)
    assert np.all(hist == 0.0)


def test_plane_strain_keeps_szz():
    t, p = material(type="elastic", density=RHO, youngs_modulus=E, poisson_ratio=NU)
    lam = E * NU / ((1 + NU) * (1 - 2 * NU))
    sig = np.zeros(6)
    k.update_stress(t, p, sig, np.zeros(ms.NHIST), np.array([1e-4, -2e-5, 0, 0, 0, 0.0]), 1e-6, 1.0, 0.0)
    assert sig[2] == pytest.approx(lam * 0.8e-4, rel=1e-13)


def test_sound_speed_solid():
    t, p = material(type="elastic", density=RHO, youngs_modulus=E, poisson_ratio=NU)
    c = math.sqrt(E * (1 - NU) / ((1 + NU) * (1 - 2 * NU) * RHO))
    assert k.sound_speed(t, p, 1.0) == pytest.approx(c, rel=1e-14)
    assert k.sound_speed(t, p, 0.9, 0.0) == pytest.approx(c * math.sqrt(0.9), rel=1e-14)


# ----------------------------------------------------------------------------------- bilinear


def test_bilinear_uniaxial_matches_exact_curve():
    t, p = bilinear(1.0)
    path, _, _ = drive(t, p, [0.01], steps_per_unit=2e4)
    eps_y = SY / E
    for eps, s, _ in path[::10]:
        exact = E * eps if eps <= eps_y else SY + ET * (eps - eps_y)
        assert s == pytest.approx(exact, rel=1e-6)


@pytest.mark.parametrize("beta", [1.0, 0.0, 0.5])
def test_bilinear_cycle_isotropic_vs_kinematic(beta):
    t, p = bilinear(beta)
    emax, efin = 0.01, -0.005
    path, sig, hist = drive(t, p, [emax, efin], steps_per_unit=2e4)
    ep_mod = E * ET / (E - ET)
    smax = SY + ET * (emax - SY / E)
    epmax = (emax - SY / E) - (smax - SY) / E  # plastic strain at emax
    radius = SY + beta * ep_mod * epmax
    srev = smax - 2 * radius  # reverse yield stress
    erev = emax - 2 * radius / E
    exact = srev + ET * (efin - erev)
    assert sig[0] == pytest.approx(exact, rel=1e-6)
    if beta == 0.0:
        assert srev == pytest.approx(smax - 2 * SY)
    if beta == 1.0:
        assert srev == pytest.approx(-smax)
    # plastic work = integral of sigma d eps_p along the path (trapezoid on the fine path)
    eps_p = np.array([h[ms.H_EPS] for _, _, h in path])
    stress = np.array([abs(s) for _, s, _ in path])
    wp = np.sum(0.5 * (stress[1:] + stress[:-1]) * np.diff(eps_p))
    assert hist[ms.H_WP] == pytest.approx(wp, rel=1e-3)


# ----------------------------------------------------------------------------------- Johnson-Cook

JC = dict(type="johnson_cook", density=RHO, youngs_modulus=E, poisson_ratio=NU, A=350e6, B=275e6,
          n=0.36, C=0.022, m=1.0, reference_strain_rate=1.0, melt_temperature=1793.0, room_temperature=293.0)


def test_jc_reference_rate_follows_hardening_curve():
    t, p = material(**JC)
    rate = 1.0
    de = 1e-5
    path, _, _ = drive(t, p, [0.1], steps_per_unit=1 / de, dt=de / rate)
    plastic = [(s, h[ms.H_EPS]) for _, s, h in path if h[ms.H_EPS] > 0]
    assert len(plastic) > 1000
    for s, ep in plastic[::50]:
        assert s == pytest.approx(JC["A"] + JC["B"] * ep ** JC["n"], rel=1e-3)


def test_jc_rate_and_thermal_terms_satisfied_each_step():
    t, p = material(**JC, specific_heat=477.0)
    rate, de = 1e3, 1e-4
    dt = de / rate
    sig, hist = np.zeros(6), np.zeros(ms.NHIST)
    checked = 0
    for _ in range(1500):
        ep0, wp0 = hist[ms.H_EPS], hist[ms.H_WP]
        s = uniaxial_step(t, p, sig, hist, de, dt)
        dl = hist[ms.H_EPS] - ep0
        if dl > 0:
            rs = dl / dt / JC["reference_strain_rate"]
            tstar = wp0 / (RHO * 477.0) / (JC["melt_temperature"] - JC["room_temperature"])
            sy = (JC["A"] + JC["B"] * hist[ms.H_EPS] ** JC["n"]) * (1 + JC["C"] * math.log(max(rs, 1.0))) * (1 - tstar)
            assert s == pytest.approx(sy, rel=1e-8)
            checked += 1
    assert checked > 1000 and hist[ms.H_WP] > 0


def test_jc_with_eos_takes_pressure_from_eos():
    kb = E / (3 * (1 - 2 * NU))
    t, p = material(**JC, eos="lp", _eos=dict(type="linear_polynomial", c1=kb, c2=2 * kb))
    sig = np.zeros(6)
    v = 0.98
    k.update_stress(t, p, sig, np.zeros(ms.NHIST), np.array([-0.02, 0, 0, 0, 0, 0.0]), 1e-6, v, 0.0)
    mu = 1 / v - 1
    assert -sig[:3].mean() == pytest.approx(kb * mu + 2 * kb * mu * mu, rel=1e-12)


@pytest.mark.parametrize("model", ["elastic_plastic", "johnson_cook"])
def test_pressure_cutoff_bounds_the_eos_pressure(model):
    """pressure_cutoff (LS-DYNA *MAT_ELASTIC_PLASTIC_HYDRO PC): in tension the EOS pressure stops at
    p_cut, in compression it is untouched, and the deviator still comes from the rate form; without
    the field the row holds -inf and the EOS's tension is kept."""
    water = dict(type="tait", reference_density=1000.0, sound_speed=1483.0)
    base = (dict(type="elastic_plastic", density=1000.0, youngs_modulus=3e7, poisson_ratio=0.49, yield_stress=1e4)
            if model == "elastic_plastic" else dict(JC, density=1000.0))
    t, p = material(**base, eos="water", pressure_cutoff=-1e5, _eos=water)
    t0, p0 = material(**base, eos="water", _eos=water)
    assert p[ms.P_PRESSURE_CUTOFF] == -1e5 and p0[ms.P_PRESSURE_CUTOFF] == -np.inf
    stretch = np.array([0.001, 0.0, 0.0, 0.0, 0.0, 0.0])
    for row, expect in ((p, -1e5), (p0, None)):
        sig = np.zeros(6)
        k.update_stress(t, row, sig, np.zeros(ms.NHIST), stretch, 1e-6, 1.001, 0.0)
        p_eos = k.eos_pressure(ms_eos_type(row), row[ms.EOS_OFFSET:], 1.0 / 1.001, 0.0)
        assert p_eos < -1e6  # the Tait tension at 0.1 % stretch: about -2.2 MPa
        assert -sig[:3].mean() == pytest.approx(p_eos if expect is None else expect, rel=1e-12)
    sig = np.zeros(6)
    k.update_stress(t, p, sig, np.zeros(ms.NHIST), -stretch, 1e-6, 0.999, 0.0)
    assert -sig[:3].mean() == pytest.approx(k.eos_pressure(ms_eos_type(p), p[ms.EOS_OFFSET:], 1.0 / 0.999, 0.0), rel=1e-12)


def ms_eos_type(row):
    return int(row[ms.P_EOS_TYPE])


def test_pressure_cutoff_needs_an_eos():
    with pytest.raises(ValidationError, match="give the material an `eos`"):
        MAT.validate_python(dict(type="elastic_plastic", density=RHO, youngs_modulus=E, poisson_ratio=NU,
                                 yield_stress=SY, pressure_cutoff=-1e5))
    with pytest.raises(ValidationError):  # a cut-off above 0 would be a tension floor
        MAT.validate_python(dict(JC, eos="water", pressure_cutoff=1e5))


# ----------------------------------------------------------------------------------- EOS


def eos_row(rho0=1000.0, **kw):
    return pack_eos(EOS.validate_python(kw), rho0)


def test_linear_polynomial():
    i, q = eos_row(type="linear_polynomial", c0=1.0, c1=10.0, c2=100.0, c3=1000.0, c4=0.5, c5=0.25, c6=2.0)
    # mu = 0.1, E = 4: 1 + 1 + 1 + 1 + (0.5 + 0.025 + 0.02) * 4
    assert k.eos_pressure(i, q, 1.1, 4.0) == pytest.approx(4.0 + 0.545 * 4.0, rel=1e-13)
    # mu = -0.1: C2 and C6 dropped: 1 - 1 - 1 + (0.5 - 0.025) * 4
    assert k.eos_pressure(i, q, 0.9, 4.0) == pytest.approx(-1.0 + 0.475 * 4.0, rel=1e-13)


def test_gruneisen():
    i, q = eos_row(type="gruneisen", c=1000.0, s1=1.5, gamma0=2.0)
    # mu = 0.1, E = 0: rho0 c^2 mu / (1 - 0.5 mu)^2
    assert k.eos_pressure(i, q, 1.1, 0.0) == pytest.approx(1e9 * 0.1 / 0.95**2, rel=1e-13)
    # expanded, mu = -0.1, E = 1e5: rho0 c^2 mu + gamma0 E
    assert k.eos_pressure(i, q, 0.9, 1e5) == pytest.approx(-1e8 + 2e5, rel=1e-13)
    i, q = eos_row(type="gruneisen", c=1500.0, s1=1.9, s2=0.1, s3=0.2, gamma0=1.6, a=0.5)
    for mu in (1e-6, -1e-6):
        assert k.eos_pressure(i, q, 1 + mu, 0.0) == pytest.approx(1000 * 1500**2 * mu, rel=1e-5)


def test_tait():
    i, q = eos_row(type="tait", reference_density=1000.0, sound_speed=10.0, gamma=7.0, background_pressure=50.0)
    assert k.eos_pressure(i, q, 1.0, 0.0) == pytest.approx(50.0, rel=1e-14)
    assert k.eos_pressure(i, q, 1.01, 0.0) == pytest.approx(1000 * 100 / 7 * (1.01**7 - 1) + 50, rel=1e-13)
    assert k.eos_sound_speed(i, q, 1.0, 0.0) == pytest.approx(10.0, rel=1e-14)


def test_ideal_and_stiffened_gas():
    rho0 = 1.2
    i, q = eos_row(rho0, type="ideal_gas", gamma=1.4)
    r, e_v = 1.5, 2.5e5  # rho = 1.8, specific energy e = e_v / rho0
    rho, e = rho0 * r, e_v / rho0
    p = 0.4 * rho * e
    assert k.eos_pressure(i, q, r, e_v) == pytest.approx(p, rel=1e-14)
    assert k.eos_sound_speed(i, q, r, e_v) == pytest.approx(math.sqrt(1.4 * p / rho), rel=1e-13)
    rho0, r, e_v = 1000.0, 1.001, 7.8e8  # water-like
    rho, e = rho0 * r, e_v / rho0
    i, q = eos_row(rho0, type="stiffened_gas", gamma=4.4, p_inf=6e8)
    p = 3.4 * rho * e - 4.4 * 6e8
    assert k.eos_pressure(i, q, r, e_v) == pytest.approx(p, rel=1e-9)
    assert k.eos_sound_speed(i, q, r, e_v) == pytest.approx(math.sqrt(4.4 * (p + 6e8) / rho), rel=1e-13)


def test_jwl():
    i, q = eos_row(1630.0, type="jwl", A=371.2e9, B=3.23e9, R1=4.15, R2=0.95, omega=0.3)
    v, e = 2.0, 3e9
    p = 371.2e9 * (1 - 0.3 / 8.3) * math.exp(-8.3) + 3.23e9 * (1 - 0.3 / 1.9) * math.exp(-1.9) + 0.3 * e / v
    assert k.eos_pressure(i, q, 1 / v, e) == pytest.approx(p, rel=1e-13)


EOS_CASES = [
    (1000.0, dict(type="linear_polynomial", c0=1e5, c1=2e9, c2=3e9, c3=1e9, c4=0.4, c5=0.3, c6=0.2)),
    (8930.0, dict(type="gruneisen", c=3940.0, s1=1.49, s2=0.2, s3=0.1, gamma0=2.02, a=0.47)),
    (1000.0, dict(type="tait", reference_density=1010.0, sound_speed=60.0, gamma=7.0, background_pressure=1e3)),
    (1.2, dict(type="ideal_gas", gamma=1.4)),
    (1000.0, dict(type="stiffened_gas", gamma=4.4, p_inf=6e8)),
    (1630.0, dict(type="jwl", A=371.2e9, B=3.23e9, R1=4.15, R2=0.95, omega=0.3)),
]


@pytest.mark.parametrize("rho0,spec", EOS_CASES, ids=[c[1]["type"] for c in EOS_CASES])
@pytest.mark.parametrize("r", [0.8, 1.0001, 1.2])
def test_eos_sound_speed_matches_finite_difference(rho0, spec, r):
    """c^2 = (dp/drho)_e + p/rho^2 (dp/de)_rho, by central differences in rho and e."""
    i, q = eos_row(rho0, **spec)
    e_v = {"jwl": 3e9, "stiffened_gas": 7.8e8}.get(spec["type"], 2e5)
    e = e_v / rho0
    rho = rho0 * r
    h = 1e-6 * rho

    def pe(rho_, e_):
        return k.eos_pressure(i, q, rho_ / rho0, e_ * rho0)

    dpdrho = (pe(rho + h, e) - pe(rho - h, e)) / (2 * h)
    dpde = (pe(rho, e * (1 + 1e-6)) - pe(rho, e * (1 - 1e-6))) / (2e-6 * e)
    c2 = dpdrho + pe(rho, e) / rho**2 * dpde
    assert c2 > 0.0
    assert k.eos_sound_speed(i, q, r, e_v) ** 2 == pytest.approx(c2, rel=1e-5)


# ----------------------------------------------------------------------------------- fluid


def test_fluid_stress_and_speed():
    t, p = material(type="fluid", density=1000.0, viscosity=1e-3, eos="w",
                    _eos=dict(type="tait", reference_density=1000.0, sound_speed=50.0))
    assert p[ms.P_G] == 0.0 and p[ms.P_K] == pytest.approx(1000 * 2500, rel=1e-14)
    sig, dt = np.zeros(6), 1e-5
    deps = np.array([2e-6, -1e-6, -1e-6, 3e-6, 0, 0])
    v = 1 / 1.001
    k.update_stress(t, p, sig, np.zeros(ms.NHIST), deps, dt, v, 0.0)
    pr = 1000 * 2500 / 7 * (1.001**7 - 1)
    assert sig[0] == pytest.approx(-pr + 2e-3 * 2e-6 / dt, rel=1e-12)
    assert sig[3] == pytest.approx(2e-3 * 3e-6 / dt, rel=1e-12)
    assert k.sound_speed(t, p, 1.0, 0.0) == pytest.approx(50.0, rel=1e-14)


def test_rigid_untouched():
    t, p = material(type="rigid", density=RHO, youngs_modulus=E, poisson_ratio=NU)
    sig = np.arange(6.0)
    assert k.update_stress(t, p, sig, np.zeros(ms.NHIST), np.full(6, 1e-3), 1e-6, 1.0, 0.0) == 0.0
    assert np.all(sig == np.arange(6.0))


# ----------------------------------------------------------------------------------- schema


@pytest.mark.parametrize("bad", [
    dict(type="elastic", density=RHO, youngs_modulus=E, poisson_ratio=0.5),
    dict(type="elastic", density=-1.0, youngs_modulus=E, poisson_ratio=NU),
    dict(type="elastic", density=RHO, youngs_modulus=E, poisson_ratio=NU, colour="red"),
    dict(type="elastic_plastic", density=RHO, youngs_modulus=E, poisson_ratio=NU, yield_stress=SY, tangent_modulus=E),
    dict(type="elastic_plastic", density=RHO, youngs_modulus=E, poisson_ratio=NU, yield_stress=SY, hardening_beta=1.5),
    dict(JC, room_temperature=2000.0),
    dict(type="fluid", density=1000.0),
    dict(type="plasticine", density=RHO),
    dict(type="elastic", density=float("nan"), youngs_modulus=E, poisson_ratio=NU),
])
def test_schema_rejects(bad):
    with pytest.raises(ValidationError):
        MAT.validate_python(bad)


def test_schema_defaults_and_eos_rejects():
    m = MAT.validate_python(dict(type="elastic_plastic", density=RHO, youngs_modulus=E, poisson_ratio=NU, yield_stress=SY))
    assert m.tangent_modulus == 0.0 and m.hardening_beta == 1.0 and m.eos is None
    assert EOS.validate_python(dict(type="tait", reference_density=1000.0, sound_speed=10.0)).gamma == 7.0
    with pytest.raises(ValidationError):
        EOS.validate_python(dict(type="ideal_gas", gamma=1.0))
    with pytest.raises(ValidationError):
        EOS.validate_python(dict(type="tait", reference_density=1000.0, sound_speed=10.0, extra=1))


def test_every_field_has_a_description():
    from sphfem_cli.deck.schema import materials as sm

    for cls in (sm.Elastic, sm.ElasticPlastic, sm.JohnsonCook, sm.Rigid, sm.Fluid, sm.LinearPolynomial,
                sm.Gruneisen, sm.Tait, sm.IdealGas, sm.StiffenedGas, sm.JWL):
        for name, field in cls.model_fields.items():
            assert field.description, f"{cls.__name__}.{name}"


def test_pack_material_eos_mismatch():
    m = MAT.validate_python(dict(type="elastic", density=RHO, youngs_modulus=E, poisson_ratio=NU))
    with pytest.raises(ValueError):
        pack_material(m, EOS.validate_python(dict(type="ideal_gas", gamma=1.4)))
    f = MAT.validate_python(dict(type="fluid", density=1000.0, eos="w"))
    with pytest.raises(ValueError):
        pack_material(f, None)


# ------------------------------------------------------------------------------ slot layout


def test_slot_layouts_are_disjoint_in_range_and_complete():
    """Within one model (or EOS) no two names share a slot; each stays in its part of the row; every
    slot name of materials/slots.py belongs to one layout."""
    value = lambda names: [getattr(ms, n) for n in names]  # noqa: E731
    common = value(ms.COMMON_SLOTS)
    assert sorted(common) == list(range(ms.P_MODEL))
    for model, names in ms.MODEL_SLOTS.items():
        slots = value(names)
        assert len(set(slots)) == len(slots) and all(ms.P_MODEL <= s < ms.P_EOS_TYPE for s in slots), model
    assert ms.P_EOS_TYPE < ms.EOS_OFFSET and ms.NQ == ms.NPARAM - ms.EOS_OFFSET
    assert sorted(value(ms.COMMON_EOS_SLOTS)) == list(range(ms.Q_MODEL))
    for eos, names in ms.EOS_SLOTS.items():
        slots = value(names)
        assert len(set(slots)) == len(slots) and all(ms.Q_MODEL <= s < ms.NQ for s in slots), eos
    assert sorted(value(ms.HISTORY_SLOTS)) == list(range(ms.NHIST))
    declared = {n for n in dir(ms) if n[:2] in ("P_", "Q_", "H_") and n not in ("P_MODEL", "Q_MODEL", "P_EOS_TYPE")}
    listed = set(ms.COMMON_SLOTS) | set(ms.COMMON_EOS_SLOTS) | set(ms.HISTORY_SLOTS)
    listed |= {n for names in (*ms.MODEL_SLOTS.values(), *ms.EOS_SLOTS.values()) for n in names}
    assert declared == listed


def _packed_slots(row):
    return {int(i) for i in np.flatnonzero(row)}


@pytest.mark.parametrize("rho0,spec", EOS_CASES, ids=[c[1]["type"] for c in EOS_CASES])
def test_pack_eos_fills_only_its_declared_slots(rho0, spec):
    _, q = eos_row(rho0, **spec)
    allowed = {getattr(ms, n) for n in (*ms.COMMON_EOS_SLOTS, *ms.EOS_SLOTS[spec["type"]])}
    assert _packed_slots(q) <= allowed and len(q) == ms.NQ
    assert {getattr(ms, n) for n in ms.EOS_SLOTS[spec["type"]]} <= _packed_slots(q)  # every constant given is nonzero


def test_pack_material_fills_only_its_declared_slots():
    jc = dict(type="johnson_cook", density=RHO, youngs_modulus=E, poisson_ratio=NU, A=350e6, B=275e6, n=0.36,
              C=0.022, m=1.0, reference_strain_rate=1.0, melt_temperature=1356.0, room_temperature=293.0,
              specific_heat=383.0)
    cases = {"elastic_plastic": bilinear()[1], "johnson_cook": material(**jc)[1],
             "elastic": material(type="elastic", density=RHO, youngs_modulus=E, poisson_ratio=NU)[1],
             "fluid": material(type="fluid", density=1000.0, viscosity=1e-3, eos="w",
                               _eos=dict(type="ideal_gas", gamma=1.4))[1]}
    for model, p in cases.items():
        own = {getattr(ms, n) for n in (*ms.COMMON_SLOTS, *ms.MODEL_SLOTS[model])}
        model_part = {s for s in _packed_slots(p) if s < ms.P_EOS_TYPE}
        assert model_part <= own, model
        assert {getattr(ms, n) for n in ms.MODEL_SLOTS[model]} - {ms.P_DETONATION_VELOCITY} <= model_part, model
    assert cases["elastic_plastic"][ms.P_EP_EP] == pytest.approx(E * ET / (E - ET), rel=1e-15)
    assert cases["johnson_cook"][ms.P_JC_CP] == 383.0 and cases["fluid"][ms.P_VISCOSITY] == 1e-3


def test_elastic_fast_path_is_update_stress_bit_for_bit():
    """elastic_stress_update / elastic_sound_speed (the element loop's inlined elastic law) give the
    bits update_stress / sound_speed give for an elastic material without an equation of state."""
    t, p = material(type="elastic", density=7850.0, youngs_modulus=2.1e11, poisson_ratio=0.3)
    assert t == k.ELASTIC and p[ms.P_EOS_TYPE] == k.EOS_NONE
    rng = np.random.default_rng(8)
    hist = np.zeros(ms.NHIST)
    for _ in range(200):
        sig = rng.normal(0.0, 1e8, 6)
        deps = rng.normal(0.0, 1e-4, 6)
        rel = rng.uniform(0.5, 1.5)
        ref, fast = sig.copy(), sig.copy()
        k.update_stress(t, p, ref, hist, deps, 1e-6, rel, 0.0)
        k.elastic_stress_update(p, fast, deps)
        assert fast.tobytes() == ref.tobytes()
        assert k.elastic_sound_speed(p, rel) == k.sound_speed(t, p, rel, 0.0)
