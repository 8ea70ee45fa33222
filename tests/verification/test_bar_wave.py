"""Speed of a longitudinal step wave in a laterally confined elastic bar (quad4 and hex8).

Reference: with the lateral faces held by symmetry conditions the bar is in uniaxial strain and
the wave travels at the dilatational (P-wave) speed
c = sqrt(E (1 - nu) / ((1 + nu)(1 - 2 nu) rho)) (e.g. Graff, Wave Motion in Elastic Solids,
1975, sec. 2.1 and 5.1; shared/reference/README.md "Elastic bar wave").
The left end is driven at a constant velocity v0 from t = 0; the front is located by the time at
which the mean velocity of the nodes of a cross-section reaches v0/2, at two stations, and
c_measured = (x2 - x1) / (t2 - t1). Criterion: within 2 % of c. Behind the front the stress is
-rho c v0 (the impedance relation), checked to the same 2 %.
"""
from __future__ import annotations

import numpy as np
import pytest

from conftest import crossing_times

pytestmark = pytest.mark.usefixtures("single_thread")

E, NU, RHO = 2.0e11, 0.3, 7850.0
C = np.sqrt(E * (1 - NU) / ((1 + NU) * (1 - 2 * NU) * RHO))
LENGTH, V0 = 1.0, 1.0
X1, X2 = 0.25, 0.75


def deck(dim: int) -> str:
    if dim == 2:
        box = "{min: [0, 0], max: [1.0, 0.005], divisions: [200, 1]}"
        sym = """
  - {type: symmetry, set: bottom, normal: y}
  - {type: symmetry, set: top, normal: y}"""
        drive = "[1.0, null]"
    else:
        box = "{min: [0, 0, 0], max: [1.0, 0.005, 0.005], divisions: [200, 1, 1]}"
        sym = """
  - {type: symmetry, set: bottom, normal: y}
  - {type: symmetry, set: top, normal: y}
  - {type: symmetry, set: back, normal: z}
  - {type: symmetry, set: front, normal: z}"""
        drive = "[1.0, null, null]"
    sides = ["left", "bottom", "top"] + (["back", "front"] if dim == 3 else [])
    sets = "\n".join(f"  {s}: {{type: node, part: bar, side: {s}}}" for s in sides)
    return f"""
title: confined bar, step velocity at the left end
dimension: {dim}
control: {{end_time: {0.9 * LENGTH / C:.6e}}}
materials:
  steel: {{type: elastic, density: {RHO}, youngs_modulus: {E}, poisson_ratio: {NU}}}
sections:
  solid: {{type: solid}}
parts:
  bar: {{material: steel, section: solid, geometry: {{box: {box}}}}}
sets:
{sets}
  station1: {{type: node, part: bar, plane: {{point: {point(dim, X1)}, normal: {point(dim, 1)}}}}}
  station2: {{type: node, part: bar, plane: {{point: {point(dim, X2)}, normal: {point(dim, 1)}}}}}
boundaries:{sym}
  - {{type: prescribed_velocity, set: left, velocity: {drive}}}
"""


def point(dim: int, x: float) -> str:
    """[x, 0] or [x, 0, 0] as deck text."""
    return "[" + ", ".join([str(x)] + ["0"] * (dim - 1)) + "]"


@pytest.mark.parametrize("dim", [2, 3])
def test_confined_bar_wave_speed(dim, sim_from_deck):
    sim = sim_from_deck(deck(dim))
    m = sim.model
    n1, n2 = m.node_sets["station1"], m.node_sets["station2"]
    assert len(n1) == len(n2) == 2 ** (dim - 1)
    times, v1, v2 = [0.0], [0.0], [0.0]

    def record(st):
        times.append(st.time)
        v1.append(st.v[n1, 0].mean())
        v2.append(st.v[n2, 0].mean())

    sim.run(record)
    times = np.array(times)
    t1 = crossing_times(times, np.array(v1), 0.5 * V0, rising=True)
    t2 = crossing_times(times, np.array(v2), 0.5 * V0, rising=True)
    assert len(t1) >= 1 and len(t2) >= 1
    c_measured = (X2 - X1) / (t2[0] - t1[0])
    print(f"\n{dim}D bar: wave speed {c_measured:.2f} m/s vs exact {C:.2f} m/s, "
          f"error {100 * (c_measured / C - 1):+.3f} %")
    assert abs(c_measured / C - 1.0) <= 0.02, f"wave speed {c_measured:.1f} vs {C:.1f}"

    # Impedance: the plateau stress behind the front is -rho c v0 (mid-bar elements, now loaded).
    centres = m.coordinates[m.connectivity].mean(axis=1)[:, 0]
    behind = (centres > 0.3) & (centres < 0.5)
    sxx = sim.state.stress[behind, 0].mean()
    print(f"{dim}D bar: plateau stress {sxx:.4e} Pa vs -rho c v0 = {-RHO * C * V0:.4e} Pa, "
          f"error {100 * (sxx / (-RHO * C * V0) - 1):+.3f} %")
    assert abs(sxx / (-RHO * C * V0) - 1.0) <= 0.02
