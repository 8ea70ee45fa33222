"""Cases of a study: one folder each (deck.yaml, status.json, run/), each run in a process of its own.

A case runs through the library (``cli.load_model`` then ``cli.execute``) in a fresh interpreter,
``python -m sphfem_cli.study CASE_DIR``, so that its memory and its numba state are its own:

- local: up to ``workers`` such processes at once, started and watched here; a process that dies
  (killed, out of memory) fails its own case only, and the queue goes on;
- Dask: each task starts the same process on its worker and returns the status (Dask workers are
  daemonic and long-lived, and a crashing case must not take a worker down). The case folders
  must be on a file system the workers share.

What a case measures (``run_case``), numba compilation kept out of the clock:

- warm-up: the same deck run for a few steps into a scratch folder first, so that every kernel
  the run calls is compiled (or loaded from numba's cache) before the clock starts; a warm-up
  that compiled re-executes the case process once (same pid), which then loads the kernels from
  the cache it just filled, so the compiler's memory is not in the timed runs' peak;
  ``compile_s`` is the time numba spent compiling (its ``numba:compile`` events), in the warm-up
  and, if a kernel first called later still compiles, in the timed run, where it is subtracted;
- ``cpu_s``: user + system CPU of the timed model build and run (``time.process_time``), the
  median over repeats: a case is run again while its runs so far and one more like
  the last stay within ``repeat_budget_s`` (at most ``max_repeats`` runs), and ``cpu_spread`` = (max - min) / median;
- ``peak_mib``: peak resident memory (``VmHWM``) of the timed runs, the high-water mark reset
  after the warm-up (``/proc/self/clear_refs``), so a compile's memory is not charged to the run;
  ``ru_maxrss`` where that is not available;
- ``dt0``: the first stable step of each domain (solid, sph, ale, contact), for the step law.

``status.json`` holds ``state`` (running, done, failed), the deck's SHA-256 and the measurements;
a case whose status is done for the same deck is skipped on a rerun.
"""
from __future__ import annotations

import hashlib
import json
import os
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Callable, Iterable

STATUS = "status.json"
DECK = "deck.yaml"
RUN = "run"
LOG = "case.log"  # the case process's stderr
WARM_STEPS = 5


def deck_hash(case_dir: Path) -> str:
    return hashlib.sha256((Path(case_dir) / DECK).read_bytes()).hexdigest()


def read_status(case_dir: Path) -> dict:
    path = Path(case_dir) / STATUS
    if not path.exists():
        return {"state": "new"}
    try:
        return json.loads(path.read_text())
    except json.JSONDecodeError:
        return {"state": "broken"}


def write_status(case_dir: Path, status: dict) -> None:
    path = Path(case_dir) / STATUS
    tmp = path.with_suffix(".tmp")
    tmp.write_text(json.dumps(status, indent=2) + "\n")
    os.replace(tmp, path)


def is_done(case_dir: Path) -> bool:
    """Finished for the deck now in the folder."""
    status = read_status(case_dir)
    return status.get("state") == "done" and status.get("deck_sha256") == deck_hash(case_dir)


def _steps(run_dir: Path) -> int | None:
    log = run_dir / "run.log"
    if log.exists():
        m = re.search(r"^steps: (\d+)$", log.read_text(), re.MULTILINE)
        if m:
            return int(m.group(1))
    return None


def _reset_peak() -> bool:
    try:
        Path("/proc/self/clear_refs").write_text("5")
        return True
    except OSError:
        return False


def _peak_mib(reset: bool) -> float:
    if reset:
        m = re.search(r"^VmHWM:\s+(\d+) kB", Path("/proc/self/status").read_text(), re.MULTILINE)
        if m:
            return int(m.group(1)) / 1024.0
    import resource

    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0  # Linux reports KiB


def _first_steps(sim) -> dict:
    """The first stable step of each domain (each already scaled by timestep_scale)."""
    scale = sim.control.timestep_scale
    dt = {d.kind: float(d.stable_dt(scale)) for d in sim.domains}
    if sim.interactions:
        dt["contact"] = float(min(scale * it.stable_dt() for it in sim.interactions))
    return {k: (v if v == v and v != float("inf") else None) for k, v in dt.items()}


def _warm_up(deck: Path) -> dict:
    """Run the deck for WARM_STEPS steps into a scratch folder (compiles or loads every kernel it calls);
    returns the first stable step of each domain."""
    from ..driver import execute, load_model
    from ..model.options import resolve_options
    from ..solver.explicit import Simulation

    sim = Simulation(load_model(str(deck)).model)
    first = _first_steps(sim)
    loaded = load_model(str(deck))
    loaded.deck.control.end_time = min(loaded.deck.control.end_time, WARM_STEPS * sim.stable_dt())
    loaded.model.options = resolve_options(loaded.deck, loaded.model)  # the run reads the changed deck's settings
    scratch = Path(tempfile.mkdtemp(prefix="sphfem-warm-"))
    try:
        execute(loaded, scratch, quiet=True)
    finally:
        shutil.rmtree(scratch, ignore_errors=True)
    return first


def run_case(case_dir: str, threads: int = 1, repeat_budget_s: float = 4.0, max_repeats: int = 3,
             compiled_before: tuple[float, float] | None = None, reexec: bool = False) -> dict:
    """Run the case in ``case_dir`` in this process (warm-up, then timed runs); write and return its status.

    With ``reexec`` (the case process), a warm-up that compiled kernels re-executes the process once
    (``os.execv``, same pid) with ``compiled_before`` = (its compile seconds, its warm-up CPU): the
    new image loads the kernels from the cache numba just wrote, so the compiler's memory and
    state stay out of the timed runs."""
    from numba.core import event

    case = Path(case_dir)
    sha = deck_hash(case)
    write_status(case, {"state": "running", "deck_sha256": sha, "pid": os.getpid(),
                        "started": time.strftime("%Y-%m-%d %H:%M:%S")})
    status: dict = {"deck_sha256": sha, "pid": os.getpid()}
    compiling = event.TimingListener()
    event.register("numba:compile", compiling)

    def compiled() -> float:
        return compiling.duration if compiling.done else 0.0

    start_wall = time.perf_counter()
    reset = False
    try:
        import numba

        from ..driver import DeckProblem, execute, load_model

        numba.set_num_threads(max(1, min(int(threads), numba.config.NUMBA_NUM_THREADS)))
        deck = case / DECK
        c0 = time.process_time()
        try:
            status["dt0"] = _warm_up(deck)
        except DeckProblem as err:
            raise RuntimeError(f"bad deck: {err.message}") from None
        status.update(warmup_cpu_s=time.process_time() - c0, warmup_compile_s=compiled())
        if reexec and compiled_before is None and compiled() > 0:
            sys.stdout.flush()
            sys.stderr.flush()
            os.execv(sys.executable, _command(case, threads) + [
                "--compiled", repr(compiled()), "--warmup-cpu", repr(status["warmup_cpu_s"])])
        if compiled_before is not None:
            status.update(warmup_compile_s=status["warmup_compile_s"] + compiled_before[0],
                          warmup_cpu_s=status["warmup_cpu_s"] + compiled_before[1], reexecuted=True)
        reset = _reset_peak()
        cpu_runs, compile_in_runs, walls = [], 0.0, []
        run_dir = case / RUN
        while True:
            first = not cpu_runs
            target = run_dir if first else Path(tempfile.mkdtemp(prefix="sphfem-repeat-"))
            k0, c0, w0 = compiled(), time.process_time(), time.perf_counter()
            try:
                loaded = load_model(str(deck))
                if first:
                    model = loaded.model
                    status.update(
                        particles=int(model.particles.n) if model.particles is not None else 0,
                        ale_elements=int(len(model.ale.elements)) if model.ale is not None else 0,
                        solid_elements=int(model.n_elements), threads=numba.get_num_threads())
                    run_dir.mkdir(exist_ok=True)
                code = execute(loaded, target, quiet=True).code
            finally:
                if not first:
                    shutil.rmtree(target, ignore_errors=True)
            k = compiled() - k0
            compile_in_runs += k
            cpu_runs.append(time.process_time() - c0 - k)
            walls.append(time.perf_counter() - w0 - k)
            if code != 0:
                why = run_dir / "diagnostics.txt"
                status.update(state="failed", exit_code=int(code), message=why.read_text().strip() if why.exists()
                              else f"exit status {code}, see {run_dir / 'run.log'}")
                break
            if first:
                status.update(exit_code=0, steps=_steps(run_dir))
            if len(cpu_runs) >= max_repeats or sum(cpu_runs) + cpu_runs[-1] > repeat_budget_s:
                status["state"] = "done"
                break
        med = sorted(cpu_runs)[len(cpu_runs) // 2] if len(cpu_runs) % 2 else \
            0.5 * sum(sorted(cpu_runs)[len(cpu_runs) // 2 - 1:len(cpu_runs) // 2 + 1])
        status.update(cpu_s=med, cpu_runs=cpu_runs, cpu_spread=(max(cpu_runs) - min(cpu_runs)) / med if med > 0 else 0.0,
                      wall_s=walls[0], compile_s=status["warmup_compile_s"] + compile_in_runs,
                      compile_in_run_s=compile_in_runs)
    except Exception as err:  # noqa: BLE001 - a case failure is recorded, never raised
        status.update(state="failed", message=f"{type(err).__name__}: {err}")
    finally:
        event.unregister("numba:compile", compiling)
    status.setdefault("wall_s", time.perf_counter() - start_wall)
    status.update(peak_mib=_peak_mib(reset), finished=time.strftime("%Y-%m-%d %H:%M:%S"))
    write_status(case, status)
    return status


def _command(case_dir: Path, threads: int) -> list[str]:
    return [sys.executable, "-m", "sphfem_cli.study", str(case_dir), "--threads", str(threads)]


def _settle(case_dir: Path, returncode: int) -> dict:
    """The status of a case whose process ended with ``returncode``; a process that died fails its case."""
    status = read_status(case_dir)
    if returncode == 0 and status.get("state") in ("done", "failed"):
        return status
    if returncode < 0:
        try:
            name = signal.Signals(-returncode).name
        except ValueError:
            name = f"signal {-returncode}"
        why = f"the case process was killed by {name}"
    else:
        why = f"the case process exited with status {returncode}"
    log = Path(case_dir) / LOG
    tail = log.read_text(errors="replace").strip()[-500:] if log.exists() else ""
    status = dict(status, state="failed", message=why + (f": {tail}" if tail else "") + "; rerun the study to retry it")
    write_status(case_dir, status)
    return status


def run_case_subprocess(case_dir: str, threads: int = 1) -> dict:
    """Run the case in a fresh ``python -m sphfem_cli.study`` and return its status."""
    case = Path(case_dir)
    with (case / LOG).open("w") as log:
        proc = subprocess.run(_command(case, threads), stdout=log, stderr=subprocess.STDOUT)
    return _settle(case, proc.returncode)


def run_local(case_dirs: Iterable[Path], workers: int, threads: int = 1,
              on_done: Callable[[Path, dict], None] | None = None, poll_s: float = 0.2) -> dict[Path, dict]:
    """Run cases as local processes, at most ``workers`` at once; one dying never stops the others."""
    queue = [Path(d) for d in case_dirs]
    results: dict[Path, dict] = {}
    running: dict[Path, tuple[subprocess.Popen, object]] = {}
    try:
        while queue or running:
            while queue and len(running) < max(1, workers):
                d = queue.pop(0)
                log = (d / LOG).open("w")
                running[d] = (subprocess.Popen(_command(d, threads), stdout=log, stderr=subprocess.STDOUT), log)
            for d, (proc, log) in list(running.items()):
                code = proc.poll()
                if code is None:
                    continue
                log.close()
                del running[d]
                results[d] = _settle(d, code)
                if on_done:
                    on_done(d, results[d])
            if running:
                time.sleep(poll_s)
    finally:
        for d, (proc, log) in running.items():  # interrupted: stop the cases this call started
            proc.terminate()
            proc.wait()
            log.close()
    return results


def run_dask(case_dirs: Iterable[Path], scheduler, threads: int = 1,
             on_done: Callable[[Path, dict], None] | None = None) -> dict[Path, dict]:
    """Run cases as tasks on a Dask cluster: ``scheduler`` is an address or a ``distributed.Client``."""
    try:
        from distributed import Client, as_completed
    except ImportError:
        raise RuntimeError("--scheduler needs dask.distributed: pip install 'sphfem[cluster]'") from None
    dirs = [Path(d).resolve() for d in case_dirs]
    results: dict[Path, dict] = {}
    if not dirs:
        return results
    own = not isinstance(scheduler, Client)
    client = Client(scheduler) if own else scheduler
    try:
        futures = client.map(run_case_subprocess, [str(d) for d in dirs], threads=threads, pure=False)
        where = {f.key: d for f, d in zip(futures, dirs)}
        for fut in as_completed(futures):
            d = where[fut.key]
            try:
                results[d] = fut.result()
            except Exception as err:  # noqa: BLE001 - a task lost with its worker
                results[d] = dict(read_status(d), state="failed", message=f"task failed: {type(err).__name__}: {err}")
                write_status(d, results[d])
            if on_done:
                on_done(d, results[d])
    finally:
        if own:
            client.close()
    return results


def main(argv: list[str] | None = None) -> int:
    """``python -m sphfem_cli.study CASE_DIR [--threads N]``: the process of one case."""
    import argparse

    parser = argparse.ArgumentParser(prog="python -m sphfem_cli.study", description="Run one mesh-study case folder.")
    parser.add_argument("case_dir")
    parser.add_argument("--threads", type=int, default=1)
    parser.add_argument("--compiled", type=float, default=None, help=argparse.SUPPRESS)
    parser.add_argument("--warmup-cpu", type=float, default=0.0, help=argparse.SUPPRESS)
    args = parser.parse_args(argv)
    before = None if args.compiled is None else (args.compiled, args.warmup_cpu)
    result = run_case(args.case_dir, args.threads, compiled_before=before, reexec=True)
    return 0 if result.get("state") in ("done", "failed") else 1
