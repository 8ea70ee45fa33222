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
* Under ``-m validation``: the free field of decks/underwater_explosion_free_field_axisymmetric_sph.yaml
  against its ALE twin at equal spacing, 5 and 2.5 mm (the SPH peaks approach the ALE's).
"""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from pydantic import TypeAdapter

from sphfem_cli import api
from sphfem_cli.deck.schema.materials import EquationOfState, Material
from sphfem_cli.sph import lattice, scenes
from sphfem_cli.sph.system import SphOptions, SphSystem, material_table
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
PROBES = ("p_r060", "p_r100", "p_r140", "p_r180")


def _free_field_peaks(folder: Path, method: str, h: float) -> np.ndarray:
    """Probe peaks (Pa) of the r-z free field at spacing h: the ALE deck meshed at h, or its SPH twin derived
    at particle spacing h (study.derive, as decks/underwater_explosion_free_field_axisymmetric_sph.yaml);
    histories at every step (1e-8 s, below every step)."""
    from sphfem_cli.study import derive
    from sphfem_cli.study.study import load_deck_data

    data = load_deck_data(ALE_FREE_FIELD)
    ratio = round(0.01 / h)
    deck = derive.sph_variant(data, ratio).data if method == "sph" else derive.ale_variant(data, h).data
    result = api.run(deck, folder, {"output.history_interval": 1.0e-8, "output.interval": 1.0}, threads=1)
    assert result.completed, result.message
    hist = result.histories()
    return np.array([np.nanmax(hist[p]["pressure"]) for p in PROBES])


@pytest.mark.validation
@pytest.mark.xfail(strict=True, reason=(
    "the r-z SPH free field overshoots: about 1.16-1.28 x the 1D spherical reference at 2.5 mm and 1.19-1.21 x at "
    "1.25 mm, while the r-z ALE with Q2 0.3 is 1.02-1.06 x it; the gap to the ALE grows with refinement (open, issue 15)"))
def test_free_field_sph_approaches_the_ale_with_refinement(tmp_path):
    """The r-z SPH free field against the r-z ALE at equal spacing, 5 and 2.5 mm (about 20 s CPU in all).
    Measured against the ALE deck with the default Q2 0.06 (SPH / ALE - 1 at R = 0.06, 0.10, 0.14, 0.18 m): 5 mm
    -7.0 / -7.9 / -14.0 / -17.2 %, 2.5 mm +2.9 / -6.5 / -10.9 / -13.0 % (1.25 mm, the study: -0.7 / -2.9 / -5.3 /
    -7.3 %; docs/studies/underwater_explosion.md, "Axisymmetric SPH free field"). That ALE converged to 1.16 x the
    1D spherical reference of the same model (its linear viscosity's overshoot); with Q2 0.3, as the ALE deck now
    ships, it converges to the reference, and the SPH is above it: 5 mm +10.3 / +13.7 / +9.0 / +7.7 %, 2.5 mm
    +21.0 / +14.4 / +12.3 / +11.6 % (this test, 6 December 2026, 69 s wall at load 6): SPH is 1.16-1.28 x the 1D
    reference at 2.5 mm. Asserted (expected to fail until the SPH overshoot is found): at 2.5 mm within 15 % at
    every probe, and the gap smaller than at 5 mm at the three far probes."""
    gaps = {}
    for h in (0.005, 0.0025):
        sph = _free_field_peaks(tmp_path / f"sph_{h}", "sph", h)
        ale = _free_field_peaks(tmp_path / f"ale_{h}", "ale", h)
        gaps[h] = sph / ale - 1.0
        print(f"h {h}: SPH {np.round(sph / 1e6, 1)} MPa, ALE {np.round(ale / 1e6, 1)} MPa, gap {np.round(gaps[h], 3)}")
    assert np.all(np.abs(gaps[0.0025]) < 0.15), gaps
    assert np.all(np.abs(gaps[0.0025][1:]) < np.abs(gaps[0.005][1:])), gaps
