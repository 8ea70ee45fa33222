"""Noh's implosion on Eulerian ALE meshes: the spherical problem in r-z (dimension: axisymmetric,
ale/axisymmetric.py) and, for comparison, the cylindrical one in x-y with the plane kernels.

    python docs/studies/ale_axisymmetric_noh.py [--planar] N [N ...]

Set-up and exact solution: tests/verification/ale_cases.noh_rz (gamma 5/3, unit inflow, t = 0.6,
shock at R = 0.2, post-shock density 64 spherical / 16 cylindrical). Prints one JSON line per mesh:
the L1 density error over 0.1 < R < 0.4 (meridian-area and volume weighted), over the post-shock
gas 0.1 < R < 0.18 and the pre-shock gas 0.25 < R < 0.4, the mean density of 0.1 < R < 0.15, the
observed order against the previous mesh, steps, CPU seconds and the load average.
"""
from __future__ import annotations

import json
import math
import os
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "tests" / "verification"))
from ale_cases import noh_l1, noh_rz  # noqa: E402


def main(argv: list[str]) -> None:
    planar = "--planar" in argv
    sizes = [int(a) for a in argv if a != "--planar"]
    previous = None
    for n in sizes:
        cpu = time.process_time()
        case = noh_rz(n, axisymmetric=not planar)
        cpu = time.process_time() - cpu
        err = noh_l1(case)
        plateau = (case["radius"] > 0.1) & (case["radius"] < 0.15)
        row = dict(n=n, geometry="cylindrical x-y" if planar else "spherical r-z", l1_area=err,
                   l1_volume=noh_l1(case, weight="volume"), l1_post=noh_l1(case, 0.1, 0.18),
                   l1_pre=noh_l1(case, 0.25, 0.4), plateau_density=float(case["density"][plateau].mean()),
                   order=None if previous is None else math.log(previous[1] / err) / math.log(n / previous[0]),
                   steps=case["steps"], cpu_s=round(cpu, 1), load=round(os.getloadavg()[0], 2))
        previous = (n, err)
        print(json.dumps(row), flush=True)


if __name__ == "__main__":
    main(sys.argv[1:])
