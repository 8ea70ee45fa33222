"""What the per-step guards cost: CPU time per step of shipped decks with `Simulation.check_guards`
on and replaced by a no-op, interleaved.

    python benchmarks/guard_overhead.py [--decks cantilever_2d,dam_break_2d,water_air_shock_tube] [--steps 3000] [--repeat 5]

Since the guards are judged after every step (a finite-state sum over every output array, the
energy table, the penetration query: solver/explicit.py `check_guards`), their cost is a fraction of
each step. Each repetition builds the deck, takes a few steps (compilation, cell order), then times
`--steps` steps with the guards and as many without, alternating which goes first; the figure is
the ratio of process CPU times (min and median over the repetitions). One thread.
"""
from __future__ import annotations

import argparse
import os
import statistics
import time
from pathlib import Path

import numba

from sphfem_cli.driver import load_model
from sphfem_cli.solver.explicit import Simulation

DECKS = Path(__file__).resolve().parents[1] / "decks"


def _time_steps(deck: Path, steps: int, guards: bool) -> float:
    sim = Simulation(load_model(str(deck)).model)
    if not guards:
        sim.check_guards = lambda: None
    for _ in range(5):
        sim.step()
    start = time.process_time()
    for _ in range(steps):
        sim.step()
    return (time.process_time() - start) / steps


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--decks", default="cantilever_2d,dam_break_2d,water_air_shock_tube")
    ap.add_argument("--steps", type=int, default=3000)
    ap.add_argument("--repeat", type=int, default=5)
    args = ap.parse_args()
    numba.set_num_threads(1)
    print(f"load average {os.getloadavg()[0]:.2f}; 1 thread; {args.steps} steps per timing")
    for name in args.decks.split(","):
        deck = DECKS / f"{name}.yaml"
        ratios, on_s = [], []
        for k in range(args.repeat):
            order = (True, False) if k % 2 == 0 else (False, True)
            t = {g: _time_steps(deck, args.steps, g) for g in order}
            ratios.append(t[True] / t[False])
            on_s.append(t[True])
        print(f"{name}: {1e6 * statistics.median(on_s):.0f} us CPU per step with the guards; with / without: "
              f"min {min(ratios):.3f}, median {statistics.median(ratios):.3f}")


if __name__ == "__main__":
    main()
