"""PNG plots (matplotlib, Agg backend): the study's error, error-against-cost and history plots, and
``sphfem plot`` of a study folder (a run folder's plots are ``output.plots``). Every plot has a title and units on both axes (the deck's ``units:``, see ``units``)."""
from __future__ import annotations

import json
import math
import re
from pathlib import Path
from typing import Sequence

import numpy as np

from . import metrics
from .units import label


def _pyplot():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def _safe(name: str) -> str:
    return re.sub(r"[^A-Za-z0-9_.-]", "_", name)


def _ok(v) -> bool:
    return isinstance(v, (int, float)) and math.isfinite(v) and v > 0


def _save(fig, path: Path, plt) -> Path:
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path


def error_plot(out: Path, result: dict) -> Path:
    plt = _pyplot()
    done = [r for r in result["cases"] if r.get("state") == "done" and r["kind"] == "sph" and not r["reference"]]
    study = sorted((r for r in done if r["role"] == "study"), key=lambda r: r["ratio"])
    fig, ax = plt.subplots(figsize=(7.0, 4.6))
    colours = {}
    for q in result["quantities"]:
        pts = [(r["ratio"], r["errors"].get(q, {}).get("l2")) for r in study]
        pts = [(x, y) for x, y in pts if _ok(y)]
        if pts:
            colours[q] = ax.loglog(*zip(*pts), "o-", lw=1, label=q)[0].get_color()
    m, rec = result["model"]["error"], result["recommendation"]
    per_q = result["model"].get("error_per_quantity") or {}
    if m.get("form") and study and per_q:
        hi = max(3 * study[-1]["ratio"], rec.get("ratio") or 0)
        r = np.geomspace(1.0, hi, 200)
        # a quantity whose error does not fall counts as its largest error (models.WorstError)
        models = {q: pq["floor"] + pq["c"] * r ** -pq["order"] if pq["falls"] else np.full_like(r, pq["largest"])
                  for q, pq in per_q.items()}
        for q, e in models.items():
            ax.loglog(r, e, ":", lw=0.8, color=colours.get(q, "grey"))
        ax.loglog(r, np.max(list(models.values()), axis=0), "k--", lw=1,
                  label="model of the worst L2: the largest of the per-quantity models (dotted)")
        ax.axvline(3 * study[-1]["ratio"], color="tab:red", ls=":", lw=1, label="3x the largest tested ratio")
    ax.axhline(result["tolerance"], color="grey", ls="--", lw=1, label=f"tolerance {100 * result['tolerance']:g} %")
    for r in done:
        if r["role"] == "verify" and _ok(r.get("worst_l2")):
            ax.loglog([r["ratio"]], [r["worst_l2"]], "k*", ms=11, label=f"{r['case']} (verification, measured)")
    p = rec.get("predicted")
    if rec.get("ratio") and p and _ok(p.get("error")):
        ax.loglog([rec["ratio"]], [p["error"]], "kx", ms=9, label=f"ratio {rec['ratio']}: the model's prediction ({rec['verdict']})")
    ax.set_xlabel("ratio: ALE element size / particle spacing [-]")
    ax.set_ylabel("normalised L2 error [-]")
    ax.set_title(f"SPH error against {result['reference']['label']}")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7)
    return _save(fig, out / "error_vs_ratio.png", plt)


def _front(points: list[tuple[float, float]]) -> list[tuple[float, float]]:
    """The non-dominated points (less cost, less error), by cost."""
    front, best = [], math.inf
    for x, y in sorted(points):
        if y < best:
            front.append((x, y))
            best = y
    return front


def pareto_plot(out: Path, result: dict) -> Path:
    plt = _pyplot()
    fig, ax = plt.subplots(figsize=(7.0, 4.6))
    every = []
    for kind, marker in (("sph", "o"), ("ale", "s")):
        rows = sorted((r for r in result["cases"] if r["kind"] == kind and r.get("state") == "done"
                       and not r["reference"] and _ok(r.get("cpu_s")) and _ok(r.get("worst_l2"))),
                      key=lambda r: r["cpu_s"])
        study = [r for r in rows if r["role"] == "study"]
        if study:
            ax.loglog([r["cpu_s"] for r in study], [r["worst_l2"] for r in study], marker + "-",
                      label=f"{kind.upper()} {'ratios' if kind == 'sph' else 'sizes'}")
        for r in rows:
            if r["role"] == "verify":
                ax.loglog([r["cpu_s"]], [r["worst_l2"]], "k*", ms=11, label=f"{r['case']} (verification)")
            ax.annotate(r["case"], (r["cpu_s"], r["worst_l2"]), fontsize=7, xytext=(3, 3), textcoords="offset points")
            every.append((r["cpu_s"], r["worst_l2"]))
    ref = next((r for r in result["cases"] if r["reference"]), None)
    bands = [u["l2"] for u in result["reference"]["uncertainty"].values() if _ok(u.get("l2"))]
    if ref and _ok(ref.get("cpu_s")) and bands:
        ax.loglog([ref["cpu_s"]], [max(bands)], "kD", label=f"reference {ref['case']} at its own L2 uncertainty")
        every.append((ref["cpu_s"], max(bands)))
    elif ref and _ok(ref.get("cpu_s")):
        ax.axvline(ref["cpu_s"], color="k", ls=":", lw=1, label=f"reference {ref['case']} cost")
    front = _front(every)
    if len(front) > 1:
        ax.step(*zip(*front), where="post", color="grey", lw=3, alpha=0.35, label="front (nothing cheaper is better)")
    ax.axhline(result["tolerance"], color="grey", ls="--", lw=1, label=f"tolerance {100 * result['tolerance']:g} %")
    ax.set_xlabel("CPU time, compilation excluded [s]")
    ax.set_ylabel("worst normalised L2 error [-]")
    ax.set_title(f"Error against cost: SPH ratios and ALE sizes (vs {result['reference']['label']})")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7)
    return _save(fig, out / "pareto.png", plt)


def study_plots(out: Path, result: dict, cases) -> list[Path]:
    """error_vs_ratio.png, pareto.png and history_<quantity>.png in ``out``."""
    written = [error_plot(out, result), pareto_plot(out, result)]
    done = [c for c in cases if c.status.get("state") == "done"]
    for q in result["quantities"]:
        written.append(overlay(q, [(c.name, c.histories) for c in done], out / f"history_{_safe(q)}.png",
                               reference=result["reference"]["label"], units=result.get("units"),
                               dimension=result.get("dimension", 2),
                               settings=(result.get("filters") or {}).get(q)))
    return written


def overlay(quantity: str, runs: Sequence[tuple[str, Path]], path: Path, reference: str | None = None,
            units: dict | None = None, dimension: int = 2, settings: dict | None = None) -> Path:
    """One quantity's history from several runs on one plot; with ``settings`` (a study filter,
    output.filters.low_pass keywords and its description) the low-passed series the study compares."""
    plt = _pyplot()
    fig, ax = plt.subplots(figsize=(7.0, 4.4))
    drawn = 0
    for name, histories in runs:
        try:
            t, v = metrics.compared_series(histories, quantity, _settings(settings))
        except KeyError:
            continue
        ref = name == reference
        ax.plot(t, v, "k-" if ref else "-", lw=2.0 if ref else 1.2, label=name + (" (ref)" if ref else ""))
        drawn += 1
    ax.set_xlabel(label("time", units, dimension))
    ax.set_ylabel(label(quantity, units, dimension))
    ax.set_title(f"{quantity} history" + (f": {drawn} runs" if drawn != 1 else "")
                 + (f", reference {reference} in black" if reference and drawn > 1 else "")
                 + (f"\ncompared as: {settings.get('description')}" if settings else ""), **({"fontsize": 9} if settings else {}))
    ax.grid(True, alpha=0.3)
    if drawn:
        ax.legend(fontsize=8)
    return _save(fig, path, plt)


def _settings(settings: dict | None) -> dict | None:
    """A study filter as output.filters.low_pass keywords (its description left out)."""
    return None if not settings else {k: v for k, v in settings.items() if k != "description"}


def plot_dir(directory: Path, quantities: Sequence[str] = (), outdir: Path | None = None,
             reference_files: Sequence[Path] = (), warn=lambda line: None) -> list[Path]:
    """``sphfem plot``: a study folder gives one overlay per quantity across its cases; a run folder
    (or its histories/) goes to ``output.plots.plot_run``."""
    directory = Path(directory)
    study = directory / "study.json"
    written: list[Path] = []
    if study.exists():
        info = json.loads(study.read_text())
        runs = [(c["name"], directory / "cases" / c["name"] / "run" / "histories") for c in info["cases"]]
        runs = [(n, h) for n, h in runs if h.is_dir()]
        report = directory / "report.json"
        rep = json.loads(report.read_text()) if report.exists() else {}
        reference = rep.get("reference")
        reference = reference.get("label") if isinstance(reference, dict) else reference  # older reports: a name
        if not quantities:
            quantities = rep.get("quantities") or (metrics.default_quantities(runs[0][1]) if runs else [])
        out = Path(outdir) if outdir else directory / "plots"
        out.mkdir(parents=True, exist_ok=True)
        for q in quantities:
            written.append(overlay(q, runs, out / f"{_safe(q)}.png", reference=reference, units=info.get("units"),
                                   dimension=info.get("dimension", 2),
                                   settings=(rep.get("filters") or {}).get(q)))  # as the report compared it
        return written
    from ..output.plots import plot_run

    return plot_run(directory, quantities, outdir, reference_files, warn)
