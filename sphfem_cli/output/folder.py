"""One run per output folder: which files a run writes, which of an earlier run are present, and
their removal (nothing else in the folder is touched).

A run lists the files it writes in ``run.manifest.json`` before it writes any of them:

    {"sphfem": version, "deck_sha256": the deck's hash (output.checkpoint.deck_hash),
     "files": [paths relative to the folder, e.g. "histories/tip.csv"]}

so a later ``--overwrite`` removes exactly those, plus the checkpoint's temporary files, the PNGs
``sphfem plot`` drew from those histories (``plots/<table>.png``, ``plots/<table>.<column>.png``) and
the tables ``sphfem probe`` sampled from its results (``probes/*.csv`` that begin "# sphfem probe:").
A folder written before manifests existed is recognised by the fixed names below and the history
tables listed in its ``results.h5`` (or its ``deck.effective.yaml``).
"""
from __future__ import annotations

import json
import re
from pathlib import Path

from .. import __version__

MANIFEST = "run.manifest.json"
FIXED = ("run.log", "deck.effective.yaml", "diagnostics.txt", "results.xdmf", "results.h5", "results.paraview.py",
         "checkpoint.npz", "checkpoint.pkl")
_STANDARD_TABLES = ("glstat", "matsum", "ale_materials")
_TEMPORARY = (".checkpoint.*.tmp", ".results.*.xdmf.tmp")


def run_files(tables: list[str], parts: list[str] = ()) -> list[str]:
    """The files (relative paths) of a run whose history tables are `tables` and whose parts are `parts`
    (each has its own ``results.<part>.xdmf``, output.xdmf)."""
    return [MANIFEST, *FIXED, *(f"results.{p}.xdmf" for p in parts), *(f"histories/{t}.csv" for t in tables)]


def write_manifest(directory: Path, tables: list[str], digest: str, parts: list[str] = ()) -> None:
    """Record the files a run of the deck of hash `digest` into `directory` writes (before it writes any)."""
    text = json.dumps({"sphfem": __version__, "deck_sha256": digest, "files": run_files(tables, parts)}, indent=1,
                      ensure_ascii=False)
    (Path(directory) / MANIFEST).write_text(text + "\n", encoding="utf-8")


def manifest_deck(directory: Path) -> str | None:
    """The deck hash the manifest of `directory` records (None without a readable manifest)."""
    try:
        digest = json.loads((Path(directory) / MANIFEST).read_text(encoding="utf-8")).get("deck_sha256")
    except (OSError, ValueError, AttributeError):
        return None
    return digest if isinstance(digest, str) else None


def _earlier_tables(directory: Path) -> list[str]:
    """History tables of a folder without a manifest: results.h5's /histories, else deck.effective.yaml's."""
    tables = set(_STANDARD_TABLES)
    try:
        import h5py

        with h5py.File(directory / "results.h5", "r", locking=False) as f:
            group = f.get("histories")
            tables.update(group.keys() if group is not None else ())
    except (OSError, KeyError, ValueError):
        pass
    try:
        import yaml

        deck = yaml.safe_load((directory / "deck.effective.yaml").read_text(encoding="utf-8"))
        out = deck.get("output") or {}
        tables.update(str(h["name"]) for key in ("histories", "probes") for h in out.get(key) or ())
    except (OSError, ValueError, AttributeError, TypeError, KeyError, yaml.YAMLError):
        pass
    return sorted(tables)


def earlier_run(directory: Path) -> list[Path]:
    """The files of an earlier run present in `directory` (empty when there is none)."""
    directory = Path(directory)
    if not directory.is_dir():
        return []
    listed = None
    try:
        manifest = json.loads((directory / MANIFEST).read_text(encoding="utf-8"))
        listed = [str(f) for f in manifest["files"]]
    except (OSError, ValueError, KeyError, TypeError):
        pass
    if listed is None:
        listed = run_files(_earlier_tables(directory))
    names = {Path(f) for f in listed if not Path(f).is_absolute() and ".." not in Path(f).parts}
    names.update(Path(p.name) for pattern in _TEMPORARY for p in directory.glob(pattern))
    tables = [p.stem for p in names if p.parent == Path("histories") and p.suffix == ".csv"]
    plots = directory / "plots"
    if tables and plots.is_dir():
        safe = [re.sub(r"[^A-Za-z0-9_.-]", "_", t) for t in tables]
        for png in plots.glob("*.png"):
            if any(png.stem == s or png.stem.startswith(s + ".") for s in safe):
                names.add(Path("plots") / png.name)
    probes = directory / "probes"
    if names and probes.is_dir():  # tables `sphfem probe` sampled from this run's results
        for csv in probes.glob("*.csv"):
            try:
                with csv.open(encoding="utf-8") as f:
                    if f.readline().startswith("# sphfem probe:"):
                        names.add(Path("probes") / csv.name)
            except (OSError, UnicodeDecodeError):
                pass
    return sorted(directory / n for n in names if (directory / n).is_file() or (directory / n).is_symlink())


def clear_earlier_run(directory: Path) -> list[Path]:
    """Remove the files of an earlier run from `directory` (and histories/, plots/ when that empties
    them); returns what was removed. Raises OSError when a file cannot be removed."""
    removed = earlier_run(directory)
    for path in removed:
        path.unlink()
    for sub in ("histories", "plots", "probes"):
        folder = Path(directory) / sub
        if folder.is_dir() and not any(folder.iterdir()):
            folder.rmdir()
    return removed
