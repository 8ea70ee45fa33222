"""docs/stability.md's table is what benchmarks/stability_extremes.py writes: the quick groups rerun here
(``-m extremes``, with the heavier cases) give the same outcome, and the same steps, energy ratios and state figures (every column but the wall time)
within the spread of the host CPU.

Why a spread: the kernels are compiled for the host CPU (``fastmath``), so their sums are ordered by its
vector width; an AVX-512 host and an AVX2 one agree to round-off, which the violent cases amplify. Measured:
"SPH column, gravity 9810 m/s^2" took 3291 steps (energy ratio 1.0047, min distance/dx 0.62) where the table
was written and 3274 (1.0052, 0.70) on an AVX-512 EPYC; every other quick case agreed to the digit. The
outcome must match exactly; steps within 2 %, energy ratios within 2e-3, the state figures within 20 %.
The SPH rates' regrouped sums (structure-of-arrays rows, December 2026; round-off) moved the same case to
3316 steps (1.0048, 0.72) and its last minimum pressure from +2.94e4 to -3.32e3 Pa: that row was rewritten
from the fresh run. The reordering of the particles at the second evaluation (issue 17, sphspeed2; round-off)
moved it again, to 3320 steps (1.0047, 0.65) and +3.04e4 Pa, rewritten likewise. On the AVX2 Zen 3 host of
7 December 2026 the same case gave 3312 steps (1.0048, 0.70) and -6.77e3 Pa. The last step's minimum pressure of
this case is the free surface's acoustic noise under 1000 g (it has changed sign four times under round-off), so
the state figures are compared without it (``_without_min_pressure``); it stays in the table as information.
"""
from __future__ import annotations

import re
import sys
from pathlib import Path

import pytest


sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "benchmarks"))

import stability_extremes as se  # noqa: E402

NUMBER = re.compile(r"[-+]?\d+(?:\.\d+)?(?:e[-+]?\d+)?")
STEPS_REL = 0.02
RATIO_ABS = 2e-3
STATE_REL = 0.20
MIN_P = re.compile(r"min p [-+]?\d+(?:\.\d+)?(?:e[-+]?\d+)? Pa")


def _key_columns(row: str) -> tuple[str, ...]:
    cells = [c.strip() for c in row.strip().strip("|").split("|")]
    return tuple(cells[:5] + cells[6:])  # all but "wall s"


def _numbers(cell: str) -> list[float]:
    return [float(x) for x in NUMBER.findall(cell)]


def _without_min_pressure(state: str) -> str:
    """The state column without its "min p ... Pa" figure (module docstring: round-off noise in violent cases)."""
    return MIN_P.sub("min p", state)


def _same_within_spread(shipped: tuple[str, ...], fresh: tuple[str, ...]) -> bool:
    if shipped[:3] != fresh[:3] or len(shipped) != len(fresh):
        return False  # group, case, outcome
    if NUMBER.sub("#", shipped[5]) != NUMBER.sub("#", fresh[5]):
        return False  # the state column names the same figures
    s_state, f_state = _without_min_pressure(shipped[5]), _without_min_pressure(fresh[5])
    pairs = [(_numbers(shipped[3]), _numbers(fresh[3]), lambda a, b: abs(a - b) <= STEPS_REL * max(abs(a), 1.0)),
             (_numbers(shipped[4]), _numbers(fresh[4]), lambda a, b: abs(a - b) <= RATIO_ABS),
             (_numbers(s_state), _numbers(f_state), lambda a, b: abs(a - b) <= STATE_REL * max(abs(a), abs(b)))]
    return all(len(s) == len(f) and all(ok(a, b) for a, b in zip(s, f)) for s, f, ok in pairs)


def test_spread_rule_accepts_round_off_and_refuses_a_changed_outcome():
    shipped = ("gravity", "SPH column, gravity 9810 m/s^2", "completed", "3291", "1.0047; 1.0000-1.0047",
               "min distance/dx 0.62, min p 2.94e+04 Pa")
    assert _same_within_spread(shipped, (*shipped[:3], "3274", "1.0052; 1.0000-1.0052",
                                         "min distance/dx 0.70, min p 2.98e+04 Pa"))
    assert not _same_within_spread(shipped, (*shipped[:2], "stopped: energy guard", *shipped[3:]))
    assert not _same_within_spread(shipped, (*shipped[:3], "3500", *shipped[4:]))
    assert not _same_within_spread(shipped, (*shipped[:4], "1.0147; 1.0000-1.0147", shipped[5]))
    assert _same_within_spread(shipped, (*shipped[:5], "min distance/dx 0.62, min p -6.77e+03 Pa"))  # noise, not compared
    assert not _same_within_spread(shipped, (*shipped[:5], "min distance/dx 0.42, min p 2.94e+04 Pa"))


@pytest.mark.extremes  # 15-17 s of CPU; five of its nine groups' outcomes run in the default suite (test_extremes.py QUICK)
def test_shipped_table_matches_a_fresh_run_of_the_quick_cases():
    shipped = {_key_columns(r)[1]: _key_columns(r) for r in se.shipped_rows()}
    names = [name for group, name, _ in se.cases(100_000)]
    assert sorted(shipped) == sorted(names), "the table's cases are not the script's: rerun it with --write"
    fresh = se.run_table(set(se.QUICK), 100_000)
    assert len(fresh) >= 30
    for row in fresh:
        cols = _key_columns(row)
        assert _same_within_spread(shipped[cols[1]], cols), \
            f"docs/stability.md is stale (rerun the script with --write): {row} against {shipped[cols[1]]}"
