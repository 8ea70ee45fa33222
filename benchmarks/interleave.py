"""Interleaved before/after timing over source trees, shared by the kernel benchmarks.

Each round runs every tree once, alternately, as a child process of the calling script
(``SCRIPT --child --tree TREE ARGS``, one numba thread, ``PYTHONPATH`` set to the tree) whose last
stdout line is a JSON object {kernel: [min ms, median ms]}; the table gives, per kernel and tree, the
minimum over rounds of the per-round minima and the median of the per-round medians, and the ratio
of the last tree's minimum to the first's. Alternating the trees within each round spreads a
changing machine load over both sides alike.
"""
from __future__ import annotations

import json
import os
import statistics
import subprocess
import sys
from pathlib import Path


def rounds(script: str, trees: list[str], child_args: list[str], n_rounds: int) -> tuple[dict, list[float]]:
    """Per tree, the children's JSON results of every round, and the load averages seen."""
    runs = {t: [] for t in trees}
    load = [os.getloadavg()[0]]
    for rnd in range(n_rounds):
        for t in trees:
            env = dict(os.environ, PYTHONPATH=t, NUMBA_NUM_THREADS="1")
            cmd = [sys.executable, str(Path(script).resolve()), "--child", "--tree", t, *child_args]
            r = subprocess.run(cmd, env=env, capture_output=True, text=True)
            if r.returncode:
                sys.exit(r.stderr[-3000:])
            runs[t].append(json.loads(r.stdout.strip().splitlines()[-1]))
            load.append(os.getloadavg()[0])
        print(f"round {rnd + 1} done, load {load[-1]:.2f}", flush=True)
    return runs, load


def table(runs: dict, load: list[float], what: str, digits: int = 3) -> None:
    """Print min / median ms per call of every kernel on every tree, and the ratio of the minima."""
    trees = list(runs)
    print(f"ms per call, 1 thread, {what}, {len(runs[trees[0]])} interleaved rounds; min over rounds of the "
          f"per-round min / median over rounds of the per-round median; load {min(load):.2f}-{max(load):.2f}")
    print(f"{'kernel':16s}" + "".join(f"{Path(t).name:>24s}" for t in trees) + "   ratio of mins (last/first)")
    for k in runs[trees[0]][0]:
        mins = [min(r[k][0] for r in runs[t]) for t in trees]
        meds = [statistics.median(r[k][1] for r in runs[t]) for t in trees]
        row = f"{k:16s}" + "".join(f"{mn:14.{digits}f} / {md:7.{digits}f}" for mn, md in zip(mins, meds))
        print(row + (f"   {mins[-1] / mins[0]:.3f}" if mins[0] else ""))
