"""``sphfem plot RUN``: a run's histories as PNGs an engineer reads (matplotlib, Agg backend).

- ``glstat.png``: the energies on one panel (J, or J/m in 2D plane strain), the energy ratio on its
  own panel with the deck's ``control.energy_band``, the time step on a log panel.
- ``TABLE.png`` for every other table: one panel per quantity (a vector's components together, a
  stress's six components together), each with its unit from the deck's ``units:``.
- ``TABLE.COLUMN.png`` for each ``--quantity``, with the reference curves that compare with it.

Reference curves (measurements, exact or published results) come from the deck's
``output.references`` (each names its CSV file, the quantity, and the scales that turn the file's
columns into the run's time and value) or from ``--reference FILE.csv`` (columns already in the run's
units). A CSV's ``#`` lines are comments; a first column that is not a number names the series.
"""
from __future__ import annotations

import csv
import re
from dataclasses import dataclass
from pathlib import Path
from typing import Sequence

import numpy as np
import yaml

from ..study.metrics import VECTOR_AXES, quantity_series, read_history
from ..study.units import label, unit_of
from .filters import FILTERED

ENERGIES = ("kinetic", "internal", "hourglass", "contact", "external_work", "total")
RUN_TABLES = ("glstat", "matsum", "ale_materials")  # written by every run, not requested


@dataclass(frozen=True)
class ReferenceCurve:
    """A reference history in the run's units: ``value(time)`` to compare with ``quantity``."""

    label: str
    quantity: str
    time: np.ndarray
    value: np.ndarray


def _pyplot():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def _safe(name: str) -> str:
    return re.sub(r"[^A-Za-z0-9_.-]", "_", name)


def _number(text: str) -> float | None:
    try:
        return float(text)
    except ValueError:
        return None


def read_reference(path: Path, quantity: str, series: str | None = None, columns: Sequence[int] = (0, 1),
                   time_scale: float = 1.0, value_scale: float = 1.0, name: str | None = None) -> list[ReferenceCurve]:
    """The curves of a reference CSV: time = time_scale x column ``columns[0]``, value = value_scale x
    column ``columns[1]``, counting numeric columns only. One curve per series (the first column when it
    is not a number), or only ``series``. A header row of names is skipped. ValueError when nothing is read."""
    rows: dict[str, list[tuple[float, float]]] = {}
    with Path(path).open(newline="") as f:
        for raw in csv.reader(line for line in f if line.strip() and not line.lstrip().startswith("#")):
            cells = [c.strip() for c in raw]
            key = "" if _number(cells[0]) is not None else cells[0]
            numbers = [_number(c) for c in (cells if key == "" else cells[1:])]
            if any(v is None for v in numbers) or len(numbers) <= max(columns):
                continue  # a header of names
            if series is not None and key != series:
                continue
            rows.setdefault(key, []).append((numbers[columns[0]] * time_scale, numbers[columns[1]] * value_scale))
    if not rows:
        raise ValueError(f"{path}: no rows of numbers" + (f" in series '{series}'" if series else ""))
    base = name or Path(path).stem
    out = []
    for key, pts in rows.items():
        t, v = np.array(pts).T
        out.append(ReferenceCurve(f"{base} {key}".strip() if len(rows) > 1 or not name else base, quantity, t, v))
    return out


def _deck_info(run: Path) -> tuple[dict, Path | None]:
    """(the run's effective deck as a dict, the original deck's folder) from deck.effective.yaml."""
    eff = run / "deck.effective.yaml"
    if not eff.exists():
        return {}, None
    text = eff.read_text()
    first = text.splitlines()[0] if text else ""
    m = re.match(r"# (.+?) with every default filled in", first)
    return (yaml.safe_load(text) or {}), (Path(m.group(1)).parent if m else None)


def deck_references(run: Path, warn=lambda line: None) -> list[ReferenceCurve]:
    """The curves of the deck's ``output.references``; a file that is gone is skipped with a warning."""
    data, folder = _deck_info(run)
    out: list[ReferenceCurve] = []
    for ref in ((data.get("output") or {}).get("references") or []):
        path = Path(ref["file"])
        if not path.is_absolute() and folder is not None:
            path = folder / path
        if not path.exists():
            warn(f"warning: reference {ref['file']} not found (looked at {path}); drawn without it")
            continue
        out += read_reference(path, ref["quantity"], ref.get("series"), ref.get("columns") or (0, 1),
                              ref.get("time_scale", 1.0), ref.get("value_scale", 1.0), ref.get("label"))
    return out


def known_quantities(histories: Path) -> list[str]:
    """Every ``TABLE.COLUMN`` of a run, and each vector family ``TABLE.NAME`` (its magnitude)."""
    out: list[str] = []
    for path in sorted(Path(histories).glob("*.csv")):
        columns, _ = read_history(path)
        for c in columns[1:]:
            out.append(f"{path.stem}.{c}")
            head, _, tail = c.rpartition("_")
            if head and tail in VECTOR_AXES and f"{path.stem}.{head}" not in out and not head.startswith("stress"):
                out.append(f"{path.stem}.{head}")
    return out


def resolve_quantity(histories: Path, quantity: str) -> str:
    """``TABLE.COLUMN`` for ``quantity``; a bare column is looked for in the requested tables. KeyError
    (listing the known quantities) when it names nothing or more than one thing."""
    known = known_quantities(histories)
    if quantity in known:
        return quantity
    if "." not in quantity:
        hits = [k for k in known if k.split(".", 1)[1] == quantity]
        preferred = [k for k in hits if k.split(".", 1)[0] not in RUN_TABLES]
        hits = preferred or hits
        if len(hits) == 1:
            return hits[0]
        if hits:
            raise KeyError(f"quantity '{quantity}' is in several tables: {', '.join(hits)}; name one as TABLE.COLUMN")
    raise KeyError(f"unknown quantity '{quantity}'; known: {', '.join(known)}")


def _family(column: str) -> str:
    """The panel a column goes on: a vector's components together, the stress components together."""
    if column.startswith("stress_"):
        return "stress"
    head, _, tail = column.rpartition("_")
    return head if head and tail in VECTOR_AXES else column


def _run_name(run: Path) -> str:
    return f"{run.parent.name}/{run.name}" if run.name == "run" else run.name


def _within(ref: ReferenceCurve, t_end: float) -> tuple[np.ndarray, np.ndarray]:
    """The reference's points up to the run's end (and 5 % beyond), so the run fills the axis."""
    keep = ref.time <= 1.05 * t_end if t_end > 0 else np.ones(len(ref.time), bool)
    return ref.time[keep], ref.value[keep]


def _draw_reference(ax, ref: ReferenceCurve, t_end: float, warn=lambda line: None) -> bool:
    """A reference as open circles, or as a thin grey line where it is a dense record (more points
    than circles can show apart). One with no point in the run's window is not drawn (a legend entry
    without points would say it was compared): ``warn`` says so, with its time range. True if drawn."""
    t, v = _within(ref, t_end)
    if not len(t):
        warn(f"warning: reference '{ref.label}' not drawn: none of its {len(ref.time)} points lies in the run's "
             f"time window (0 to {1.05 * t_end:g}); its times run from {ref.time.min():g} to {ref.time.max():g}. "
             "Is it in the run's units? (a deck's output.references can scale its columns)")
        return False
    if len(t) > _MARKED_POINTS:
        ax.plot(t, v, "-", color="0.45", lw=0.8, label=ref.label)
    else:
        ax.plot(t, v, "ko", ms=4, mfc="none", label=ref.label)
    return True


_MARKED_POINTS = 80


def _save(fig, path: Path, plt) -> Path:
    for ax in fig.axes:
        if ax.get_yscale() == "linear":
            ax.ticklabel_format(axis="y", style="sci", scilimits=(-3, 4), useMathText=True)
        ax.ticklabel_format(axis="x", style="sci", scilimits=(-3, 4), useMathText=True)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path


def glstat_plot(table: Path, path: Path, units: dict, dimension: int, band: Sequence[float] | None) -> Path:
    """Energies, the energy ratio with its band, and dt (log) on three panels."""
    plt = _pyplot()
    columns, data = read_history(table)
    t = data[:, 0]
    fig, (ax_e, ax_r, ax_dt) = plt.subplots(3, 1, figsize=(7.5, 8.0), sharex=True,
                                            gridspec_kw={"height_ratios": [2.2, 1.0, 1.0]})
    for name in ENERGIES:
        if name in columns:
            ax_e.plot(t, data[:, columns.index(name)], lw=2.0 if name == "total" else 1.2,
                      color="k" if name == "total" else None, label=name)
    ax_e.set_ylabel(f"energy [{unit_of('kinetic', units, dimension)}]")
    ax_e.legend(fontsize=7, ncol=3)
    if "energy_ratio" in columns:
        ax_r.plot(t[1:], data[1:, columns.index("energy_ratio")], "k-", lw=1.2, label="energy ratio")
    if band:
        ax_r.axhspan(band[0], band[1], color="tab:green", alpha=0.12, label=f"energy_band [{band[0]:g}, {band[1]:g}]")
        for b in band:
            ax_r.axhline(b, color="tab:green", lw=0.8, ls="--")
    ax_r.set_ylabel("energy ratio [-]")
    ax_r.legend(fontsize=7)
    if "dt" in columns:
        dt = data[:, columns.index("dt")]
        ok = dt > 0
        ax_dt.semilogy(t[ok], dt[ok], "-", lw=1.2, color="tab:blue")
    ax_dt.set_ylabel(f"dt [{unit_of('dt', units, dimension)}] (log)")
    ax_dt.set_xlabel(label("time", units, dimension))
    for ax in (ax_e, ax_r, ax_dt):
        ax.grid(True, which="both", alpha=0.3)
    ax_e.set_title(f"glstat of {_run_name(table.parent.parent)}: energies, energy ratio, time step")
    return _save(fig, path, plt)


def table_plot(table: Path, path: Path, units: dict, dimension: int, references: Sequence[ReferenceCurve] = (),
               filtered: Path | None = None, warn=lambda line: None) -> Path:
    """One panel per quantity of a history table, with the references that compare with its columns
    and, drawn over the raw columns, the probe's low-passed table ``filtered`` (``<name>_filtered.csv``)."""
    plt = _pyplot()
    columns, data = read_history(table)
    fcolumns, fdata = read_history(filtered) if filtered is not None else ([], None)
    panels: dict[str, list[int]] = {}
    for i, c in enumerate(columns[1:], start=1):
        panels.setdefault(_family(c), []).append(i)
    n = max(1, len(panels))
    fig, axes = plt.subplots(n, 1, figsize=(7.5, 1.6 + 2.2 * n), sharex=True, squeeze=False)
    for ax, (family, idx) in zip(axes[:, 0], panels.items()):
        for i in idx:
            ax.plot(data[:, 0], data[:, i], "o-" if len(data) < 3 else "-", lw=1.2, label=columns[i])
            if columns[i] in fcolumns[1:]:
                ax.plot(fdata[:, 0], fdata[:, fcolumns.index(columns[i])], "-", color="C3", lw=1.2,
                        label=f"{columns[i]}, filtered")
        for ref in references:
            tab, _, col = ref.quantity.partition(".")
            if tab == table.stem and (col == family or col in (columns[i] for i in idx)):
                _draw_reference(ax, ref, data[-1, 0] if len(data) else 0.0, warn)
        ax.set_ylabel(label(columns[idx[0]] if len(idx) == 1 else family, units, dimension))
        ax.set_title(family, fontsize=9)
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=7, ncol=2)
    axes[-1, 0].set_xlabel(label("time", units, dimension))
    fig.suptitle(f"{table.stem} history of {_run_name(table.parent.parent)}", fontsize=11)
    return _save(fig, path, plt)


def quantity_plot(histories: Path, quantity: str, path: Path, units: dict, dimension: int,
                  references: Sequence[ReferenceCurve] = (), warn=lambda line: None) -> Path:
    """One quantity's history, with the references that compare with it."""
    plt = _pyplot()
    t, v = quantity_series(histories, quantity)
    fig, ax = plt.subplots(figsize=(7.0, 4.4))
    ax.plot(t, v, "o-" if len(t) < 3 else "-", lw=1.4, label=f"{_run_name(histories.parent)}")
    t_end = t[-1] if len(t) else 0.0
    drawn = [r for r in references if r.quantity == quantity and _draw_reference(ax, r, t_end, warn)]
    ax.set_xlabel(label("time", units, dimension))
    ax.set_ylabel(label(quantity, units, dimension))
    ax.set_title(f"{quantity} of {_run_name(histories.parent)}" + (" against the reference" if drawn else ""))
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8)
    return _save(fig, path, plt)


def plot_run(run: Path, quantities: Sequence[str] = (), outdir: Path | None = None,
             reference_files: Sequence[Path] = (), warn=lambda line: None) -> list[Path]:
    """The PNGs of a run folder (or its histories/): one per table, or one per ``quantities``.

    KeyError for an unknown quantity (the CLI makes it a usage error); ``reference_files`` need quantities."""
    run = Path(run)
    histories = run / "histories" if (run / "histories").is_dir() else run
    run = histories.parent if histories.name == "histories" else run
    tables = sorted(histories.glob("*.csv"))
    if not tables:
        raise FileNotFoundError(f"{run}: neither a study folder (study.json) nor a run (histories/*.csv)")
    data, _ = _deck_info(run)
    units = data.get("units") or {}
    dimension = 3 if data.get("dimension") == "axisymmetric" else int(data.get("dimension", 2))  # 2 pi: no per-length
    names = [resolve_quantity(histories, q) for q in quantities]
    if reference_files and not names:
        raise KeyError("--reference needs --quantity: the quantity the reference compares with")
    refs = deck_references(run, warn)
    for f in reference_files:
        for q in names:
            refs += read_reference(Path(f), q)
    out = Path(outdir) if outdir else run / "plots"
    out.mkdir(parents=True, exist_ok=True)
    if names:
        return [quantity_plot(histories, q, out / f"{_safe(q)}.png", units, dimension, refs, warn) for q in names]
    band = (data.get("control") or {}).get("energy_band")
    written = []
    stems = {t.stem for t in tables}
    for table in tables:
        path = out / f"{_safe(table.stem)}.png"
        if table.stem == "glstat":
            written.append(glstat_plot(table, path, units, dimension, band))
        elif not (table.stem.endswith(FILTERED) and table.stem[:-len(FILTERED)] in stems):  # drawn with its raw table
            filtered = histories / f"{table.stem}{FILTERED}.csv"
            written.append(table_plot(table, path, units, dimension, refs, filtered if filtered.is_file() else None,
                                      warn))
    return written
