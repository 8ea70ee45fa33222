"""One run per output folder, and output that fails to write: a folder holding another run is refused
(exit 2, nothing touched) unless --overwrite, which removes that run's files and nothing else; a
folder or file that cannot be created ends with exit 73, a write that fails during the run (a full
disk, a file-size limit) with exit 74, one line each, and the files written so far stay readable."""
from __future__ import annotations

import errno
import os
import resource
import subprocess
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import h5py
import numpy as np
import pytest
import yaml
from click.testing import CliRunner

from sphfem_cli.cli import main

from . import decks
from .test_restart import _fields, _histories


def _run(*args) -> tuple[int, str]:
    result = CliRunner().invoke(main, ["run", "-q", *map(str, args)])
    return result.exit_code, result.output


def _tree(folder: Path) -> dict[str, tuple[int, bytes]]:
    """Every file under `folder`: (mtime in ns, content)."""
    return {str(p.relative_to(folder)): (p.stat().st_mtime_ns, p.read_bytes())
            for p in sorted(folder.rglob("*")) if p.is_file()}


def _with_history(tmp_path: Path, name: str) -> Path:
    tree = yaml.safe_load(decks.SOLID)
    tree["output"]["histories"][0]["name"] = name
    folder = tmp_path / name
    folder.mkdir()
    path = folder / "solid.yaml"
    path.write_text(yaml.safe_dump(tree, sort_keys=False))
    return path


def test_a_folder_holding_another_run_is_refused_and_left_untouched(tmp_path):
    deck = decks.write(tmp_path, "solid")
    code, text = _run(deck, "-o", tmp_path / "out")
    assert code == 0, text
    before = _tree(tmp_path / "out")
    code, text = _run(deck, "-o", tmp_path / "out")
    assert code == 2, text
    lines = text.strip().splitlines()
    assert len(lines) == 1 and "holds the results of an earlier run" in lines[0] and "--overwrite" in lines[0], text
    assert _tree(tmp_path / "out") == before


def test_overwrite_removes_the_earlier_runs_files_and_nothing_else(tmp_path):
    """The earlier run stopped on a guard (diagnostics.txt) and had a history the new deck lacks; the user
    kept notes and a plot of their own beside it. No file of the earlier run may remain."""
    old = _with_history(tmp_path, "old_tip")
    text = old.read_text().replace("timestep_scale: 0.9", "timestep_scale: 1.2")
    old.write_text(text)
    out = tmp_path / "out"
    code, text = _run(old, "-o", out)
    assert code == 3 and (out / "diagnostics.txt").is_file() and (out / "histories" / "old_tip.csv").is_file(), text
    (out / "plots").mkdir()
    (out / "plots" / "old_tip.png").write_bytes(b"png of the earlier run")  # as `sphfem plot` names them
    (out / "plots" / "mine.png").write_bytes(b"the user's own")
    (out / "notes.txt").write_text("mine")
    (out / "histories" / "by_hand.txt").write_text("mine too")
    earlier = _tree(out)

    new = _with_history(tmp_path, "new_tip")
    code, text = _run(new, "-o", out, "--overwrite")
    assert code == 0, text
    now = _tree(out)
    user = {"notes.txt", "plots/mine.png", "histories/by_hand.txt"}
    assert user <= set(now) and now["notes.txt"][1] == b"mine"
    for name in set(earlier) - user:  # every file of the earlier run is gone or was written anew by this run
        assert name not in now or now[name] != earlier[name], name
    assert not (out / "diagnostics.txt").exists() and not (out / "histories" / "old_tip.csv").exists()
    assert not (out / "plots" / "old_tip.png").exists()
    assert (out / "histories" / "new_tip.csv").is_file()
    assert "new_tip" in (out / "run.manifest.json").read_text()


def test_overwrite_recognises_a_folder_written_before_manifests(tmp_path):
    deck = _with_history(tmp_path, "legacy_tip")
    out = tmp_path / "out"
    code, text = _run(deck, "-o", out)
    assert code == 0, text
    (out / "run.manifest.json").unlink()
    (out / "checkpoint.npz").rename(out / "checkpoint.pkl")  # as the earlier versions named it
    code, text = _run(decks.write(tmp_path, "solid"), "-o", out)
    assert code == 2 and "earlier run" in text, text
    code, text = _run(decks.write(tmp_path, "solid"), "-o", out, "--overwrite")
    assert code == 0, text
    assert not (out / "histories" / "legacy_tip.csv").exists() and not (out / "checkpoint.pkl").exists()


def test_overwrite_and_restart_exclude_each_other(tmp_path):
    deck = decks.write(tmp_path, "solid")
    code, text = _run(deck, "-o", tmp_path / "out", "--overwrite", "--restart", tmp_path / "out" / "checkpoint.npz")
    assert code == 2 and len(text.strip().splitlines()) == 1 and "exclude each other" in text, text
    assert not (tmp_path / "out").exists()


def test_an_output_folder_that_cannot_be_created_is_exit_73(tmp_path):
    """A path under a regular file cannot become a folder, for root too (chmod would not stop root)."""
    deck = decks.write(tmp_path, "solid")
    (tmp_path / "plain_file").write_text("")
    code, text = _run(deck, "-o", tmp_path / "plain_file" / "out")
    assert code == 73, text
    lines = text.strip().splitlines()
    assert len(lines) == 1 and "cannot create the output folder" in lines[0] and "Not a directory" in lines[0], text


def test_a_full_disk_mid_run_is_exit_74_with_every_written_step_readable(tmp_path, monkeypatch):
    """The disk fills at the fourth field step: posix_fallocate, which reserves the step's space before
    HDF5 writes, reports ENOSPC as a full disk does."""
    from sphfem_cli.output import xdmf

    calls = []
    real = os.posix_fallocate

    def filling(fd, offset, length):
        calls.append(length)
        if len(calls) > 12:
            raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))
        real(fd, offset, length)

    monkeypatch.setattr(xdmf.os, "posix_fallocate", filling)
    deck = decks.write(tmp_path, "solid")
    code, text = _run(deck, "-o", tmp_path / "out")
    assert code == 74, text
    lines = text.strip().splitlines()
    assert len(lines) == 1 and "No space left on device" in lines[0] and "results.h5" in lines[0], text
    assert "the files written so far are kept" in lines[0]
    _assert_readable(tmp_path / "out")


def _assert_readable(out: Path) -> int:
    """Every listed field step and history row reads back whole; returns the number of field steps."""
    with h5py.File(out / "results.h5", "r") as f:
        times = f["times"][()]
        for i in range(len(times)):
            step = f["bar"][f"step_{i:06d}"]
            assert step["coordinates"].shape == (105, 3) and np.all(np.isfinite(step["coordinates"][()]))
        mirrored = {name: f["histories"][name][()] for name in f["histories"]}
    listed = [float(t.get("Value")) for t in ET.parse(out / "results.xdmf").getroot().iter("Time")] \
        if (out / "results.xdmf").exists() else []
    assert np.array_equal(listed, times[: len(listed)])
    for name, rows in mirrored.items():
        csv = np.loadtxt(out / "histories" / f"{name}.csv", delimiter=",", skiprows=1, ndmin=2)
        assert csv.shape[1] == rows.shape[1] and csv.shape[0] >= rows.shape[0], name  # whole rows only
    return len(times)


def _limited_run(deck: Path, out: Path, limit: int, *extra) -> subprocess.CompletedProcess:
    def limit_file_size():
        resource.setrlimit(resource.RLIMIT_FSIZE, (limit, limit))

    return subprocess.run([sys.executable, "-m", "sphfem_cli.cli", "run", "-q", str(deck), "-o", str(out), *extra],
                          preexec_fn=limit_file_size if limit else None, capture_output=True, text=True, timeout=600)


def test_a_file_size_limit_mid_run_is_exit_74_and_the_run_restarts_bit_identical(tmp_path):
    """RLIMIT_FSIZE makes every write past the limit fail with EFBIG, in the HDF5 library's own writes too
    (Python ignores SIGXFSZ): a real failure, not a patched one. The run stops with every file readable;
    a restart from its last checkpoint, the limit lifted, ends bit-identical to an uninterrupted run."""
    deck = decks.write(tmp_path, "solid")
    whole = _limited_run(deck, tmp_path / "whole", 0)
    assert whole.returncode == 0, whole.stderr
    size = (tmp_path / "whole" / "results.h5").stat().st_size
    cut = _limited_run(deck, tmp_path / "cut", 3 * size // 4)
    assert cut.returncode == 74, cut.stderr
    lines = cut.stderr.strip().splitlines()
    assert len(lines) == 1 and "File too large" in lines[0] and "last checkpoint" in lines[0], cut.stderr
    n_steps = _assert_readable(tmp_path / "cut")
    assert 0 < n_steps < len(h5py.File(tmp_path / "whole" / "results.h5", "r")["times"])
    assert "status: I/O error" in (tmp_path / "cut" / "run.log").read_text()

    again = _limited_run(deck, tmp_path / "cut", 0, "--restart", tmp_path / "cut" / "checkpoint.npz")
    assert again.returncode == 0, again.stderr
    a, b = _histories(tmp_path / "whole"), _histories(tmp_path / "cut")
    assert sorted(a) == sorted(b) and all(np.array_equal(a[k], b[k]) for k in a)
    for (name, x), (_, y) in zip(_fields(tmp_path / "whole"), _fields(tmp_path / "cut")):
        assert np.array_equal(x, y), name


@pytest.fixture
def tmpfs(tmp_path):
    """A mount point for a tmpfs of our own (root with CAP_SYS_ADMIN only; skipped elsewhere)."""
    point = tmp_path / "mnt"
    point.mkdir()
    mounted = []

    def mount(options: str) -> Path:
        done = subprocess.run(["mount", "-t", "tmpfs", "-o", options, "tmpfs", str(point)], capture_output=True)
        if done.returncode != 0:
            pytest.skip("cannot mount a tmpfs here")
        mounted.append(point)
        return point

    yield mount
    for p in mounted:
        subprocess.run(["umount", str(p)], capture_output=True)


def test_a_read_only_file_system_is_exit_73(tmp_path, tmpfs):
    deck = decks.write(tmp_path, "solid")
    point = tmpfs("ro,size=1m")
    code, text = _run(deck, "-o", point / "out")
    assert code == 73, text
    lines = text.strip().splitlines()
    assert len(lines) == 1 and "Read-only file system" in lines[0], text


def test_a_really_full_disk_is_exit_74_with_the_files_readable(tmp_path, tmpfs):
    deck = decks.write(tmp_path, "solid")
    point = tmpfs("size=256k")
    code, text = _run(deck, "-o", point / "out")
    assert code == 74, text
    assert len(text.strip().splitlines()) == 1 and "No space left on device" in text, text
    _assert_readable(point / "out")


def test_unicode_names_run_stop_and_restart(tmp_path, monkeypatch):
    """Part and history names in any Unicode: UTF-8 CSV, HDF5 and XDMF; a restart continues them."""
    from .test_restart import _interrupt_at

    text = decks.SOLID.replace("name: tip", "name: 名前").replace("  bar:", "  🔥:").replace("part: bar", "part: 🔥")
    deck = tmp_path / "unicode.yaml"
    deck.write_text(text, encoding="utf-8")
    code, out = _run(deck, "-o", tmp_path / "whole")
    assert code == 0, out
    with monkeypatch.context() as patch:
        _interrupt_at(patch, 120)
        code, out = _run(deck, "-o", tmp_path / "split")
    assert code == 130, out
    code, out = _run(deck, "-o", tmp_path / "split", "--restart", tmp_path / "split" / "checkpoint.npz")
    assert code == 0, out
    for name in ("名前.csv", "matsum.csv"):
        whole = (tmp_path / "whole" / "histories" / name).read_text(encoding="utf-8")
        assert whole == (tmp_path / "split" / "histories" / name).read_text(encoding="utf-8")
    assert whole.startswith("time,🔥_kinetic")
    assert "🔥" in ET.parse(tmp_path / "split" / "results.xdmf").getroot().find(".//Grid/Grid/Grid").get("Name")


def test_a_completed_run_writes_its_state_at_end_time(tmp_path):
    """end_time off the field interval: the saved times are the interval's multiples and then end_time itself
    (the termination state, as LS-DYNA's d3plot), in results.h5, results.xdmf and the part's own XDMF; on the
    interval, no time is written twice; `check` counts the extra step."""
    for name, end, expected in (("off", 5.0e-5, [0.0, 2e-5, 4e-5, 5e-5]), ("on", 4.0e-5, [0.0, 2e-5, 4e-5])):
        tree = yaml.safe_load(decks.SOLID)
        tree["control"]["end_time"] = end
        deck = tmp_path / f"{name}.yaml"
        deck.write_text(yaml.safe_dump(tree))
        code, text = _run(deck, "-o", tmp_path / name)
        assert code == 0, text
        with h5py.File(tmp_path / name / "results.h5", "r") as f:
            assert np.allclose(f["times"][()], expected, rtol=1e-12, atol=0), (name, f["times"][()])
        assert _assert_readable(tmp_path / name) == len(expected)
        for xdmf in ("results.xdmf", "results.bar.xdmf"):
            listed = [float(t.get("Value")) for t in ET.parse(tmp_path / name / xdmf).getroot().iter("Time")]
            assert np.allclose(listed, expected, rtol=1e-12, atol=0), (name, xdmf, listed)
        result = CliRunner().invoke(main, ["check", str(deck)])
        assert f"output size: {len(expected)} field steps" in result.output, result.output
