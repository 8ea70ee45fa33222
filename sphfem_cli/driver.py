"""The run driver: deck -> model (``load_model``), a prepared output folder (``prepare_folder``), and
the run into it (``execute``) with its checkpoints, guards' diagnostics, log and progress lines.
``api`` is the public face of this module; ``cli`` and ``regress`` and the mesh study call it.

Exit codes (``RunOutcome.code``, the CLI's exit status): 0 ok, 2 usage (also: an output folder
holding another run), 65 bad deck or unusable checkpoint, 3 run stopped by a guard, 73 cannot create
the output folder or a file in it, 74 I/O error while writing (the files written so far are kept),
1 internal error, 130 interrupted by the user (output so far kept). 65, 73 and 74 are sysexits(3)'s
EX_DATAERR, EX_CANTCREAT, EX_IOERR.
"""
from __future__ import annotations

import os
import signal
import sys
import threading
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


class DeckProblem(Exception):
    """A bad deck or an unusable checkpoint: `message` is one line (file:line:col: ...); exit 65."""

    exit_code = EXIT_DECK

    def __init__(self, message: str):
        super().__init__(message)
        self.message = message


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
    from .deck.errors import DeckError

    try:
        data, positions = loader.load(deck_path)
    except DeckError as err:
        raise DeckProblem(str(err)) from None
    return build_loaded(data, positions, Path(deck_path))


def build_loaded(data, positions, deck_path: Path) -> Loaded:
    """Validate a deck's data (``positions`` map key paths to line and column of ``deck_path``) and build
    its model; files named in the deck are read relative to ``deck_path``'s folder."""
    from .deck.errors import DeckError, parse_path
    from .deck.schema import Deck
    from .deck.validate import validate_model
    from .model.build import ModelError, build_model

    try:
        deck = validate_model(Deck, data, positions, str(deck_path))
    except DeckError as err:
        raise DeckProblem(str(err)) from None
    try:
        model = build_model(deck, Path(deck_path))
    except ModelError as err:
        line, col = positions.position_of(parse_path(err.path))
        raise DeckProblem(str(DeckError(err.message, file=str(deck_path), line=line, col=col, path=err.path))) from None
    return Loaded(deck, model, Path(deck_path))


def prepare_folder(out: Path, restart: Path | None = None, overwrite: bool = False) -> Path:
    """Check and create the output folder of a run: a folder holding another run's results is refused
    (OutputProblem, exit 2) unless `overwrite` or `restart`; one that cannot be made exits 73."""
    from .output.runlog import io_failure

    if restart is not None and overwrite:
        raise OutputProblem("--overwrite and --restart exclude each other: --restart continues the run in its "
                            "folder, --overwrite replaces it", EXIT_USAGE)
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
    return out


@dataclass(frozen=True)
class RunOutcome:
    """How a run ended: `code` (the exit codes above), `status` ("completed", "stopped by a guard",
    "interrupted", "I/O error", "internal error"), the one-line `message`, the simulated `time` and
    `steps` reached and the `wall` seconds."""

    code: int
    status: str
    message: str
    time: float
    steps: int
    wall: float


def execute(loaded: Loaded, out: Path, quiet: bool = False, verbose: bool = False,
            restart: Path | None = None, announced: bool = False) -> RunOutcome:
    """Run a built model into `out`; returns how it ended (`RunOutcome.code` is the exit code). Keeps the
    effective deck and a log.

    Without `restart` the files of an earlier run in `out` are removed first, and nothing else there
    (output.folder; the `run` command refuses such a folder unless --overwrite, library callers such as
    the mesh study's cases replace an earlier attempt). Checkpoints go to `out`/checkpoint.npz: at every
    field output, or every control.checkpoint_interval of simulated time and
    control.checkpoint_wall_interval of wall time, and when Ctrl-C or SIGTERM stops the run (after the
    step under way; a second signal stops at once, without a checkpoint). `restart` continues the run
    of a checkpoint in `out`: the Simulation is built from the deck and its state restored from the
    checkpoint (output.checkpoint). A checkpoint that cannot be used raises DeckProblem (exit 65), a
    folder or file that cannot be created OutputProblem (exit 73); a write that fails during the run
    ends it with exit 73 or 74, the files written so far kept. `announced`: the caller has printed
    ``announce_compiling``'s notice before it built the model (which compiles some kernels itself).
    """
    from .output.checkpoint import deck_hash

    digest = deck_hash(loaded.deck, loaded.model)
    progress = _Progress(loaded.deck.control.end_time, quiet, sys.stderr.isatty(), announced)
    try:
        return _execute(loaded, out, verbose, restart, digest, progress)
    finally:
        progress.cancel()


def _execute(loaded: Loaded, out: Path, verbose: bool, restart: Path | None, digest: str, progress) -> RunOutcome:
    """`execute` once its progress lines are set up."""
    import numba
    import numpy as np
    import yaml

    from .output.checkpoint import (CHECKPOINT_NAME, CheckpointError, read_checkpoint, restore_simulation,
                                    write_checkpoint)
    from .output.folder import clear_earlier_run, manifest_deck, write_manifest
    from .output.runlog import RunLog, errno_of, io_failure
    from .output.results import RunOutput, history_tables, output_grids
    from .solver.explicit import RunStopped, Simulation

    quiet = progress.quiet
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
            write_manifest(out, history_tables(loaded.model), digest, output_grids(loaded.model))
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

        with progress:
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
        output.write_final_state()
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
    for line in output.warnings if output else ():
        log.write(f"warning: {line}\n")
        click.echo(f"warning: {line}", err=True)
    if eroded:
        log.write(f"erosion: {eroded}\n" + "".join(f"  t = {t:.6e}: element {e} of part '{p}' ({why})\n"
                                                   for t, e, p, why in output.sim.eroded))
    log.close(status, message, wall, steps, numba.get_num_threads())
    if log.error is not None and status == "completed":
        io_code, message = io_failure(log.error, False)
        status = "I/O error"
    t_end = output.sim.state.time if output else 0.0
    if status == "completed":
        code = EXIT_OK
        if not quiet:
            row = output.last_energy
            click.echo(f"completed: t = {t_end:.6g}, {steps} steps, {wall:.2f} s wall, "
                       f"energy ratio {row.ratio:.4f}{'; ' + eroded if eroded else ''}; results in {out}", err=True)
    elif status == "stopped by a guard":
        code = EXIT_GUARD
        try:
            _write_diagnostics(out / "diagnostics.txt", stopped, output, last_checkpoint, checkpoint_path, loaded.path)
        except OSError as err:
            message += f" (diagnostics.txt not written: {io_failure(err, False)[1]})"
        click.echo(f"run stopped: {message}; last state written to {out}", err=True)
    elif status == "interrupted":
        code = EXIT_INTERRUPTED
        click.echo(message, err=True)
    elif status == "I/O error":
        code = io_code
        kept = (f"; the last checkpoint is {checkpoint_path} (t = {last_checkpoint[0]:.6e}, step {last_checkpoint[1]})"
                if last_checkpoint is not None else "")
        what = "cannot create the output" if io_code == EXIT_CANTCREAT else "writing the output failed"
        at = f" at t = {sim.state.time:.6e}, step {sim.state.step}" if sim is not None else ""
        click.echo(f"{what} in {out}: {message}; the run stopped{at}, the files written so far are kept{kept}",
                   err=True)
    else:
        code = EXIT_INTERNAL
        click.echo(f"internal error: {message} (details in {out / 'run.log'})", err=True)
    return RunOutcome(code, status, message, t_end, steps, wall)


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
    "energy_injected": "lower timestep_scale; use the stiffness hourglass form or raise its coefficient; erode "
                       "crushed elements (erosion.min_time_step_ratio); check contact stiffness and initial "
                       "penetrations; widen control.energy_band",
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


HEARTBEAT_S = 30.0  # wall seconds between progress lines when stderr is not a terminal
SLOW_START_S = 5.0  # wall seconds before the first step after which a run says what it is doing


def kernel_cache_is_cold() -> bool:
    """True when numba's cache (NUMBA_CACHE_DIR, keyed by the kernels' sources) holds no compiled kernel."""
    folder = os.environ.get("NUMBA_CACHE_DIR")
    return bool(folder) and not any(Path(folder).rglob("*.nbi"))


def announce_compiling(quiet: bool) -> bool:
    """Say "compiling kernels (first run only; cached in ...)" on stderr when numba's cache is cold;
    True when it was said. Called before the model is built: building compiles some kernels (the
    EOS of a hydrostatic start, a fill's sample points), after which the cache is no longer empty."""
    if quiet or not kernel_cache_is_cold():
        return False
    click.echo(f"compiling kernels (first run only; cached in {os.environ.get('NUMBA_CACHE_DIR')})", err=True)
    return True


class _Progress:
    """Progress on stderr, nothing when quiet. Before the first step: "compiling kernels" at once when the
    numba cache is cold (unless the caller said it before building the model: `announced`), else a
    line after SLOW_START_S. Then a rich bar on a terminal (simulated time,
    step, dt, ETA), or elsewhere (a log, a batch job) a line every HEARTBEAT_S of wall time with t, step,
    dt, wall time and ETA."""

    def __init__(self, end_time: float, quiet: bool, terminal: bool, announced: bool = False):
        self.end_time = end_time
        self.quiet = quiet
        self.bar_on = not quiet and terminal
        self._last = 0.0
        self._started = time.monotonic()
        self._first: tuple[float, float] | None = None  # (wall, t) at the first step
        self._timer: threading.Timer | None = None
        if quiet or announced or announce_compiling(quiet):
            return
        cache = os.environ.get("NUMBA_CACHE_DIR", "numba's cache")
        self._timer = threading.Timer(SLOW_START_S, click.echo, (
            f"preparing the first step: building the model or compiling kernels new to the cache ({cache}); "
            "later runs of this kind start faster",), {"err": True})
        self._timer.daemon = True
        self._timer.start()

    def __enter__(self):
        if self.bar_on:
            from rich.progress import BarColumn, Progress, TextColumn, TimeRemainingColumn

            self.bar = Progress(
                TextColumn("t = {task.fields[t]:.4e}"), BarColumn(),
                TextColumn("step {task.fields[step]} dt {task.fields[dt]:.2e}"), TimeRemainingColumn(),
                transient=True, console=None,
            )
            self.bar.__enter__()
            self.task = self.bar.add_task("run", total=self.end_time, t=0.0, step=0, dt=0.0)
        return self

    def update(self, st) -> None:
        if self.quiet:
            return
        now = time.monotonic()
        if self._first is None:
            self._first = (now, st.time)
            self._last = now
            self.cancel()
        if self.bar_on:
            if now - self._last > 0.2:
                self._last = now
                self.bar.update(self.task, completed=st.time, t=st.time, step=st.step, dt=st.dt_prev)
        elif now - self._last >= HEARTBEAT_S:
            self._last = now
            w0, t0 = self._first
            rate = (st.time - t0) / (now - w0) if now > w0 and st.time > t0 else 0.0
            eta = f"{(self.end_time - st.time) / rate:.0f} s" if rate > 0 else "unknown"
            click.echo(f"t = {st.time:.4e} of {self.end_time:.4e}, step {st.step}, dt {st.dt_prev:.3e}, "
                       f"wall {now - self._started:.0f} s, ETA {eta}", err=True)

    def echo(self, line: str) -> None:
        """A line on stderr that does not break the bar."""
        if self.bar_on:
            self.bar.console.print(line, highlight=False)
        else:
            click.echo(line, err=True)

    def cancel(self) -> None:
        if self._timer is not None:
            self._timer.cancel()
            self._timer = None

    def __exit__(self, *exc):
        self.cancel()
        if self.bar_on:
            self.bar.__exit__(*exc)
        return False
