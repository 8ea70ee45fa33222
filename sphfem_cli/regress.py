"""Deck regression: run each shipped deck for a short time and compare with stored references.

For every deck ``decks/<stem>.yaml`` a reference ``tests/regression/references/<stem>.json`` holds
what a short run of it gave:

- the run's end time (a fraction of the deck's ``end_time``, chosen when the reference was made);
- the final row of ``histories/glstat.csv`` (time, kinetic, internal, hourglass, external_work,
  total);
- for each history the deck requests, every column at a few fixed times (linear interpolation in
  the CSV), leaving out columns that are zero to round-off (symmetry planes, 2D out-of-plane
  components);
- the relative tolerance ``tolerance`` (default 1e-4).

A quantity passes when ``|value - reference| <= tolerance * scale``. The ``scale`` is stored with
each quantity: the largest magnitude the quantity reached during the reference run, floored at
1e-6 of the largest magnitude of its family (all energies together; the x/y/z or tensor
components of one history quantity together), so that a component that should be near zero
(hourglass energy of a smooth run, a lateral velocity) is not judged on its round-off.
This is the spirit of OpenRadioss's QA, which compares the last energy line of each test deck to
about 6.6e-4 relative.

Runs are single-threaded (the models are small, where a parallel launch per step costs more
than it saves, the more so on a loaded machine; results do not depend on the thread count).
The short run is a prefix of the full run: output intervals left to their defaults are pinned to
the full run's values (end_time/50, end_time/1000) before ``end_time`` is shortened, so the solver
takes the same steps up to the short end time.

``sphfem regress [DECKS...] [--update-refs] [--end-time-fraction F] [--keep-output FOLDER]`` drives this
(the short runs go to temporary folders, removed afterwards, or with ``--keep-output`` to FOLDER/<stem>); the
test ``tests/regression/test_decks.py`` runs the same comparison under pytest and reads the kept run's
per-part XDMF files too.
"""
from __future__ import annotations

import contextlib
import json
import math
import tempfile
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Iterable, Sequence

import numpy as np

from . import __version__

DEFAULT_TOLERANCE = 1e-4
DEFAULT_FRACTION = 0.1
ENERGY_COLUMNS = ("time", "kinetic", "internal", "hourglass", "external_work", "total")
SAMPLE_FRACTIONS = (1.0 / 3.0, 2.0 / 3.0, 1.0)
FAMILY_FLOOR = 1e-6  # a quantity's scale is at least this fraction of its family's largest magnitude
NOISE = 1e-9  # history columns below this fraction of their family's magnitude are not stored
_COMPONENTS = ("x", "y", "z", "xx", "yy", "zz", "xy", "yz", "zx")


@dataclass
class Row:
    """One compared quantity."""

    deck: str
    quantity: str
    reference: float | None
    value: float | None
    error: float | None  # |value - reference| / scale
    status: str  # PASS, FAIL, or a short reason for a failure
    tolerance: float = DEFAULT_TOLERANCE

    @property
    def passed(self) -> bool:
        return self.status == "PASS"


@dataclass
class DeckResult:
    """The comparison of one deck: its rows, the run's wall time and a one-line summary."""

    deck: str
    rows: list[Row] = field(default_factory=list)
    wall: float = 0.0
    note: str = ""
    output: Path | None = None  # the run's folder when kept (``regress_deck``'s keep)

    @property
    def passed(self) -> bool:
        return bool(self.rows) and all(r.passed for r in self.rows)


# ------------------------------------------------------------------------------------ locations


def find_root(start: Path | None = None) -> Path:
    """The project folder holding ``decks/``: the current directory or one above it, else the
    folder above the package (an editable install), else the current directory."""
    here = (start or Path.cwd()).resolve()
    for folder in (here, *here.parents):
        if (folder / "decks").is_dir():
            return folder
    package_parent = Path(__file__).resolve().parents[1]
    if (package_parent / "decks").is_dir():
        return package_parent
    return here


def shipped_decks(root: Path) -> list[Path]:
    """Every ``decks/*.yaml`` under `root`, sorted by name."""
    return sorted((root / "decks").glob("*.yaml"))


def reference_path(deck: Path, references: Path) -> Path:
    return references / f"{deck.stem}.json"


# ------------------------------------------------------------------------------------------ run


def run_short(deck: Path, end_time: float | None, fraction: float, workdir: Path) -> tuple[float, float, Path, list[str]]:
    """Run `deck` into `workdir` up to `end_time` (or `fraction` of its own end_time).

    Returns (end time used, wall seconds, output folder, requested history names). Raises
    RuntimeError when the run does not complete.
    """
    from .driver import execute, load_model

    loaded = load_model(str(deck))
    d = loaded.deck
    full_end = d.control.end_time
    if d.output.interval is None:
        d.output.interval = full_end / 50.0
    if d.output.history_interval is None:
        d.output.history_interval = full_end / 1000.0
    t_end = float(end_time) if end_time is not None else fraction * full_end
    d.control.end_time = t_end
    from .model.options import resolve_options

    loaded.model.options = resolve_options(d, loaded.model)  # the run reads the settings of the changed deck
    workdir.mkdir(parents=True, exist_ok=True)
    import numba

    threads = numba.get_num_threads()
    numba.set_num_threads(1)  # small models: a parallel launch per step costs more than it saves
    start = time.perf_counter()
    try:
        code = execute(loaded, workdir, quiet=True).code
    finally:
        wall = time.perf_counter() - start
        numba.set_num_threads(threads)
    if code != 0:
        why = (workdir / "diagnostics.txt")
        message = why.read_text().strip() if why.exists() else f"see {workdir / 'run.log'}"
        raise RuntimeError(f"run exited with status {code}: {message}")
    return t_end, wall, workdir, [h.name for h in d.output.histories]


def read_table(path: Path) -> tuple[list[str], np.ndarray]:
    """(column names, rows) of a history CSV."""
    with path.open() as f:
        columns = f.readline().strip().split(",")
    data = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)
    return columns, data


def _family(column: str) -> str:
    head, _, tail = column.rpartition("_")
    return head if head and tail in _COMPONENTS else column


def measure(outdir: Path, histories: Sequence[str], times: dict[str, list[float]] | None = None) -> dict:
    """The compared quantities of a finished run, in the reference layout (without tolerance).

    `times` gives the sample times per history (from a reference), and then every column is
    measured; by default the times are SAMPLE_FRACTIONS of the history's last recorded time and
    columns that are zero to round-off (below NOISE of their family) are left out.
    """
    hist_dir = outdir / "histories"
    columns, data = read_table(hist_dir / "glstat.csv")
    energy_peak = max(float(np.abs(data[:, columns.index(c)]).max()) for c in ENERGY_COLUMNS[1:])
    glstat = {}
    for c in ENERGY_COLUMNS:
        col = data[:, columns.index(c)]
        if c == "time":
            scale = float(abs(col[-1])) or 1.0
        else:
            scale = max(float(np.abs(col).max()), FAMILY_FLOOR * energy_peak)
        glstat[c] = {"value": float(col[-1]), "scale": scale or 1.0}

    samples = {}
    for name in histories:
        columns, data = read_table(hist_dir / f"{name}.csv")
        t = data[:, 0]
        at = list(times[name]) if times and name in times else [float(f * t[-1]) for f in SAMPLE_FRACTIONS]
        peaks = {c: float(np.abs(data[:, i]).max()) for i, c in enumerate(columns) if c != "time"}
        family_peak: dict[str, float] = {}
        for c, p in peaks.items():
            family_peak[_family(c)] = max(family_peak.get(_family(c), 0.0), p)
        stored = {}
        for i, c in enumerate(columns):
            if c == "time":
                continue
            fam = family_peak[_family(c)]
            if times is None and (fam == 0.0 or peaks[c] <= NOISE * fam):
                continue
            stored[c] = {
                "values": [float(np.interp(s, t, data[:, i])) for s in at],
                "scale": max(peaks[c], FAMILY_FLOOR * fam),
            }
        samples[name] = {"times": at, "last_time": float(t[-1]), "columns": stored}
    return {"glstat": glstat, "histories": samples}


# ------------------------------------------------------------------------------------- compare


def compare(deck: str, reference: dict, measured: dict) -> list[Row]:
    """Rows comparing `measured` (from :func:`measure`) with `reference`."""
    tol = float(reference.get("tolerance", DEFAULT_TOLERANCE))
    rows = []

    def judge(quantity: str, ref: float, scale: float, value: float | None) -> None:
        if value is None:
            rows.append(Row(deck, quantity, ref, None, None, "FAIL (missing)", tol))
            return
        err = abs(value - ref) / scale if scale > 0 else (0.0 if value == ref else math.inf)
        ok = err <= tol and math.isfinite(value)
        rows.append(Row(deck, quantity, ref, value, err, "PASS" if ok else "FAIL", tol))

    for c, ref in reference["glstat"].items():
        got = measured["glstat"].get(c)
        judge(f"glstat.{c}", ref["value"], ref["scale"], None if got is None else got["value"])

    for name, ref_hist in reference["histories"].items():
        got_hist = measured["histories"].get(name)
        if got_hist is None:
            rows.append(Row(deck, f"{name}", None, None, None, "FAIL (history not written)", tol))
            continue
        reached = got_hist["last_time"] >= max(ref_hist["times"]) * (1.0 - 1e-9)
        for c, ref in ref_hist["columns"].items():
            got = got_hist["columns"].get(c)
            for k, (t, r) in enumerate(zip(ref_hist["times"], ref["values"])):
                q = f"{name}.{c}@{t:.4g}"
                if not reached:
                    rows.append(Row(deck, q, r, None, None, "FAIL (time not reached)", tol))
                    continue
                judge(q, r, ref["scale"], None if got is None else got["values"][k])
    return rows


def _load_reference(path: Path) -> dict | None:
    if not path.exists():
        return None
    return json.loads(path.read_text())


def write_reference(path: Path, deck: Path, end_time: float, tolerance: float, measured: dict, steps: int | None) -> None:
    """Pretty, key-sorted JSON so that a git diff shows what moved."""
    data = {
        "deck": f"decks/{deck.name}",
        "end_time": end_time,
        "tolerance": tolerance,
        "sphfem_version": __version__,
        "steps": steps,
        **measured,
    }
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps(data, indent=2, sort_keys=True) + "\n")


def _steps(outdir: Path) -> int | None:
    log = outdir / "run.log"
    if log.exists():
        for line in log.read_text().splitlines():
            if line.startswith("steps:"):
                return int(line.split(":")[1])
    return None


def regress_deck(
    deck: Path,
    references: Path,
    update: bool = False,
    fraction: float | None = None,
    workdir: Path | None = None,
    keep: Path | None = None,
) -> DeckResult:
    """Run one deck and compare it with (or, when `update`, rewrite) its reference.

    The run goes to a temporary folder (under `workdir`) that is removed afterwards, or with `keep` to
    keep / <deck stem>, which must not exist yet (an earlier run is never overwritten), and is left there
    (``DeckResult.output``).
    """
    deck = Path(deck)
    result = DeckResult(deck.stem)
    ref_path = reference_path(deck, references)
    reference = _load_reference(ref_path)
    if reference is None and not update:
        result.rows.append(Row(deck.stem, "reference", None, None, None,
                               f"FAIL (no reference {ref_path}; run 'sphfem regress --update-refs')"))
        return result
    if fraction is not None:
        end_time, frac = None, fraction
    elif reference is not None:
        end_time, frac = reference["end_time"], DEFAULT_FRACTION
    else:
        end_time, frac = None, DEFAULT_FRACTION
    tolerance = float(reference.get("tolerance", DEFAULT_TOLERANCE)) if reference else DEFAULT_TOLERANCE

    result.output = Path(keep) / deck.stem if keep is not None else None
    if result.output is not None and result.output.exists():
        result.rows.append(Row(deck.stem, "run", None, None, None,
                               f"FAIL (the output folder {result.output} exists: remove it or keep elsewhere)",
                               tolerance))
        return result
    with (contextlib.nullcontext(str(result.output)) if result.output is not None
          else tempfile.TemporaryDirectory(prefix=f"sphfem-regress-{deck.stem}-", dir=workdir)) as tmp:
        try:
            t_end, wall, outdir, names = run_short(deck, end_time, frac, Path(tmp))
        except Exception as err:  # noqa: BLE001 - a failing deck is a FAIL row, not a crash
            from .driver import DeckProblem

            what = err.message if isinstance(err, DeckProblem) else f"{type(err).__name__}: {err}"
            result.rows.append(Row(deck.stem, "run", None, None, None, f"FAIL ({what})", tolerance))
            return result
        result.wall = wall
        steps = _steps(outdir)
        if update:
            measured = measure(outdir, names)
            write_reference(ref_path, deck, t_end, tolerance, measured, steps)
            reference = _load_reference(ref_path)
            result.note = f"reference written: {ref_path}"
        elif not math.isclose(t_end, reference["end_time"], rel_tol=1e-12):
            result.note = f"t = {t_end:.4g}, {steps} steps"
            result.rows.append(Row(deck.stem, "end_time", reference["end_time"], t_end, None,
                                   "FAIL (the reference was made at another end time)", tolerance))
            return result
        times = {n: h["times"] for n, h in reference["histories"].items()}
        measured = measure(outdir, names, times)
        result.rows.extend(compare(deck.stem, reference, measured))
        result.note = result.note or f"t = {t_end:.4g}, {steps} steps"
    return result


# --------------------------------------------------------------------------------------- report


def format_table(results: Iterable[DeckResult], failures_only: bool = False) -> str:
    """A plain text table: deck, quantity, reference, value, relative error, status."""
    header = ("deck", "quantity", "reference", "value", "rel. error", "status")
    lines = []
    body = []
    for res in results:
        for r in res.rows:
            if failures_only and r.passed:
                continue
            body.append((
                r.deck, r.quantity,
                "-" if r.reference is None else f"{r.reference:.6e}",
                "-" if r.value is None else f"{r.value:.6e}",
                "-" if r.error is None else f"{r.error:.1e}",
                r.status,
            ))
    widths = [max([len(h)] + [len(b[i]) for b in body]) for i, h in enumerate(header)]
    widths[-1] = len(header[-1])
    fmt = "  ".join(f"{{:{'<' if i < 2 else '>'}{w}}}" for i, w in enumerate(widths[:-1])) + "  {}"
    lines.append(fmt.format(*header))
    lines.append("  ".join("-" * w for w in widths))
    lines.extend(fmt.format(*b) for b in body)
    return "\n".join(lines)


def summary(results: Sequence[DeckResult]) -> str:
    lines = []
    for res in results:
        n_fail = sum(not r.passed for r in res.rows)
        state = "PASS" if res.passed else "FAIL"
        ran = f", {res.wall:.2f} s run ({res.note})" if res.wall > 0 else ""
        lines.append(f"{state}  {res.deck}: {len(res.rows) - n_fail}/{len(res.rows)} quantities within "
                     f"tolerance{ran}")
    n_bad = sum(not r.passed for r in results)
    lines.append(f"{len(results) - n_bad} of {len(results)} deck(s) passed")
    return "\n".join(lines)


def main(
    decks: Sequence[str] = (),
    update: bool = False,
    fraction: float | None = None,
    references: str | None = None,
    failures_only: bool = False,
    echo=print,
    keep: str | None = None,
) -> int:
    """The ``sphfem regress`` command; returns the exit status (0 when every deck passed)."""
    root = find_root()
    paths = [Path(d) for d in decks] if decks else shipped_decks(root)
    refdir = Path(references) if references else root / "tests" / "regression" / "references"
    if not paths:
        echo(f"no decks found under {root / 'decks'}: `sphfem regress` is a repository command. It runs the "
             "shipped decks (decks/*.yaml) against their references (tests/regression/references/) of a clone "
             "of the repository: run it inside one, or name DECKS and --references FOLDER")
        return 2
    if not refdir.is_dir() and not update:
        echo(f"no references folder {refdir}: give --references FOLDER, or --update-refs to write one")
        return 2
    results = []
    for path in paths:
        results.append(regress_deck(path, refdir, update=update, fraction=fraction,
                                    keep=Path(keep) if keep else None))
    echo(format_table(results, failures_only=failures_only))
    echo("")
    echo(summary(results))
    return 0 if all(r.passed for r in results) else 1
