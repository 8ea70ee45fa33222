"""The Python API (sphfem_cli.api): overrides checked as deck lines are, a dict deck, the outcome of a
run as data, and the parameter sweep of docs/api.md run as written."""
from __future__ import annotations

import contextlib
import io
import re
from pathlib import Path

import pytest
import yaml

from sphfem_cli import api

ROOT = Path(__file__).resolve().parents[2]
CANTILEVER = ROOT / "decks" / "cantilever_2d.yaml"


def test_overrides_are_validated_like_the_deck():
    loaded = api.load(CANTILEVER, {"materials.steel.youngs_modulus": 1.0e11, "control.end_time": 1e-3})
    assert loaded.deck.materials["steel"].youngs_modulus == 1.0e11 and loaded.deck.control.end_time == 1e-3
    with pytest.raises(api.DeckProblem, match=r"cantilever_2d.yaml:\d+:\d+: materials.steel.youngs_modulus: must be > 0"):
        api.load(CANTILEVER, {"materials.steel.youngs_modulus": -1.0})
    with pytest.raises(api.DeckProblem, match="not an index of the list at 'boundaries'"):
        api.load(CANTILEVER, {"boundaries.5.directions": ["x"]})
    with pytest.raises(api.DeckProblem, match="is a value, not a mapping"):
        api.load(CANTILEVER, {"control.end_time.value": 1.0})


def test_a_dict_deck_runs_and_its_outcome_is_data(tmp_path):
    data = yaml.safe_load((ROOT / "decks" / "elastic_bar_wave.yaml").read_text())
    result = api.run(data, tmp_path / "bar", overrides={"control.end_time": 2e-5})
    assert result.completed and result.code == 0 and result.steps > 0
    assert result.time == pytest.approx(2e-5)
    t, v = result.series("middle", "velocity_x")
    assert t[0] == 0.0 and len(t) == len(v) > 2
    assert set(result.histories()) >= {"glstat", "matsum", "middle"}
    with pytest.raises(KeyError, match="columns: time"):
        result.series("middle", "nothing")
    with pytest.raises(api.OutputProblem, match="holds the results of an earlier run") as err:
        api.run(data, tmp_path / "bar")
    assert err.value.exit_code == 2


def test_a_guard_stop_is_an_outcome_not_an_exception(tmp_path):
    result = api.run(CANTILEVER, tmp_path / "run", overrides={"control.end_time": 1e-3, "control.max_steps": 10})
    assert not result.completed and result.status == "stopped by a guard" and result.code == 3
    assert "max_steps" in result.message and (tmp_path / "run" / "diagnostics.txt").exists()


def test_the_sweep_in_the_docs_runs_as_written(tmp_path, monkeypatch):
    code = re.findall(r"```python\n(.*?)```", (ROOT / "docs" / "api.md").read_text(), re.S)[0]
    monkeypatch.chdir(tmp_path)
    (tmp_path / "decks").symlink_to(ROOT / "decks")
    printed = io.StringIO()
    with contextlib.redirect_stdout(printed):
        exec(compile(code, "docs/api.md", "exec"), {"__name__": "docs_api"})
    rows = [line.split() for line in printed.getvalue().splitlines()[1:]]
    assert len(rows) == 3
    peaks = [float(r[1]) for r in rows]
    assert peaks[0] > peaks[1] > peaks[2]
    # twice the static deflection 2 F L^3 (1 - nu^2) / (3 E I) where the peak falls inside the window
    for r in rows[1:]:
        assert float(r[4]) == pytest.approx(21.0, rel=0.03)


def test_no_module_of_the_package_imports_the_cli():
    """The click shell sits on top: the driver, regress and the study never import it back."""
    offenders = [str(p.relative_to(ROOT)) for p in (ROOT / "sphfem_cli").rglob("*.py")
                 if re.search(r"^\s*(from\s+(\.+|sphfem_cli\.)cli\s+import|import\s+sphfem_cli\.cli)", p.read_text(), re.M)]
    assert not offenders, offenders
