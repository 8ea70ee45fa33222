"""A cavitated Gruneisen liquid (pressure cut-off set, density below RHO_CAVITATED rho0) carries the
cut-off pressure and its reference sound speed, whatever its energy.

The state measured in decks/underwater_explosion_ale.yaml before the rule: water stretched to
1.3e-5 of its reference density, filling an element, with 7.8e6 J/kg of energy (here 7.85e6) (the cut-off's work
p_c dV): the EOS's thermal term gave +1.4 MPa and c = 1.5e6 m/s, and the run's step collapsed to
3e-10 s. Without a cut-off the EOS is used as it is.
"""
from __future__ import annotations

import numpy as np
import pytest

from sphfem_cli.ale import AleOptions, AleSystem
from sphfem_cli.ale import kernels as K
from sphfem_cli.deck.schema import materials as sm
from sphfem_cli.materials.tables import pack_material
from sphfem_cli.model.mesh import box_mesh


def _water(rho, e, **kw):
    eos = sm.Gruneisen(type="gruneisen", c=1480.0, s1=1.92, gamma0=0.28)
    row = pack_material(sm.Fluid(type="fluid", density=1000.0, eos="water"), eos)[1]
    mesh = box_mesh([0.0, 0.0], [0.0025, 0.0025], divisions=[1, 1])
    return AleSystem(mesh.nodes, mesh.elements, [row], np.ones((1, 1)), [rho], energy=[e], options=AleOptions(**kw))


def test_cavitated_water_has_cutoff_pressure_and_reference_sound_speed():
    rho, e = 0.0128, 7.85e6
    free = _water(rho, e)
    assert free.pressure()[0, 0] > 1e6  # the EOS far outside its range: +8 MPa
    c_free = np.sqrt(free.bulk_m[0, 0] / rho)
    assert c_free > 1e6
    cut = _water(rho, e, pressure_cutoff=-1e5)
    assert cut.pressure()[0, 0] == -1e5
    np.testing.assert_allclose(np.sqrt(cut.bulk_m[0, 0] / rho), 1480.0, rtol=1e-9)
    assert cut.stable_dt(1.0) > 100.0 * free.stable_dt(1.0)
    # above the limit nothing changes
    for r in (600.0, 990.0, 1010.0):
        a, b = _water(r, 1e3, pressure_cutoff=-1e5), _water(r, 1e3)
        assert a.pressure()[0, 0] == max(b.pressure()[0, 0], -1e5)
        assert a.bulk_m[0, 0] == pytest.approx(b.bulk_m[0, 0], rel=1e-12)
    assert K.RHO_CAVITATED == 0.5
