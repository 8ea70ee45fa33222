"""`sphfem` with structure_in_water_corner_truncation.py's corner correction on every SPH-slave nodes_to_surface contact (issue 12,
docs/studies/structure_in_water.md, "Convex corners"; used by structure_in_water_gap.py's kinds tt and ttc0).

    python docs/studies/structure_in_water_corner_run.py PRESSURE run DECK -o OUT ...

PRESSURE: "particle" (p_i of each particle) or a number in Pa (one uniform p for every particle, e.g. the
water's ambient C0). The rest are the `sphfem` command's arguments. The correction is added after the contact's
own forces, to the particles' f_ext and, as its reaction, to the plate's contact forces; it is added to the
contact's force arrays too, so its work is booked as the contact's energy.
"""
import sys

import numpy as np

from sphfem_cli.contact import system as contact_system
from structure_in_water_corner_truncation import add_corner_correction  # beside this script
from sphfem_cli.sph.slots import SI_KERNEL

PRESSURE = None if sys.argv[1] == "particle" else float(sys.argv[1])
_contact_forces = contact_system.NodesToSurfaceContact.forces


def forces(self, st) -> None:
    _contact_forces(self, st)
    if not self.particle_slaves:
        return
    ps = self.sim.particles.system
    mask = self._slaves()[3]
    f_corr, reaction = np.zeros_like(self._f_point), np.zeros_like(self._f_master)
    add_corner_correction(ps, mask, st.x, self.faces, int(ps.settings_i[SI_KERNEL]), f_corr, reaction, PRESSURE)
    ps.f_ext += f_corr
    st.f_contact += reaction
    self._f_point += f_corr  # booked by record_work with the contact's own forces
    self._f_master += reaction


contact_system.NodesToSurfaceContact.forces = forces

if __name__ == "__main__":
    from sphfem_cli.cli import main
    main(sys.argv[2:], prog_name="sphfem")
