"""The mesh study: derive the cases, run what is not finished, measure, and report.

Folder layout (``-o DIR``, default ``<deck stem>_study``)::

    study.json                     the settings and the case list
    cases/ale_h<size>/             deck.yaml, status.json, run/ (the run's output, histories/ in it)
    cases/sph_r<ratio>/            likewise for each SPH ratio
    report.csv, report.json, report.md, *.png
"""
from __future__ import annotations

import json
import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable, Sequence

import yaml

from . import derive, metrics, runner


@dataclass
class StudyConfig:
    deck: Path
    ratios: Sequence[int] = (1, 2, 3)
    reference: str = "ale"  # ale | finest | PATH of a run folder
    quantities: Sequence[str] | None = None
    tolerance: float = 0.05
    workers: int = 1
    scheduler: object | None = None  # address or distributed.Client
    outdir: Path | None = None
    ale_sizes: Sequence[float] = ()
    threads: int = 1
    end_time: float | None = None


@dataclass
class Case:
    name: str
    kind: str  # sph | ale
    size: float  # particle spacing or ALE element size
    ratio: float  # ALE element size (of the deck) / size
    dir: Path
    notes: list[str] = field(default_factory=list)
    status: dict = field(default_factory=dict)

    @property
    def histories(self) -> Path:
        return self.dir / runner.RUN / "histories"

    @property
    def count(self) -> int:
        return int(self.status.get("particles" if self.kind == "sph" else "ale_elements") or 0)


def _fmt(v: float) -> str:
    return f"{v:.6g}"


def load_deck_data(path: Path) -> dict:
    """The deck's YAML data, validated with file:line:col errors (StudyError on a bad deck)."""
    from ..deck import loader
    from ..deck.errors import DeckError
    from ..deck.schema import Deck
    from ..deck.validate import validate_model

    try:
        data, positions = loader.load(str(path))
        validate_model(Deck, data, positions, str(path))
    except DeckError as err:
        raise derive.StudyError(str(err)) from None
    return derive.absolute_files(data, path.parent)


def plan(config: StudyConfig) -> tuple[Path, list[Case]]:
    """Write every case's deck (untouched when unchanged) and return the study folder and cases."""
    deck_path = Path(config.deck)
    out = Path(config.outdir) if config.outdir else Path.cwd() / f"{deck_path.stem}_study"
    data = load_deck_data(deck_path)
    if config.end_time is not None:
        data["control"]["end_time"] = float(config.end_time)
    info = derive.ale_info(derive.validated(data))
    h = info.element_size
    cases: list[tuple[str, str, float, derive.Derived]] = []
    sizes = sorted({h, *(float(s) for s in config.ale_sizes)}, reverse=True)
    for s in sizes:
        d = derive.Derived(data) if s == h else derive.ale_variant(data, s)
        actual = float(((info.hi - info.lo) / d.data["parts"][info.name]["geometry"]["box"]["divisions"]).mean()) \
            if s != h else h
        cases.append((f"ale_h{_fmt(actual)}", "ale", actual, d))
    for r in sorted({int(r) for r in config.ratios}):
        d = derive.sph_variant(data, r)
        cases.append((f"sph_r{r}", "sph", d.spacing, d))
    out.mkdir(parents=True, exist_ok=True)
    result = []
    for name, kind, size, d in cases:
        derive.validated(d.data)
        case_dir = out / "cases" / name
        case_dir.mkdir(parents=True, exist_ok=True)
        text = (f"# {name}: derived by sphfem mesh-study from {deck_path.resolve()}\n"
                + "".join(f"# {n}\n" for n in d.notes)
                + yaml.safe_dump(d.data, sort_keys=False, default_flow_style=None))
        deck_file = case_dir / runner.DECK
        if not deck_file.exists() or deck_file.read_text() != text:
            deck_file.write_text(text)
        result.append(Case(name, kind, size, h / size, case_dir, d.notes, runner.read_status(case_dir)))
    (out / "study.json").write_text(json.dumps({
        "deck": str(deck_path.resolve()), "ale_element_size": h, "ratios": sorted({int(r) for r in config.ratios}),
        "ale_sizes": sizes, "reference": str(config.reference), "tolerance": config.tolerance,
        "end_time": data["control"]["end_time"],
        "cases": [{"name": c.name, "kind": c.kind, "size": c.size, "ratio": c.ratio} for c in result],
    }, indent=2) + "\n")
    return out, result


def run_cases(cases: Sequence[Case], config: StudyConfig, echo: Callable[[str], None] = print) -> None:
    """Run the cases not finished yet (local pool or Dask) and refresh every case's status."""
    pending = [c for c in cases if not runner.is_done(c.dir)]
    for c in cases:
        if c not in pending:
            echo(f"  {c.name}: done before, skipped")
    by_dir = {c.dir.resolve(): c for c in cases}

    def done(d: Path, status: dict) -> None:
        c = by_dir[Path(d).resolve()]
        extra = f" ({status.get('message')})" if status.get("state") != "done" else ""
        echo(f"  {c.name}: {status.get('state')} in {status.get('wall_s', float('nan')):.1f} s{extra}")

    dirs = [c.dir for c in pending]
    if config.scheduler is not None:
        runner.run_dask(dirs, config.scheduler, config.threads, on_done=done)
    else:
        runner.run_local(dirs, config.workers, config.threads, on_done=done)
    for c in cases:
        c.status = runner.read_status(c.dir)


def reference_histories(config: StudyConfig, cases: Sequence[Case]) -> tuple[str, Path]:
    """(label, histories folder) of the reference."""
    ok = [c for c in cases if c.status.get("state") == "done"]
    if config.reference in ("ale", "finest"):  # the finest finished case of that kind
        kind, what = ("ale", "ALE") if config.reference == "ale" else ("sph", "finest")
        finished = [c for c in ok if c.kind == kind]
        if not finished:
            raise derive.StudyError(f"no {kind.upper()} case finished, so there is no {what} reference")
        best = min(finished, key=lambda c: c.size)
        return best.name, best.histories
    path = Path(config.reference)
    for candidate in (path / runner.RUN / "histories", path / "histories", path):
        if candidate.is_dir() and any(candidate.glob("*.csv")):
            return str(path), candidate
    raise derive.StudyError(f"--reference {path}: no history CSVs found there (give a run folder)")


def evaluate(config: StudyConfig, out: Path, cases: Sequence[Case]) -> dict:
    """Errors, convergence, cost model and recommendation, as one JSON-ready dict."""
    ref_label, ref_dir = reference_histories(config, cases)
    quantities = list(config.quantities or metrics.default_quantities(ref_dir))
    ref_series = {q: metrics.quantity_series(ref_dir, q) for q in quantities}
    rows = []
    for c in cases:
        row = {"case": c.name, "kind": c.kind, "size": c.size, "ratio": c.ratio, "count": c.count,
               "reference": c.histories.resolve() == ref_dir.resolve(), **{k: c.status.get(k) for k in (
                   "state", "wall_s", "cpu_s", "peak_mib", "steps", "particles", "ale_elements", "solid_elements",
                   "message")}, "errors": {}}
        if c.status.get("state") == "done":
            for q in quantities:
                try:
                    t, v = metrics.quantity_series(c.histories, q)
                except KeyError as err:
                    row["errors"][q] = {"missing": str(err)}
                    continue
                row["errors"][q] = metrics.history_error(t, v, *ref_series[q]).as_dict()
        rows.append(row)

    def series(kind: str) -> list[dict]:
        return sorted((r for r in rows if r["kind"] == kind and r["state"] == "done"), key=lambda r: r["size"])

    convergence = {}
    for kind in ("sph", "ale"):
        done = series(kind)
        if len(done) < 3:
            continue
        three = done[:3]
        convergence[kind] = {}
        for q in quantities:
            phis = [r["errors"].get(q, {}).get("peak_value") for r in three]
            if any(p is None or not math.isfinite(p) for p in phis):
                continue
            convergence[kind][q] = metrics.three_grid([r["size"] for r in three], phis).as_dict()
            convergence[kind][q]["cases"] = [r["case"] for r in three]

    sph = [r for r in series("sph") if not r["reference"]]
    worst = [max((e.get("l2", float("nan")) for e in r["errors"].values() if "l2" in e), default=float("nan"))
             for r in sph]
    prediction = metrics.predict([r["ratio"] for r in sph], worst, [r["count"] for r in sph],
                                 [r["wall_s"] for r in sph], config.tolerance)
    ale_cost = [r["wall_s"] for r in series("ale")]
    result = {
        "deck": str(Path(config.deck).resolve()), "reference": ref_label, "quantities": quantities,
        "tolerance": config.tolerance, "cases": rows, "convergence": convergence,
        "prediction": prediction.as_dict(), "worst_l2": dict(zip([r["case"] for r in sph], worst)),
    }
    result["recommendation"] = recommend(prediction, sph, worst, ale_cost, ref_label, config.tolerance)
    return result


def recommend(pred: metrics.Prediction, sph: list[dict], worst: list[float], ale_cost: list[float],
              ref_label: str, tolerance: float) -> str:
    """One line: which ratio to use, at what cost."""
    tol = f"{100 * tolerance:g} %"
    ale = f"; the ALE reference took {ale_cost[0]:.1f} s" if ale_cost else ""
    if not sph:
        return "no SPH case finished: nothing to recommend"
    if pred.met_by is not None:
        r = next(x for x in sph if x["ratio"] == pred.met_by)
        return (f"use ratio {pred.met_by:g}: worst L2 error {100 * worst[sph.index(r)]:.2f} % <= {tol} against "
                f"{ref_label} with {r['count']} particles in {r['wall_s']:.1f} s{ale}")
    if pred.ratio is not None and pred.wall is not None:
        return (f"no tested ratio reaches {tol} against {ref_label} (best {100 * min(worst):.2f} %); the fits predict "
                f"ratio {pred.ratio:.2f} ({pred.particles:.3g} particles, about {pred.wall:.3g} s){ale}")
    return (f"no tested ratio reaches {tol} against {ref_label} (best {100 * min(worst):.2f} %) and the error does "
            f"not fall with the ratio: refining the particles alone will not get there{ale}")


def run_study(config: StudyConfig, echo: Callable[[str], None] = print) -> tuple[Path, dict]:
    """Plan, run, evaluate, and write the report files and plots; returns (folder, results)."""
    from . import plots, report

    out, cases = plan(config)
    echo(f"mesh study in {out}: {len(cases)} cases")
    run_cases(cases, config, echo)
    result = evaluate(config, out, cases)
    report.write_all(out, result)
    plots.study_plots(out, result, cases)
    return out, result
