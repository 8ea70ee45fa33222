"""docs/stability.md's table is what benchmarks/stability_extremes.py writes: the quick groups rerun here
give the same outcome, steps and energy ratios (every column but the wall time)."""
from __future__ import annotations

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "benchmarks"))

import stability_extremes as se  # noqa: E402


def _key_columns(row: str) -> tuple[str, ...]:
    cells = [c.strip() for c in row.strip().strip("|").split("|")]
    return tuple(cells[:5] + cells[6:])  # all but "wall s"


def test_shipped_table_matches_a_fresh_run_of_the_quick_cases():
    shipped = {_key_columns(r)[1]: _key_columns(r) for r in se.shipped_rows()}
    names = [name for group, name, _ in se.cases(100_000)]
    assert sorted(shipped) == sorted(names), "the table's cases are not the script's: rerun it with --write"
    fresh = se.run_table(set(se.QUICK), 100_000)
    assert len(fresh) >= 30
    for row in fresh:
        cols = _key_columns(row)
        assert shipped[cols[1]] == cols, f"docs/stability.md is stale (rerun the script with --write): {row}"
