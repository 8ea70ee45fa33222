"""Stability at the extremes (docs/stability.md): every case either completes with its energy ratio inside
the band or stops with a named guard (exit 3): never silent garbage. The cases and the runner are those of
benchmarks/stability_extremes.py; the quick ones run in the default suite, the rest with -m extremes."""
from __future__ import annotations

import importlib.util
from pathlib import Path

import pytest

_spec = importlib.util.spec_from_file_location(
    "stability_extremes", Path(__file__).parents[2] / "benchmarks" / "stability_extremes.py")
extremes = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(extremes)

QUICK = {"one element", "one particle", "density ratio", "near incompressible", "gravity"}
LONG_STEPS = 100_000
BAND = (0.9, 1.1)


def _cases(quick: bool):
    for group, name, tree in extremes.cases(LONG_STEPS):
        if (group in QUICK) == quick:
            yield pytest.param(group, name, tree, id=name)


def _check(group, name, tree, tmp_path):
    row = extremes.run_case(tree, tmp_path, LONG_STEPS if group == "long run" else None)
    assert row["exit"] in (0, 3), row
    if row["exit"] == 0:
        assert BAND[0] <= row["ratio"] <= BAND[1], row  # completed means trustworthy by the energy balance
    else:
        assert row["guard"] in ("energy_ratio", "energy_injected", "negative_volume", "non_finite", "time_step",
                                "lost_particles"), row
        assert row["diagnosis"], row
    return row


@pytest.mark.parametrize("group, name, tree", list(_cases(quick=True)))
def test_quick_extremes_complete_or_stop_with_a_guard(group, name, tree, tmp_path):
    row = _check(group, name, tree, tmp_path)
    if group in ("one element", "density ratio", "near incompressible"):
        assert row["guard"] == "completed", row
    if name == "SPH column, gravity 0":
        assert row["guard"] == "completed" and abs(row["ratio"] - 1.0) < 1e-9, row


@pytest.mark.extremes
@pytest.mark.parametrize("group, name, tree", list(_cases(quick=False)))
def test_extremes_complete_or_stop_with_a_guard(group, name, tree, tmp_path):
    row = _check(group, name, tree, tmp_path)
    if name.startswith("solid bar 100 m/s, scale"):
        scale = float(name.rsplit(" ", 1)[1])
        assert (row["guard"] == "completed") == (scale <= 1.0), row  # stable to 1.0, a guard trips from 1.2
    if name.startswith("SPH dam break, scale"):
        scale = float(name.rsplit(" ", 1)[1])
        assert (row["guard"] == "completed") == (scale <= 2.0), row
    if group == "impact speed":
        assert row["guard"] == "completed", row
    if "erosion" in name:
        assert "eroded" in row["eroded"], row
    if group == "thin 3D parts":  # the step of elements free to dilate (model.build.free_dilatation_factor)
        assert row["guard"] == "completed", row
    if name == "the same with pressure_cutoff 0":
        assert "min p 0 Pa" in row["sph"], row
