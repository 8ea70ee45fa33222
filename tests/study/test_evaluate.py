"""Study evaluation on manufactured case folders (no runs): the reference when the finest ALE level
failed, its GCI band and which errors lie below it, driven histories left out of the defaults, and
the recommendation's verdicts (met, predicted, extrapolated, not reachable: floor)."""
from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from sphfem_cli.study import StudyError, evaluate, report, runner
from sphfem_cli.study.study import Case, Plan, StudyConfig, load_deck_data

HERE = Path(__file__).parent
TINY = HERE / "tiny_ale.yaml"
DECKS = HERE.parents[1] / "decks"
T = np.linspace(0.0, 1e-3, 201)


def _case(root: Path, name: str, kind: str, size: float, amplitude: float | None, count: int, cpu: float,
          steps: int, message: str | None = None, noise: float = 0.0) -> Case:
    d = root / "cases" / name
    (d / "run" / "histories").mkdir(parents=True)
    (d / runner.DECK).write_text(f"# {name}\n")
    status = {"state": "failed", "message": message} if amplitude is None else {
        "state": "done", "cpu_s": cpu, "cpu_runs": [cpu], "cpu_spread": 0.0, "compile_s": 0.0, "peak_mib": 170 + count / 1e3,
        "steps": steps, "particles": count if kind == "sph" else 0, "ale_elements": count if kind == "ale" else 0,
        "dt0": {"solid": 1e-6, kind: 1e-6 * size / 0.05}}
    if amplitude is not None:
        # noise: a sample-to-sample alternation (the Nyquist frequency), as a ringing contact's samples,
        # under the same half-sine envelope (zero at both ends, as a contact force before contact)
        shape = np.sin(np.pi * T / 1e-3)
        rows = np.stack([T, (amplitude + noise * (-1.0) ** np.arange(T.size)) * shape], axis=1)
        np.savetxt(d / "run" / "histories" / "probe.csv", rows, delimiter=",", header="time,height", comments="")
    status["deck_sha256"] = runner.deck_hash(d)
    runner.write_status(d, status)
    return Case(name, kind, size, 0.05 / size, d, status=runner.read_status(d))


def _ale_peak(h: float) -> float:
    """ALE peaks converging with order 2; the finest (0.0125) is exactly 1."""
    return 1.0 + 0.4 * ((h / 0.05) ** 2 - 1.0 / 16.0)


def _plan(tmp_path: Path, sph_errors: dict[int, float], finest_fails: bool, message: str = "ALE blew up",
          sph_noise: float = 0.0) -> Plan:
    """ALE at 0.05, 0.025, 0.0125 (order 2, the finest exactly 1) and SPH ratios whose amplitude error
    against that finest level is the given one."""
    cases = []
    for h in (0.05, 0.025, 0.0125):
        amp = None if (finest_fails and h == 0.0125) else _ale_peak(h)
        cases.append(_case(tmp_path, f"ale_h{h:g}", "ale", h, amp, int(32 * (0.05 / h) ** 2), 0.1 * (0.05 / h) ** 3,
                           int(5 * 0.05 / h), message=message))
    for r, e in sph_errors.items():
        cases.append(_case(tmp_path, f"sph_r{r}", "sph", 0.05 / r, 1.0 + e, 30 * r * r, 0.05 + 1e-4 * 30 * r**3 * 8,
                           8 * r, noise=sph_noise))
    return Plan(tmp_path, cases, load_deck_data(TINY), 0.05)


def _config(tmp_path, tolerance):
    return StudyConfig(deck=TINY, tolerance=tolerance, outdir=tmp_path)


def test_failed_finest_reference_falls_back_and_says_so(tmp_path):
    plan = _plan(tmp_path, {1: 0.3, 2: 0.15, 3: 0.1}, finest_fails=True)
    result = evaluate.evaluate(_config(tmp_path, 0.2), plan)
    ref = result["reference"]
    assert ref["case"] == "ale_h0.025" and ref["failed"] == [{"case": "ale_h0.0125", "message": "ALE blew up"}]
    # two levels left: Fs 3 and order 1 assumed
    u = ref["uncertainty"]["probe.height"]
    assert u["method"].startswith("two levels")
    p1, p2 = _ale_peak(0.025), _ale_peak(0.05)
    assert u["gci"] == pytest.approx(3.0 * abs(p2 - p1) / p1 / (2.0 - 1.0), rel=1e-3)
    assert "ALE blew up" in result["recommendation"]["text"]
    report.write_all(tmp_path, result)
    assert "The finer reference ale_h0.0125 failed" in (tmp_path / "report.md").read_text()
    assert "ALE blew up" in (tmp_path / "report.csv").read_text()


def test_a_long_failure_message_is_one_line_in_the_recommendation(tmp_path):
    message = "guard: time_step\nmessage: time step 7.9e-11 fell below 1/1000 of the first step\n  dt: 7.9e-11\n" + "x" * 400
    plan = _plan(tmp_path, {1: 0.3, 2: 0.15, 3: 0.1}, finest_fails=True, message=message)
    rec = evaluate.evaluate(_config(tmp_path, 0.2), plan)["recommendation"]
    assert "\n" not in rec["text"] and "guard: time_step message: time step 7.9e-11 fell" in rec["text"]
    assert len(rec["text"]) < len(message)  # capped, with "..."
    assert rec["failures"][0]["message"] == message  # the full message is kept
    report.write_all(tmp_path, evaluate.evaluate(_config(tmp_path, 0.2), plan))
    lines = (tmp_path / "report.md").read_text().splitlines()
    bold = lines[lines.index("## Recommendation") + 2]
    assert bold.startswith("**") and bold.endswith("**")  # the bold recommendation is one line


def test_reference_gci_band_and_errors_below_it(tmp_path):
    plan = _plan(tmp_path, {1: 0.3, 2: 0.08, 3: 0.002}, finest_fails=False)
    result = evaluate.evaluate(_config(tmp_path, 0.05), plan)
    u = result["reference"]["uncertainty"]["probe.height"]
    phi = [_ale_peak(h) for h in (0.0125, 0.025, 0.05)]
    assert u["order"] == pytest.approx(2.0, rel=1e-6) and u["monotone"]
    assert u["extrapolated"] == pytest.approx(1.0 - 0.4 / 16.0, rel=1e-6)
    assert u["gci"] == pytest.approx(1.25 * abs(phi[0] - phi[1]) / phi[0] / 3.0, rel=1e-6)
    errors = {r["case"]: r["errors"]["probe.height"] for r in result["cases"]}
    # SPH at ratio 3 is 0.2 % off the finest ALE peak, less than its GCI (2.9 %): indistinguishable
    assert errors["sph_r3"]["below_reference_uncertainty"]["peak"] is True
    assert errors["sph_r1"]["below_reference_uncertainty"]["peak"] is False


def test_verdicts_never_leave_a_far_ratio_unqualified(tmp_path):
    e = {r: 0.4 * r**-0.5 for r in (1, 2, 3)}
    result = evaluate.evaluate(_config(tmp_path / "a", 0.05), _plan(tmp_path / "a", e, False))
    rec = result["recommendation"]
    # power law p = 0.5: ratio 64 for 5 %, beyond 3 x 3: extrapolated, with its prediction
    assert rec["ratio"] == 64 and rec["verdict"] == "extrapolated" and rec["text"].startswith("extrapolated:")
    assert rec["predicted"]["error"] == pytest.approx(0.05, rel=1e-6)
    e = {r: 0.17 + 0.3 * r**-1.5 for r in (1, 2, 3, 4)}
    result = evaluate.evaluate(_config(tmp_path / "b", 0.1), _plan(tmp_path / "b", e, False))
    rec = result["recommendation"]
    assert result["model"]["error"]["form"] == "floor"
    assert rec["ratio"] is None and rec["verdict"].startswith("not reachable: floor e_inf = 17")
    result = evaluate.evaluate(_config(tmp_path / "c", 0.19), _plan(tmp_path / "c", e, False))
    # (0.3 / (0.19 - 0.17))^(1 / 1.5) = 6.08, rounded up
    assert result["recommendation"]["verdict"] == "predicted" and result["recommendation"]["ratio"] == 7
    result = evaluate.evaluate(_config(tmp_path / "d", 0.25), _plan(tmp_path / "d", e, False))
    assert result["recommendation"]["verdict"] == "met" and result["recommendation"]["ratio"] == 3
    for case in json.loads(json.dumps(report._finite(result)))["cases"]:
        assert case["method"] in ("ale", "sph")


def test_driven_histories_are_no_default_quantities():
    driven = evaluate.driven_histories(DECKS / "structure_in_water_ale.yaml")
    assert set(driven) == {"bottom"}  # the plate's bottom nodes follow the prescribed drive; mid, clamp do not


def test_a_filtered_quantity_compares_the_low_passed_series_and_says_so(tmp_path):
    """Sample-to-sample noise (0.3 at the Nyquist frequency, 100 kHz) on SPH amplitudes 10 / 5 / 2 % high:
    raw, the noise sets every L2 (about 0.3 / 1 = 30 %, more than any amplitude error) and it does not
    fall with the ratio; a zero-phase Butterworth at 10 kHz (the signal is a 1 ms half sine, 0.5 kHz)
    removes it, and the L2 and peak errors are the amplitude errors again."""
    errors = {1: 0.10, 2: 0.05, 3: 0.02}
    raw = evaluate.evaluate(_config(tmp_path / "raw", 0.05), _plan(tmp_path / "raw", errors, False, sph_noise=0.3))
    cfg = _config(tmp_path / "bw", 0.05)
    cfg.filters = {"*": {"kind": "butterworth", "cutoff": 1e4, "order": 2}}
    plan = _plan(tmp_path / "bw", errors, False, sph_noise=0.3)
    result = evaluate.evaluate(cfg, plan)
    for r, e in errors.items():
        row_raw = next(c for c in raw["cases"] if c["case"] == f"sph_r{r}")["errors"]["probe.height"]
        row = next(c for c in result["cases"] if c["case"] == f"sph_r{r}")["errors"]["probe.height"]
        assert row_raw["l2"] > 0.3
        assert row["l2"] == pytest.approx(e, rel=0.01)
        assert row["peak"] == pytest.approx(e, abs=0.002)
    assert raw["filters"] == {"probe.height": None}
    f = result["filters"]["probe.height"]
    assert f["kind"] == "butterworth" and f["cutoff"] == 1e4 and "Butterworth" in f["description"]
    report.write_all(tmp_path / "bw", result)
    md = (tmp_path / "bw" / "report.md").read_text()
    assert "`probe.height` compared as: zero-phase Butterworth low-pass, order 2, -3 dB at 10000" in md
    assert json.loads((tmp_path / "bw" / "report.json").read_text())["filters"]["probe.height"]["cutoff"] == 1e4
    assert "Butterworth" in (tmp_path / "bw" / "report.csv").read_text().splitlines()[1]
    from sphfem_cli.study import plots

    assert (tmp_path / "bw" / "history_probe.height.png") in plots.study_plots(tmp_path / "bw", result, plan.cases)
    # a per-quantity entry wins over "*"; one that names no compared quantity is refused
    cfg.filters = {"*": {"kind": "butterworth", "cutoff": 1e4, "order": 2},
                   "probe.height": {"kind": "running_mean", "window": 1e-4}}
    assert evaluate.evaluate(cfg, plan)["filters"]["probe.height"]["kind"] == "running_mean"
    cfg.filters = {"probe.depth": {"kind": "running_mean", "window": 1e-4}}
    with pytest.raises(StudyError, match="probe.depth is no compared quantity"):
        evaluate.evaluate(cfg, plan)
    cfg.filters = {"*": {"kind": "butterworth", "cutoff": 2e5, "order": 2}}  # above the Nyquist 100 kHz
    with pytest.raises(StudyError, match="--filter probe.height: cutoff must lie below the Nyquist"):
        evaluate.evaluate(cfg, plan)


def test_mesh_study_filter_option_is_parsed_and_checked():
    from click.testing import CliRunner

    from sphfem_cli.cli import _study_filters, main

    assert _study_filters(("running_mean:0.001", "cyl.contact_force=butterworth:500:4")) == {
        "*": {"kind": "running_mean", "window": 0.001},
        "cyl.contact_force": {"kind": "butterworth", "cutoff": 500.0, "order": 4}}
    res = CliRunner().invoke(main, ["mesh-study", str(TINY), "--filter", "lowpass:3"])
    assert res.exit_code != 0 and "expected butterworth:CUTOFF[:ORDER]" in res.output
    res = CliRunner().invoke(main, ["mesh-study", str(TINY), "--filter", "running_mean:1", "--filter", "running_mean:2"])
    assert res.exit_code != 0 and "a second filter for every quantity" in res.output
