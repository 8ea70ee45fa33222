"""ALE kernels one by one: CPU time per call of the element and node kernels on plane, ring and hex8 meshes.

    python benchmarks/ale_kernels.py --trees BASE THIS [--rounds 5] [--calls 30] [--n 240] [--n3 36] [--only forces,nodal]

The kernels that ``AleSystem`` binds per element kind (``_k_forces``: ``lagrange_forces`` /
``axisymmetric.lagrange_forces_rz`` / ``lagrange_forces_3d``; ``_k_nodal``: ``nodal_update`` /
``nodal_update_3d``; ``_k_energy``: ``lagrange_energy`` / ``lagrange_energy_3d``; ``_k_finish``:
``finish_remap_nodes`` / ``finish_remap_nodes_3d``), on four cases: ``ale_throughput.build(n, False)``
(plane1, one ideal gas), ``build(n, True)`` (plane2, water and air), ``ale_axisymmetric_throughput.build(n,
True)`` (ring, the gas as rings) and ``ale_throughput.build_3d(n3)`` (hex8). Each case is built,
advanced 3 steps (compilation), then the arguments of each kernel's next call are captured and the
kernel is timed ``calls`` times, each call on fresh copies of the captured arrays, with the process
CPU time around the call only.

``--trees A B``: every round runs each tree once, alternating, in a child process with ``PYTHONPATH``
the tree and one numba thread (this file drives both); prints per kernel min over rounds of the
per-round min / median over rounds of the per-round median (ms), the ratio of the minima (last
tree / first), and the load average range. Used for the kernel-twin folding of issue 14 (figures in
the comments above the kernels in ale/lagrange.py, ale/energy.py and ale/remap.py).
"""
from __future__ import annotations

import argparse
import json
import statistics
import sys
import time
from pathlib import Path

import interleave

KERNELS = {"_k_forces": "forces", "_k_nodal": "nodal", "_k_energy": "energy", "_k_finish": "finish"}


def child(args):
    import numba
    import numpy as np
    sys.path.insert(0, str(Path(__file__).resolve().parent))
    import ale_axisymmetric_throughput as R
    import ale_throughput as T
    numba.set_num_threads(1)
    cases = {"plane1": lambda: T.build(args.n, False), "plane2": lambda: T.build(args.n, True),
             "ring": lambda: R.build(args.n, True), "hex8": lambda: T.build_3d(args.n3)}
    out = {}
    for cname, make in cases.items():
        ale = make()
        for _ in range(3):
            ale.step(ale.stable_dt(0.5))
        captured = {}
        saved = {}
        for attr in KERNELS:
            fn = getattr(ale, attr)
            saved[attr] = fn

            def rec(*a, _attr=attr, _fn=fn, **kw):
                if _attr not in captured:
                    captured[_attr] = ([x.copy() if isinstance(x, np.ndarray) else x for x in a], dict(kw))
                return _fn(*a, **kw)
            setattr(ale, attr, rec)
        ale.step(ale.stable_dt(0.5))
        for attr, fn in saved.items():
            if args.only and KERNELS[attr] not in args.only.split(","):
                continue
            a, kw = captured[attr]
            ts = []
            for _ in range(args.calls):
                aa = [x.copy() if isinstance(x, np.ndarray) else x for x in a]
                c0 = time.process_time()
                fn(*aa, **kw)
                ts.append(time.process_time() - c0)
            out[f"{cname} {KERNELS[attr]}"] = [min(ts) * 1e3, statistics.median(ts) * 1e3]
    print(json.dumps(out))


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--trees", nargs="+", help="source trees, interleaved (child processes)")
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--calls", type=int, default=30)
    ap.add_argument("--n", type=int, default=240)
    ap.add_argument("--n3", type=int, default=36)
    ap.add_argument("--child", action="store_true")
    ap.add_argument("--tree", help=argparse.SUPPRESS)  # the child's tree: its PYTHONPATH
    ap.add_argument("--only", default="", help="comma-separated subset of forces,nodal,energy,finish")
    args = ap.parse_args()
    if args.child:
        return child(args)
    if not args.trees:
        ap.error("--trees is required")
    runs, load = interleave.rounds(__file__, args.trees, ["--calls", str(args.calls), "--n", str(args.n),
                                                      "--n3", str(args.n3), "--only", args.only], args.rounds)
    interleave.table(runs, load, f"{args.calls} calls per round")

if __name__ == "__main__":
    main()
