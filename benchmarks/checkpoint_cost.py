"""Cost of a restart checkpoint (output.checkpoint) on a 30^3 hex8 cube: write and read+restore time,
file size, next to one step and one field output. Prints figures; it is not a timed test.

    python benchmarks/checkpoint_cost.py [n]      # n elements per side, default 30
"""
from __future__ import annotations

import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).parent))
from fem_throughput import CUBE_DECK  # noqa: E402


def _best(fn, repeat: int = 5) -> float:
    best = float("inf")
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t0)
    return best


def main(n: int = 30) -> None:
    import numba

    from sphfem_cli.driver import load_model
    from sphfem_cli.output.checkpoint import CHECKPOINT_NAME, deck_hash, read_checkpoint, restore_simulation, \
        write_checkpoint
    from sphfem_cli.output.results import RunOutput
    from sphfem_cli.solver.explicit import Simulation

    numba.set_num_threads(1)
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        deck = tmp / "cube.yaml"
        deck.write_text(CUBE_DECK.format(n=n))
        loaded = load_model(str(deck))
        digest = deck_hash(loaded.deck, loaded.model)
        sim = Simulation(loaded.model)
        output = RunOutput(sim, tmp)
        sim.step()
        step = _best(sim.step, 3)
        field = _best(output.write_fields, 3)
        path = tmp / CHECKPOINT_NAME
        write = _best(lambda: write_checkpoint(path, sim, output.state(), digest))

        def read():
            fresh = Simulation(load_model(str(deck)).model)
            t0 = time.perf_counter()
            restore_simulation(fresh, read_checkpoint(path, digest), path)
            return time.perf_counter() - t0

        restore = min(read() for _ in range(3))
        output.close()
        print(f"{n}^3 hex8 ({n ** 3} elements), 1 thread: step {step * 1e3:.0f} ms, field output "
              f"{field * 1e3:.0f} ms, checkpoint write {write * 1e3:.0f} ms, read + restore {restore * 1e3:.0f} ms, "
              f"file {path.stat().st_size / 2 ** 20:.1f} MiB")


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 30)
