"""Every shipped deck: `sphfem check` passes and a short run matches its stored reference.

The decks are found by globbing decks/*.yaml, so a new deck is picked up here at once, and fails
until its reference exists (``sphfem regress --update-refs decks/<new>.yaml``).
References: tests/regression/references/<deck stem>.json (see sphfem_cli/regress.py).
"""
from __future__ import annotations

import json
from pathlib import Path

import h5py
import pytest
import yaml
from click.testing import CliRunner
from conftest import xdmf_series

from sphfem_cli import regress
from sphfem_cli.cli import main

ROOT = Path(__file__).resolve().parents[2]
DECKS = sorted((ROOT / "decks").glob("*.yaml"))
REFERENCES = Path(__file__).resolve().parent / "references"


def test_decks_are_shipped():
    assert DECKS, f"no decks under {ROOT / 'decks'}"


@pytest.mark.parametrize("deck", DECKS, ids=lambda p: p.stem)
def test_check(deck):
    """`sphfem check` passes, and no material of a shipped deck gets a units warning (its output holds stderr)."""
    result = CliRunner().invoke(main, ["check", str(deck)])
    assert result.exit_code == 0, result.output
    assert "warning:" not in result.output, result.output


@pytest.mark.parametrize("deck", DECKS, ids=lambda p: p.stem)
def test_regression(deck, tmp_path):
    """The short run matches the reference; and each part of the deck, opened alone with the VTK wheel's
    XDMF reader (as ParaView opens results.<part>.xdmf), is that part at every saved time: the same point
    count and array names from the first saved time to the last, read from the same run. Every run saves at
    least two times: t = 0 and the short window's end (the termination state, written when the deck's interval
    is longer than the window)."""
    result = regress.regress_deck(deck, REFERENCES, keep=tmp_path)
    assert result.passed, "\n" + regress.format_table([result], failures_only=True)
    pytest.importorskip("vtkmodules.vtkIOXdmf2")
    with h5py.File(result.output / "results.h5", "r") as f:
        n_times = len(f["times"])
    parts = yaml.safe_load(deck.read_text())["parts"]
    assert sorted(p.name[len("results."):-len(".xdmf")] for p in result.output.glob("results.*.xdmf")
                  if p.name != "results.xdmf") == sorted(parts)
    for name in parts:
        series = list(xdmf_series(result.output / f"results.{name}.xdmf"))
        assert len(series) == n_times >= 2, (name, len(series), n_times)
        first = series[0]
        for t, kind, n, point, cell, _ in series:
            assert (kind, n, point, cell) == first[1:5], (name, t)
        assert n > 0 and (point or cell), name


def test_missing_reference_fails(tmp_path):
    """A deck without a reference is a failure (reported, not run)."""
    deck = tmp_path / "new_deck.yaml"
    deck.write_text(DECKS[0].read_text())
    result = regress.regress_deck(deck, tmp_path / "references")
    assert not result.passed
    assert "no reference" in result.rows[0].status


def test_moved_value_fails(tmp_path):
    """A value moved by more than the tolerance fails; the table names it."""
    reference = json.loads((REFERENCES / "elastic_bar_wave.json").read_text())
    measured = {"glstat": json.loads(json.dumps(reference["glstat"])),
                "histories": {n: {"times": h["times"], "last_time": h["last_time"],
                                  "columns": json.loads(json.dumps(h["columns"]))}
                              for n, h in reference["histories"].items()}}
    tol = reference["tolerance"]
    kinetic = measured["glstat"]["kinetic"]
    kinetic["value"] += 2.0 * tol * reference["glstat"]["kinetic"]["scale"]
    internal = measured["glstat"]["internal"]
    internal["value"] += 0.5 * tol * reference["glstat"]["internal"]["scale"]
    rows = {r.quantity: r for r in regress.compare("bar", reference, measured)}
    assert rows["glstat.kinetic"].status == "FAIL"
    assert rows["glstat.internal"].status == "PASS"
    assert sum(not r.passed for r in rows.values()) == 1
    assert "glstat.kinetic" in regress.format_table([regress.DeckResult("bar", list(rows.values()))])


def test_regress_command_exit_status(tmp_path):
    """`sphfem regress` exits non-zero when a deck has no reference."""
    deck = tmp_path / "orphan.yaml"
    deck.write_text(DECKS[0].read_text())
    result = CliRunner().invoke(main, ["regress", str(deck), "--references", str(tmp_path)])
    assert result.exit_code != 0
    assert "no reference" in result.output


def test_a_kept_run_is_never_overwritten(tmp_path):
    """`regress --keep-output FOLDER` refuses a deck whose FOLDER/<deck> exists (a FAIL row naming it, no run)."""
    deck = DECKS[0]
    (tmp_path / deck.stem).mkdir()
    (tmp_path / deck.stem / "mine.txt").write_text("a user's file")
    result = regress.regress_deck(deck, REFERENCES, keep=tmp_path)
    assert not result.passed and "exists" in result.rows[0].status
    assert sorted(p.name for p in (tmp_path / deck.stem).iterdir()) == ["mine.txt"]
