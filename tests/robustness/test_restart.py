"""Checkpoint and restart: a run stopped by a signal and continued with --restart gives bit-identical
histories and field steps to an uninterrupted run, for a solid, an SPH and an ALE deck."""
from __future__ import annotations

import os
import re
import signal
import xml.etree.ElementTree as ET
from pathlib import Path

import h5py
import numpy as np
import pytest
from click.testing import CliRunner

from sphfem_cli.cli import main
from sphfem_cli.solver import explicit

from . import decks


def _run(*args) -> tuple[int, str]:
    result = CliRunner().invoke(main, ["run", "-q", *map(str, args)])
    return result.exit_code, result.output


def _interrupt_at(monkeypatch, step: int, signum=signal.SIGINT) -> None:
    """Send `signum` to this process during step `step` (the handler acts after the step)."""
    original = explicit.Simulation.step

    def step_and_signal(self, stop=None):
        original(self, stop)
        if self.state.step == step:
            os.kill(os.getpid(), signum)

    monkeypatch.setattr(explicit.Simulation, "step", step_and_signal)


def _histories(out: Path) -> dict[str, np.ndarray]:
    with h5py.File(out / "results.h5", "r") as f:
        group = f["histories"]
        return {name: group[name][()] for name in group}


def _fields(out: Path) -> list[tuple[str, np.ndarray]]:
    with h5py.File(out / "results.h5", "r") as f:
        found = [("times", f["times"][()])]
        f.visititems(lambda name, obj: found.append((name, obj[()]))
                     if isinstance(obj, h5py.Dataset) and "/step_" in name else None)
    return sorted(found, key=lambda item: item[0])


FUZZ = Path(__file__).parents[1] / "data" / "fuzz"

# the charge, water and time of the two open-sides decks (ALE and SPH)
TNT_IN_WATER = """units: {length: m, mass: kg, time: s}
dimension: 2
control: {end_time: 8.0e-5, energy_band: null}
equations_of_state:
  tnt: {type: jwl, A: 3.712e11, B: 3.231e9, R1: 4.15, R2: 0.95, omega: 0.30, e0: 7.0e9}
  water: {type: gruneisen, c: 1480.0, s1: 1.92, gamma0: 0.28}
materials:
  tnt: {type: high_explosive, density: 1630.0, detonation_velocity: 6930.0, eos: tnt}
  water: {type: fluid, density: 1000.0, eos: water}
detonations: [{point: [0.0, 0.0], time: 0.0}]
"""

INLINE = {  # decks of this module: r-z, open sides, and a smoothed 3D ALE mesh
    "axi_ale": """
title: elastic disc into r-z ALE water (restart test)
units: {length: m, mass: kg, time: s}
dimension: axisymmetric
control: {end_time: 1.5e-4}
equations_of_state:
  water: {type: linear_polynomial, c1: 2.2e9}
materials:
  water: {type: fluid, density: 1000.0, eos: water}
  void: {type: void}
  pmma: {type: elastic, density: 1200.0, youngs_modulus: 3.0e9, poisson_ratio: 0.35}
sections:
  ale: {type: ale_multi_material}
  solid: {type: solid}
parts:
  tank:
    material: void
    section: ale
    geometry: {box: {min: [0.0, 0.0], max: [0.05, 0.05], element_size: 0.005}}
    fill: [{material: water, box: {min: [0.0, 0.0], max: [0.05, 0.025]}}]
  disc:
    material: pmma
    section: solid
    geometry: {box: {min: [0.0, 0.026], max: [0.025, 0.031], divisions: [5, 1]}}
couplings: [{type: lagrange_in_solid, structure: disc, fluid: tank}]
initial: [{type: velocity, part: disc, velocity: [0.0, -10.0]}]
boundaries: [{type: ale_boundary, part: tank, sides: [right, bottom, top], condition: slip}]
output: {interval: 5.0e-5, history_interval: 5.0e-6}
""",
    "ale_open": """
title: TNT in water with non-reflecting sides (restart test)
""" + TNT_IN_WATER + """sections:
  fluid: {type: ale_multi_material, pressure_cutoff: -1.0e5}
parts:
  pool:
    material: water
    section: fluid
    geometry: {box: {min: [0.0, 0.0], max: [0.06, 0.06], element_size: 0.005}}
    fill: [{material: tnt, ball: {center: [0.0, 0.0], radius: 0.01}}]
boundaries:
  - {type: ale_boundary, part: pool, sides: [left, bottom], condition: slip}
  - {type: ale_boundary, part: pool, sides: [right, top], condition: non_reflecting, source: [0.0, 0.0]}
output: {interval: 2.0e-5, history_interval: 2.0e-6, probes: [{name: p, type: pressure, point: [0.0475, 0.0025]}]}
""",
    "sph_open": """
title: TNT in SPH water with non-reflecting sides (restart test)
""" + TNT_IN_WATER + """sections:
  fluid: {type: sph, pressure_cutoff: -1.0e5}
parts:
  water: {material: water, section: fluid, spacing: 0.004,
          geometry: {polygon: {vertices: [[0.012, 0.0], [0.06, 0.0], [0.06, 0.06], [0.0, 0.06], [0.0, 0.012],
                                          [0.012, 0.012]]}}}
  charge: {material: tnt, section: fluid, spacing: 0.004, geometry: {box: {min: [0.0, 0.0], max: [0.012, 0.012]}}}
boundaries:
  - {type: wall, min: [0.0, 0.0], max: [0.06, 0.06], sides: [left, bottom], condition: slip}
  - {type: wall, min: [0.0, 0.0], max: [0.06, 0.06], sides: [right, top], condition: non_reflecting, source: [0.0, 0.0]}
output: {interval: 2.0e-5, history_interval: 2.0e-6, probes: [{name: p, type: pressure, point: [0.05, 0.002]}]}
""",
    "axi_sph": """
title: r-z SPH water column falling on an elastic disc (restart test)
units: {length: m, mass: kg, time: s}
dimension: axisymmetric
control: {end_time: 0.01}
equations_of_state:
  water: {type: tait, reference_density: 1000.0, sound_speed: 15.0, gamma: 7.0}
materials:
  water: {type: fluid, density: 1000.0, eos: water}
  rubber: {type: elastic, density: 1000.0, youngs_modulus: 1.0e6, poisson_ratio: 0.3}
sections:
  fluid: {type: sph, kernel: cubic_spline, smoothing_ratio: 1.2}
  solid: {type: solid}
parts:
  column: {material: water, section: fluid, spacing: 0.01,
           geometry: {box: {min: [0.0, 0.045], max: [0.05, 0.1]}}}
  disc: {material: rubber, section: solid,
         geometry: {box: {min: [0.0, 0.0], max: [0.06, 0.04], divisions: [3, 2]}}}
sets:
  disc_base: {type: node, part: disc, side: bottom}
contacts:
  - {type: nodes_to_surface, nodes: column, surface: disc, penalty_scale: 0.1}
initial:
  - {type: velocity, part: column, velocity: [0.0, -1.0]}
boundaries:
  - {type: fixed, set: disc_base}
loads:
  - {type: gravity, acceleration: [0.0, -9.81]}
output: {interval: 0.005, history_interval: 0.0005}
""",
    "ale_3d_smoothed": """
title: 3D ALE box, equipotential mesh with sliding walls (restart test)
units: {length: m, mass: kg, time: s}
dimension: 3
control: {end_time: 1.0e-4}
equations_of_state:
  air: {type: ideal_gas, gamma: 1.4}
materials:
  air: {type: fluid, density: 1.2, eos: air}
sections:
  fluid: {type: ale_multi_material, mesh_motion: smoothed, smoothing: equipotential, smoothing_boundary: sliding}
parts:
  box:
    material: air
    section: fluid
    geometry: {box: {min: [0, 0, 0], max: [0.1, 0.08, 0.06], divisions: [5, 4, 3]}}
    fill: [{material: air, ball: {center: [0, 0, 0], radius: 0.04}, pressure: 1.0e6}]
boundaries:
  - {type: ale_boundary, part: box, sides: [left, right, bottom, top, front, back], condition: slip}
output: {interval: 5.0e-5, history_interval: 1.0e-5}
""",
}


@pytest.mark.parametrize("kind, stop_step", [("solid", 333), ("sph", 97), ("ale", 71),
                                             ("fsi_sph", 31), ("fsi_ale", 7),
                                             ("axi_ale", 9), ("axi_sph", 11), ("ale_3d_smoothed", 13),
                                             ("ale_open", 60), ("sph_open", 200)])
def test_restart_is_bit_identical(tmp_path, monkeypatch, kind, stop_step):
    """fsi_sph has a nodes_to_surface contact, fsi_ale a lagrange_in_solid coupling (their state and work
    travel in the checkpoint too); axi_ale and axi_sph are the same in r-z (rings, the axis);
    ale_3d_smoothed a moving hex8 mesh (the mesh mover's stencil and sliding sets are rebuilt, the
    mesh restored); ale_open non-reflecting sides with a source (their radiation impulses, by then
    non-zero, travel in the checkpoint); sph_open its SPH twin (the particles' far pressures, impulses and
    initial distances from the open sides, which place the sides' images, all permuted by the reorders; the
    radiated energy; its open sides meet the slip walls at two corners)."""
    text = (FUZZ / f"{kind}.yaml").read_text() if kind.startswith("fsi") else INLINE.get(kind)
    deck = decks.write(tmp_path, kind, text)
    code, text = _run(deck, "-o", tmp_path / "whole")
    assert code == 0, text

    with monkeypatch.context() as patch:
        _interrupt_at(patch, stop_step)
        code, text = _run(deck, "-o", tmp_path / "split")
    assert code == 130, text
    checkpoint = tmp_path / "split" / "checkpoint.npz"
    assert f"--restart {checkpoint}" in text
    code, text = _run(deck, "-o", tmp_path / "split", "--restart", checkpoint)
    assert code == 0, text

    whole, split = _histories(tmp_path / "whole"), _histories(tmp_path / "split")
    assert sorted(whole) == sorted(split)
    for name in whole:
        assert whole[name].shape == split[name].shape, name
        assert np.array_equal(whole[name], split[name]), name  # bit-identical, not close
        csv_whole = (tmp_path / "whole" / "histories" / f"{name}.csv").read_text()
        assert csv_whole == (tmp_path / "split" / "histories" / f"{name}.csv").read_text(), name
    fields_whole, fields_split = _fields(tmp_path / "whole"), _fields(tmp_path / "split")
    assert [n for n, _ in fields_whole] == [n for n, _ in fields_split]
    for (name, a), (_, b) in zip(fields_whole, fields_split):
        assert np.array_equal(a, b), name
    xml_whole = ET.parse(tmp_path / "whole" / "results.xdmf").getroot()
    xml_split = ET.parse(tmp_path / "split" / "results.xdmf").getroot()
    assert ET.tostring(xml_whole) == ET.tostring(xml_split)


def test_sigterm_writes_a_checkpoint_at_a_complete_step(tmp_path, monkeypatch):
    deck = decks.write(tmp_path, "solid")
    _interrupt_at(monkeypatch, 50, signal.SIGTERM)
    code, text = _run(deck, "-o", tmp_path / "out")
    assert code == 130, text
    from sphfem_cli.driver import load_model
    from sphfem_cli.output.checkpoint import deck_hash, load_simulation, read_checkpoint

    loaded = load_model(str(deck))
    path = tmp_path / "out" / "checkpoint.npz"
    payload = read_checkpoint(path, deck_hash(loaded.deck, loaded.model))
    sim = load_simulation(path, loaded.deck, loaded.model)
    assert payload["step"] == 50
    assert sim.state.step == 50


def test_restart_refuses_a_checkpoint_of_another_deck(tmp_path):
    deck = decks.write(tmp_path, "solid")
    code, text = _run(deck, "-o", tmp_path / "out")
    assert code == 0, text
    other = decks.write(tmp_path / "other" if (tmp_path / "other").mkdir() is None else tmp_path, "solid",
                        timestep_scale=0.5)
    code, text = _run(other, "-o", tmp_path / "out", "--restart", tmp_path / "out" / "checkpoint.npz")
    assert code == 65
    lines = text.strip().splitlines()
    assert len(lines) == 1 and "written for another deck" in lines[0], text


def test_restart_refuses_a_file_that_is_not_a_checkpoint(tmp_path):
    deck = decks.write(tmp_path, "solid")
    bogus = tmp_path / "bogus.pkl"
    bogus.write_bytes(b"not a pickle")
    code, text = _run(deck, "-o", tmp_path / "out", "--restart", bogus)
    assert code == 65
    assert len(text.strip().splitlines()) == 1 and "not a readable sphfem checkpoint" in text


def test_restart_refuses_an_output_folder_without_the_run(tmp_path):
    deck = decks.write(tmp_path, "solid")
    code, text = _run(deck, "-o", tmp_path / "out")
    assert code == 0, text
    code, text = _run(deck, "-o", tmp_path / "elsewhere", "--restart", tmp_path / "out" / "checkpoint.npz")
    assert code == 65
    lines = text.strip().splitlines()
    assert len(lines) == 1 and "does not hold the run of this checkpoint" in lines[0], text


def test_checkpoints_follow_the_simulated_and_wall_intervals(tmp_path, monkeypatch):
    from sphfem_cli.output import checkpoint as ckpt

    written = []
    original = ckpt.write_checkpoint

    def record(path, sim, output_state, digest):
        written.append((sim.state.time, sim.state.step))
        original(path, sim, output_state, digest)

    monkeypatch.setattr(ckpt, "write_checkpoint", record)
    code, text = _run(decks.write(tmp_path, "solid", checkpoint_interval=3.0e-5), "-o", tmp_path / "sim")
    assert code == 0, text
    times = np.array([t for t, _ in written])
    assert len(times) == 6  # 3e-5, 6e-5, ..., 1.8e-4 within end_time 2e-4
    assert np.all(np.floor(times / 3.0e-5 + 1e-9) == np.arange(1, 7))  # the first step at or after each multiple
    steps = [s for _, s in written]
    written.clear()
    # a wall interval shorter than any step: a checkpoint after every step (a shorter run: each costs a write)
    code, text = _run(decks.write(tmp_path, "solid", end_time=3.0e-5, checkpoint_interval=1.0,
                                  checkpoint_wall_interval=1.0e-9), "-o", tmp_path / "wall")
    assert code == 0, text
    n_steps = int(re.search(r"^steps: (\d+)$", (tmp_path / "wall" / "run.log").read_text(), re.M).group(1))
    assert [s for _, s in written] == list(range(1, n_steps + 1)) and n_steps == steps[0]  # the first at 3e-5 above


def test_restart_of_a_restarted_run_is_still_bit_identical(tmp_path, monkeypatch):
    deck = decks.write(tmp_path, "solid")
    code, text = _run(deck, "-o", tmp_path / "whole")
    assert code == 0, text
    checkpoint = tmp_path / "split" / "checkpoint.npz"
    for stop_step, restart in ((201, False), (457, True)):
        with monkeypatch.context() as patch:
            _interrupt_at(patch, stop_step)
            code, text = _run(deck, "-o", tmp_path / "split", *(["--restart", checkpoint] if restart else []))
        assert code == 130, text
    code, text = _run(deck, "-o", tmp_path / "split", "--restart", checkpoint)
    assert code == 0, text
    whole, split = _histories(tmp_path / "whole"), _histories(tmp_path / "split")
    for name in whole:
        assert np.array_equal(whole[name], split[name]), name
    assert (tmp_path / "split" / "run.log").read_text().count("restarted from") == 2


def test_restart_continues_in_the_checkpoints_folder_by_default(tmp_path, monkeypatch):
    deck = decks.write(tmp_path, "solid")
    with monkeypatch.context() as patch:
        _interrupt_at(patch, 100)
        code, text = _run(deck, "-o", tmp_path / "run")
    assert code == 130, text
    monkeypatch.chdir(tmp_path)
    code, text = _run(deck, "--restart", tmp_path / "run" / "checkpoint.npz")
    assert code == 0, text
    assert not (tmp_path / "solid_results").exists()
    glstat = np.loadtxt(tmp_path / "run" / "histories" / "glstat.csv", delimiter=",", skiprows=1)
    assert glstat[-1, 0] == pytest.approx(2.0e-4) and np.all(np.diff(glstat[:, 0]) > 0)
