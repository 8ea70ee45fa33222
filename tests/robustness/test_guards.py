"""Guards: each trip stops the run with exit 3, one line on stderr, diagnostics.txt (guard, where, values,
remedies, last good state) and readable output; erosion lets a run go on past what would stop it."""
from __future__ import annotations

import re

import numpy as np
import pytest
import yaml
from click.testing import CliRunner

from sphfem_cli.driver import load_model
from sphfem_cli.cli import main
from sphfem_cli.solver import explicit

from . import decks


def _run(deck, out) -> tuple[int, str]:
    result = CliRunner().invoke(main, ["run", "-q", str(deck), "-o", str(out)])
    return result.exit_code, result.output


def _diagnostics(out) -> dict[str, str]:
    lines = (out / "diagnostics.txt").read_text().splitlines()
    return {line.split(": ", 1)[0]: line.split(": ", 1)[1] for line in lines if ": " in line and line[0] != " "}


def _checkpointed(deck, out) -> explicit.Simulation:
    """The simulation of the checkpoint in `out`, restored into a fresh build of `deck`."""
    from sphfem_cli.output.checkpoint import load_simulation

    loaded = load_model(str(deck))
    return load_simulation(out / "checkpoint.npz", loaded.deck, loaded.model)


def _edit(tmp_path, kind, edit) -> object:
    tree = yaml.safe_load(decks.DECKS[kind])
    edit(tree)
    path = tmp_path / f"{kind}.yaml"
    path.write_text(yaml.safe_dump(tree, sort_keys=False))
    return path


def test_timestep_scale_1_2_trips_the_energy_guard(tmp_path):
    deck = decks.write(tmp_path, "solid", timestep_scale=1.2)
    code, text = _run(deck, tmp_path / "out")
    assert code == 3, text
    assert len(text.strip().splitlines()) == 1 and text.startswith("run stopped: energy ratio")
    diag = _diagnostics(tmp_path / "out")
    assert diag["guard"] == "energy_ratio"
    assert "lower timestep_scale" in diag["remedies"]
    assert "checkpoint.npz" in diag["last good state"] and "--restart" in diag["last good state"]
    ratio = float(diag["message"].split()[2])
    assert not 0.9 <= ratio <= 1.1
    assert (tmp_path / "out" / "results.xdmf").is_file()


def test_timestep_scale_2_trips_the_energy_guard_first_then_the_volume_guard(tmp_path):
    deck = decks.write(tmp_path, "solid", timestep_scale=2.0)
    code, text = _run(deck, tmp_path / "on")
    assert code == 3 and _diagnostics(tmp_path / "on")["guard"] == "energy_ratio", text
    deck = decks.write(tmp_path, "solid", timestep_scale=2.0, energy_band=None)
    code, text = _run(deck, tmp_path / "off")
    assert code == 3, text
    diag = _diagnostics(tmp_path / "off")
    assert diag["guard"] == "negative_volume", diag
    assert re.search(r"negative volume in element \d+ of part 'bar' at t = ", diag["message"])
    assert re.search(r"^  element: \d+$", (tmp_path / "off" / "diagnostics.txt").read_text(), re.M)
    assert "remedies" in diag and "erosion" in diag["remedies"]


def test_energy_band_is_configurable_and_can_be_switched_off(tmp_path):
    deck = decks.write(tmp_path, "solid", energy_band=[0.9999, 1.0001])
    code, text = _run(deck, tmp_path / "tight")
    assert code == 3 and _diagnostics(tmp_path / "tight")["guard"] == "energy_ratio", text
    deck = decks.write(tmp_path, "solid", energy_band=None, timestep_scale=1.2)
    code, text = _run(deck, tmp_path / "off")
    if code == 3:
        assert _diagnostics(tmp_path / "off")["guard"] != "energy_ratio"


def test_energy_band_must_bracket_one(tmp_path):
    deck = decks.write(tmp_path, "solid", energy_band=[1.1, 1.2])
    result = CliRunner().invoke(main, ["check", str(deck)])
    assert result.exit_code == 65
    assert "control.energy_band" in result.output and len(result.output.strip().splitlines()) == 1


def _leaving(tree, fraction):
    tree["sections"]["fluid"]["domain"] = {"min": [-0.01, -0.01], "max": [0.06, 0.3]}
    tree["initial"] = [{"type": "velocity", "part": "column", "velocity": [5.0, 0.0]}]
    tree["boundaries"][0]["sides"] = ["left", "bottom"]
    tree["control"]["max_lost_fraction"] = fraction
    # The energy balance of this flow is off (ratio about 0.12 by t = 0.0135: the block pulling away from the
    # left ghost wall, and the particles leaving), so the energy guard would stop it; this test is about the other.
    tree["control"]["energy_band"] = None


def test_lost_particles_guard(tmp_path):
    deck = _edit(tmp_path, "sph", lambda t: _leaving(t, 0.2))
    code, text = _run(deck, tmp_path / "out")
    assert code == 3, text
    diag = _diagnostics(tmp_path / "out")
    assert diag["guard"] == "lost_particles"
    assert "have left the domain" in diag["message"] and "max_lost_fraction 0.2" in diag["message"]
    lost = _checkpointed(deck, tmp_path / "out").particles.system.lost
    assert lost <= 0.2 * 200  # the last good state is within the limit


def test_lost_particles_guard_off(tmp_path):
    deck = _edit(tmp_path, "sph", lambda t: _leaving(t, None))
    code, text = _run(deck, tmp_path / "out")
    assert code == 0, text


class _PenetratingContact:
    """An interaction that pushes nothing and reports a fixed penetration (the guard's contract)."""

    penetration_limit = 1.0e-3
    work = 0.0

    def __init__(self, depth):
        self.depth = depth

    def forces(self, st):
        pass

    def stable_dt(self):
        return np.inf

    def record_work(self, dt, dt_avg, v_old, st):
        pass

    def max_penetration(self):
        return self.depth, "node 7 of contact fake->bar"


def _with_contact(monkeypatch, depth):
    original = explicit.Simulation.__init__

    def init(self, model):
        original(self, model)
        self.interactions.append(_PenetratingContact(depth))

    monkeypatch.setattr(explicit.Simulation, "__init__", init)


def test_penetration_guard_uses_the_contacts_limit(tmp_path, monkeypatch):
    _with_contact(monkeypatch, 2.0e-3)
    code, text = _run(decks.write(tmp_path, "solid"), tmp_path / "out")
    assert code == 3, text
    diag = _diagnostics(tmp_path / "out")
    assert diag["guard"] == "penetration"
    assert "node 7 of contact fake->bar" in diag["message"] and "limit 1.0000e-03" in diag["message"]


def test_penetration_guard_deck_limit_overrides(tmp_path, monkeypatch):
    _with_contact(monkeypatch, 2.0e-3)
    code, text = _run(decks.write(tmp_path, "solid", max_penetration=5.0e-3), tmp_path / "out")
    assert code == 0, text
    _with_contact(monkeypatch, 2.0e-3)
    model = load_model(str(decks.write(tmp_path, "solid", max_penetration=1.0e-3))).model
    sim = explicit.Simulation(model)
    with pytest.raises(explicit.RunStopped) as err:
        sim.check_guards()
    assert err.value.guard == "penetration" and err.value.values["depth"] == 2.0e-3


def _eroding(tree, **erosion):
    tree["initial"][0]["velocity"] = [500.0, 0.0]
    tree["parts"]["bar"]["erosion"] = erosion


def test_plastic_strain_erosion_goes_on_and_reports(tmp_path):
    deck = _edit(tmp_path, "solid", lambda t: _eroding(t, max_plastic_strain=0.5))
    code, text = _run(deck, tmp_path / "out")
    assert code == 0, text
    log = (tmp_path / "out" / "run.log").read_text()
    assert "erosion: " in log and "(plastic strain)" in log
    sim = _checkpointed(deck, tmp_path / "out")
    n_eroded = len(sim.eroded)
    assert n_eroded > 0 and int(np.sum(~sim.model.element_active)) == n_eroded
    assert f"{n_eroded} element(s) eroded (bar: {n_eroded})" in log
    assert np.all(sim.state.hist[~sim.model.element_active, 0] > 0.5)


def test_time_step_erosion_removes_the_crushed_elements(tmp_path):
    """min_time_step_ratio (LS-DYNA DTMIN with ERODE = 1): the bar driven at 500 m/s erodes the elements
    whose step fell below the fraction of the part's first smallest step, and the run's step never falls
    below it by more than timestep_scale's margin; the eroded nodes keep their mass."""
    deck = _edit(tmp_path, "solid", lambda t: _eroding(t, min_time_step_ratio=0.5))
    code, text = _run(deck, tmp_path / "out")
    assert code == 0, text
    log = (tmp_path / "out" / "run.log").read_text()
    assert "(time step)" in log
    sim = _checkpointed(deck, tmp_path / "out")
    gone = ~sim.model.element_active
    assert 0 < int(gone.sum()) == len(sim.eroded)
    floor = float(sim.solids._erode_dt[gone].min())
    assert floor > 0.0 and float(sim.solids._dt_elem[sim.model.element_active].min()) >= floor
    assert np.array_equal(sim.model.mass, load_model(str(deck)).model.mass)


def test_negative_volume_erosion_instead_of_a_stop(tmp_path):
    deck = _edit(tmp_path, "solid", lambda t: (t["control"].update(timestep_scale=1.5, energy_band=None),
                                               t["parts"]["bar"].update(erosion={"on_negative_volume": True})))
    code, text = _run(deck, tmp_path / "out")
    log = (tmp_path / "out" / "run.log").read_text()
    assert "(negative volume)" in log, text
    if code == 3:  # erosion may not save a run that is unstable everywhere, but it must not be the volume guard
        assert _diagnostics(tmp_path / "out")["guard"] != "negative_volume"


def test_non_finite_sph_state_stops_with_the_guard_not_an_exception(tmp_path):
    """Found by the run fuzzer: reference_density 1e308 gives p = -inf at once, NaN positions after one
    step, and the cell search then divided by zero inside a kernel."""
    deck = _edit(tmp_path, "sph", lambda t: t["equations_of_state"]["water"].update(reference_density=1.0e308))
    code, text = _run(deck, tmp_path / "out")
    assert code == 3, text
    diag = _diagnostics(tmp_path / "out")
    assert diag["guard"] == "non_finite" and "non-finite SPH " in diag["message"]


def test_energy_injected_by_a_contact_or_the_hourglass_is_caught():
    """guards.energy_injected: a contact or hourglass energy below -(1 - band low) x the energy in play is
    energy those put in (the balance stays closed, so the ratio guard cannot see it); a small negative one
    (a penalty spring's first-order error) is not, nor anything before ENERGY_GUARD_FIRST."""
    from sphfem_cli.solver.guards import ENERGY_GUARD_FIRST, energy_injected

    band, step = (0.9, 1.1), ENERGY_GUARD_FIRST
    assert energy_injected(-132.0, -53.0, 380.0, band, step) == ("contact", -132.0)  # the 1.25 mm Lagrangian bird at 2.8 ms
    assert energy_injected(1.0, -53.0, 380.0, band, step) == ("hourglass", -53.0)
    assert energy_injected(-9.4e-4, 0.0, 1.0, band, step) is None  # a rigid block into ALE water
    assert energy_injected(-37.0, 0.0, 380.0, band, step) is None  # 9.7 % of the energy in play
    assert energy_injected(-132.0, 0.0, 380.0, band, step - 1) is None
    assert energy_injected(-0.2, 0.0, 1.0, (0.7, 1.3), step) is None  # a wider band allows more
