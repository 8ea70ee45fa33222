"""No run ends "completed" over a non-finite state; the guards' verdicts do not depend on the output
cadence; a step never jumps past end_time; `check` says what sets the step and flags implausible units
(issue 13, items 3, 6 and 7)."""
from __future__ import annotations

from pathlib import Path

import h5py
import numpy as np
import yaml
from click.testing import CliRunner

from sphfem_cli.driver import default_threads, load_model
from sphfem_cli.cli import main
from sphfem_cli.solver import explicit

from . import decks

DECKS = Path(__file__).parents[2] / "decks"


def _run(deck, out) -> tuple[int, str]:
    result = CliRunner().invoke(main, ["run", "-q", str(deck), "-o", str(out)])
    return result.exit_code, result.output


def _guard(out) -> str:
    return (out / "diagnostics.txt").read_text().splitlines()[0].split(": ", 1)[1]


def _edit(tmp_path, kind, edit, name=None) -> Path:
    tree = yaml.safe_load(decks.DECKS[kind])
    edit(tree)
    path = tmp_path / f"{name or kind}.yaml"
    path.write_text(yaml.safe_dump(tree, sort_keys=False))
    return path


def _all_finite(out: Path) -> bool:
    """Every float in results.h5 and in every history CSV is finite."""
    finite = []

    def visit(_, obj):
        if isinstance(obj, h5py.Dataset) and obj.dtype.kind == "f":
            finite.append(bool(np.isfinite(obj[()]).all()))

    with h5py.File(out / "results.h5", "r") as f:
        f.visititems(visit)
    for csv in (out / "histories").glob("*.csv"):
        table = np.genfromtxt(csv, delimiter=",", skip_header=1)
        finite.append(bool(np.isfinite(table).all()))
    return all(finite)


def test_an_overflowing_prescribed_velocity_stops_on_the_finite_state_guard(tmp_path):
    """A prescribed velocity of 1e308 puts an infinity into the coordinates in the first step."""
    deck = _edit(tmp_path, "solid", lambda t: t["initial"][0].update(velocity=[1.0e308, 0.0]))
    code, text = _run(deck, tmp_path / "out")
    assert code == 3, text
    assert _guard(tmp_path / "out") == "non_finite"
    assert text.startswith("run stopped: non-finite node coordinates") and "Warning" not in text


def test_nan_in_one_particle_is_caught_although_the_time_step_skips_it(tmp_path, monkeypatch):
    """The SPH stable step is a minimum over particles, which passes over a NaN; the state guard does not."""
    original = explicit.Simulation.step

    def step(self, stop=None):
        original(self, stop)
        if self.state.step == 5:
            self.particles.system.x[17] = np.nan

    monkeypatch.setattr(explicit.Simulation, "step", step)
    code, text = _run(decks.write(tmp_path, "sph"), tmp_path / "out")
    assert code == 3, text
    assert _guard(tmp_path / "out") == "non_finite"
    assert "non-finite SPH coordinates (row 17)" in text and "step 6 " in text  # judged after the next step


def test_a_completed_run_has_only_finite_values_in_its_output(tmp_path):
    code, text = _run(decks.write(tmp_path, "ale"), tmp_path / "out")
    assert code == 0, text
    assert _all_finite(tmp_path / "out")


def test_a_step_never_jumps_past_end_time(tmp_path):
    """E = 1e-300 gives a stable step of ~1e149 s: the first step went to t = 8.6e143 s."""
    deck = _edit(tmp_path, "solid", lambda t: t["materials"]["steel"].update(youngs_modulus=1.0e-300, tangent_modulus=1.0e-301))
    code, text = _run(deck, tmp_path / "out")
    glstat = np.genfromtxt(tmp_path / "out" / "histories" / "glstat.csv", delimiter=",", names=True)
    assert np.atleast_1d(glstat["time"]).max() <= 2.0e-4, text
    assert code in (0, 3), text


def test_a_run_that_would_not_end_stops_at_once(tmp_path):
    """timestep_scale 2e-308 asks for ~1e312 steps: it hung; now the step-count guard stops it at step 0."""
    deck = decks.write(tmp_path, "solid", timestep_scale=2.0e-308)
    code, text = _run(deck, tmp_path / "out")
    assert code == 3, text
    assert _guard(tmp_path / "out") == "time_step"
    assert "control.max_steps" in text
    deck = decks.write(tmp_path, "solid", timestep_scale=0.9, max_steps=100)
    code, text = _run(deck, tmp_path / "capped")
    assert code == 3 and "needs about 533 steps" in text, text  # estimated from the first step
    deck = decks.write(tmp_path, "solid", timestep_scale=0.9, max_steps=600)
    code, text = _run(deck, tmp_path / "during")
    assert code == 3 and text.startswith("run stopped: 600 steps taken by"), text  # the step shrinks: 724 needed


def _gate(tmp_path, history_interval: float) -> Path:
    tree = yaml.safe_load((DECKS / "elastic_gate_sph.yaml").read_text())
    dt = 7.36e-6
    tree["control"]["end_time"] = 6 * dt
    tree["output"].update(interval=6 * dt, history_interval=history_interval)
    path = tmp_path / f"gate_{history_interval:g}.yaml"
    path.write_text(yaml.safe_dump(tree, sort_keys=False))
    return path


def test_energy_guard_verdict_does_not_depend_on_the_history_interval(tmp_path):
    """The elastic gate cut to 6 steps stopped at step 6 on "energy ratio -27" with a history row every
    half step (the water released from rest: kinetic energy out of negative internal energy, a ratio of
    two numbers 300 times smaller than the energies they balance) and completed with one row at its end."""
    verdicts = []
    for interval in (3.7e-6, 6 * 7.36e-6):
        code, text = _run(_gate(tmp_path, interval), tmp_path / f"out_{interval:g}")
        verdicts.append(code)
        assert code == 0, text
    assert verdicts[0] == verdicts[1]


def test_energy_guard_trips_at_the_same_step_whatever_the_history_interval(tmp_path):
    """A history row only at the end: the guard trips at the same step as with a row every few steps."""
    steps = []
    for interval in (2.0e-6, 2.0e-4):
        deck = decks.write(tmp_path, "solid", timestep_scale=1.2)
        tree = yaml.safe_load(deck.read_text())
        tree["output"]["history_interval"] = interval
        deck.write_text(yaml.safe_dump(tree))
        code, text = _run(deck, tmp_path / f"out_{interval:g}")
        assert code == 3 and _guard(tmp_path / f"out_{interval:g}") == "energy_ratio", text
        steps.append(text.split("step ")[1].split()[0])
    assert steps[0] == steps[1]


def test_check_names_what_sets_the_step_with_its_unit(tmp_path):
    result = CliRunner().invoke(main, ["check", str(DECKS / "cantilever_2d.yaml")])
    assert result.exit_code == 0, result.output
    assert "stable time step 1.8747e-06 s" in result.output
    assert "set by element" in result.output and "of part 'beam'" in result.output
    assert "Young's modulus 2.1e+11 Pa" in result.output and "sound speed 6001 m/s" in result.output
    result = CliRunner().invoke(main, ["check", str(DECKS / "elastic_gate_sph.yaml")])
    assert "material water: fluid, density 1000 kg/m^3, sound speed 40 m/s" in result.output


def _cantilever(tmp_path, edit) -> Path:
    tree = yaml.safe_load((DECKS / "cantilever_2d.yaml").read_text())
    edit(tree)
    path = tmp_path / "deck.yaml"
    path.write_text(yaml.safe_dump(tree, sort_keys=False))
    return path


def test_check_warns_of_constants_in_other_units(tmp_path):
    """SI numbers in an mm-t-s deck; a modulus in MPa in an SI deck: a warning each, exit 0."""
    mixed = _cantilever(tmp_path, lambda t: t.update(units={"length": "mm", "mass": "t", "time": "s"}))
    result = CliRunner().invoke(main, ["check", str(mixed)])
    assert result.exit_code == 0
    assert "warning: material steel: density 7850 t/mm^3 is 7.85e+15 kg/m^3" in result.output
    mpa = _cantilever(tmp_path, lambda t: t["materials"]["steel"].update(youngs_modulus=2.1e5))
    result = CliRunner().invoke(main, ["check", str(mpa)])
    assert result.exit_code == 0
    assert "warning: material steel: Young's modulus 210000 Pa" in result.output


def test_threads_count_ale_elements(tmp_path):
    deck = decks.write(tmp_path, "ale")
    tree = yaml.safe_load(deck.read_text())
    tree["parts"]["tube"]["geometry"]["box"]["divisions"] = [400, 100]
    deck.write_text(yaml.safe_dump(tree))
    assert default_threads(load_model(str(deck)).model) == 2
