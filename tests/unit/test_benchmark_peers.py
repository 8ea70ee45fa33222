"""benchmarks/peers.py: the table and the "peer not built" path, with fake cases (no timing asserted)."""
from __future__ import annotations

import importlib.util
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="module")
def peers():
    spec = importlib.util.spec_from_file_location("peers_bench", ROOT / "benchmarks" / "peers.py")
    mod = importlib.util.module_from_spec(spec)
    sys.modules["peers_bench"] = mod
    spec.loader.exec_module(mod)
    return mod


def fake_case(peers, name, ours_rates, peer_rates=None, missing=None):
    ours = iter(ours_rates)
    peer = iter(peer_rates or [])

    def peer_call():
        if missing is not None:
            raise peers.PeerMissing(missing)
        return next(peer)
    return peers.Case(name, "things/s", "tiny", lambda: next(ours), peer_call, "fakepeer")


def test_ratios_min_and_median_in_the_table(peers):
    case = fake_case(peers, "alpha", [2e6, 3e6, 4e6], [1e6, 1e6, 2e6])
    result = peers.run_pairs(case, 3)
    assert result.missing is None and len(result.peer) == 3
    table = peers.format_table([result], (1.0, 2.0, 3.0), (4.0, 5.0, 6.0))
    row = [line for line in table.splitlines() if line.startswith("| alpha")][0]
    cells = [c.strip() for c in row.strip("|").split("|")]
    # ratios 2.0, 3.0, 2.0: min 2.00, median 2.00; sphfem median 3 M, peer median 1 M
    assert cells == ["alpha", "tiny", "3.000 M things/s", "fakepeer", "1.000 M", "2.00", "2.00"]
    assert "load average before 1.0 2.0 3.0, after 4.0 5.0 6.0" in table


def test_missing_peer_is_a_printed_line_not_an_error(peers):
    case = fake_case(peers, "beta", [1e6, 1e6, 1e6], missing="/nowhere/peer missing; build it (README)")
    result = peers.run_pairs(case, 3)
    assert len(result.ours) == 3 and result.peer == []
    table = peers.format_table([result], (0.0, 0.0, 0.0), (0.0, 0.0, 0.0))
    assert "beta: peer not built: /nowhere/peer missing; build it (README)" in table
    row = [line for line in table.splitlines() if line.startswith("| beta")][0]
    assert row.split("|")[3].strip() == "1.000 M things/s" and row.split("|")[-2].strip() == "-"


def test_external_peer_absent_under_an_empty_peers_dir(peers, tmp_path, monkeypatch):
    monkeypatch.setattr(peers, "PEERS", tmp_path)
    for make in (peers.hex8_case, peers.ale2d_case):
        with pytest.raises(peers.PeerMissing, match="missing"):
            make(4, 3).peer()


def test_child_cpu_reads_the_child_rusage(peers, tmp_path):
    cpu, text = peers.child_cpu([sys.executable, "-c", "print('hello')"], tmp_path)
    assert text.strip() == "hello" and cpu >= 0.0
    with pytest.raises(RuntimeError, match="exited 3"):
        peers.child_cpu([sys.executable, "-c", "raise SystemExit(3)"], tmp_path)
