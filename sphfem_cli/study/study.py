"""The mesh study: derive the cases, run what is not finished, measure, and report.

Folder layout (``-o DIR``, default ``<deck stem>_study``)::

    study.json                     the settings and the case list
    cases/ale_h<size>/             deck.yaml, status.json, case.log, run/ (the run's output, histories/ in it)
    cases/sph_r<ratio>/            likewise for each SPH ratio (and the --verify case)
    report.csv, report.json, report.md, *.png
"""
from __future__ import annotations

import json
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable, Sequence

import yaml

from . import derive, runner


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
    ale_sizes: Sequence[float] | None = None  # None: h, h/2, h/4 where the scene allows; (): the deck's h only
    threads: int = 1
    end_time: float | None = None
    verify: bool = False
    # low-pass filters of the compared quantities (output.filters.low_pass settings), by quantity name,
    # "*" for every quantity; None or {}: raw samples (docs/mesh-study.md, "Filtered quantities")
    filters: dict[str, dict] | None = None


@dataclass
class Case:
    name: str
    kind: str  # sph | ale
    size: float  # particle spacing or ALE element size
    ratio: float  # ALE element size (of the deck) / size
    dir: Path
    notes: list[str] = field(default_factory=list)
    status: dict = field(default_factory=dict)
    role: str = "study"  # study | verify (run by --verify: not in the fits)

    @property
    def histories(self) -> Path:
        return self.dir / runner.RUN / "histories"

    @property
    def count(self) -> int:
        return int(self.status.get("particles" if self.kind == "sph" else "ale_elements") or 0)


@dataclass
class Plan:
    out: Path
    cases: list[Case]
    data: dict  # the deck's data (with --end-time applied)
    element_size: float
    notes: list[str] = field(default_factory=list)  # what the plan left out, and why


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


def ale_sizes(config: StudyConfig, data: dict, h: float) -> tuple[list[float], list[str]]:
    """The ALE element sizes to run, finest last, and notes on the refinements the scene refuses.

    Default: h, h/2 and h/4 (h the deck's own), each where the scene allows it: square elements on
    the ALE box, and a model that fits in the memory available now (model.build.check_memory)."""
    from ..model.build import ModelError, check_memory

    if config.ale_sizes is not None:
        return sorted({h, *(float(s) for s in config.ale_sizes)}, reverse=True), []
    sizes, notes = [h], []
    for k in (2, 4):
        try:
            check_memory(derive.validated(derive.ale_variant(data, h / k).data))
            sizes.append(h / k)
        except (derive.StudyError, ModelError) as err:
            notes.append(f"ALE size h/{k} = {_fmt(h / k)} left out: {getattr(err, 'message', err)}")
            break
    return sizes, notes


def _write_case(out: Path, deck_path: Path, name: str, kind: str, size: float, h: float, d: derive.Derived,
                role: str = "study") -> Case:
    derive.validated(d.data)
    case_dir = out / "cases" / name
    case_dir.mkdir(parents=True, exist_ok=True)
    text = (f"# {name}: derived by sphfem mesh-study from {deck_path.resolve()}\n"
            + "".join(f"# {n}\n" for n in d.notes)
            + yaml.safe_dump(d.data, sort_keys=False, default_flow_style=None))
    deck_file = case_dir / runner.DECK
    if not deck_file.exists() or deck_file.read_text() != text:
        deck_file.write_text(text)
    return Case(name, kind, size, h / size, case_dir, d.notes, runner.read_status(case_dir), role)


def sph_case(plan: Plan, deck_path: Path, ratio: int, role: str = "study") -> Case:
    d = derive.sph_variant(plan.data, ratio)
    return _write_case(plan.out, deck_path, f"sph_r{ratio}", "sph", d.spacing, plan.element_size, d, role)


def plan(config: StudyConfig) -> Plan:
    """Write every case's deck (untouched when unchanged) and return the plan."""
    deck_path = Path(config.deck)
    out = Path(config.outdir) if config.outdir else Path.cwd() / f"{deck_path.stem}_study"
    data = load_deck_data(deck_path)
    if config.end_time is not None:
        data["control"]["end_time"] = float(config.end_time)
    info = derive.ale_info(derive.validated(data))
    h = info.element_size
    sizes, notes = ale_sizes(config, data, h)
    out.mkdir(parents=True, exist_ok=True)
    result = Plan(out, [], data, h, notes)
    for s in sizes:
        d = derive.Derived(data) if s == h else derive.ale_variant(data, s)
        actual = h if s == h else float(
            ((info.hi - info.lo) / d.data["parts"][info.name]["geometry"]["box"]["divisions"]).mean())
        result.cases.append(_write_case(out, deck_path, f"ale_h{_fmt(actual)}", "ale", actual, h, d))
    for r in sorted({int(r) for r in config.ratios}):
        result.cases.append(sph_case(result, deck_path, r))
    units = data.get("units") or {}
    (out / "study.json").write_text(json.dumps({
        "deck": str(deck_path.resolve()), "ale_element_size": h, "ratios": sorted({int(r) for r in config.ratios}),
        "ale_sizes": sizes, "reference": str(config.reference), "tolerance": config.tolerance,
        "end_time": data["control"]["end_time"], "units": units, "dimension": data.get("dimension", 2),
        "notes": notes, "filters": dict(config.filters or {}),
        "cases": [{"name": c.name, "kind": c.kind, "size": c.size, "ratio": c.ratio} for c in result.cases],
    }, indent=2) + "\n")
    return result


def run_cases(cases: Sequence[Case], config: StudyConfig, echo: Callable[[str], None] = print) -> None:
    """Run the cases not finished yet (local processes or Dask) and refresh every case's status."""
    pending = [c for c in cases if not runner.is_done(c.dir)]
    for c in cases:
        if c not in pending:
            echo(f"  {c.name}: done before, skipped")
    by_dir = {c.dir.resolve(): c for c in cases}

    def done(d: Path, status: dict) -> None:
        c = by_dir[Path(d).resolve()]
        extra = f" ({status.get('message')})" if status.get("state") != "done" else ""
        echo(f"  {c.name}: {status.get('state')}, cpu {status.get('cpu_s') or float('nan'):.2f} s "
             f"(compile {status.get('compile_s') or 0.0:.1f} s apart){extra}")

    dirs = [c.dir for c in pending]
    if config.scheduler is not None:
        runner.run_dask(dirs, config.scheduler, config.threads, on_done=done)
    else:
        runner.run_local(dirs, config.workers, config.threads, on_done=done)
    for c in cases:
        c.status = runner.read_status(c.dir)


def run_study(config: StudyConfig, echo: Callable[[str], None] = print) -> tuple[Path, dict]:
    """Plan, run, evaluate (and with ``verify`` run the recommended case and evaluate again), and
    write the report files and plots; returns (folder, results)."""
    from . import evaluate, plots, report

    p = plan(config)
    echo(f"mesh study in {p.out}: {len(p.cases)} cases")
    for note in p.notes:
        echo(f"  {note}")
    run_cases(p.cases, config, echo)
    result = evaluate.evaluate(config, p)
    rec = result["recommendation"]
    if config.verify:
        ratio = rec.get("ratio")
        if ratio is None or rec["verdict"] not in ("met", "predicted"):
            rec["verify_note"] = f"--verify: nothing run (verdict: {rec['verdict']})"
        elif not any(c.kind == "sph" and abs(c.ratio - ratio) < 1e-6 for c in p.cases):
            case = sph_case(p, Path(config.deck), int(ratio), role="verify")
            p.cases.append(case)
            echo(f"  verifying the recommendation: {case.name}")
            run_cases([case], config, echo)
            result = evaluate.evaluate(config, p)
    report.write_all(p.out, result)
    plots.study_plots(p.out, result, p.cases)
    return p.out, result
