"""Mesh study on tiny scenes: deck derivation (particles at element sub-centres, fills, boundaries,
couplings), cases and resume, report files, the plot command, and the Dask executor."""
from __future__ import annotations

import copy
import json
import os
import signal
import threading
import time
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
                                "stiffness": "soft_constraint", "soft_scale": 0.1, "damping": 0.2}]  # pfac 0.3 is not a soft_scale
    Deck.model_validate(out)  # a valid deck


def test_non_reflecting_sides_stay_non_reflecting():
    """An ALE non_reflecting side (with its source) becomes the SPH non-reflecting side, not a domain end."""
    bcs = [{"type": "ale_boundary", "part": "tank", "sides": ["left", "right", "bottom"],
            "condition": "non_reflecting", "source": [0.5, 0.3]},
           {"type": "ale_boundary", "part": "tank", "sides": ["top"], "condition": "slip"}]
    data = _scene([{"material": "gas", "box": {"min": [0.0, 0.0], "max": [0.3, 0.3]}}], bcs)
    out = derive.sph_variant(data, 1).data
    walls = {w["condition"]: w for w in out["boundaries"] if w["type"] == "wall"}
    assert walls["non_reflecting"]["sides"] == ["left", "right", "bottom"]
    assert walls["non_reflecting"]["source"] == [0.5, 0.3]
    assert walls["non_reflecting"]["min"] == [0.0, 0.0] and walls["non_reflecting"]["max"] == [1.0, 0.6]
    assert walls["slip"]["sides"] == ["top"]
    assert "domain" not in out["sections"]["sph"]  # no transmit side: nothing deletes particles
    Deck.model_validate(out)


def test_transmit_beside_non_reflecting_sides():
    """With a transmit side the section gets a domain; beyond the non_reflecting sides, which move with the
    water and delete nothing, it leaves the tank's own extent (1.0 x 0.6 here), beyond walls 3 spacings
    (0.1 m at ratio 1)."""
    bcs = [{"type": "ale_boundary", "part": "tank", "sides": ["left", "bottom"], "condition": "non_reflecting"},
           {"type": "ale_boundary", "part": "tank", "sides": ["right"], "condition": "slip"},
           {"type": "ale_boundary", "part": "tank", "sides": ["top"], "condition": "transmit"}]
    data = _scene([{"material": "gas", "box": {"min": [0.0, 0.0], "max": [0.3, 0.3]}}], bcs)
    out = derive.sph_variant(data, 1).data
    domain = out["sections"]["sph"]["domain"]
    assert domain["min"] == pytest.approx([-1.0, -0.6])  # the non_reflecting left and bottom
    assert domain["max"][1] == pytest.approx(0.6)  # transmit top
    assert domain["max"][0] == pytest.approx(1.3)  # slip right: 3 spacings of 0.1 m
    Deck.model_validate(out)


def test_ale_variant_and_bad_decks():
    data = _scene([])
    d = derive.ale_variant(data, 0.05)
    assert d.data["parts"]["tank"]["geometry"]["box"]["divisions"] == [20, 12]
    with pytest.raises(StudyError, match="square"):
        derive.ale_variant(data, 0.07)
    # the coupling points follow the fluid mesh (2 per segment at h -> 4 at h/2, 5 at most)
    coupled = _scene([], couplings=[{"type": "lagrange_in_solid", "structure": "plate", "fluid": "tank"}], solid=True)
    h = derive.ale_info(derive.validated(coupled)).element_size
    half, quarter = derive.ale_variant(coupled, h / 2), derive.ale_variant(coupled, h / 4)
    assert half.data["couplings"][0]["nquad"] == 4 and quarter.data["couplings"][0]["nquad"] == 5
    assert any("capped at 5" in n for n in quarter.notes)
    # the penalty's layer L_c / h = n / pfac, n = h nquad / l_segment (docs/theory/coupling.md): the same
    # fraction of h at h/2, smaller (stiffer, never softer) where nquad is capped
    layer = {r: (1.0 / r) * v.data["couplings"][0]["nquad"] / derive.NQUAD_DEFAULT for r, v in ((2, half), (4, quarter))}
    assert layer[2] == pytest.approx(1.0) and layer[4] == pytest.approx(0.625)
    assert "nquad" not in coupled["couplings"][0]  # the input is not changed
    assert "nquad" not in derive.ale_variant(coupled, h).data["couplings"][0]
    Deck.model_validate(quarter.data)
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


def assert_interface(report: dict) -> None:
    """The report.json keys scripts and checks rely on (issue 12)."""
    ref = report["reference"]
    assert {"case", "sizes", "uncertainty"} <= set(ref)
    for u in ref["uncertainty"].values():
        assert {"gci", "extrapolated"} <= set(u)
    for c in report["cases"]:
        assert {"name", "method", "cpu_s", "compile_s", "peak_mib", "steps", "errors"} <= set(c)
        assert c["method"] in ("sph", "ale") and ("ratio" in c or "size" in c)
        for e in c["errors"].values():
            assert {"l2", "peak"} <= set(e)
    assert {"form", "floor", "order"} <= set(report["model"]["error"])
    assert {"form", "coefficients"} <= set(report["model"]["cost"])
    rec = report["recommendation"]
    assert {"tolerance", "ratio", "verdict", "predicted", "verified"} <= set(rec)
    assert rec["ratio"] is None or isinstance(rec["ratio"], int)
    if rec["predicted"] is not None:
        assert {"error", "cpu_s"} <= set(rec["predicted"])
    if rec["verified"] is not None:
        assert {"error", "cpu_s"} <= set(rec["verified"]["measured"])
        assert {"error", "cpu_s"} <= set(rec["verified"]["prediction_error"])


def test_tiny_study_runs_verifies_resumes_and_reports(tmp_path):
    out = tmp_path / "study"
    config = StudyConfig(deck=TINY, ratios=(1, 2), workers=2, outdir=out, end_time=6e-4, tolerance=0.065,
                         verify=True)
    _, result = run_study(config, echo=lambda s: None)
    names = sorted(p.name for p in (out / "cases").iterdir())
    # the ALE reference refined by default (h, h/2, h/4); the recommended ratio run by --verify
    assert names == ["ale_h0.0125", "ale_h0.025", "ale_h0.05", "sph_r1", "sph_r2", "sph_r3"]
    for name in names:
        status = json.loads((out / "cases" / name / "status.json").read_text())
        assert status["state"] == "done", status
        assert status["steps"] > 0 and status["cpu_s"] > 0 and status["peak_mib"] > 10
        assert status["compile_s"] >= 0 and len(status["cpu_runs"]) >= 1
        assert status["dt0"]["sph" if name.startswith("sph") else "ale"] > 0
        assert (out / "cases" / name / "run" / "histories" / "glstat.csv").exists()
    for f in ("report.csv", "report.json", "report.md", "error_vs_ratio.png", "pareto.png",
              "history_glstat.kinetic.png", "study.json"):
        assert (out / f).stat().st_size > 0, f
    rows = {r["case"]: r for r in result["cases"]}
    assert rows["sph_r1"]["particles"] == 30 and rows["sph_r2"]["particles"] == 120
    assert rows["ale_h0.0125"]["reference"] and rows["ale_h0.0125"]["errors"]["glstat.kinetic"]["l2"] == 0.0
    assert rows["sph_r3"]["role"] == "verify"
    ref = result["reference"]
    assert ref["case"] == "ale_h0.0125" and ref["sizes"] == [0.0125, 0.025, 0.05]
    u = ref["uncertainty"]["glstat.kinetic"]
    assert u["gci"] > 0 and u["levels"] == ["ale_h0.0125", "ale_h0.025", "ale_h0.05"]
    rec = result["recommendation"]
    # two ratios: the power law, solved for the tolerance and rounded up to a whole ratio
    assert result["model"]["error"]["form"] == "power"
    m = result["model"]["error"]
    r_star = (m["c"] / 0.065) ** (1 / m["order"])
    assert rec["ratio"] == int(np.ceil(r_star)) == 3 and rec["verdict"] == "predicted"
    v = rec["verified"]
    assert v["case"] == "sph_r3" and not v["in_fit"]
    assert v["measured"]["error"] == pytest.approx(rows["sph_r3"]["worst_l2"])
    assert v["prediction_error"]["error"] == pytest.approx(
        (rec["predicted"]["error"] - v["measured"]["error"]) / v["measured"]["error"])
    assert v["prediction_error"]["cpu_s"] == pytest.approx(
        (rec["predicted"]["cpu_s"] - v["measured"]["cpu_s"]) / v["measured"]["cpu_s"])
    assert rec["predicted"]["particles"] == 270  # derived exactly
    report = json.loads((out / "report.json").read_text())
    assert_interface(report)
    assert report["recommendation"]["text"] == rec["text"]
    md = (out / "report.md").read_text()
    assert "## Reference uncertainty" in md and "verified by sph_r3" in md and "monotone" in md

    before = {n: json.loads((out / "cases" / n / "status.json").read_text())["finished"] for n in names}
    lines = []
    run_study(config, echo=lines.append)
    assert sum("skipped" in line for line in lines) == 6
    after = {n: json.loads((out / "cases" / n / "status.json").read_text())["finished"] for n in names}
    assert after == before

    result = CliRunner().invoke(main, ["plot", str(out)])
    assert result.exit_code == 0, result.output
    assert (out / "plots" / "glstat.kinetic.png").exists()
    run = out / "cases" / "sph_r1" / "run"
    result = CliRunner().invoke(main, ["plot", str(run), "--quantity", "glstat.kinetic"])
    assert result.exit_code == 0, result.output
    assert (run / "plots" / "glstat.kinetic.png").exists()
    result = CliRunner().invoke(main, ["plot", str(run)])
    assert result.exit_code == 0, result.output
    assert (run / "plots" / "glstat.png").exists()


def test_a_killed_case_fails_alone_and_a_failed_reference_still_reports(tmp_path):
    """Killing the reference's process (the first queued) fails that case only: the two queued
    behind it run, and the report says why there are no errors, in every format."""
    out = tmp_path / "study"
    config = StudyConfig(deck=TINY, ratios=(1, 2), workers=1, outdir=out, end_time=2e-3, ale_sizes=())
    status_file = out / "cases" / "ale_h0.05" / "status.json"
    killed = []

    def kill_when_running():
        deadline = time.monotonic() + 120
        while time.monotonic() < deadline:
            try:
                status = json.loads(status_file.read_text())
            except (OSError, ValueError):
                status = {}
            if status.get("state") == "running":
                os.kill(status["pid"], signal.SIGKILL)
                killed.append(status["pid"])
                return
            time.sleep(0.005)

    watcher = threading.Thread(target=kill_when_running)
    watcher.start()
    _, result = run_study(config, echo=lambda s: None)
    watcher.join()
    assert killed
    states = {r["case"]: r["state"] for r in result["cases"]}
    assert states == {"ale_h0.05": "failed", "sph_r1": "done", "sph_r2": "done"}
    message = next(r["message"] for r in result["cases"] if r["case"] == "ale_h0.05")
    assert "killed by SIGKILL" in message
    rec = result["recommendation"]
    assert rec["verdict"].startswith("failed: no finished ALE case") and rec["ratio"] is None
    assert "killed by SIGKILL" in rec["text"]
    assert "killed by SIGKILL" in (out / "report.md").read_text()
    assert "killed by SIGKILL" in (out / "report.csv").read_text()
    assert "killed by SIGKILL" in json.loads((out / "report.json").read_text())["cases"][0]["message"]
    assert result["reference"]["failed"][0]["case"] == "ale_h0.05"


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
        config = StudyConfig(deck=TINY, ratios=(1,), scheduler=client, outdir=out, end_time=3e-4, ale_sizes=())
        _, result = run_study(config, echo=lambda s: None)
    states = {r["case"]: r["state"] for r in result["cases"]}
    assert states == {"ale_h0.05": "done", "sph_r1": "done"}
    status = json.loads((out / "cases" / "sph_r1" / "status.json").read_text())
    assert status["pid"] != __import__("os").getpid()  # ran in its own process
    assert (out / "report.md").exists()


def test_ale_sizes_default_to_h_h2_h4_where_the_scene_allows(monkeypatch):
    from sphfem_cli.cli import _ale_sizes
    from sphfem_cli.model import build
    from sphfem_cli.study.study import ale_sizes

    data = load_deck_data(TINY)
    assert ale_sizes(StudyConfig(deck=TINY), data, 0.05) == ([0.05, 0.025, 0.0125], [])
    assert ale_sizes(StudyConfig(deck=TINY, ale_sizes=()), data, 0.05) == ([0.05], [])
    assert ale_sizes(StudyConfig(deck=TINY, ale_sizes=(0.1,)), data, 0.05) == ([0.1, 0.05], [])
    monkeypatch.setattr(build, "available_memory", lambda: 100_000)  # bytes: h/2 does not fit
    sizes, notes = ale_sizes(StudyConfig(deck=TINY), data, 0.05)
    assert sizes == [0.05] and "h/2 = 0.025 left out" in notes[0] and "GiB" in notes[0]
    assert _ale_sizes(None, None, "default") is None and _ale_sizes(None, None, "none") == ()
    assert _ale_sizes(None, None, "0.02,0.01") == (0.02, 0.01)


@pytest.mark.validation
def test_a_case_on_an_empty_numba_cache_keeps_the_compile_apart(tmp_path):
    """On an empty numba cache the warm-up compiles (compile_s > 0), the case process re-executes
    and loads the kernels from the cache it filled, so the timed runs neither compile nor carry
    the compiler's memory: the peak is the warm run's (CPU times: benchmarks/study_cold_cache.py)."""
    import subprocess
    import sys

    import yaml

    data = yaml.safe_load(TINY.read_text())
    data["control"]["end_time"] = 6e-4
    statuses = []
    cache = tmp_path / "numba"
    for name in ("cold", "warm"):
        case = tmp_path / name
        case.mkdir()
        (case / "deck.yaml").write_text(yaml.safe_dump(data))
        env = dict(os.environ, NUMBA_CACHE_DIR=str(cache))
        subprocess.run([sys.executable, "-m", "sphfem_cli.study", str(case)], env=env, check=True)
        statuses.append(json.loads((case / "status.json").read_text()))
    cold, warm = statuses
    assert cold["state"] == warm["state"] == "done"
    assert cold["compile_s"] > 0 and cold["reexecuted"] and cold["compile_in_run_s"] == 0.0
    assert warm["compile_s"] == 0.0 and "reexecuted" not in warm
    assert cold["peak_mib"] == pytest.approx(warm["peak_mib"], rel=0.05)
