"""The `sphfem` command: a thin click shell over the run driver (``driver``; ``api`` for scripts).

Exit codes (``driver``): 0 ok, 2 usage (also: an output folder holding another run), 65 bad deck or
unusable checkpoint, 3 run stopped by a guard, 73 cannot create the output folder or a file in it, 74 I/O
error while writing (the files written so far are kept), 1 internal error, 130 interrupted by the user
(output so far kept).
"""
from __future__ import annotations

import os
import sys
from pathlib import Path

import click

from . import __version__
from .driver import (EXIT_INTERNAL, EXIT_INTERRUPTED, DeckProblem, announce_compiling, default_threads, execute,
                     load_model, prepare_folder)

EXIT_BROKEN_PIPE = 141  # 128 + SIGPIPE, what a shell reports for a writer whose reader closed the pipe


class _Commands(click.Group):
    """The command group; an unexpected exception becomes one line and exit 1, never a traceback."""

    def invoke(self, ctx):
        try:
            return super().invoke(ctx)
        except (click.exceptions.Exit, click.ClickException, click.Abort, SystemExit):
            raise
        except DeckProblem as err:  # a bad deck, checkpoint or output folder: its one line, its exit code
            click.echo(err.message, err=True)
            sys.exit(err.exit_code)
        except KeyboardInterrupt:
            click.echo("interrupted", err=True)
            sys.exit(EXIT_INTERRUPTED)
        except BrokenPipeError:  # the reader went away (`sphfem check deck | head -1`): stop as `cat` would
            try:  # nothing more reaches it, and the exit's flush must not fail again
                os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
            except (OSError, ValueError, AttributeError):
                pass
            sys.exit(EXIT_BROKEN_PIPE)
        except Exception as err:  # noqa: BLE001 - the CLI's last line of defence
            click.echo(f"internal error: {type(err).__name__}: {err} (please report it)", err=True)
            sys.exit(EXIT_INTERNAL)


@click.group(cls=_Commands, context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(__version__, prog_name="sphfem")
def main() -> None:
    """sphfem: explicit-dynamics fluid-structure interaction from a YAML deck."""


@main.command()
@click.argument("deck", type=click.Path(dir_okay=False))
def check(deck: str) -> None:
    """Validate DECK and print a model summary (counts, materials, stable step, memory)."""
    loaded = load_model(deck)
    from .solver.guards import RunStopped
    from .summary import model_summary

    try:
        lines, warnings = model_summary(loaded.deck, loaded.model, Path(deck))
    except RunStopped as err:
        raise DeckProblem(f"{deck}:1:1: model: {err}") from None
    for line in lines:
        click.echo(line)
    for w in warnings:
        click.echo(w, err=True)


@main.command()
@click.argument("deck", type=click.Path(dir_okay=False))
@click.option("-o", "--output", "outdir", type=click.Path(file_okay=False),
              help="Output folder. Default: <deck name>_results in the current directory "
                   "(with --restart: the checkpoint's folder).")
@click.option("--threads", type=click.IntRange(min=1), default=None,
              help="Worker threads. Default: one per 20 000 solid elements, ALE elements and particles together, up to the number of cores "
                   "(small models run fastest on one thread).")
@click.option("-q", "--quiet", is_flag=True, help="Print nothing but errors.")
@click.option("-v", "--verbose", is_flag=True, help="Print the energy balance at every field output.")
@click.option("--restart", "restart", type=click.Path(dir_okay=False), default=None,
              help="Continue the run from this checkpoint (e.g. <output>/checkpoint.npz), appending to the output "
                   "folder's histories and XDMF series; the deck must be the one the run started from. Pickled "
                   "checkpoints (checkpoint.pkl) of earlier versions are refused: loading a pickle can run code.")
@click.option("--overwrite", is_flag=True,
              help="Run into a folder that holds an earlier run: remove that run's files first (only those "
                   "sphfem wrote; other files stay). Without it such a folder is refused (exit 2).")
def run(deck: str, outdir: str | None, threads: int | None, quiet: bool, verbose: bool, restart: str | None,
        overwrite: bool) -> None:
    """Run DECK and write XDMF/HDF5 fields and CSV histories to the output folder.

    A checkpoint (checkpoint.npz in the output folder) is written at every field output (or every
    control.checkpoint_interval) and on Ctrl-C or SIGTERM; --restart continues from it. One folder
    holds one run: a folder with another run's results is refused unless --overwrite or --restart.
    """
    if restart and overwrite:
        prepare_folder(Path(restart).parent, Path(restart), overwrite)  # refuses the pair, exit 2
    announced = announce_compiling(quiet)
    loaded = load_model(deck)
    import numba

    if threads is None:
        threads = default_threads(loaded.model)
    numba.set_num_threads(min(threads, numba.config.NUMBA_NUM_THREADS))
    out = (Path(outdir) if outdir else Path(restart).parent if restart
           else Path.cwd() / f"{Path(deck).stem}_results")
    prepare_folder(out, Path(restart) if restart else None, overwrite)
    outcome = execute(loaded, out, quiet=quiet, verbose=verbose, restart=Path(restart) if restart else None,
                      announced=announced)
    sys.exit(outcome.code)


@main.command()
@click.argument("decks", nargs=-1, type=click.Path(exists=True, dir_okay=False))
@click.option("--update-refs", is_flag=True, help="Rewrite the reference files from this run.")
@click.option("--end-time-fraction", type=click.FloatRange(0.0, 1.0, min_open=True), default=None,
              help="Run each deck to this fraction of its end_time (default: the reference's end time, "
                   "else 0.1); a reference made at another end time fails unless --update-refs.")
@click.option("--references", type=click.Path(file_okay=False), default=None,
              help="Reference folder. Default: tests/regression/references of the project.")
@click.option("--failures-only", is_flag=True, help="List only the quantities that failed.")
@click.option("--keep-output", type=click.Path(file_okay=False), default=None, metavar="FOLDER",
              help="Keep each deck's short run in FOLDER/<deck name> (which must not exist yet), to open its "
                   "results. Default: temporary folders, removed after the comparison.")
def regress(decks, update_refs, end_time_fraction, references, failures_only, keep_output) -> None:
    """Run DECKS (default: every decks/*.yaml) briefly and compare energies and histories with stored references."""
    from .regress import main as regress_main

    sys.exit(regress_main(decks, update=update_refs, fraction=end_time_fraction, references=references,
                          failures_only=failures_only, echo=click.echo, keep=keep_output))


def _number_list(kind):
    def parse(ctx, param, value):
        if value is None or value == "":
            return ()
        try:
            return tuple(kind(v) for v in str(value).split(",") if v.strip())
        except ValueError:
            raise click.BadParameter(f"expected comma-separated numbers, got {value!r}") from None
    return parse


def _fraction(ctx, param, value):
    text = str(value).strip()
    try:
        return float(text[:-1]) / 100.0 if text.endswith("%") else float(text)
    except ValueError:
        raise click.BadParameter(f"expected a fraction or a percentage (5%), got {value!r}") from None


def _ale_sizes(ctx, param, value):
    """--ale-sizes: "default" (None: h, h/2, h/4 where the scene allows), "none" (()), or a number list."""
    text = str(value).strip().lower() if value is not None else "default"
    if text == "default":
        return None
    if text == "none":
        return ()
    return _number_list(float)(ctx, param, value)


@main.command("mesh-study")
@click.argument("deck", type=click.Path(exists=True, dir_okay=False))
@click.option("--ratios", default="1,2,3", callback=_number_list(int), show_default=True,
              help="Particle-spacing ratios (ALE element size / particle spacing), whole numbers.")
@click.option("--reference", default="ale", show_default=True,
              help="ale (the finest finished ALE case), finest (the finest SPH case) or PATH of a run folder.")
@click.option("--quantities", default=None, callback=lambda c, p, v: tuple(q for q in (v or "").split(",") if q),
              help="TABLE.COLUMN list, e.g. plate.displacement,plate.von_mises. Default: every requested history "
                   "but the driven ones (nodes with a prescribed velocity).")
@click.option("--tolerance", default="5%", callback=_fraction, show_default=True,
              help="Target normalised L2 error (the worst over the quantities), for the recommended ratio.")
@click.option("--workers", type=click.IntRange(min=1), default=1, show_default=True,
              help="Cases run at once as local processes.")
@click.option("--scheduler", default=None, help="Dask scheduler ADDRESS: run the cases on that cluster.")
@click.option("--ale-sizes", default="default", callback=_ale_sizes, show_default=True,
              help="ALE element sizes to run besides the deck's h (the reference's own convergence): default "
                   "h/2 and h/4 where the scene allows; none: the deck's h only; or a list s1,s2.")
@click.option("--threads", type=click.IntRange(min=1), default=1, show_default=True, help="Threads per case.")
@click.option("--end-time", type=click.FloatRange(min=0, min_open=True), default=None,
              help="Run every case to this time instead of the deck's end_time.")
@click.option("--verify", is_flag=True,
              help="Run the recommended ratio and report its predicted against its measured error and cost.")
@click.option("--filter", "filters", multiple=True, callback=lambda c, p, v: _study_filters(v),
              help="Compare low-passed series: [QUANTITY=]butterworth:CUTOFF[:ORDER] (zero phase, -3 dB at CUTOFF) "
                   "or [QUANTITY=]running_mean:WINDOW (causal), the same filter on every case and the reference; "
                   "without QUANTITY= for every quantity (repeatable). Default: raw samples.")
@click.option("-o", "--output", "outdir", type=click.Path(file_okay=False), default=None,
              help="Study folder. Default: <deck name>_study in the current directory.")
def mesh_study(deck, ratios, reference, quantities, tolerance, workers, scheduler, ale_sizes, threads, end_time,
               verify, filters, outdir) -> None:
    """Run DECK's ALE scene and its SPH variants at several ratios; report error, convergence and cost."""
    from rich.console import Console

    from .study import StudyConfig, StudyError, run_study
    from .study.report import table

    config = StudyConfig(deck=Path(deck), ratios=ratios, reference=reference, quantities=quantities or None,
                         tolerance=tolerance, workers=workers, scheduler=scheduler,
                         outdir=Path(outdir) if outdir else None, ale_sizes=ale_sizes, threads=threads,
                         end_time=end_time, verify=verify, filters=filters or None)
    try:
        out, result = run_study(config, echo=lambda line: click.echo(line, err=True))
    except StudyError as err:
        raise DeckProblem(str(err)) from None
    Console().print(table(result))
    click.echo(result["recommendation"]["text"])
    click.echo(f"report: {out / 'report.md'}")


@main.command()
@click.argument("directory", type=click.Path(exists=True, file_okay=False))
@click.option("--quantity", "quantities", multiple=True,
              help="Quantity to draw, TABLE.COLUMN or a column found in one table (repeatable). Default: every table.")
@click.option("--reference", "references", multiple=True, type=click.Path(exists=True, dir_okay=False),
              help="CSV of a reference curve (time, value in the run's units; '#' lines are comments) drawn with "
                   "each --quantity (repeatable); one with no point in the run's time window is left out, with a warning. "
                   "The deck's output.references are drawn without asking.")
@click.option("-o", "--output", "outdir", type=click.Path(file_okay=False), default=None,
              help="Folder for the PNGs. Default: DIRECTORY/plots.")
def plot(directory, quantities, references, outdir) -> None:
    """Draw the histories of a run folder, or of every case of a study folder, to PNG."""
    from .study.plots import plot_dir

    try:
        written = plot_dir(Path(directory), quantities, Path(outdir) if outdir else None,
                           [Path(r) for r in references], warn=lambda line: click.echo(line, err=True))
    except (FileNotFoundError, ValueError) as err:
        raise click.UsageError(str(err)) from None
    except KeyError as err:
        raise click.UsageError(err.args[0]) from None
    for path in written:
        click.echo(str(path))


@main.command()
@click.argument("directory", type=click.Path(exists=True, file_okay=False))
@click.option("--point", required=True, callback=_number_list(float), help="X,Y (2D) or X,Y,Z: where to sample.")
@click.option("--quantity", required=True, help="A saved field: displacement, velocity, von_mises, stress, pressure, ...")
@click.option("--part", default=None, help="The part to sample. Default: the first that holds the point and the field.")
@click.option("--name", default=None, help="Table name. Default: probe_<quantity>.")
@click.option("-o", "--output", "path", type=click.Path(dir_okay=False), default=None,
              help="CSV to write. Default: DIRECTORY/probes/<name>.csv.")
@click.option("--sensor-diameter", type=click.FloatRange(min=0.0), default=0.0,
              help="Mean over a sensor of this diameter (a face with --normal, else a disc / ball). Default 0: the point.")
@click.option("--normal", default=None, callback=_number_list(float),
              help="NX,NY[,NZ]: the wall normal; the sensor's face lies perpendicular to it.")
@click.option("--filter", "filter_spec", default=None,
              help="butterworth:CUTOFF[:ORDER] (zero phase, -3 dB at CUTOFF) or running_mean:WINDOW (causal); "
                   "adds a <column>_filtered column after each raw one.")
def probe(directory, point, quantity, part, name, path, sensor_diameter, normal, filter_spec) -> None:
    """Sample a saved run's field at a point over time (SPH by kernel interpolation, meshes by element)."""
    from .output.probe import ProbeError, probe as take

    if len(point) not in (2, 3):
        raise click.BadParameter(f"expected 2 or 3 coordinates, got {len(point)}", param_hint="--point")
    normal = normal or None
    if normal is not None and (len(normal) != len(point) or not any(normal)):
        raise click.BadParameter(f"expected a nonzero vector of {len(point)} components", param_hint="--normal")
    try:
        table = take(Path(directory), point, quantity, part, sensor=sensor_diameter, normal=normal,
                     filtering=_filter_spec(filter_spec))
    except ProbeError as err:
        raise click.UsageError(str(err)) from None
    name = name or f"probe_{quantity}"
    out = Path(path) if path else Path(directory) / "probes" / f"{name}.csv"
    table.write(out, f"{quantity} at {','.join(f'{c:g}' for c in point)} in part {table.part} of {directory}")
    click.echo(str(out))


def _filter_spec(spec: str | None) -> dict | None:
    """--filter's text as output.filters.low_pass settings."""
    if spec is None:
        return None
    kind, *numbers = spec.split(":")
    try:
        values = [float(v) for v in numbers]
    except ValueError:
        values = []
    if kind == "butterworth" and len(values) in (1, 2) and values[0] > 0 and (
            len(values) == 1 or (values[1].is_integer() and 1 <= values[1] <= 8)):
        return {"kind": kind, "cutoff": values[0], "order": int(values[1]) if len(values) == 2 else 2}
    if kind == "running_mean" and len(values) == 1 and values[0] > 0:
        return {"kind": kind, "window": values[0]}
    raise click.BadParameter(f"{spec!r}: expected butterworth:CUTOFF[:ORDER] (CUTOFF > 0, ORDER 1 to 8) or "
                             "running_mean:WINDOW (WINDOW > 0)", param_hint="--filter")


def _study_filters(specs) -> dict:
    """mesh-study --filter: {QUANTITY or "*": low_pass settings} from [QUANTITY=]SPEC entries."""
    out = {}
    for spec in specs or ():
        name, _, text = spec.rpartition("=")
        key = name.strip() or "*"
        if key in out:
            raise click.BadParameter(f"{spec!r}: a second filter for {'every quantity' if key == '*' else key}",
                                     param_hint="--filter")
        out[key] = _filter_spec(text.strip())
    return out


@main.command()
@click.option("-o", "--output", "path", type=click.Path(dir_okay=False), default=None,
              help="File to write. Default: standard output.")
def schema(path) -> None:
    """Write the deck's JSON Schema, for completion and checks in YAML editors (docs/deck-reference.md)."""
    from .deck.editor_schema import schema_text

    text = schema_text()
    if path is None:
        click.echo(text, nl=False)
        return
    try:
        Path(path).write_text(text)
    except OSError as err:
        click.echo(f"error: cannot write {path}: {err.strerror}", err=True)
        raise SystemExit(73) from None
    click.echo(path)


if __name__ == "__main__":  # pragma: no cover
    main()
