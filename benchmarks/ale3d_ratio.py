"""ALE 3D (hex8) per cell against ALE 2D (quad4): issue 17's goal "3D >= 0.4 of 2D per cell", measured in pairs.

    python benchmarks/ale3d_ratio.py [--trees TREE ...] [--repeat 3] [--n3 60] [--n2 480] [--steps3 5] [--steps2 10]
                                     [--json OUT]

Each repetition runs, for every tree in turn, four ``ale_passes.py`` children (one numba thread, CPU time,
``PYTHONPATH`` the tree; this directory's ``ale_passes.py`` drives every tree): the n3^3 hex8 box of
``ale_throughput.build_3d`` at rest but for its spherical bump, the n2^2 quad4 box of ``ale_throughput.build`` at
rest but for its bump (``peers.py``'s ``ale2d``), then both boxes flowing (``--vortex``: the Taylor-Green vortex,
in every z layer with w = 0 in 3D; ``ale2dflow``). Each child builds its box, advances 2 steps (compilation) and
times ``steps`` steps pass by pass (``ale_passes.measure``). The 3D child and the 2D child of a pair run one after
the other, so that a changing machine load falls on both alike; the pair's ratio is
(2D ns per cell-step) / (3D ns per cell-step), the 3D throughput per cell as a fraction of the 2D one.

Prints per tree and case the pass-by-pass min / median over the repetitions (ns per cell-step), each pair's ratio
and their min and median, and the load average before and after each child. Figures: benchmarks/README.md,
"ALE 3D per cell against 2D, second round".
"""
from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

from ale_passes import PASSES  # noqa: E402

CASES = ("3D rest", "2D rest", "3D vortex", "2D vortex")


def child_args(case: str, args) -> list[str]:
    dim = case[0]
    n, steps = (args.n3, args.steps3) if dim == "3" else (args.n2, args.steps2)
    out = ["--dim", dim, "--n", str(n), "--steps", str(steps), "--repeat", "1", "--json"]
    return out + (["--vortex"] if "vortex" in case else [])


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--trees", nargs="+", default=[str(HERE.parent)], help="source trees (default: this one)")
    ap.add_argument("--repeat", type=int, default=3, help="repetitions (pairs per case and tree; default 3)")
    ap.add_argument("--n3", type=int, default=60, help="3D: elements per side (default 60)")
    ap.add_argument("--n2", type=int, default=480, help="2D: elements per side (default 480)")
    ap.add_argument("--steps3", type=int, default=5, help="3D timed steps (default 5)")
    ap.add_argument("--steps2", type=int, default=10, help="2D timed steps (default 10)")
    ap.add_argument("--json", help="write every child's figures to this file")
    args = ap.parse_args()
    res = {t: {c: [] for c in CASES} for t in args.trees}
    for r in range(args.repeat):
        for t in args.trees:
            for case in CASES:
                env = dict(os.environ, PYTHONPATH=t, NUMBA_NUM_THREADS="1")
                l0 = os.getloadavg()[0]
                p = subprocess.run([sys.executable, str(HERE / "ale_passes.py"), *child_args(case, args)], env=env,
                                   capture_output=True, text=True)
                if p.returncode:
                    sys.exit(p.stderr[-3000:])
                d = json.loads(p.stdout.strip().splitlines()[-1])["one"]
                d["load"] = [l0, os.getloadavg()[0]]
                d["utc"] = time.strftime("%H:%M:%S", time.gmtime())
                res[t][case].append(d)
                print(f"rep {r} {t} {case}: {d['utc']} UTC, load {l0:.2f}-{d['load'][1]:.2f}, "
                      f"{d['total']:.1f} ns per cell-step", flush=True)
    if args.json:
        Path(args.json).write_text(json.dumps(res))
    for t in args.trees:
        print(f"tree {t}: ns per cell-step, min / median over {args.repeat} repetitions "
              f"({args.n3}^3 hex8, {args.steps3} steps; {args.n2}^2 quad4, {args.steps2} steps)")
        print(f"{'pass':16s}" + "".join(f"{c:>22s}" for c in CASES))
        for k in PASSES + ("rest", "total"):
            row = f"{k:16s}"
            for c in CASES:
                vals = [d[k] for d in res[t][c]]
                row += f"{min(vals):12.1f} / {statistics.median(vals):7.1f}"
            print(row)
        for kind in ("rest", "vortex"):
            ratios = [b["total"] / a["total"] for a, b in zip(res[t]["3D " + kind], res[t]["2D " + kind])]
            print(f"3D / 2D per cell, {kind}: pairs " + ", ".join(f"{x:.3f}" for x in ratios)
                  + f"; min {min(ratios):.3f}, median {statistics.median(ratios):.3f}")


if __name__ == "__main__":
    main()
