"""Contact throughput: slave-steps per second of the nodes-to-surface contact, and its share of a step.

    python benchmarks/contact_throughput.py [--cases small,large] [--steps N] [--threads 1,2]

The scene is the hydrostatic plate (decks/hydrostatic_plate_sph.yaml) at two resolutions, built as
a deck through the whole input path: a water column of width 1 m and height 2 m on an elastic plate,
every particle a slave candidate (the contact sorts the plate's segments into cells, then each
particle looks up its cell):

* ``small``: dx = 25 mm, 3 200 particles, 40 plate segments;
* ``large``: dx = 2.5 mm, 320 000 particles, 400 plate segments.

Printed per case and thread count: contact slave-steps/s (particles x steps / time in the contact's
force pass and work bookkeeping), the whole loop's particle-steps/s, and the contact's share of the
step. The time in the contact is measured by timing its two methods around each call.
"""
from __future__ import annotations

import argparse
import tempfile
import time
from pathlib import Path

import yaml

DECK = Path(__file__).resolve().parents[1] / "decks" / "hydrostatic_plate_sph.yaml"
CASES = {"small": {"spacing": 0.025, "plate": 40, "steps": 200}, "large": {"spacing": 0.0025, "plate": 400, "steps": 6}}


def build(spacing: float, plate_elements: int):
    from sphfem_cli.driver import load_model
    from sphfem_cli.solver.explicit import Simulation

    deck = yaml.safe_load(DECK.read_text())
    deck["parts"]["water"]["spacing"] = spacing
    deck["parts"]["plate"]["geometry"]["box"]["divisions"] = [plate_elements, 4]
    path = Path(tempfile.mkdtemp()) / "plate.yaml"
    path.write_text(yaml.safe_dump(deck))
    return Simulation(load_model(str(path)).model)


def measure(sim, steps: int, threads: int) -> tuple[float, float]:
    """(contact slave-steps/s, loop particle-steps/s, contact share) over ``steps`` steps."""
    import numba

    numba.set_num_threads(threads)
    contact = sim.interactions[0]
    spent = [0.0]

    def timed(method):
        def wrapper(*args):
            t0 = time.perf_counter()
            method(*args)
            spent[0] += time.perf_counter() - t0
        return wrapper

    contact.forces, contact.record_work = timed(contact.forces), timed(contact.record_work)
    sim.step()
    spent[0] = 0.0
    t0 = time.perf_counter()
    for _ in range(steps):
        sim.step()
    wall = time.perf_counter() - t0
    n = sim.particles.system.n
    return n * steps / spent[0], n * steps / wall, spent[0] / wall


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cases", default="small,large")
    ap.add_argument("--steps", type=int, default=None)
    ap.add_argument("--threads", default="1,2")
    args = ap.parse_args()
    for name in args.cases.split(","):
        case = CASES[name]
        for threads in (int(t) for t in args.threads.split(",")):
            sim = build(case["spacing"], case["plate"])
            contact_rate, loop_rate, share = measure(sim, args.steps or case["steps"], threads)
            print(f"{name:6s} {sim.particles.system.n:8d} particles  {threads} thread(s): "
                  f"contact {contact_rate / 1e6:6.2f} M slave-steps/s, loop {loop_rate / 1e6:5.2f} M particle-steps/s, "
                  f"contact {100 * share:4.1f} % of the step")


if __name__ == "__main__":
    main()
