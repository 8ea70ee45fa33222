"""ALE -> structure coupling kernels one by one: CPU time per call of the 2D and 3D force and stiffness kernels.

    python benchmarks/coupling_kernels.py --trees BASE THIS [--rounds 5] [--calls 30] [--repeat 20] [--only plane,hex8]

The kernels ``LagrangeInSolidCoupling`` calls each step (``coupling_kernels.coupling_forces`` /
``coupling_kernels_3d.coupling_forces_3d`` in ``forces``, ``stiffness_sums`` / ``stiffness_sums_3d`` in
``stable_dt``) on four built models, each advanced a number of steps first (compilation, and contact
made): ``plane`` decks/structure_in_water_ale.yaml (100 steps, a plate in water, every point hosted),
``entry`` decks/cylinder_entry_constant_speed_ale.yaml (70 steps, a rigid cylinder just entering: free
points take the interface reconstruction), ``ring`` decks/underwater_explosion_axisymmetric_ale.yaml
(150 steps, r-z rings) and ``hex8`` the rigid block of tests/verification/test_ale_coupling_3d.py (60
steps, hex8 against quad faces). The arguments of each kernel's next call are captured; a sample is
``repeat`` calls, each on its own fresh copies of the captured arrays (made beforehand), timed by the
process CPU time around the calls only, per call; ``calls`` samples per round.

``--trees A B``: every round runs each tree once, alternating, in a child process that imports
``sphfem_cli`` from that tree (ahead of any editable install) with one numba thread; prints per kernel
the min over rounds of the per-round min / the median over rounds of the per-round median (ms), the
ratio of the minima (last tree / first) and the load average range.
"""
from __future__ import annotations

import argparse
import json
import statistics
import sys
import time
from pathlib import Path

import interleave

STEPS = {"plane": 100, "entry": 70, "ring": 150, "hex8": 60}


def _import_from(tree):
    """Import sphfem_cli from ``tree``, not from an editable install's finder."""
    sys.meta_path[:] = [f for f in sys.meta_path if "editable" not in repr(f) and "editable" not in type(f).__module__]
    sys.path.insert(0, tree)
    import sphfem_cli
    assert sphfem_cli.__file__.startswith(str(Path(tree).resolve())) or sphfem_cli.__file__.startswith(tree)


def child(args):
    _import_from(args.tree)
    import tempfile

    import numba
    import numpy as np

    from sphfem_cli.contact import coupling
    from sphfem_cli.driver import load_model
    from sphfem_cli.solver.explicit import Simulation
    numba.set_num_threads(1)
    tree = Path(args.tree)
    deck3 = (tree / "tests/verification/test_ale_coupling_3d.py").read_text().split('DECK = """')[1].split('"""')[0]
    tmp = Path(tempfile.mkdtemp())
    (tmp / "block3d.yaml").write_text(deck3)
    decks = {"plane": tree / "decks/structure_in_water_ale.yaml",
             "entry": tree / "decks/cylinder_entry_constant_speed_ale.yaml",
             "ring": tree / "decks/underwater_explosion_axisymmetric_ale.yaml", "hex8": tmp / "block3d.yaml"}
    names = {"forces": ("ck", "coupling_forces", "ck3", "coupling_forces_3d"),
             "stiffness": ("ck", "stiffness_sums", "ck3", "stiffness_sums_3d")}
    out = {}
    for cname, deck in decks.items():
        if args.only and cname not in args.only.split(","):
            continue
        sim = Simulation(load_model(str(deck)).model)
        for _ in range(STEPS[cname]):
            sim.step()
        captured = {}
        saved = []
        for kind, (m2, f2, m3, f3) in names.items():
            mod, fname = (getattr(coupling, m3), f3) if cname == "hex8" else (getattr(coupling, m2), f2)
            fn = getattr(mod, fname)
            saved.append((mod, fname, fn))

            def rec(*a, _kind=kind, _fn=fn):
                if _kind not in captured:
                    captured[_kind] = [x.copy() if isinstance(x, np.ndarray) else x for x in a]
                return _fn(*a)
            setattr(mod, fname, rec)
        sim.step()
        for mod, fname, fn in saved:
            setattr(mod, fname, fn)
        n_coupled = sim.interactions[0].n_coupled
        for kind, (_, f2, _, f3) in names.items():
            fn = [f for m, n, f in saved if n in (f2, f3)][0]
            a = captured[kind]
            ts = []
            for _ in range(args.calls):
                batch = [[x.copy() if isinstance(x, np.ndarray) else x for x in a] for _ in range(args.repeat)]
                c0 = time.process_time()
                for aa in batch:
                    fn(*aa)
                ts.append((time.process_time() - c0) / args.repeat)
            out[f"{cname} {kind}"] = [min(ts) * 1e3, statistics.median(ts) * 1e3]
        out[f"{cname} coupled"] = [n_coupled, n_coupled]
    print(json.dumps(out))


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--trees", nargs="+", help="source trees, interleaved (child processes)")
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--calls", type=int, default=30, help="timed samples per round")
    ap.add_argument("--repeat", type=int, default=20, help="calls per sample, each on its own copies")
    ap.add_argument("--only", default="", help="comma-separated subset of plane,entry,ring,hex8")
    ap.add_argument("--child", action="store_true")
    ap.add_argument("--tree", help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.child:
        return child(args)
    if not args.trees:
        ap.error("--trees is required")
    trees = [str(Path(t).resolve()) for t in args.trees]
    runs, load = interleave.rounds(__file__, trees, ["--calls", str(args.calls), "--repeat", str(args.repeat),
                                                     "--only", args.only], args.rounds)
    interleave.table(runs, load, f"{args.calls} samples of {args.repeat} calls per round", digits=4)

if __name__ == "__main__":
    main()
