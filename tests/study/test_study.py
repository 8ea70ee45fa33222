"""Mesh study on tiny scenes: deck derivation (particles at element sub-centres, fills, boundaries,
couplings), cases and resume, report files, the plot command, and the Dask executor."""
from __future__ import annotations

import copy
import json
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

from sphfem_cli.cli import main
from sphfem_cli.deck.schema import Deck
from sphfem_cli.model.build import build_model
from sphfem_cli.study import StudyConfig, StudyError, derive, run_study, runner
from sphfem_cli.study.study import load_deck_data

HERE = Path(__file__).parent
TINY = HERE / "tiny_ale.yaml"


def _scene(fills, boundaries=None, couplings=None, solid=False):
    data = {
        "dimension": 2, "control": {"end_time": 1e-4},
        "equations_of_state": {"w": {"type": "ideal_gas", "gamma": 1.4, "e0": 2.5e5}},
        "materials": {"water": {"type": "fluid", "density": 1.0, "eos": "w"},
                      "gas": {"type": "fluid", "density": 1.0, "eos": "w"}, "empty": {"type": "void"}},
        "sections": {"ale": {"type": "ale_multi_material"}},
        "parts": {"tank": {"material": "water", "section": "ale", "fill": fills,
                           "geometry": {"box": {"min": [0.0, 0.0], "max": [1.0, 0.6], "divisions": [10, 6]}}}},
        "boundaries": boundaries or [],
    }
    if solid:
        data["materials"]["steel"] = {"type": "elastic", "density": 7850.0, "youngs_modulus": 2e11,
                                      "poisson_ratio": 0.3}
        data["sections"]["shell"] = {"type": "solid"}
        data["parts"]["plate"] = {"material": "steel", "section": "shell",
                                  "geometry": {"box": {"min": [0.4, 0.6], "max": [0.6, 0.62], "divisions": [4, 1]}}}
    if couplings:
        data["couplings"] = couplings
    return data


def _particles(derived):
    model = build_model(Deck.model_validate(derived.data), Path("."))
    return model, model.particles


def _expected(data, ratio, label_material):
    """Sub-centres and the material each gets, by brute force over the elements."""
    deck = Deck.model_validate(data)
    info = derive.ale_info(deck)
    xs, ys, dx = derive.sub_centres(info, ratio)
    labels = derive.source_labels(deck, info, xs, ys)
    X, Y = np.meshgrid(xs, ys)
    return X, Y, labels, dx


@pytest.mark.parametrize("ratio", [1, 2, 3])
def test_particles_sit_at_element_sub_centres(ratio):
    fills = [
        {"material": "gas", "ball": {"center": [0.33, 0.27], "radius": 0.17}},
        {"material": "empty", "half_space": {"point": [0.0, 0.45], "normal": [0.3, 1.0]}},
        {"material": "gas", "polygon": {"vertices": [[0.6, 0.05], [0.95, 0.1], [0.8, 0.4]]}},
        {"material": "water", "box": {"min": [0.05, 0.05], "max": [0.15, 0.15]}, "velocity": [1.0, 0.0]},
    ]
    data = _scene(fills)
    d = derive.sph_variant(data, ratio)
    model, ps = _particles(d)
    X, Y, labels, dx = _expected(data, ratio, None)
    assert d.spacing == pytest.approx(0.1 / ratio)
    # every particle is a sub-centre (lattice index + 1/2), and each sub-centre of a fluid holds one
    idx = ps.x / dx - 0.5
    assert np.abs(idx - np.round(idx)).max() < 1e-9
    fluid = labels != 2  # fill 1 is void
    assert ps.n == int(fluid.sum())
    got = {(int(round(i)), int(round(j))) for i, j in idx}
    want = {(i, j) for j, i in zip(*np.nonzero(fluid))}
    assert got == want
    # the part a particle belongs to is the fill that owns its sub-centre (later fills win)
    names = [p.name for p in model.parts]
    for label, part in ((0, "tank"), (1, "tank_fill0"), (3, "tank_fill2"), (4, "tank_fill3")):
        sel = ps.part == names.index(part)
        cells = {(int(round(i)), int(round(j))) for i, j in idx[sel]}
        assert cells == {(i, j) for j, i in zip(*np.nonzero(labels == label))}, part
    assert "tank_fill1" not in names  # void: no particles
    assert {"type": "velocity", "part": "tank_fill3", "velocity": [1.0, 0.0]} in d.data["initial"]


def test_fill_pressure_becomes_a_material_state():
    from sphfem_cli.materials.kernels import EOS_OFFSET, P_EOS_TYPE, eos_pressure

    data = _scene([{"material": "gas", "box": {"min": [0.0, 0.0], "max": [0.5, 0.6]}, "pressure": 3.0e5,
                    "density": 2.0}])
    d = derive.sph_variant(data, 1)
    model, ps = _particles(d)
    part = d.data["parts"]["tank_fill0"]
    m = model.material_names.index(part["material"])
    row = model.material_param[m]
    assert row[0] == 2.0
    p = eos_pressure(int(row[P_EOS_TYPE]), row[EOS_OFFSET:], 1.0, row[EOS_OFFSET + 1])
    assert p == pytest.approx(3.0e5, rel=1e-12)


def test_boundaries_and_couplings_are_translated():
    bcs = [{"type": "ale_boundary", "part": "tank", "sides": ["left", "bottom"], "condition": "slip"},
           {"type": "ale_boundary", "part": "tank", "sides": ["right"], "condition": "fixed"},
           {"type": "ale_boundary", "part": "tank", "sides": ["top"], "condition": "transmit"}]
    couplings = [{"type": "lagrange_in_solid", "structure": "plate", "fluid": "tank", "pfac": 0.3, "damping": 0.2,
                  "materials": ["gas"]}]
    data = _scene([{"material": "gas", "box": {"min": [0.0, 0.0], "max": [0.3, 0.3]}}], bcs, couplings, solid=True)
    d = derive.sph_variant(data, 2)
    out = d.data
    walls = {w["condition"]: w for w in out["boundaries"] if w["type"] == "wall"}
    assert walls["slip"]["sides"] == ["left", "bottom"] and walls["no_slip"]["sides"] == ["right"]
    assert walls["slip"]["min"] == [0.0, 0.0] and walls["slip"]["max"] == [1.0, 0.6]
    domain = out["sections"]["sph"]["domain"]
    assert domain["max"][1] == pytest.approx(0.6)  # transmit: particles leaving the top are dropped
    assert domain["min"][1] < 0.0 and domain["max"][0] > 1.0  # walls: room beyond them
    assert "couplings" not in out and "ale" not in out["sections"]
    assert out["contacts"] == [{"type": "nodes_to_surface", "nodes": "tank_fill0", "surface": "plate",
                                "stiffness": "soft_constraint", "soft_scale": 0.3, "damping": 0.2}]
    Deck.model_validate(out)  # a valid deck


def test_ale_variant_and_bad_decks():
    data = _scene([])
    d = derive.ale_variant(data, 0.05)
    assert d.data["parts"]["tank"]["geometry"]["box"]["divisions"] == [20, 12]
    with pytest.raises(StudyError, match="square"):
        derive.ale_variant(data, 0.07)
    two = copy.deepcopy(data)
    two["parts"]["tank"]["geometry"]["box"]["divisions"] = [10, 3]
    with pytest.raises(StudyError, match="square elements"):
        derive.sph_variant(two, 1)
    with pytest.raises(StudyError, match="whole numbers"):
        derive.sph_variant(data, 1.5)


def test_mask_geometry_is_exact_for_any_mask():
    from sphfem_cli.sph import lattice

    rng = np.random.default_rng(7)
    for _ in range(20):
        mask = rng.random((9, 13)) < 0.5
        if not mask.any():
            continue
        geom = derive.mask_geometry(mask, -0.3, 0.2, 0.05)
        pts = lattice.polygon(geom["polygon"]["vertices"], 0.05) if "polygon" in geom else \
            lattice.box(geom["box"]["min"], geom["box"]["max"], 0.05)
        ij = {(int(round((x + 0.3) / 0.05 - 0.5)), int(round((y - 0.2) / 0.05 - 0.5))) for x, y in pts}
        assert ij == {(i, j) for j, i in zip(*np.nonzero(mask))}
    full = np.zeros((5, 6), dtype=bool)
    full[1:4, 2:5] = True
    assert derive.mask_geometry(full, 0.0, 0.0, 1.0) == {"box": {"min": [2.0, 1.0], "max": [5.0, 4.0]}}


def test_tiny_study_runs_resumes_and_reports(tmp_path):
    out = tmp_path / "study"
    config = StudyConfig(deck=TINY, ratios=(1, 2), workers=2, outdir=out, end_time=6e-4)
    _, result = run_study(config, echo=lambda s: None)
    names = sorted(p.name for p in (out / "cases").iterdir())
    assert names == ["ale_h0.05", "sph_r1", "sph_r2"]
    for name in names:
        status = json.loads((out / "cases" / name / "status.json").read_text())
        assert status["state"] == "done", status
        assert status["steps"] > 0 and status["wall_s"] > 0 and status["cpu_s"] > 0 and status["peak_mib"] > 10
        assert (out / "cases" / name / "run" / "histories" / "glstat.csv").exists()
    for f in ("report.csv", "report.json", "report.md", "error_vs_ratio.png", "pareto.png",
              "history_glstat.kinetic.png", "study.json"):
        assert (out / f).stat().st_size > 0, f
    rows = {r["case"]: r for r in result["cases"]}
    assert rows["sph_r1"]["particles"] == 30 and rows["sph_r2"]["particles"] == 120
    assert rows["ale_h0.05"]["reference"] and rows["ale_h0.05"]["errors"]["glstat.kinetic"]["l2"] == 0.0
    assert 0.0 < rows["sph_r2"]["errors"]["glstat.kinetic"]["l2"] < 1.0
    report = json.loads((out / "report.json").read_text())
    assert report["recommendation"] == result["recommendation"]

    before = {n: json.loads((out / "cases" / n / "status.json").read_text())["finished"] for n in names}
    lines = []
    run_study(config, echo=lines.append)
    assert sum("skipped" in line for line in lines) == 3
    after = {n: json.loads((out / "cases" / n / "status.json").read_text())["finished"] for n in names}
    assert after == before

    result = CliRunner().invoke(main, ["plot", str(out)])
    assert result.exit_code == 0, result.output
    assert (out / "plots" / "glstat.kinetic.png").exists()
    run = out / "cases" / "sph_r1" / "run"
    result = CliRunner().invoke(main, ["plot", str(run), "--quantity", "glstat.kinetic"])
    assert result.exit_code == 0, result.output
    assert (run / "plots" / "glstat.kinetic.png").exists()


def test_a_changed_deck_reruns_its_case(tmp_path):
    case = tmp_path / "c"
    case.mkdir()
    (case / "deck.yaml").write_text("a: 1\n")
    runner.write_status(case, {"state": "done", "deck_sha256": runner.deck_hash(case)})
    assert runner.is_done(case)
    (case / "deck.yaml").write_text("a: 2\n")
    assert not runner.is_done(case)


def test_mesh_study_command_reports_a_deck_without_ale(tmp_path):
    result = CliRunner().invoke(main, ["mesh-study", str(HERE.parent.parent / "decks" / "dam_break_2d.yaml"),
                                       "-o", str(tmp_path / "s")])
    assert result.exit_code == 65
    assert "exactly one ALE part" in result.output


def test_dask_executor_on_a_local_cluster(tmp_path):
    distributed = pytest.importorskip("distributed")
    with distributed.LocalCluster(n_workers=1, threads_per_worker=2, processes=False,
                                  dashboard_address=None) as cluster, distributed.Client(cluster) as client:
        out = tmp_path / "study"
        config = StudyConfig(deck=TINY, ratios=(1,), scheduler=client, outdir=out, end_time=3e-4)
        _, result = run_study(config, echo=lambda s: None)
    states = {r["case"]: r["state"] for r in result["cases"]}
    assert states == {"ale_h0.05": "done", "sph_r1": "done"}
    status = json.loads((out / "cases" / "sph_r1" / "status.json").read_text())
    assert status["pid"] != __import__("os").getpid()  # ran in its own process
    assert (out / "report.md").exists()
