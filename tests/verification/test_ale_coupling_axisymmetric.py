"""ALE -> structure coupling in r-z (``dimension: axisymmetric``, couplings: lagrange_in_solid).

A coupling point at radius r_p stands for its ring: A = 2 pi r_p l, k = pfac K A^2 / V with V the
host's ring volume, forces for the full 2 pi (contact.coupling, docs/theory/coupling.md).

1. A closed r-z box (slip walls on the three sides off the axis) half full of water, an elastic disc
   on the axis entering it at 10 m/s, no gravity: the axial momentum of disc and water, less the
   impulse of the walls, is conserved to round-off; the energy balance holds to the coupling's
   first-order penalty error (the same deck in plane strain gives the same size); every stored
   stiffness is pfac K (2 pi r_p l)^2 / V. Run at pfac 0.1, where these were measured: at the default
   (auto, 4 here: L_c = h / 2) the light disc (12 kg/m^2) stops on the water instead of bouncing back at
   +3.15 m/s, and the balance swings by up to 7.6 % (3.5 % at pfac 2, 1.7 % at 1) during the impact, when
   the penalty spring's step is 1.3 times the run's (a stiff spring under the leapfrog; not a drift: the
   ratio returns to within 1.5 % by 0.12 ms).
2. A water column (H = 0.1 m, radius R = 0.1 m, hydrostatic start, gravity) on a clamped plate
   held fixed over its whole face: once the column's ringing has decayed the axial force the
   coupling puts on the plate is the column's weight rho g H pi R^2.
"""
from __future__ import annotations

import numpy as np

from sphfem_cli.driver import load_model
from sphfem_cli.solver.explicit import Simulation

BOX = """
title: elastic disc into a closed r-z box of ALE water (test)
units: {length: m, mass: kg, time: s}
dimension: axisymmetric
control: {end_time: 5.0e-4}
equations_of_state:
  water: {type: linear_polynomial, c1: 2.2e9}
materials:
  water: {type: fluid, density: 1000.0, eos: water}
  void: {type: void}
  pmma: {type: elastic, density: 1200.0, youngs_modulus: 3.0e9, poisson_ratio: 0.35}
sections:
  ale: {type: ale_multi_material}
  solid: {type: solid}
parts:
  tank:
    material: void
    section: ale
    geometry: {box: {min: [0.0, 0.0], max: [0.1, 0.1], element_size: 0.005}}
    fill: [{material: water, box: {min: [0.0, 0.0], max: [0.1, 0.05]}}]
  disc:
    material: pmma
    section: solid
    geometry: {box: {min: [0.0, 0.051], max: [0.05, 0.061], divisions: [10, 2]}}
couplings: [{type: lagrange_in_solid, structure: disc, fluid: tank, pfac: 0.1}]
initial: [{type: velocity, part: disc, velocity: [0.0, -10.0]}]
boundaries: [{type: ale_boundary, part: tank, sides: [right, bottom, top], condition: slip}]
output: {interval: 1.0e-3}
"""

COLUMN = """
title: water column on a clamped circular plate, r-z ALE (test)
units: {length: m, mass: kg, time: s}
dimension: axisymmetric
control: {end_time: 0.02}
equations_of_state:
  water: {type: linear_polynomial, c1: 4.0e7}
materials:
  water: {type: fluid, density: 1000.0, eos: water}
  void: {type: void}
  plate: {type: elastic, density: 1000.0, youngs_modulus: 1.0e8, poisson_ratio: 0.3}
sections:
  ale: {type: ale_multi_material}
  plate: {type: solid}
parts:
  tank:
    material: void
    section: ale
    geometry: {box: {min: [0.0, -0.01], max: [0.1, 0.12], element_size: 0.01}}
    hydrostatic: true
    fill: [{material: water, box: {min: [0.0, 0.0], max: [0.1, 0.1]}}]
  plate:
    material: plate
    section: plate
    geometry: {box: {min: [0.0, -0.02], max: [0.1, 0.0], divisions: [10, 2]}}
sets:
  held: {type: node, part: plate}
boundaries:
  - {type: fixed, set: held, directions: [x, y]}
  - {type: ale_boundary, part: tank, sides: [right, bottom], condition: slip}
loads: [{type: gravity, acceleration: [0.0, -9.81]}]
couplings: [{type: lagrange_in_solid, structure: plate, fluid: tank, pfac: 1.0, damping: 1.0}]
output: {interval: 0.01}
"""


def _sim(tmp_path, text, name):
    path = tmp_path / f"{name}.yaml"
    path.write_text(text)
    return Simulation(load_model(str(path)).model)


def test_disc_into_closed_rz_box_conserves_axial_momentum(tmp_path):
    sim = _sim(tmp_path, BOX, "box")
    ale, model = sim.ale.system, sim.model
    coupling = sim.interactions[0]
    disc = np.arange(model.n_nodes)[model.parts[1].nodes]
    axis = disc[sim.state.x[disc, 0] == 0.0]

    def axial():
        return ((model.mass * sim.state.v[:, 1]).sum() + (ale.node_mass * ale.velocity[:, 1]).sum()
                - ale.wall_impulse[1])

    p0 = axial()
    scale = (model.mass * np.abs(sim.state.v[:, 1])).sum()
    ke0 = sim.kinetic_energy()
    err, ratio, contact = 0.0, 0.0, []
    while sim.state.time < sim.control.end_time * (1 - 1e-12):
        sim.step()
        err = max(err, abs(axial() - p0) / scale)
        row = sim.energy_row()
        ratio = max(ratio, abs(row.ratio - 1.0))
        contact.append(row.contact)
    assert err < 1e-13  # measured 2.5e-15
    # the disc has pushed water: it slowed (measured +3.15 m/s: it bounced) and many points hold a host
    # (measured 20 of 44). Run to 0.5 ms (it ran to 1 ms): since the closure takes the void in the elements
    # the disc presses on for the disc's volume (docs/theory/ale.md, "Void behind a structure's face") the
    # water there compresses and the soft default penalty layer (pfac 0.1) holds 54 % of the impact energy
    # at its peak and throws the light disc back; by 1 ms no point held a host, which left the stiffness
    # check below nothing to check. Before the fix, at 1 ms: -2.0 m/s, 20 of 24 hosted, peak 30 %.
    assert (model.mass[disc] * sim.state.v[disc, 1]).sum() / model.mass[disc].sum() > -5.0
    assert np.count_nonzero(coupling.host >= 0) > 10
    # the penalty's first-order energy error: measured 5.7e-4 here (4.3e-4 before the fix, 5.8e-4 for this
    # deck in plane strain then); contact energy min -1.03e-3 of the impact energy (-1.1e-3 before; plane
    # -1.2e-3)
    assert ratio < 1e-3
    assert min(contact) > -2e-3 * ke0
    # the axis: disc and ALE axis nodes stay on it, nothing crosses it
    assert np.all(sim.state.x[axis, 0] == 0.0) and np.all(ale.velocity[ale.x[:, 0] == 0.0, 0] == 0.0)
    assert sim.state.x[:, 0].min() >= 0.0 and ale.x[:, 0].min() >= 0.0
    # ring stiffness: one more force pass, then k = pfac K (2 pi r_p l)^2 / V (V the ring volume)
    sim.state.f_contact[:] = 0.0
    ale.f_couple[:] = 0.0
    coupling.forces(sim.state)
    _, bulk, vol = coupling._fluid_fields(ale)
    seg = coupling.segments
    xs = sim.state.x
    hosted = np.flatnonzero(coupling.host >= 0)
    s, q = np.divmod(hosted, coupling.nquad)
    r = -1.0 + (2.0 * q + 1.0) / coupling.nquad
    rp = 0.5 * (1.0 - r) * xs[seg[s, 0], 0] + 0.5 * (1.0 + r) * xs[seg[s, 1], 0]
    ell = np.linalg.norm(xs[seg[s, 1]] - xs[seg[s, 0]], axis=1) / coupling.nquad
    e = coupling.host[hosted]
    expected = float(coupling.spec.pfac) * bulk[e] * (2.0 * np.pi * rp * ell) ** 2 / vol[e]
    assert np.allclose(coupling.stiff[hosted], expected, rtol=1e-12, atol=0.0)
    # forces balance along the axis: what the disc receives the water receives opposite
    assert abs(coupling.f_solid[:, 1].sum() + coupling.f_fluid[:, 1].sum()) <= 1e-12 * np.abs(coupling.f_solid).sum()


def test_water_column_weight_on_a_held_circular_plate(tmp_path):
    sim = _sim(tmp_path, COLUMN, "column")
    coupling = sim.interactions[0]
    ale = sim.ale.system
    weight_formula = 1000.0 * 9.81 * 0.1 * np.pi * 0.1 ** 2
    water = ale.mass_m[:, 1].sum()  # ring masses of the fill: the full 2 pi
    # rho0 pi R^2 H, plus the hydrostatic compression: mean p / K = rho g H / (2 K) = 1.23e-5
    assert abs(water / (1000.0 * 0.1 * np.pi * 0.1 ** 2) - 1.0 - 1000.0 * 9.81 * 0.1 / 8.0e7) < 1e-6
    time, force = [], []
    while sim.state.time < sim.control.end_time * (1 - 1e-12):
        sim.step()
        time.append(sim.state.time)
        force.append(-coupling.f_solid[:, 1].sum())  # downward on the plate
    time, force = np.array(time), np.array(force)
    late = time > 0.5 * time[-1]
    # the column rings at about 2 ms and its ringing decays through the damped penalty by 10 ms;
    # measured mean over 10..20 ms 0.99994 W, last 2 ms 0.9995 W (min 0.999, max 1.000)
    assert abs(force[late].mean() / weight_formula - 1.0) < 0.01
    assert abs(force[time > 0.9 * time[-1]].mean() / (9.81 * water) - 1.0) < 0.01
    # no radial force is left on the axis: the point nearest it is on a ring of small area
    assert np.all(sim.state.x[sim.state.x[:, 0] == 0.0, 0] == 0.0)
