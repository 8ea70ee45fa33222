"""Bilinear plasticity through the whole FEM path: one hex8 in uniaxial tension.

A unit cube with symmetry conditions on its x = 0, y = 0 and z = 0 faces is pulled at x = 1
(prescribed velocity with a smooth start) while its lateral faces are free, so the stress state
is uniaxial. For the hypoelastic rate form driven by the rate of deformation, the uniaxial
Cauchy (true) stress is an exact bilinear function of the logarithmic strain eps = ln(l / l0):
sigma = E eps up to sigma_y, then sigma_y + Et (eps - sigma_y / E) (linear hardening; the radial
return is exact for this proportional path; Simo & Hughes, Computational Inelasticity, 1998,
sec. 3.3). Before yield the criterion's 1e-6 (relative to sigma_y) is met. Reference values as
in tests/unit/test_materials.py (which checks the material kernel alone to 1e-6).

What explicit dynamics achieves here, and the tolerances used. The lateral faces move by inertia:
when the material yields, the lateral contraction rate must jump from nu to about 1/2 of the
axial rate, and the lateral nodes lag by about one wave transit, which leaves a lateral stress
and a stress error of order E (1/2 - nu) (axial strain per step). With 20000 steps to 16 times the
yield strain (measured): error 2.0e-4 sigma_y at the yield point, 4e-6 sigma_y beyond 1.1 times
the yield strain (the oscillation decays by the bulk viscosity), 1e-6 sigma_y at the end. The error
falls as 1/steps, so 1e-6 throughout would take millions of steps. The tolerances below are
about 2.5 times these measured figures.
"""
from __future__ import annotations

import numpy as np
import pytest

pytestmark = pytest.mark.usefixtures("single_thread")

E, NU, SY, ET, RHO = 200e9, 0.3, 250e6, 2e9, 7850.0
EPS_Y = SY / E
EPS_END = 0.02
STEPS = 20000


def exact_stress(eps):
    return np.where(eps <= EPS_Y, E * eps, SY + ET * (eps - EPS_Y))


def deck() -> str:
    c = np.sqrt(E * (1 - NU) / ((1 + NU) * (1 - 2 * NU) * RHO))
    end = STEPS * 0.9 / c  # about STEPS stable steps of the unit cube
    ramp = 0.05 * end
    ts = np.linspace(0.0, ramp, 21)
    points = ", ".join(f"[{t:.12e}, {0.5 * (1 - np.cos(np.pi * t / ramp)):.12e}]" for t in ts)
    v = (np.exp(EPS_END) - 1.0) / (end - 0.5 * ramp)  # stretch exp(EPS_END) at the end
    return f"""
title: one hex8 in uniaxial tension, bilinear plasticity
dimension: 3
control: {{end_time: {end:.12e}}}
curves:
  start: {{points: [{points}]}}
materials:
  steel: {{type: elastic_plastic, density: {RHO}, youngs_modulus: {E}, poisson_ratio: {NU},
           yield_stress: {SY}, tangent_modulus: {ET}}}
sections:
  solid: {{type: solid}}
parts:
  cube: {{material: steel, section: solid,
          geometry: {{box: {{min: [0, 0, 0], max: [1, 1, 1], divisions: [1, 1, 1]}}}}}}
sets:
  x0: {{type: node, part: cube, side: left}}
  y0: {{type: node, part: cube, side: bottom}}
  z0: {{type: node, part: cube, side: back}}
  x1: {{type: node, part: cube, side: right}}
boundaries:
  - {{type: symmetry, set: x0, normal: x}}
  - {{type: symmetry, set: y0, normal: y}}
  - {{type: symmetry, set: z0, normal: z}}
  - {{type: prescribed_velocity, set: x1, velocity: [{v:.12e}, null, null], curve: start}}
"""


def test_uniaxial_true_stress_vs_log_strain(sim_from_deck):
    sim = sim_from_deck(deck())
    pulled = sim.model.node_sets["x1"]
    eps, sxx, lateral = [], [], []

    def record(st):
        eps.append(np.log(st.x[pulled, 0].mean()))
        sxx.append(st.stress[0, 0])
        lateral.append(np.abs(st.stress[0, 1:]).max())

    sim.run(record)
    eps, sxx, lateral = np.array(eps), np.array(sxx), np.array(lateral)
    err = np.abs(sxx - exact_stress(eps)) / SY
    assert abs(eps[-1] - EPS_END) < 1e-9
    elastic = eps < 0.9 * EPS_Y
    plastic = eps > 1.1 * EPS_Y
    print(f"\nuniaxial hex8: |sigma - exact|/sigma_y: elastic range {err[elastic].max():.2e}, "
          f"overall {err.max():.2e} (at eps/eps_y = {eps[np.argmax(err)] / EPS_Y:.3f}), "
          f"beyond 1.1 eps_y {err[plastic].max():.2e}, end {err[-1]:.2e}; "
          f"lateral stress max {lateral.max() / SY:.2e} sigma_y ({sim.state.step} steps)")
    assert err[elastic].max() <= 1e-6  # the criterion's 1e-6 holds before yield
    assert err.max() <= 5e-4
    assert err[plastic].max() <= 1e-5
    assert err[-1] <= 2.5e-6
    assert lateral[plastic].max() <= 1e-5 * SY
    # Effective plastic strain: the log strain less the elastic part sigma/E.
    eps_p = EPS_END - exact_stress(EPS_END) / E
    print(f"effective plastic strain {sim.state.hist[0, 0]:.8e} vs {eps_p:.8e}")
    assert abs(sim.state.hist[0, 0] / eps_p - 1.0) <= 1e-6
