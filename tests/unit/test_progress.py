"""Progress lines of a run whose stderr is not a terminal: a heartbeat with t, step, dt, wall time and
ETA; "compiling kernels" when numba's cache is cold; nothing with quiet."""
from __future__ import annotations

from pathlib import Path

from sphfem_cli import api, driver

DECK = Path(__file__).resolve().parents[2] / "decks" / "elastic_bar_wave.yaml"


def test_heartbeat_when_not_a_terminal(tmp_path, monkeypatch, capsys):
    monkeypatch.setattr(driver, "HEARTBEAT_S", 0.0)  # every step, instead of every 30 s
    result = api.run(DECK, tmp_path / "a", overrides={"control.end_time": 5e-6}, quiet=False)
    assert result.completed
    lines = [line for line in capsys.readouterr().err.splitlines() if line.startswith("t = ")]
    assert len(lines) >= result.steps - 1
    assert "of 5.0000e-06, step" in lines[-1] and " dt " in lines[-1] and "wall" in lines[-1] and "ETA" in lines[-1]
    api.run(DECK, tmp_path / "b", overrides={"control.end_time": 5e-6}, quiet=True)
    assert capsys.readouterr().err == ""


def test_a_cold_cache_says_it_is_compiling(tmp_path, monkeypatch, capsys):
    monkeypatch.setenv("NUMBA_CACHE_DIR", str(tmp_path / "empty-cache"))
    assert driver.kernel_cache_is_cold()
    api.run(DECK, tmp_path / "a", overrides={"control.end_time": 1e-6}, quiet=False)
    err = capsys.readouterr().err
    # said once, before the model is built (building compiles kernels of its own, which fill the cache)
    assert f"compiling kernels (first run only; cached in {tmp_path / 'empty-cache'})" in err
    assert err.count("compiling kernels") == 1 and "preparing the first step" not in err
    (tmp_path / "empty-cache" / "sub").mkdir(parents=True)
    (tmp_path / "empty-cache" / "sub" / "kernel.nbi").write_bytes(b"")
    assert not driver.kernel_cache_is_cold()
