"""High explosives in axisymmetric SPH (issue 15): programmed burn, JWL products and the renormalised
r-z continuity (sph/axisymmetric.py ``renormalise_ring_continuity``; docs/theory/sph.md, "Explosive
products in r-z").

* The renormalised r-z divergence is exact for the linear axisymmetric fields v = (a r, d z) (div v =
  2 a + d) on a jittered lattice, up to the axis (whose images carry the odd continuation of v_r)
  and at the free surfaces: drho_i / rho_i = -(2 a + d) for every explosive particle. Measured
  (sphfem 0.1.0): largest relative error 1.3e-15; the plain areal sum of a water particle at the same
  state (no renormalisation) is off by up to 0.30 of 2a + d (at a free surface; 0.097 in the bulk and
  next to the axis), which is what the products' expansion suffers from (expansion.py). Asserted below
  1e-10.
* A burning TNT charge (radius 8 mm, centre z = 40.5 mm on the axis, a quarter cell off the lattice so
  that nothing is symmetric in z) in water in the closed cylinder r < 40 mm, 0 < z < 100 mm (slip ghost
  walls at r = R, z = 0 and z = 0.1; the axis a ghost line), Gruneisen water, JWL products, dx = 2 mm
  (1000 particles, 26 of TNT), alpha 0.1, timestep_scale 0.9:
  - mass exact: no particle lost, every ring mass unchanged;
  - no particle crosses or reaches the axis: no wall crossing, closest r 0.451 dx (asserted > 0.4 dx);
  - axial momentum: until the shock reaches the floor (at about 14 us; 32.5 mm at 2000-2500 m/s) the
    walls carry no load and sum m v_z drifts only by the axis images' truncation error (sph/axisymmetric.py
    docstring): measured |sum m v_z| / sum m |v_z| <= 2.8e-4 over 0-12 us (2.4e-4 at dx = 1 mm, free ends);
    asserted below 1e-3. Afterwards the walls' impulse changes it, as it must (0.8 at 40 us);
  - total energy (kinetic + internal, the walls are at rest): |E(t) / E(0) - 1| <= 2.9e-3 over 0-40 us,
    through the reflections (asserted below 5e-3); it is the leapfrog's error at the burn's start (the
    products' pressure rises from 0 to the CJ state within 1.5 cells of the burn front): 2.5e-3 at
    timestep_scale 0.9 and 3.9e-4 at 0.45 at 20 us (ratio 6.4 for a halved step);
  - the products did work: their mean density fell below 0.12 of 1630 kg/m^3 and the kinetic energy
    peaked at 0.38 of E(0).
* Under ``-m validation``: the free field of decks/underwater_explosion_free_field_axisymmetric_sph.yaml at 5 /
  2.5 / 1.25 mm converges to the 1D spherical reference (tests/verification/spherical_blast_reference.py).
"""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from pydantic import TypeAdapter

from sphfem_cli import api
from sphfem_cli.deck.schema.materials import EquationOfState, Material
from sphfem_cli.sph import lattice, scenes
from sphfem_cli.sph.options import SphOptions, material_table
from sphfem_cli.sph.system import SphSystem
from sphfem_cli.sph.walls import box_walls

_M, _E = TypeAdapter(Material), TypeAdapter(EquationOfState)
WATER = (_M.validate_python({"type": "fluid", "density": 1000.0, "eos": "water"}),
         _E.validate_python({"type": "gruneisen", "c": 1480.0, "s1": 1.92, "gamma0": 0.28}))
TNT = (_M.validate_python({"type": "high_explosive", "density": 1630.0, "detonation_velocity": 6930.0, "eos": "tnt"}),
       _E.validate_python({"type": "jwl", "A": 3.712e11, "B": 3.231e9, "R1": 4.15, "R2": 0.95, "omega": 0.3,
                           "e0": 7.0e9}))


def _system(x, mat, dx, walls, v=None):
    rho = np.where(mat == 1, 1630.0, 1000.0)
    opt = SphOptions(alpha=0.1, walls=walls, axisymmetric=True, pressure_cutoff=-1e5)
    v = np.zeros_like(x) if v is None else v
    return SphSystem(x, v, scenes.ring_particles(x, dx, rho), rho, mat, material_table([WATER, TNT]), opt)


def test_renormalised_ring_divergence_is_exact_for_linear_fields():
    dx, a, d = 0.002, 300.0, -120.0
    x = lattice.box([0.0, 0.0], [0.03, 0.03], dx)
    rng = np.random.default_rng(3)
    x += rng.uniform(-0.2, 0.2, x.shape) * dx  # jittered, still at r > 0
    v = np.column_stack([a * x[:, 0], d * x[:, 1]])
    div = 2.0 * a + d
    errs = {}
    for name, material in (("renormalised", 1), ("plain", 0)):
        ps = _system(x, np.full(len(x), material), dx, (), v)
        if material:
            ps.set_burn([((0.0, 0.0), 0.0)])
        ps.compute_rates()
        errs[name] = np.abs(ps.drho / ps.rho + div) / abs(div)
    inner = (x[:, 0] < 0.03 - 3 * dx) & (x[:, 1] > 3 * dx) & (x[:, 1] < 0.03 - 3 * dx)
    print(f"renormalised max {errs['renormalised'].max():.2e}; plain max {errs['plain'].max():.3f}, "
          f"bulk and axis {errs['plain'][inner].max():.3f}")
    assert errs["renormalised"].max() < 1e-10, errs["renormalised"].max()
    assert errs["plain"].max() > 0.1  # what the renormalisation is for (measured 0.30)


def test_burning_charge_in_a_closed_cylinder_conserves_mass_momentum_and_energy():
    dx, R, Z, zc, radius = 0.002, 0.04, 0.1, 0.0405, 0.008
    x = lattice.box([0.0, 0.0], [R, Z], dx)
    mat = (np.hypot(x[:, 0], x[:, 1] - zc) < radius).astype(np.int64)
    ps = _system(x, mat, dx, box_walls([0.0, 0.0], [R, Z], ["right", "bottom", "top"]))
    ps.set_burn([((0.0, zc), 0.0)])
    m0 = ps.m[np.argsort(ps.ids)].copy()
    e0 = ps.energies()["total"]
    drift_pz = drift_e = 0.0
    closest, ke_max = ps.x[:, 0].min(), 0.0
    for t in np.arange(2e-6, 40.01e-6, 2e-6):
        ps.run(t, scale=0.9)
        en = ps.energies()
        closest = min(closest, ps.x[:, 0].min())
        drift_e = max(drift_e, abs(en["total"] / e0 - 1.0))
        ke_max = max(ke_max, en["kinetic"] / e0)
        if t <= 12.01e-6:  # before the shock reaches the floor
            drift_pz = max(drift_pz, abs(ps.momentum()[1]) / float(np.sum(ps.m * np.abs(ps.v[:, 1]))))
    he = ps.mat == 1
    print(f"pz drift {drift_pz:.2e}, energy drift {drift_e:.2e}, closest r/dx {closest / dx:.3f}, "
          f"products rho {ps.rho[he].mean() / 1630:.3f} of rho0, KE max {ke_max:.3f} of E0")
    assert ps.lost == 0 and np.array_equal(ps.m[np.argsort(ps.ids)], m0)
    assert ps.wall_crossings == 0 and closest > 0.4 * dx, closest / dx
    assert drift_pz < 1e-3, drift_pz
    assert drift_e < 5e-3, drift_e
    assert ps.rho[he].mean() < 0.2 * 1630.0 and ke_max > 0.3


ALE_FREE_FIELD = Path(__file__).parents[2] / "decks" / "underwater_explosion_free_field_axisymmetric_ale.yaml"
SPH_FREE_FIELD = ALE_FREE_FIELD.with_name("underwater_explosion_free_field_axisymmetric_sph.yaml")
PROBES = ("p_r060", "p_r100", "p_r140", "p_r180")
RADII = (0.06, 0.10, 0.14, 0.18)  # the probes' distances from the charge centre, m


LEVELS = (0.005, 0.0025, 0.00125)  # particle spacings, m


def _free_field_peaks(folder: Path, h: float, continuity: str = "volume") -> np.ndarray:
    """Probe peaks (Pa) of the r-z SPH free field at particle spacing h: the SPH twin of the ALE deck derived at
    ratio 10 mm / h (study.derive.sph_variant, as decks/underwater_explosion_free_field_axisymmetric_sph.yaml) with
    that shipped deck's artificial viscosity (the derivation's default is the weakly compressible alpha 0.1, beta
    0); histories at every step (1e-8 s, below every step); ``continuity`` the section's form (an override)."""
    import yaml

    from sphfem_cli.study import derive
    from sphfem_cli.study.study import load_deck_data

    deck = derive.sph_variant(load_deck_data(ALE_FREE_FIELD), round(0.01 / h)).data
    shipped = yaml.safe_load(SPH_FREE_FIELD.read_text())["sections"]["sph"]["artificial_viscosity"]
    deck["sections"]["sph"]["artificial_viscosity"] = dict(shipped)
    result = api.run(deck, folder, {"output.history_interval": 1.0e-8, "output.interval": 1.0,
                                    "sections.sph.continuity": continuity}, threads=1)
    assert result.completed, result.message
    hist = result.histories()
    return np.array([np.nanmax(hist[p]["pressure"]) for p in PROBES])


@pytest.fixture(scope="module")
def volume_form_peaks(tmp_path_factory):
    """The free field's probe peaks (Pa) with the shipped volume form, per level of ``LEVELS`` (rows)."""
    folder = tmp_path_factory.mktemp("free_field_volume")
    return np.array([_free_field_peaks(folder / f"sph_{h}", h) for h in LEVELS])


@pytest.fixture(scope="module")
def one_d_reference():
    """The 1D spherical Lagrangian reference's peaks at ``RADII`` (dr 0.5 / 0.25 / 0.125 mm), extrapolated."""
    from sphfem_cli.study.metrics import three_grid
    from tests.verification.spherical_blast_reference import blast, peaks, setup_from_deck

    drs = (5e-4, 2.5e-4, 1.25e-4)
    setup = setup_from_deck(ALE_FREE_FIELD)
    one_d = np.array([peaks(blast(setup, dr, np.array(RADII), t_end=1.2e-4))["peak"] for dr in drs])
    return np.array([three_grid(drs, one_d[:, k]).extrapolated for k in range(len(RADII))])


@pytest.mark.validation
def test_free_field_sph_converges_to_the_1d_spherical_reference(volume_form_peaks, one_d_reference):
    """The r-z SPH free field (decks/underwater_explosion_free_field_axisymmetric_sph.yaml, Monaghan alpha 1, beta 2)
    at 5 / 2.5 / 1.25 mm against the 1D spherical Lagrangian reference of the same model
    (spherical_blast_reference.blast at dr 0.5 / 0.25 / 0.125 mm, Richardson-extrapolated: Celik et al. 2008,
    sphfem_cli.study.metrics.three_grid). About 35 s CPU.

    Measured (one thread, load 4-5): SPH peaks 368.0 / 468.7 / 537.7, 165.8 / 215.3 / 243.4, 99.8 / 130.8 / 149.4,
    68.9 / 90.4 / 104.2 MPa at 0.06 / 0.10 / 0.14 / 0.18 m, 0.81-0.85 of the 1D's 664 / 285 / 180 / 130 MPa at
    1.25 mm; they rise monotonically towards it (observed order 0.55 / 0.82 / 0.74 / 0.64) and their extrapolation
    is 688 / 280 / 178 / 129 MPa, +3.6 / -1.9 / -1.3 / -0.7 % of the reference (GCI 19-35 %). The 0.625 mm level
    (the study, docs/studies/underwater_explosion.md "Axisymmetric SPH free field": 0.88-0.92 of the reference)
    gives an order of 0.46-0.57 and +5.6 to +8.3 % on 2.5 / 1.25 / 0.625 mm: not yet asymptotic, the converged
    peak is bracketed by the reference -2 to +8 %. With the old alpha 0.1, beta 0 the same levels overshot:
    1.19-1.20 x the 1D at equal size at 1.25 mm and 1.11-1.16 x the converged reference at 0.625 mm, rising (the
    front's ringing, test_sph_axisymmetric_shock.py). Asserted: every level below the reference + 2 %, the error
    falling at every refinement at every probe, and the extrapolation within 5 % of the reference (the finer
    triple's +8 % shows that these levels are not asymptotic: this checks the trend and the bracket, not a
    converged value)."""
    from sphfem_cli.study.metrics import three_grid

    sph, ref = volume_form_peaks, one_d_reference
    ext = np.array([three_grid(LEVELS, sph[:, k]).extrapolated for k in range(len(RADII))])
    err = sph / ref - 1.0
    print(f"SPH peaks (MPa) per level {np.round(sph / 1e6, 1).tolist()}; 1D extrapolated {np.round(ref / 1e6, 1)}; "
          f"SPH / 1D - 1 per level {np.round(100 * err, 1).tolist()} %; SPH extrapolated {np.round(ext / 1e6, 1)}, "
          f"{np.round(100 * (ext / ref - 1), 1)} %")
    assert np.all(err < 0.02), err
    assert np.all(np.abs(err[1:]) < np.abs(err[:-1])), err
    assert np.all(np.abs(ext / ref - 1.0) < 0.05), ext / ref


@pytest.mark.validation
def test_free_field_mass_form_matches_the_volume_form(tmp_path, volume_form_peaks, one_d_reference):
    """The same free field with the mass form of the continuity equation (``continuity: mass`` through api.run's
    overrides; drho_i/dt = sum_j rho_j A_j v_ij.grad W - rho_i v_r/r, sph/axisymmetric.py) at 5 / 2.5 / 1.25 mm,
    against the volume form of the shipped deck and the 1D reference. About 50 s CPU (and the volume form's 45).

    Measured (one thread, load about 5; CPU s 1.4 / 4.9 / 42.1, the volume form 0.7 / 4.6 / 38.9): peaks 367.4 /
    467.2 / 536.2, 165.8 / 215.7 / 243.6, 100.2 / 131.4 / 149.7, 69.3 / 91.0 / 104.4 MPa at 0.06 / 0.10 / 0.14 /
    0.18 m, within -0.33 to +0.59 % of the volume form's at every level and probe; 0.81-0.85 of the 1D reference
    (663.7 / 285.2 / 179.9 / 129.7 MPa) at 1.25 mm; observed order 0.53 / 0.84 / 0.77 / 0.69, extrapolated +4.1 /
    -2.3 / -2.5 / -2.5 % of the reference (the volume form +3.6 / -1.9 / -1.3 / -0.7 %; GCI 18-36 %); peak times
    within 0.3 us; energy ratio 1.0010 / 1.0009 / 1.0008 (the same to 2e-5). The two forms differ by
    sum_j (rho_j - rho_i) A_j v_ij.grad W: in the water, compressed at most 16 % at these peaks (the Hugoniot of
    c 1480, s 1.92 at 540 MPa), that is small, and the products' continuity is renormalised, the same in both
    forms (renormalise_ring_continuity). Nothing here prefers the mass form: the shipped deck keeps the volume form.
    Asserted: the mass form's peaks within 1.5 % of the volume form's at every level and probe (measured 0.6 %, a
    ninth of the smallest change between two levels, 13 %), and the volume form's convergence checks (below the
    reference + 2 %, the error falling at every refinement, extrapolated within 5 %)."""
    from sphfem_cli.study.metrics import three_grid

    mass = np.array([_free_field_peaks(tmp_path / f"sph_{h}", h, "mass") for h in LEVELS])
    ref = one_d_reference
    ext = np.array([three_grid(LEVELS, mass[:, k]).extrapolated for k in range(len(RADII))])
    err = mass / ref - 1.0
    print(f"mass form peaks (MPa) per level {np.round(mass / 1e6, 1).tolist()}; mass / volume - 1 "
          f"{np.round(100 * (mass / volume_form_peaks - 1), 2).tolist()} %; extrapolated {np.round(ext / 1e6, 1)}, "
          f"{np.round(100 * (ext / ref - 1), 1)} % of the 1D")
    assert np.all(np.abs(mass / volume_form_peaks - 1.0) < 0.015), mass / volume_form_peaks
    assert np.all(err < 0.02), err
    assert np.all(np.abs(err[1:]) < np.abs(err[:-1])), err
    assert np.all(np.abs(ext / ref - 1.0) < 0.05), ext / ref
