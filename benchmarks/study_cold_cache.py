"""Mesh-study cost on an empty against a warm numba cache: the case's cpu_s must not carry the compile.

Runs one study case folder (``cases/<case>`` of a study: its deck.yaml) twice through the study's
own case process (``python -m sphfem_cli.study CASE``), first with NUMBA_CACHE_DIR pointing at an
empty folder (every kernel compiles, in the warm-up), then with that folder filled (kernels load
from it), and prints cpu_s, compile_s, warm-up CPU and peak memory of each, and the cpu_s ratio.
Issue 12's acceptance: the ALE reference's cpu_s within 15 % between the two.

    python benchmarks/study_cold_cache.py STUDY/cases/ale_h0.0025 [--threads 1]
"""
from __future__ import annotations

import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path


def run(case: Path, cache: Path, threads: int) -> dict:
    scratch = Path(tempfile.mkdtemp(prefix="sphfem-bench-case-"))
    shutil.copy(case / "deck.yaml", scratch / "deck.yaml")
    env = dict(os.environ, NUMBA_CACHE_DIR=str(cache))
    subprocess.run([sys.executable, "-m", "sphfem_cli.study", str(scratch), "--threads", str(threads)], env=env,
                   check=True)
    status = json.loads((scratch / "status.json").read_text())
    shutil.rmtree(scratch, ignore_errors=True)
    return status


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("case", type=Path)
    parser.add_argument("--threads", type=int, default=1)
    args = parser.parse_args()
    cache = Path(tempfile.mkdtemp(prefix="sphfem-bench-numba-"))
    try:
        rows = [("empty cache", run(args.case, cache, args.threads)), ("warm cache", run(args.case, cache, args.threads))]
    finally:
        shutil.rmtree(cache, ignore_errors=True)
    print(f"{'':12} {'state':6} {'cpu_s':>8} {'runs':>22} {'compile_s':>10} {'warm-up cpu':>12} {'peak MiB':>9}")
    for name, s in rows:
        runs = ", ".join(f"{c:.2f}" for c in s.get("cpu_runs", []))
        print(f"{name:12} {s['state']:6} {s.get('cpu_s', float('nan')):8.2f} {runs:>22} {s.get('compile_s', 0):10.1f} "
              f"{s.get('warmup_cpu_s', 0):12.1f} {s.get('peak_mib', 0):9.0f}")
    cold, warm = rows[0][1]["cpu_s"], rows[1][1]["cpu_s"]
    print(f"cpu_s empty / warm = {cold / warm:.3f}")


if __name__ == "__main__":
    main()
