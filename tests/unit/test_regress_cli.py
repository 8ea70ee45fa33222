"""`sphfem regress` outside a clone of the repository says it is a repository command (exit 2)."""
from __future__ import annotations

from click.testing import CliRunner

from sphfem_cli import regress
from sphfem_cli.cli import main


def test_regress_outside_the_repository_is_a_usage_error(tmp_path, monkeypatch):
    monkeypatch.setattr(regress, "find_root", lambda start=None: tmp_path)
    result = CliRunner().invoke(main, ["regress"])
    assert result.exit_code == 2
    assert "repository command" in result.output and "--references" in result.output
    deck = tmp_path / "mine.yaml"
    deck.write_text("title: x\n")
    result = CliRunner().invoke(main, ["regress", str(deck)])
    assert result.exit_code == 2 and "no references folder" in result.output
