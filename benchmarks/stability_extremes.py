"""Stability at the extremes: run small decks pushed to the edge and print what happened.

    python benchmarks/stability_extremes.py [--only NAME,...] [--long-steps 100000]

    python benchmarks/stability_extremes.py --write     # rerun every case, rewrite docs/stability.md's table

Each case is a small deck run through `sphfem run` (in process); the table gives the guard that
stopped it (or "completed"), steps, the last energy ratio and its range, the wall time and the first
line of the diagnosis. docs/stability.md holds the table this script wrote; every column but the wall
time is deterministic, and `tests/robustness/test_stability_table.py` (`-m extremes`) reruns the QUICK groups and
compares them with it. The wall times are not timed tests.
"""
from __future__ import annotations

import argparse
import copy
import tempfile
import time
from pathlib import Path

import numpy as np
import yaml
from click.testing import CliRunner

from sphfem_cli.cli import main

SOLID = {
    "units": {"length": "m", "mass": "kg", "time": "s"}, "dimension": 2,
    "control": {"end_time": 2.0e-4, "timestep_scale": 0.9},
    "materials": {"steel": {"type": "elastic_plastic", "density": 7850.0, "youngs_modulus": 2.1e11,
                            "poisson_ratio": 0.3, "yield_stress": 3.0e8, "tangent_modulus": 1.0e9}},
    "sections": {"solid": {"type": "solid"}},
    "parts": {"bar": {"material": "steel", "section": "solid",
                      "geometry": {"box": {"min": [0.0, 0.0], "max": [0.05, 0.01], "divisions": [20, 4]}}}},
    "sets": {"struck": {"type": "node", "part": "bar", "side": "left"}},
    "initial": [{"type": "velocity", "part": "bar", "velocity": [100.0, 0.0]}],
    "boundaries": [{"type": "prescribed_velocity", "set": "struck", "velocity": [0.0, 0.0]}],
    "output": {"interval": 2.0e-5, "history_interval": 2.0e-6},
}

SPH = {
    "units": {"length": "m", "mass": "kg", "time": "s"}, "dimension": 2,
    "control": {"end_time": 0.1, "timestep_scale": 1.0},
    "equations_of_state": {"water": {"type": "tait", "reference_density": 1000.0, "sound_speed": 15.0, "gamma": 7.0}},
    "materials": {"water": {"type": "fluid", "density": 1000.0, "viscosity": 0.0, "eos": "water"}},
    "sections": {"fluid": {"type": "sph", "kernel": "cubic_spline", "smoothing_ratio": 1.2,
                           "density_diffusion": 0.1, "artificial_viscosity": {"alpha": 0.1}}},
    "parts": {"column": {"material": "water", "section": "fluid", "spacing": 0.005, "hydrostatic": True,
                         "geometry": {"box": {"min": [0.0, 0.0], "max": [0.05, 0.1]}}}},
    "boundaries": [{"type": "wall", "min": [0.0, 0.0], "max": [0.3, 0.3], "sides": ["left", "right", "bottom"],
                    "condition": "no_slip"}],
    "loads": [{"type": "gravity", "acceleration": [0.0, -9.81]}],
    "output": {"interval": 0.01, "history_interval": 0.001},
}

ALE = {
    "units": {"length": "m", "mass": "kg", "time": "s"}, "dimension": 2,
    "control": {"end_time": 3.0e-4},
    "equations_of_state": {"water": {"type": "stiffened_gas", "gamma": 4.4, "p_inf": 6.0e8},
                           "air": {"type": "ideal_gas", "gamma": 1.4}},
    "materials": {"water": {"type": "fluid", "density": 1000.0, "eos": "water"},
                  "air": {"type": "fluid", "density": 50.0, "eos": "air"}},
    "sections": {"ale": {"type": "ale_multi_material", "advection": "van_leer", "interface": "slic",
                         "closure": "relax"}},
    "parts": {"tube": {"material": "air", "section": "ale",
                       "geometry": {"box": {"min": [0.0, 0.0], "max": [1.0, 0.01], "divisions": [100, 1]}},
                       "fill": [{"material": "air", "box": {"min": [0.0, 0.0], "max": [1.0, 0.01]}, "pressure": 1.0e5},
                                {"material": "water", "box": {"min": [0.0, 0.0], "max": [0.7, 0.01]},
                                 "pressure": 1.0e9}]}},
    "boundaries": [{"type": "ale_boundary", "part": "tube", "sides": ["left", "right", "bottom", "top"],
                    "condition": "slip"}],
    "output": {"interval": 3.0e-5, "history_interval": 3.0e-6},
}


def _set(tree: dict, path: str, value) -> None:
    keys = path.split(".")
    for k in keys[:-1]:
        tree = tree[int(k)] if isinstance(tree, list) else tree[k]
    last = keys[-1]
    if isinstance(tree, list):
        tree[int(last)] = value
    else:
        tree[last] = value


def variant(base: dict, **changes) -> dict:
    """A copy of `base` with dotted-path keys replaced (`control__timestep_scale=...` style)."""
    tree = copy.deepcopy(base)
    for key, value in changes.items():
        _set(tree, key.replace("__", "."), value)
    return tree


def cases(long_steps: int) -> list[tuple[str, str, dict]]:
    out = []
    for s in (0.1, 0.3, 0.5, 0.7, 0.9, 1.0, 1.2, 1.5, 2.0):
        out.append(("timestep_scale", f"solid bar 100 m/s, scale {s}", variant(SOLID, control__timestep_scale=s)))
    for s in (0.5, 1.0, 1.2, 1.5, 2.0, 3.0, 4.0, 6.0):
        out.append(("timestep_scale", f"SPH dam break, scale {s}", variant(SPH, control__timestep_scale=s,
                                                                           control__end_time=0.05)))
    for s in (1.2, 2.0):
        out.append(("timestep_scale", f"ALE water-air tube, section timestep_scale x{s}",
                    variant(ALE, sections__ale__timestep_scale=min(1.0, 0.5 * s))))
    for v in (1.0, 10.0, 100.0, 300.0, 500.0):
        out.append(("impact speed", f"solid bar on a fixed end, {v:g} m/s", variant(SOLID, initial__0__velocity=[v, 0.0])))
    eroding = variant(SOLID, initial__0__velocity=[500.0, 0.0])
    eroding["parts"]["bar"]["erosion"] = {"on_negative_volume": True, "max_plastic_strain": 0.5}
    out.append(("impact speed", "solid bar 500 m/s with erosion (plastic strain 0.5)", eroding))
    out.append(("density ratio", "ALE water 1000 / air 1 kg/m^3 (ratio 1000)",
                variant(ALE, materials__air__density=1.0)))
    out.append(("density ratio", "ALE water 1000 / air 50 kg/m^3 (ratio 20, shipped)", variant(ALE)))
    for nu in (0.45, 0.49, 0.499):
        elastic = variant(SOLID, initial__0__velocity=[10.0, 0.0])
        elastic["materials"]["steel"] = {"type": "elastic", "density": 7850.0, "youngs_modulus": 2.1e11,
                                         "poisson_ratio": nu}
        out.append(("near incompressible", f"elastic bar nu = {nu}", elastic))
    for dx in (0.025, 0.0125, 0.0025, 0.00125):
        out.append(("spacing", f"SPH dam break dx = {dx:g} m ({0.05 / dx:.0f} x {0.1 / dx:.0f} particles)",
                    variant(SPH, parts__column__spacing=dx, control__end_time=0.05)))
    for div in ([1, 1], [200, 40]):
        out.append(("spacing", f"solid bar {div[0]} x {div[1]} elements",
                    variant(SOLID, parts__bar__geometry__box__divisions=div, control__end_time=2.0e-5,
                            output__interval=2.0e-6, output__history_interval=2.0e-7)))
    for div, scale in (([10, 1, 1], 0.9), ([10, 1, 1], 0.8), ([10, 1, 1], 0.7), ([10, 10, 1], 0.9),
                       ([10, 10, 1], 0.8), ([10, 10, 2], 0.9)):
        thin = variant(SOLID, dimension=3, control__timestep_scale=scale, initial__0__velocity=[10.0, 0.0, 0.0],
                       boundaries__0__velocity=[0.0, 0.0, 0.0], control__end_time=1.0e-4)
        thin["materials"]["steel"] = {"type": "elastic", "density": 7850.0, "youngs_modulus": 2.1e11,
                                      "poisson_ratio": 0.3}
        thin["parts"]["bar"]["geometry"] = {"box": {"min": [0.0, 0.0, 0.0], "max": [0.05, 0.005 * div[1], 0.005 * div[2]],
                                                    "divisions": div}}
        out.append(("thin 3D parts", f"hex8 {div[0]} x {div[1]} x {div[2]} struck at 10 m/s, scale {scale}", thin))
    tension = variant(SPH, control__end_time=0.05)
    tension["loads"] = []
    tension["parts"]["column"]["hydrostatic"] = False
    tension["initial"] = [{"type": "velocity", "part": "column", "velocity": [2.0, 0.0]}]
    tension["boundaries"][0]["sides"] = ["left", "bottom"]
    tension["boundaries"][0]["condition"] = "slip"
    out.append(("tensile instability", "SPH block pulled off a wall at 2 m/s, no pressure cut-off", tension))
    cut = copy.deepcopy(tension)
    cut["sections"]["fluid"]["pressure_cutoff"] = 0.0
    out.append(("tensile instability", "the same with pressure_cutoff 0", cut))
    one = variant(SOLID, parts__bar__geometry__box__divisions=[1, 1], boundaries=[],
                  initial__0__velocity=[10.0, 5.0])
    one.pop("sets")
    out.append(("one element", "a single free quad4 at 10 m/s", one))
    single = variant(SPH, parts__column__geometry__box__max=[0.005, 0.005], parts__column__hydrostatic=False)
    out.append(("one particle", "a single SPH particle falling onto a wall", single))
    out.append(("gravity", "SPH column, gravity 0", variant(SPH, loads=[], control__end_time=0.05,
                                                         parts__column__hydrostatic=False)))
    for g in (981.0, 9810.0):
        out.append(("gravity", f"SPH column, gravity {g:g} m/s^2", variant(SPH, loads__0__acceleration=[0.0, -g],
                                                                              control__end_time=0.05)))
    free = variant(SOLID, parts__bar__geometry__box__divisions=[4, 2], boundaries=[],
                   initial__0__velocity=[1.0, 0.0])
    free["sets"] = {"tip": {"type": "node", "part": "bar", "side": "right"}}
    free["materials"]["steel"] = {"type": "elastic", "density": 7850.0, "youngs_modulus": 2.1e11, "poisson_ratio": 0.3}
    free["initial"] = [{"type": "velocity", "set": "tip", "velocity": [1.0, 0.0]}]
    out.append(("long run", f"free-free elastic bar ringing, {long_steps} steps", free))
    still = copy.deepcopy(free)
    still["sections"]["solid"] = {"type": "solid", "hourglass": {"coefficient": 0.0}, "bulk_viscosity": {"q1": 0.0, "q2": 0.0}}
    out.append(("long run", f"the same without hourglass control and bulk viscosity, {long_steps} steps", still))
    water = variant(SPH, parts__column__spacing=0.01, boundaries__0__max=[0.05, 0.3])
    out.append(("long run", f"SPH water column at rest (5 x 10 particles), {long_steps} steps", water))
    return out


def run_case(tree: dict, workdir: Path, long_steps: int | None = None) -> dict:
    deck = workdir / "deck.yaml"
    if long_steps:
        tree = _long_run_deck(tree, workdir, long_steps)
    deck.write_text(yaml.safe_dump(tree, sort_keys=False))
    out = workdir / "out"
    start = time.perf_counter()
    result = CliRunner().invoke(main, ["run", "-q", str(deck), "-o", str(out)])
    wall = time.perf_counter() - start
    row = {"exit": result.exit_code, "wall": wall, "message": result.output.strip().splitlines()[-1:] or [""]}
    glstat = out / "histories" / "glstat.csv"
    if glstat.exists():
        g = np.genfromtxt(glstat, delimiter=",", names=True)
        g = np.atleast_1d(g)
        row["ratio"] = float(g["energy_ratio"][-1])
        row["ratio_range"] = (float(g["energy_ratio"].min()), float(g["energy_ratio"].max()))
        row["time"] = float(g["time"][-1])
        if long_steps and len(g) > 10:  # drift after the start-up transient: from 10 % of the run to its end
            k = int(np.searchsorted(g["time"], 0.1 * tree["control"]["end_time"]))
            row["drift"] = (f"ratio {g['energy_ratio'][k]:.6f} at t = {g['time'][k]:.3g} (10 % of end_time), "
                            f"{g['energy_ratio'][-1]:.6f} at t = {g['time'][-1]:.3g}: drift "
                            f"{g['energy_ratio'][-1] - g['energy_ratio'][k]:+.1e}")
    log = (out / "run.log").read_text() if (out / "run.log").exists() else ""
    row["steps"] = next((line.split()[1] for line in log.splitlines() if line.startswith("steps:")), "?")
    row["eroded"] = next((line[9:] for line in log.splitlines() if line.startswith("erosion: ")), "")
    row["sph"] = _sph_state(out)
    diag = out / "diagnostics.txt"
    row["guard"] = diag.read_text().splitlines()[0].split(": ", 1)[1] if diag.exists() else (
        "completed" if result.exit_code == 0 else f"exit {result.exit_code}")
    row["diagnosis"] = diag.read_text().splitlines()[1][9:] if diag.exists() else ""
    return row


def _sph_state(out: Path) -> str:
    """For SPH runs: smallest particle distance over the initial spacing and the lowest pressure, last step."""
    import h5py

    if not (out / "results.h5").exists():
        return ""
    with h5py.File(out / "results.h5", "r") as f:
        for name in f:
            grid = f[name]
            if not isinstance(grid, h5py.Group) or grid.attrs.get("topology") != "Polyvertex":
                continue
            steps = sorted(k for k in grid if k.startswith("step_"))
            first, last = grid[steps[0]], grid[steps[-1]]
            x0, x = first["coordinates"][()], last["coordinates"][()]
            if len(x) < 2:
                return f"{len(x)} particle"
            def nearest(p):
                d = np.sqrt(((p[:, None, :] - p[None, :, :]) ** 2).sum(-1))
                np.fill_diagonal(d, np.inf)
                return d.min()
            return f"min distance/dx {nearest(x) / nearest(x0):.2f}, min p {last['point/pressure'][()].min():.3g} Pa"
    return ""


def _long_run_deck(tree: dict, workdir: Path, steps: int) -> dict:
    """Set end_time so that the run takes about `steps` steps (from `sphfem check`'s stable step)."""
    from sphfem_cli.driver import load_model
    from sphfem_cli.solver.explicit import Simulation

    probe = workdir / "probe.yaml"
    probe.write_text(yaml.safe_dump(tree, sort_keys=False))
    dt = Simulation(load_model(str(probe)).model).stable_dt()
    tree = copy.deepcopy(tree)
    tree["control"]["end_time"] = float(dt * steps)
    tree["output"] = {"interval": float(dt * steps / 10), "history_interval": float(dt * steps / 1000)}
    return tree


HEADER = ("| group | case | outcome | steps | energy ratio (last; min-max) | wall s | notes |\n"
          "|---|---|---|---|---|---|---|")
DOC = Path(__file__).resolve().parents[1] / "docs" / "stability.md"
BEGIN = "<!-- table: written by `python benchmarks/stability_extremes.py --write`; do not edit by hand -->"
END = "<!-- end of the table -->"
QUICK = ("timestep_scale", "impact speed", "density ratio", "near incompressible", "thin 3D parts",
         "tensile instability", "one element", "one particle", "gravity")
"""The groups `tests/robustness/test_stability_table.py` reruns under -m extremes and test_extremes.py runs in the default suite (the others take minutes)."""


def table_row(group: str, name: str, row: dict) -> str:
    """One markdown row of the table; its columns but the wall time are deterministic."""
    ratio = (f"{row['ratio']:.4f}; {row['ratio_range'][0]:.4f}-{row['ratio_range'][1]:.4f}"
             if "ratio" in row else "-")
    note = "; ".join(x for x in (row.get("drift", ""), row["eroded"], row["sph"], row["diagnosis"][:160]) if x)
    return f"| {group} | {name} | {row['guard']} | {row['steps']} | {ratio} | {row['wall']:.1f} | {note} |"


def run_table(only: set[str], long_steps: int, echo=None) -> list[str]:
    """The table's rows for the groups in `only` (all when empty)."""
    rows = []
    for group, name, tree in cases(long_steps):
        if only and group not in only:
            continue
        with tempfile.TemporaryDirectory() as tmp:
            row = run_case(tree, Path(tmp), long_steps if group == "long run" else None)
        rows.append(table_row(group, name, row))
        if echo is not None:
            echo(rows[-1])
    return rows


def shipped_rows(doc: Path = DOC) -> list[str]:
    """The rows of the table in docs/stability.md."""
    text = doc.read_text()
    body = text[text.index(BEGIN) + len(BEGIN):text.index(END)]
    return [line for line in body.strip().splitlines()[2:] if line.startswith("| ")]


def write_doc(rows: list[str], doc: Path = DOC) -> None:
    """Replace the table in docs/stability.md by `rows`."""
    text = doc.read_text()
    head, tail = text[:text.index(BEGIN) + len(BEGIN)], text[text.index(END):]
    doc.write_text(head + "\n" + HEADER + "\n" + "\n".join(rows) + "\n" + tail)


def main_() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--only", default="", help="comma-separated case groups to run")
    parser.add_argument("--long-steps", type=int, default=100_000)
    parser.add_argument("--write", action="store_true", help="write the whole table into docs/stability.md")
    args = parser.parse_args()
    only = {s.strip() for s in args.only.split(",") if s.strip()}
    if args.write and only:
        parser.error("--write runs every case: leave out --only")
    print(HEADER, flush=True)
    rows = run_table(only, args.long_steps, echo=lambda line: print(line, flush=True))
    if args.write:
        write_doc(rows)
        print(f"wrote {len(rows)} rows into {DOC}")


if __name__ == "__main__":
    main_()
