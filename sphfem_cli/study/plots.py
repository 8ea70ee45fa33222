"""PNG plots (matplotlib, Agg backend): the study's error, Pareto and history plots, and ``sphfem plot``."""
from __future__ import annotations

import json
import math
import re
from pathlib import Path
from typing import Sequence

from . import metrics


def _pyplot():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def _safe(name: str) -> str:
    return re.sub(r"[^A-Za-z0-9_.-]", "_", name)


def study_plots(out: Path, result: dict, cases) -> list[Path]:
    """error_vs_ratio.png, pareto.png and history_<quantity>.png in ``out``."""
    plt = _pyplot()
    written = []
    rows = [r for r in result["cases"] if r.get("state") == "done" and not r["reference"]]
    sph = sorted((r for r in rows if r["kind"] == "sph"), key=lambda r: r["ratio"])

    fig, ax = plt.subplots(figsize=(6.4, 4.4))
    for q in result["quantities"]:
        pts = [(r["ratio"], r["errors"][q]["l2"]) for r in sph if "l2" in r["errors"].get(q, {})]
        pts = [(x, y) for x, y in pts if y is not None and math.isfinite(y) and y > 0]
        if pts:
            ax.loglog(*zip(*pts), "o-", label=q)
    ax.axhline(result["tolerance"], color="grey", ls="--", lw=1, label=f"tolerance {100 * result['tolerance']:g} %")
    ax.set_xlabel("ratio (ALE element size / particle spacing)")
    ax.set_ylabel(f"normalised L2 error vs {result['reference']}")
    ax.set_title("SPH error against the reference")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    written.append(out / "error_vs_ratio.png")
    fig.savefig(written[-1], dpi=120)
    plt.close(fig)

    fig, ax = plt.subplots(figsize=(6.4, 4.4))
    for kind, marker in (("sph", "o-"), ("ale", "s-")):
        pts = []
        for r in sorted((r for r in rows if r["kind"] == kind), key=lambda r: r["wall_s"] or 0):
            errs = [e["l2"] for e in r["errors"].values() if e.get("l2") is not None and math.isfinite(e["l2"])]
            if errs and max(errs) > 0 and r.get("wall_s"):
                pts.append((r["wall_s"], max(errs), r["case"]))
        if pts:
            ax.loglog([p[0] for p in pts], [p[1] for p in pts], marker, label=kind.upper())
            for x, y, name in pts:
                ax.annotate(name, (x, y), fontsize=7, xytext=(3, 3), textcoords="offset points")
    ref = next((r for r in result["cases"] if r["reference"]), None)
    if ref and ref.get("wall_s"):
        ax.axvline(ref["wall_s"], color="k", ls=":", lw=1, label=f"reference {ref['case']} cost")
    ax.axhline(result["tolerance"], color="grey", ls="--", lw=1, label="tolerance")
    ax.set_xlabel("wall time [s]")
    ax.set_ylabel("worst normalised L2 error")
    ax.set_title("Error against cost (Pareto)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    written.append(out / "pareto.png")
    fig.savefig(written[-1], dpi=120)
    plt.close(fig)

    done = [c for c in cases if c.status.get("state") == "done"]
    for q in result["quantities"]:
        written.append(out / f"history_{_safe(q)}.png")
        overlay(q, [(c.name, c.histories) for c in done], written[-1], reference=result["reference"])
    return written


def overlay(quantity: str, runs: Sequence[tuple[str, Path]], path: Path, reference: str | None = None) -> Path | None:
    """One quantity's history from several runs on one plot."""
    plt = _pyplot()
    fig, ax = plt.subplots(figsize=(7.0, 4.4))
    drawn = 0
    for label, histories in runs:
        try:
            t, v = metrics.quantity_series(histories, quantity)
        except KeyError:
            continue
        ref = label == reference
        ax.plot(t, v, "k-" if ref else "-", lw=2.0 if ref else 1.2, label=label + (" (ref)" if ref else ""))
        drawn += 1
    ax.set_xlabel("time")
    ax.set_ylabel(quantity)
    ax.grid(True, alpha=0.3)
    if drawn:
        ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path


def plot_dir(directory: Path, quantities: Sequence[str] = (), outdir: Path | None = None) -> list[Path]:
    """``sphfem plot``: a study folder gives one overlay per quantity across its cases; a run folder
    (or its histories/) one PNG per quantity, or per table when no quantity is named."""
    directory = Path(directory)
    study = directory / "study.json"
    written: list[Path] = []
    if study.exists():
        cases = json.loads(study.read_text())["cases"]
        runs = [(c["name"], directory / "cases" / c["name"] / "run" / "histories") for c in cases]
        runs = [(n, h) for n, h in runs if h.is_dir()]
        report = directory / "report.json"
        reference = json.loads(report.read_text()).get("reference") if report.exists() else None
        if not quantities:
            quantities = (json.loads(report.read_text()).get("quantities") if report.exists() else None) or \
                metrics.default_quantities(runs[0][1]) if runs else []
        out = Path(outdir) if outdir else directory / "plots"
        out.mkdir(parents=True, exist_ok=True)
        for q in quantities:
            written.append(overlay(q, runs, out / f"{_safe(q)}.png", reference=reference))
        return written
    histories = directory / "histories" if (directory / "histories").is_dir() else directory
    tables = sorted(histories.glob("*.csv"))
    if not tables:
        raise FileNotFoundError(f"{directory}: neither a study folder (study.json) nor a run (histories/*.csv)")
    out = Path(outdir) if outdir else directory / "plots"
    out.mkdir(parents=True, exist_ok=True)
    if quantities:
        for q in quantities:
            written.append(overlay(q, [(directory.name, histories)], out / f"{_safe(q)}.png"))
        return written
    plt = _pyplot()
    for table in tables:
        columns, data = metrics.read_history(table)
        fig, ax = plt.subplots(figsize=(7.0, 4.4))
        for i, c in enumerate(columns[1:], start=1):
            ax.plot(data[:, 0], data[:, i], label=c)
        ax.set_xlabel(columns[0])
        ax.set_title(table.stem)
        ax.grid(True, alpha=0.3)
        if len(columns) > 1:
            ax.legend(fontsize=7, ncol=2)
        fig.tight_layout()
        written.append(out / f"{_safe(table.stem)}.png")
        fig.savefig(written[-1], dpi=120)
        plt.close(fig)
    return written
