"""Traces in the ALE multi-material closure and remap (``lagrange.is_trace``, ``AleOptions.trace_fraction``).

A trace is a material with an EOS state whose mass is at most ``trace_fraction`` (1e-9) of its element's mass, or of
the mass rho0 V the element would hold filled with it: it keeps its volume in the closure and gives no van Leer
slope. The mechanism it mends (docs/studies/underwater_explosion.md, "The stop traced further at 10 mm"): in water
under tension at the pressure cut-off, a products' trace with almost no stiffness took nearly all the element's
expansion in the pressure relaxation and its -p dV, a specific energy of 1e13 J/kg and more, which the remap spread.
"""
from __future__ import annotations

import numpy as np
import pytest

from sphfem_cli.ale import AleOptions
from sphfem_cli.ale import kernels as K
from sphfem_cli.ale.lagrange import RHO_VOID, is_trace
from sphfem_cli.ale.remap import _face_flux

TRACE = AleOptions().trace_fraction
RHO_W, RHO_HE, CUTOFF = 1000.0, 1630.0, -1.0e5
# the products' trace of element 9624 of the 10 mm plate deck at its step 77 (5.9e-15 m^3, 2e-15 kg in an element of
# 1e-6 m^3; docs/studies/underwater_explosion.md), in a unit element: its mass 2e-12 of the element's, 1.2e-12 of
# rho0 V, its density 2e-4 of rho0 (above RHO_VOID: it has a pressure)
PHI_T, M_T = 6e-9, 2e-9


def test_trace_fraction_default():
    assert TRACE == 1e-9  # the options' stated default (OpenRadioss's law 51 uses 1e-10 on the same two fractions)


@pytest.mark.parametrize("vol, mass, rho0, vtot, mtot, want", [
    (0.5, 0.0, 0.0, 1.0, 500.0, False),  # void: no EOS state
    (0.5, 0.5 * RHO_HE * RHO_VOID, RHO_HE, 1.0, 500.0, False),  # volume the remap left without mass: void too
    (PHI_T, M_T, RHO_HE, 1.0, 1000.0, True),  # the products' trace of the 10 mm plate deck
    (1e-3, 1e-3 * RHO_HE, RHO_HE, 1.0, 1000.0, False),  # a thousandth of the element at its reference density
    (0.5, 1e-7, 1.2, 1.0, 500.0, True),  # 2e-10 of the element's mass (rho0 V fraction 8e-8): a trace by mass
    (2e-9, 2e-9 * RHO_W / 4, RHO_W, 1.0, 5e-7, True),  # alone with void (mass fraction 1), rho0 V fraction 5e-10
    (4e-9, 4e-9 * RHO_W, RHO_W, 1.0, 4e-6, False),  # alone with void, rho0 V fraction 4e-9
])
def test_is_trace(vol, mass, rho0, vtot, mtot, want):
    assert is_trace(vol, mass, rho0, vtot, mtot, TRACE) is want


def _expand(vol_m, mass_m, ener_m, pres_m, bulk_m, rho0, trace, stretch=0.1):
    """One Lagrangian step of a unit quad whose top moves up by `stretch` (no forces: W_e = 0), relax closure."""
    x = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
    v_new = np.array([[0.0, 0.0], [0.0, 0.0], [0.0, stretch], [0.0, stretch]])
    K.lagrange_energy(x, np.zeros((4, 2)), v_new, 1.0, np.array([[0, 1, 2, 3]]), np.zeros((1, 4, 2)), vol_m, mass_m,
                      ener_m, np.zeros_like(vol_m), pres_m, bulk_m, np.zeros(1), K.CLOSURE_RELAX, 0.5, 0.5, 1e-9,
                      np.zeros(1, dtype=np.bool_), np.asarray(rho0, dtype=float), trace, np.zeros(1), False)


def _water_and_products_trace(trace):
    """Water at the cut-off (K = rho c^2 = 2.2e9 Pa) with the products' trace (PHI_T, M_T) at the cut-off with
    almost no stiffness (1e-3 Pa), expanded by a tenth."""
    vol_m = np.array([[1.0 - PHI_T, PHI_T]])
    mass_m = np.array([[RHO_W * (1.0 - PHI_T), M_T]])
    ener_m = np.zeros((1, 2))
    pres_m = np.array([[CUTOFF, CUTOFF]])
    bulk_m = np.array([[2.2e9, 1e-3]])
    _expand(vol_m, mass_m, ener_m, pres_m, bulk_m, [RHO_W, RHO_HE], trace)
    return vol_m, mass_m, ener_m


def test_a_trace_keeps_its_volume_and_gets_no_work():
    """With the floor the trace keeps its volume and gets no -p dV; the water takes the whole expansion. (No forces,
    so W_e = 0: the rest W_e - sum(-p_m dV_m) = -1e4 J goes by mass, the trace's share the water's -10 J/kg.)"""
    vol_m, mass_m, ener_m = _water_and_products_trace(TRACE)
    assert vol_m[0, 1] == PHI_T
    assert vol_m.sum() == pytest.approx(1.1, rel=1e-14)
    assert ener_m[0, 1] / mass_m[0, 1] == pytest.approx(CUTOFF * 0.1 / mass_m.sum(), rel=1e-9)  # -10.003 J/kg
    assert abs(ener_m.sum()) < 1e-9  # the element's energy changes by W_e = 0


def test_without_the_floor_the_trace_takes_the_expansion():
    """trace_fraction 0 (no floor, as before): by compliance V_m / K_m (the trace's K raised to the closure's
    1e-9 K_max = 2.2 Pa) the trace takes 86 % of the tenth (1.4e7 times its volume) and its -p dV, 8.6e3 J in
    2e-9 kg: 4.3e12 J/kg (the 10 mm deck's trace: 1e13 J/kg)."""
    vol_m, mass_m, ener_m = _water_and_products_trace(0.0)
    share = 0.1 * (PHI_T / 2.2) / (PHI_T / 2.2 + (1.0 - PHI_T) / 2.2e9)
    assert vol_m[0, 1] == pytest.approx(PHI_T + share, rel=1e-6)
    assert share > 0.085
    assert ener_m[0, 1] / mass_m[0, 1] == pytest.approx(-CUTOFF * share / M_T, rel=1e-6)


def test_an_element_of_traces_alone_still_takes_its_change():
    """Two materials, both traces (rho0 V fractions 7.5e-10, 9e-10) and nothing else: they take the volume change
    as if there were no floor (the closure's fallback), so the element's volumes still sum to its new volume."""
    vol_m = np.array([[0.5, 0.5]])
    mass_m = np.array([[0.5 * 1.5e-9 * RHO_W, 0.5 * 1.8e-9 * 1.2]])
    ener_m = np.zeros((1, 2))
    pres_m = np.array([[CUTOFF, 0.1]])
    bulk_m = np.array([[2.2e9, 1.4e5]])
    _expand(vol_m, mass_m, ener_m, pres_m, bulk_m, [RHO_W, 1.2], TRACE)
    assert vol_m.sum() == pytest.approx(1.1, rel=1e-14)
    assert vol_m[0, 1] > 0.55  # the softer gas takes the larger share, as without a floor


def _products_flux(trace):
    """Specific energy of the products leaving donor 1 for acceptor 2 (upwind element 0) by van Leer, donor
    fractions: products present in 0 and 1 (e 2e6 and 3e6 J/kg), a trace (PHI_T, M_T) in 2 at 1e13 J/kg."""
    vol_m = np.array([[0.5, 0.5], [0.5, 0.5], [1.0 - PHI_T, PHI_T]])
    mass_m = np.array([[500.0, 20.0], [500.0, 20.0], [RHO_W * (1.0 - PHI_T), M_T]])
    ener_m = mass_m * np.array([[1e5, 2e6], [1e5, 3e6], [1e5, 1e13]])
    fvol, fmass, fener = np.zeros((1, 2)), np.zeros((1, 2)), np.zeros((1, 2))
    scratch = np.zeros(2), np.zeros(2), np.zeros(2, dtype=np.bool_)
    _face_flux(0, 0.1, 1, 2, 0, 1.0, vol_m, mass_m, ener_m, 2, K.IFACE_DONOR, 1e-9, np.array([RHO_W, RHO_HE]), trace,
               fvol, fmass, fener, *scratch)
    return fener[0, 1] / fmass[0, 1]


def test_a_trace_gives_no_van_leer_slope():
    """The acceptor's trace is no neighbour of the slope: the products leave at the donor's 3e6 J/kg (donor cell).
    Without the floor its 1e13 J/kg steepens the slope: van Leer's e_d + (1 - c) d1 d2 / (d1 + d2), d1 = 1e13 - 3e6,
    d2 = 3e6 - 2e6, c = 0.1, is 3.9e6 J/kg to 2e-8."""
    assert _products_flux(TRACE) == pytest.approx(3e6, rel=1e-15)
    assert _products_flux(0.0) == pytest.approx(3e6 + 0.9e6, rel=1e-6)


def test_a_fog_node_has_no_velocity_between_the_sweeps():
    """``dual.node_velocities``: p / m, but 0 at or below the node's mass floor, as the remap's finish and the
    Lagrangian update hold such a node. The 10 mm plate deck had a node of 1.7e-41 kg (floor 1.6e-13) at 9.4e26 m/s
    after one sweep, whose kinetic energy the next sweep carried: 4.7e10 J of internal energy pairs by DeBar's fix."""
    mnode = np.array([1.0e-3, 1.7e-41, 1.6e-13, 0.0])
    pnode = np.array([[2e-3, 0.0, -1e-3], [1.6e-14, 0.0, 0.0], [1.6e-12, 0.0, 0.0], [0.0, 0.0, 0.0]])
    m_floor = np.full(4, 1.63e-13)
    u = np.full((4, 3), np.nan)
    K.node_velocities(mnode, pnode, m_floor, u)
    np.testing.assert_array_equal(u[0], [2.0, 0.0, -1.0])
    assert not u[1:].any()  # 1.7e-41 and 1.6e-13 kg: at or below the floor; and no mass
