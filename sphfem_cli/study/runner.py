"""Cases of a study: one folder each (deck.yaml, status.json, run/), run by a local pool or by Dask.

A case runs through the library (``cli.load_model`` then ``cli.execute``), in a process of its own
so that its peak memory (``getrusage`` ``ru_maxrss``) is its own:

- local: a ``ProcessPoolExecutor`` with the spawn start method and ``max_tasks_per_child=1`` (a
  fresh interpreter per case; fork would copy the parent's numba and thread state);
- Dask: each task starts ``python -m sphfem_cli.study.runner CASE_DIR`` on its worker and returns
  the status: Dask workers are daemonic processes (no child pools), a worker is long-lived (its
  ``ru_maxrss`` is not per case), and a crashing case must not take a worker down. The case
  folders must be on a file system the workers share.

``status.json`` holds ``state`` (running, done, failed), the deck's SHA-256 and the measurements;
a case whose status is done for the same deck is skipped on a rerun.
"""
from __future__ import annotations

import hashlib
import json
import os
import re
import subprocess
import sys
import time
from pathlib import Path
from typing import Callable, Iterable

STATUS = "status.json"
DECK = "deck.yaml"
RUN = "run"


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


def run_case(case_dir: str, threads: int = 1) -> dict:
    """Run the case in ``case_dir`` in this process; write and return its status."""
    import resource

    case = Path(case_dir)
    sha = deck_hash(case)
    write_status(case, {"state": "running", "deck_sha256": sha, "pid": os.getpid(),
                        "started": time.strftime("%Y-%m-%d %H:%M:%S")})
    usage0 = resource.getrusage(resource.RUSAGE_SELF)
    start = time.perf_counter()
    status: dict = {"deck_sha256": sha, "pid": os.getpid()}
    try:
        import numba

        from ..cli import DeckProblem, execute, load_model

        numba.set_num_threads(max(1, min(int(threads), numba.config.NUMBA_NUM_THREADS)))
        try:
            loaded = load_model(str(case / DECK))
        except DeckProblem as err:
            raise RuntimeError(f"bad deck: {err.message}") from None
        model = loaded.model
        status.update(
            particles=int(model.particles.n) if model.particles is not None else 0,
            ale_elements=int(len(model.ale.elements)) if model.ale is not None else 0,
            solid_elements=int(model.n_elements),
            threads=numba.get_num_threads(),
        )
        run_dir = case / RUN
        run_dir.mkdir(exist_ok=True)
        build = time.perf_counter() - start
        code = execute(loaded, run_dir, quiet=True)
        status.update(exit_code=int(code), build_s=build, steps=_steps(run_dir))
        if code == 0:
            status["state"] = "done"
        else:
            why = run_dir / "diagnostics.txt"
            status.update(state="failed", message=why.read_text().strip() if why.exists()
                          else f"exit status {code}, see {run_dir / 'run.log'}")
    except Exception as err:  # noqa: BLE001 - a case failure is recorded, never raised into the pool
        status.update(state="failed", message=f"{type(err).__name__}: {err}")
    usage = resource.getrusage(resource.RUSAGE_SELF)
    status.update(
        wall_s=time.perf_counter() - start,
        cpu_s=(usage.ru_utime - usage0.ru_utime) + (usage.ru_stime - usage0.ru_stime),
        peak_mib=usage.ru_maxrss / 1024.0,  # Linux reports KiB
        finished=time.strftime("%Y-%m-%d %H:%M:%S"),
    )
    write_status(case, status)
    return status


def run_case_subprocess(case_dir: str, threads: int = 1) -> dict:
    """Run the case in a fresh ``python -m sphfem_cli.study.runner`` and return its status."""
    proc = subprocess.run([sys.executable, "-m", "sphfem_cli.study.runner", str(case_dir), "--threads", str(threads)],
                          capture_output=True, text=True)
    status = read_status(Path(case_dir))
    if proc.returncode != 0 or status.get("state") not in ("done", "failed"):
        status = dict(status, state="failed",
                      message=f"case process exited with {proc.returncode}: {proc.stderr.strip()[-500:]}")
        write_status(Path(case_dir), status)
    return status


def run_local(case_dirs: Iterable[Path], workers: int, threads: int = 1,
              on_done: Callable[[Path, dict], None] | None = None) -> dict[Path, dict]:
    """Run cases on a spawn process pool, a fresh worker per case."""
    import multiprocessing
    from concurrent.futures import ProcessPoolExecutor, as_completed

    dirs = list(case_dirs)
    results: dict[Path, dict] = {}
    if not dirs:
        return results
    with ProcessPoolExecutor(max_workers=max(1, min(workers, len(dirs))), max_tasks_per_child=1,
                             mp_context=multiprocessing.get_context("spawn")) as pool:
        futures = {pool.submit(run_case, str(d), threads): d for d in dirs}
        for fut in as_completed(futures):
            d = futures[fut]
            try:
                results[d] = fut.result()
            except Exception as err:  # noqa: BLE001 - a worker that died (killed, out of memory)
                results[d] = {"state": "failed", "message": f"worker died: {type(err).__name__}: {err}"}
                write_status(d, dict(read_status(d), **results[d]))
            if on_done:
                on_done(d, results[d])
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
                results[d] = {"state": "failed", "message": f"task failed: {type(err).__name__}: {err}"}
            if on_done:
                on_done(d, results[d])
    finally:
        if own:
            client.close()
    return results


if __name__ == "__main__":  # the process a Dask task starts for one case
    import argparse

    parser = argparse.ArgumentParser(description="Run one mesh-study case folder.")
    parser.add_argument("case_dir")
    parser.add_argument("--threads", type=int, default=1)
    args = parser.parse_args()
    result = run_case(args.case_dir, args.threads)
    sys.exit(0 if result.get("state") in ("done", "failed") else 1)
