"""The `sphfem` command: a thin click shell over deck -> model -> solver -> output.

Exit codes: 0 ok, 2 usage (also: an output folder holding another run), 65 bad deck or unusable
checkpoint, 3 run stopped by a guard, 73 cannot create the output folder or a file in it, 74 I/O error
while writing (the files written so far are kept), 1 internal error, 130 interrupted by the user
(output so far kept). The exit codes 65, 73 and 74 are sysexits(3)'s EX_DATAERR, EX_CANTCREAT, EX_IOERR.
"""
from __future__ import annotations

import signal
import sys
import time
import traceback
from dataclasses import dataclass
from pathlib import Path

import click

from . import __version__

EXIT_OK, EXIT_INTERNAL, EXIT_USAGE, EXIT_GUARD, EXIT_DECK = 0, 1, 2, 3, 65
EXIT_INTERRUPTED = 130  # 128 + SIGINT, as shells report it
EXIT_CANTCREAT, EXIT_IOERR = 73, 74  # sysexits(3); output.runlog.io_failure chooses between them

# Below this much work per thread a parallel loop costs more in synchronisation than it saves.
ELEMENTS_PER_THREAD = 20_000


def default_threads(model) -> int:
    """One thread per ELEMENTS_PER_THREAD of work: solid elements, ALE elements and SPH particles."""
    work = (model.n_elements + (len(model.ale.elements) if model.ale is not None else 0)
            + (model.particles.n if model.particles is not None else 0))
    return max(1, work // ELEMENTS_PER_THREAD)


class DeckProblem(click.ClickException):
    """A bad deck: one line on stderr, exit 65."""

    exit_code = EXIT_DECK

    def show(self, file=None) -> None:
        click.echo(self.message, err=True)


class OutputProblem(DeckProblem):
    """An output folder that cannot be used: one line on stderr, exit `code` (2, 73 or 74)."""

    def __init__(self, message: str, code: int):
        super().__init__(message)
        self.exit_code = code


@dataclass
class Loaded:
    deck: object
    model: object
    path: Path


def load_model(deck_path: str) -> Loaded:
    """Read, validate and build; every deck problem becomes a one-line DeckProblem."""
    from .deck import loader
    from .deck.errors import DeckError, parse_path
    from .deck.schema import Deck
    from .deck.validate import validate_model
    from .model.build import ModelError, build_model

    try:
        data, positions = loader.load(deck_path)
        deck = validate_model(Deck, data, positions, deck_path)
    except DeckError as err:
        raise DeckProblem(str(err)) from None
    try:
        model = build_model(deck, Path(deck_path))
    except ModelError as err:
        line, col = positions.position_of(parse_path(err.path))
        raise DeckProblem(str(DeckError(err.message, file=deck_path, line=line, col=col, path=err.path))) from None
    return Loaded(deck, model, Path(deck_path))


class _Commands(click.Group):
    """The command group; an unexpected exception becomes one line and exit 1, never a traceback."""

    def invoke(self, ctx):
        try:
            return super().invoke(ctx)
        except (click.exceptions.Exit, click.ClickException, click.Abort, SystemExit):
            raise
        except KeyboardInterrupt:
            click.echo("interrupted", err=True)
            sys.exit(EXIT_INTERRUPTED)
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
              help="Output folder. Default: <deck name>_results beside the current directory "
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
    from .output.runlog import io_failure

    if restart and overwrite:
        raise OutputProblem("--overwrite and --restart exclude each other: --restart continues the run in its "
                            "folder, --overwrite replaces it", EXIT_USAGE)
    loaded = load_model(deck)
    import numba

    if threads is None:
        threads = default_threads(loaded.model)
    numba.set_num_threads(min(threads, numba.config.NUMBA_NUM_THREADS))
    out = (Path(outdir) if outdir else Path(restart).parent if restart
           else Path.cwd() / f"{Path(deck).stem}_results")
    if restart is None and not overwrite:
        from .output.folder import earlier_run

        earlier = earlier_run(out)
        if earlier:
            names = ", ".join(str(p.relative_to(out)) for p in earlier[:4]) + (", ..." if len(earlier) > 4 else "")
            raise OutputProblem(f"{out}: holds the results of an earlier run ({names}); nothing was changed: give "
                                "another folder with -o, --overwrite to replace that run, or --restart "
                                "CHECKPOINT to continue it", EXIT_USAGE)
    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError as err:
        raise OutputProblem(f"cannot create the output folder {out}: {io_failure(err, True)[1]}",
                            EXIT_CANTCREAT) from None
    code = execute(loaded, out, quiet=quiet, verbose=verbose, restart=Path(restart) if restart else None)
    sys.exit(code)


@main.command()
@click.argument("decks", nargs=-1, type=click.Path(exists=True, dir_okay=False))
@click.option("--update-refs", is_flag=True, help="Rewrite the reference files from this run.")
@click.option("--end-time-fraction", type=click.FloatRange(0.0, 1.0, min_open=True), default=None,
              help="Run each deck to this fraction of its end_time (default: the reference's end time, "
                   "else 0.1); a reference made at another end time fails unless --update-refs.")
@click.option("--references", type=click.Path(file_okay=False), default=None,
              help="Reference folder. Default: tests/regression/references of the project.")
@click.option("--failures-only", is_flag=True, help="List only the quantities that failed.")
def regress(decks, update_refs, end_time_fraction, references, failures_only) -> None:
    """Run DECKS (default: every decks/*.yaml) briefly and compare energies and histories with stored references."""
    from .regress import main as regress_main

    sys.exit(regress_main(decks, update=update_refs, fraction=end_time_fraction, references=references,
                          failures_only=failures_only, echo=click.echo))


def execute(loaded: Loaded, out: Path, quiet: bool = False, verbose: bool = False, restart: Path | None = None) -> int:
    """Run a built model into `out`; returns the exit code. Keeps the effective deck and a log.

    Without `restart` the files of an earlier run in `out` are removed first, and nothing else there
    (output.folder; the `run` command refuses such a folder unless --overwrite, library callers such as
    the mesh study's cases replace an earlier attempt). Checkpoints go to `out`/checkpoint.npz: at every
    field output, or every control.checkpoint_interval of simulated time and
    control.checkpoint_wall_interval of wall time, and when Ctrl-C or SIGTERM stops the run (after the
    step under way; a second signal stops at once, without a checkpoint). `restart` continues the run
    of a checkpoint in `out`: the Simulation is built from the deck and its state restored from the
    checkpoint (output.checkpoint). A checkpoint that cannot be used raises DeckProblem (exit 65), a
    folder or file that cannot be created OutputProblem (exit 73); a write that fails during the run
    ends it with exit 73 or 74, the files written so far kept.
    """
    import numba
    import numpy as np
    import yaml

    from .output.checkpoint import (CHECKPOINT_NAME, CheckpointError, deck_hash, read_checkpoint,
                                    restore_simulation, write_checkpoint)
    from .output.folder import clear_earlier_run, manifest_deck, write_manifest
    from .output.runlog import RunLog, errno_of, io_failure
    from .output.results import RunOutput, history_tables
    from .solver.explicit import RunStopped, Simulation

    digest = deck_hash(loaded.deck, loaded.model)
    payload = sim = None
    if restart is not None:
        try:
            payload = read_checkpoint(restart, digest)
            sim = Simulation(loaded.model)
            restore_simulation(sim, payload, restart)
        except CheckpointError as err:
            raise DeckProblem(str(err)) from None
        if manifest_deck(out) not in (None, digest):
            raise DeckProblem(f"{restart}: the output folder {out} does not hold the run of this checkpoint (it "
                              "holds a run of another deck); give the run's folder with -o")
    checkpoint_path = out / CHECKPOINT_NAME

    try:
        if payload is None:
            clear_earlier_run(out)
            write_manifest(out, history_tables(loaded.model), digest)
        (out / "deck.effective.yaml").write_text(
            f"# {loaded.path} with every default filled in (sphfem {__version__})\n"
            + yaml.safe_dump(loaded.deck.model_dump(mode="json"), sort_keys=False, allow_unicode=True),
            encoding="utf-8")
        log = RunLog(out / "run.log", loaded.path, append=payload is not None)
    except OSError as err:
        raise OutputProblem(f"cannot create the run's files in {out}: {io_failure(err, True)[1]}",
                            EXIT_CANTCREAT) from None
    stop = _StopRequest()
    previous = _install(stop)
    start = time.perf_counter()
    status, message, stopped, io_code = "completed", "", None, 0
    output = None
    creating = True  # until the output files exist, an OSError means they cannot be created
    control = loaded.deck.control
    last_checkpoint: tuple[float, int] | None = None
    np_errors = np.seterr(all="ignore")  # overflow and invalid values stop the run through the finite-state guard
    try:
        if payload is None:
            sim = Simulation(loaded.model)
            output = RunOutput(sim, out)
        else:
            try:
                output = RunOutput(sim, out, resume=payload["output"])
            except (OSError, ValueError, KeyError, TypeError) as err:
                if isinstance(err, OSError) and not isinstance(err, FileNotFoundError) and errno_of(err) is not None:
                    raise  # the files are there but cannot be written: exit 73 below
                raise DeckProblem(f"{restart}: the output folder {out} does not hold the run of this checkpoint "
                                  f"({err}); give the run's folder with -o") from None
            log.write(f"restarted from {restart} at t = {sim.state.time:.6e}, step {sim.state.step}\n")
            last_checkpoint = (sim.state.time, sim.state.step)
        creating = False
        output()
        next_checkpoint = [_next_multiple(sim.state.time, control.checkpoint_interval)]
        last_wall = [time.monotonic()]

        def checkpoint(st) -> None:
            nonlocal last_checkpoint
            write_checkpoint(checkpoint_path, sim, output.state(), digest)
            last_checkpoint = (st.time, st.step)
            last_wall[0] = time.monotonic()

        with _Progress(sim, enabled=not quiet and sys.stderr.isatty()) as progress:
            def on_step(st):
                fields_before = output.xdmf.n_steps
                output()
                if control.checkpoint_interval is None:
                    due = output.xdmf.n_steps > fields_before
                else:
                    due = st.time >= next_checkpoint[0] * (1.0 - 1e-12)
                    if due:
                        next_checkpoint[0] = _next_multiple(st.time, control.checkpoint_interval)
                wall = control.checkpoint_wall_interval
                if due or (wall is not None and time.monotonic() - last_wall[0] >= wall):
                    checkpoint(st)
                if stop.signum is not None:
                    checkpoint(st)  # the step is complete: a consistent state to restart from
                    raise _Interrupted
                progress.update(st)
                if verbose and output.xdmf.n_steps > fields_before:
                    row = sim.energy_row()
                    progress.echo(f"t = {row.time:.5e}  step {st.step}  dt {row.dt:.3e}  kinetic {row.kinetic:.4e}  "
                                  f"internal {row.internal:.4e}  hourglass {row.hourglass:.3e}  "
                                  f"energy ratio {row.ratio:.5f}")
            sim.run(on_step, next_stop=output.next_field_time)
    except RunStopped as err:
        status, message, stopped = "stopped by a guard", str(err), err
    except DeckProblem:
        log.close("refused", "", 0.0, 0, numba.get_num_threads())
        for sig, handler in previous.items():
            signal.signal(sig, handler)
        raise
    except KeyboardInterrupt as err:
        status = "interrupted"
        message = "interrupted; the output so far is kept and the last state written"
        if isinstance(err, _Interrupted):
            message += f"; continue with --restart {checkpoint_path}"
    except OSError as err:
        io_code, reason = io_failure(err, creating)
        status, message = "I/O error", reason
    except Exception as err:  # noqa: BLE001 - the CLI's last line of defence
        status, message = "internal error", f"{type(err).__name__}: {err}"
        log.write(traceback.format_exc())
    finally:
        for sig, handler in previous.items():
            signal.signal(sig, handler)
        try:
            if output is not None:
                try:
                    if status not in ("completed", "I/O error"):
                        output(force=True)
                except OSError as err:
                    if status != "I/O error":
                        io_code, message = io_failure(err, False)
                        status = "I/O error"
                finally:
                    try:
                        output.close()
                    except OSError as err:
                        if status != "I/O error":
                            io_code, message = io_failure(err, False)
                            status = "I/O error"
        finally:
            np.seterr(**np_errors)
    wall = time.perf_counter() - start
    steps = output.sim.state.step if output else 0
    eroded = output.sim.erosion_summary() if output else ""
    if eroded:
        log.write(f"erosion: {eroded}\n" + "".join(f"  t = {t:.6e}: element {e} of part '{p}' ({why})\n"
                                                   for t, e, p, why in output.sim.eroded))
    log.close(status, message, wall, steps, numba.get_num_threads())
    if log.error is not None and status == "completed":
        io_code, message = io_failure(log.error, False)
        status = "I/O error"
    if status == "completed":
        if not quiet:
            row = output.last_energy
            click.echo(f"completed: t = {output.sim.state.time:.6g}, {steps} steps, {wall:.2f} s wall, "
                       f"energy ratio {row.ratio:.4f}{'; ' + eroded if eroded else ''}; results in {out}", err=True)
        return EXIT_OK
    if status == "stopped by a guard":
        try:
            _write_diagnostics(out / "diagnostics.txt", stopped, output, last_checkpoint, checkpoint_path, loaded.path)
        except OSError as err:
            message += f" (diagnostics.txt not written: {io_failure(err, False)[1]})"
        click.echo(f"run stopped: {message}; last state written to {out}", err=True)
        return EXIT_GUARD
    if status == "interrupted":
        click.echo(message, err=True)
        return EXIT_INTERRUPTED
    if status == "I/O error":
        kept = (f"; the last checkpoint is {checkpoint_path} (t = {last_checkpoint[0]:.6e}, step {last_checkpoint[1]})"
                if last_checkpoint is not None else "")
        what = "cannot create the output" if io_code == EXIT_CANTCREAT else "writing the output failed"
        at = f" at t = {sim.state.time:.6e}, step {sim.state.step}" if sim is not None else ""
        click.echo(f"{what} in {out}: {message}; the run stopped{at}, the files written so far are kept{kept}",
                   err=True)
        return io_code
    click.echo(f"internal error: {message} (details in {out / 'run.log'})", err=True)
    return EXIT_INTERNAL


class _Interrupted(KeyboardInterrupt):
    """Ctrl-C or SIGTERM, acted on after a complete step (a checkpoint was written)."""


class _StopRequest:
    """Signal handler for SIGINT and SIGTERM: the first asks the loop to stop after the step under way
    (checkpoint, last state, files closed); a second stops at once."""

    def __init__(self):
        self.signum: int | None = None

    def __call__(self, signum, frame):
        if self.signum is not None:
            raise KeyboardInterrupt
        self.signum = signum


def _install(handler) -> dict:
    """Install `handler` for SIGINT and SIGTERM; the previous handlers (none outside the main thread,
    where signals cannot be caught and a run keeps the caller's handling)."""
    previous = {}
    for sig in (signal.SIGINT, signal.SIGTERM):
        try:
            previous[sig] = signal.signal(sig, handler)
        except ValueError:
            break
    return previous


def _next_multiple(t: float, interval: float | None) -> float:
    """The first multiple of interval after t (inf without an interval)."""
    if interval is None:
        return float("inf")
    return (int((t + 1e-9 * interval) // interval) + 1) * interval


_REMEDIES = {
    "non_finite": "lower timestep_scale; check material constants, equations of state and units",
    "negative_volume": "lower timestep_scale; refine the mesh where it inverts; raise the hourglass stiffness; "
                       "or let the part erode (parts.<name>.erosion)",
    "time_step": "look at the element or domain named; a collapsing element or violent impact; lower dt_min",
    "energy_ratio": "lower timestep_scale; raise the hourglass stiffness when hourglass energy grows; refine; "
                    "check contact stiffness; widen control.energy_band if the energy change is physical",
    "lost_particles": "enlarge the SPH section's domain or add walls; lower timestep_scale if particles were "
                      "thrown out by a blow-up; raise control.max_lost_fraction",
    "penetration": "raise the contact's penalty_scale; lower timestep_scale; refine the master surface",
}


def _write_diagnostics(path: Path, err, output, last_checkpoint, checkpoint_path: Path, deck: Path) -> None:
    """diagnostics.txt: which guard, where, the values, the state at the stop, what to try, where to restart."""
    sim = output.sim if output is not None else None
    lines = [f"guard: {err.guard or 'unnamed'}", f"message: {err}"]
    if sim is not None:
        st = sim.state
        lines.append(f"stopped at: t = {st.time:.9e}, step {st.step}, last dt {st.dt_prev:.6e}")
    for key, value in err.values.items():
        lines.append(f"  {key}: {value}")
    if output is not None and output.last_energy is not None:
        row = output.last_energy
        lines.append("last history row: " + ", ".join(f"{name} {value:.6e}" for name, value in
                                                     zip(row.COLUMNS, row.values())))
    if sim is not None and sim.eroded:
        lines.append(f"erosion: {sim.erosion_summary()}")
    lines.append(f"remedies: {_REMEDIES.get(err.guard, 'see the message')}")
    lines.append("state at the stop: the last step of results.xdmf / results.h5 and the history tables")
    if last_checkpoint is not None:
        lines.append(f"last good state: {checkpoint_path} (t = {last_checkpoint[0]:.9e}, step {last_checkpoint[1]}); "
                     f"sphfem run {deck} --restart {checkpoint_path} continues from it with the same deck")
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")


class _Progress:
    """A rich progress bar on stderr (simulated time, step, dt, ETA), only on a terminal."""

    def __init__(self, sim, enabled: bool):
        self.sim = sim
        self.enabled = enabled
        self._last = 0.0

    def __enter__(self):
        if self.enabled:
            from rich.progress import BarColumn, Progress, TextColumn, TimeRemainingColumn

            self.bar = Progress(
                TextColumn("t = {task.fields[t]:.4e}"), BarColumn(),
                TextColumn("step {task.fields[step]} dt {task.fields[dt]:.2e}"), TimeRemainingColumn(),
                transient=True, console=None,
            )
            self.bar.__enter__()
            self.task = self.bar.add_task("run", total=self.sim.control.end_time, t=0.0, step=0, dt=0.0)
        return self

    def update(self, st) -> None:
        if not self.enabled:
            return
        now = time.perf_counter()
        if now - self._last > 0.2:
            self._last = now
            self.bar.update(self.task, completed=st.time, t=st.time, step=st.step, dt=st.dt_prev)

    def echo(self, line: str) -> None:
        """A line on stderr that does not break the bar."""
        if self.enabled:
            self.bar.console.print(line, highlight=False)
        else:
            click.echo(line, err=True)

    def __exit__(self, *exc):
        if self.enabled:
            self.bar.__exit__(*exc)
        return False


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
@click.option("-o", "--output", "outdir", type=click.Path(file_okay=False), default=None,
              help="Study folder. Default: <deck name>_study in the current directory.")
def mesh_study(deck, ratios, reference, quantities, tolerance, workers, scheduler, ale_sizes, threads, end_time,
               verify, outdir) -> None:
    """Run DECK's ALE scene and its SPH variants at several ratios; report error, convergence and cost."""
    from rich.console import Console

    from .study import StudyConfig, StudyError, run_study
    from .study.report import table

    config = StudyConfig(deck=Path(deck), ratios=ratios, reference=reference, quantities=quantities or None,
                         tolerance=tolerance, workers=workers, scheduler=scheduler,
                         outdir=Path(outdir) if outdir else None, ale_sizes=ale_sizes, threads=threads,
                         end_time=end_time, verify=verify)
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
                   "each --quantity (repeatable). The deck's output.references are drawn without asking.")
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
