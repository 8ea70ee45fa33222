"""Output integrity: a `sphfem run` killed with SIGKILL leaves an HDF5 file whose every flushed step
reads back, and an XDMF index that is valid and lists only steps on disk."""
from __future__ import annotations

import signal
import subprocess
import sys
import time
import xml.etree.ElementTree as ET

import h5py
import numpy as np

from . import decks


def test_sigkill_mid_run_leaves_every_flushed_step_readable(tmp_path):
    deck = decks.write(tmp_path, "solid", end_time=0.1)  # 50 000 field outputs: within the deck bound, far past the kill
    text = deck.read_text().replace("interval: 2.0e-05", "interval: 2.0e-6").replace(
        "history_interval: 2.0e-06", "history_interval: 2.0e-7")
    deck.write_text(text)
    out = tmp_path / "out"
    proc = subprocess.Popen([sys.executable, "-m", "sphfem_cli.cli", "run", str(deck), "-o", str(out), "-q"],
                            stderr=subprocess.PIPE, text=True)
    try:
        for _ in range(1200):  # until a few field steps are on disk
            if (out / "results.xdmf").exists() and len(ET.parse(out / "results.xdmf").getroot().findall(
                    ".//Time")) >= 5:
                break
            assert proc.poll() is None, proc.stderr.read()
            time.sleep(0.05)
        time.sleep(0.3)
    finally:
        proc.send_signal(signal.SIGKILL)
        proc.communicate(timeout=60)
    assert proc.returncode == -signal.SIGKILL

    with h5py.File(out / "results.h5", "r") as f:
        times = f["times"][()]
        assert len(times) >= 5 and np.all(np.diff(times) > 0)
        grid = f["bar"]
        n_cells = grid["connectivity"].shape[0]
        for i in range(len(times)):  # every step the file lists reads back, finite and of the right shape
            step = grid[f"step_{i:06d}"]
            xyz = step["coordinates"][()]
            assert xyz.shape == (105, 3) and np.all(np.isfinite(xyz))
            for name in step["point"]:
                assert step["point"][name].shape[0] == 105
            for name in step["cell"]:
                values = step["cell"][name][()]
                assert values.shape[0] == n_cells and np.all(np.isfinite(values))
        glstat = f["histories/glstat"][()]
        assert glstat.shape[0] >= 1 and glstat.shape[1] == 9 and np.all(np.isfinite(glstat))
        assert glstat[-1, 0] >= times[-1] - 1e-12  # history rows up to the last field step were flushed with it
        assert np.all(np.diff(glstat[:, 0]) > 0)

        root = ET.parse(out / "results.xdmf").getroot()  # valid XML
        listed = [float(t.get("Value")) for t in root.iter("Time")]
        assert len(listed) >= 5
        assert np.array_equal(listed, times[: len(listed)])  # a prefix of what is on disk
        for item in root.iter("DataItem"):
            file_name, path = item.text.strip().split(":", 1)
            assert file_name == "results.h5"
            dims = tuple(int(d) for d in item.get("Dimensions").split())
            assert f[path].shape == dims, path


def test_sigkill_then_restart_loses_at_most_one_output_interval_and_ends_bit_identical(tmp_path):
    from sphfem_cli.driver import load_model
    from sphfem_cli.output.checkpoint import deck_hash, read_checkpoint

    from .test_restart import _fields, _histories

    deck = decks.write(tmp_path, "solid", end_time=1.0e-3)  # 50 output times; the kill comes after 5
    interval = 2.0e-5
    whole = subprocess.run([sys.executable, "-m", "sphfem_cli.cli", "run", str(deck), "-o", str(tmp_path / "whole"),
                            "-q"], capture_output=True, text=True, timeout=600)
    assert whole.returncode == 0, whole.stderr
    out = tmp_path / "out"
    proc = subprocess.Popen([sys.executable, "-m", "sphfem_cli.cli", "run", str(deck), "-o", str(out), "-q"],
                            stderr=subprocess.PIPE, text=True)
    try:
        for _ in range(2400):
            if (out / "results.xdmf").exists() and len(ET.parse(out / "results.xdmf").getroot().findall(
                    ".//Time")) >= 5:
                break
            assert proc.poll() is None, proc.stderr.read()
            time.sleep(0.025)
    finally:
        proc.send_signal(signal.SIGKILL)
        proc.communicate(timeout=60)
    assert proc.returncode == -signal.SIGKILL
    with h5py.File(out / "results.h5", "r") as f:
        reached = float(f["times"][-1])
    loaded = load_model(str(deck))
    saved = read_checkpoint(out / "checkpoint.npz", deck_hash(loaded.deck, loaded.model))
    assert reached - saved["time"] <= interval * (1 + 1e-9)  # at most one output interval lost
    again = subprocess.run([sys.executable, "-m", "sphfem_cli.cli", "run", str(deck), "-o", str(out), "-q",
                            "--restart", str(out / "checkpoint.npz")], capture_output=True, text=True, timeout=600)
    assert again.returncode == 0, again.stderr
    a, b = _histories(tmp_path / "whole"), _histories(out)
    assert sorted(a) == sorted(b) and all(np.array_equal(a[k], b[k]) for k in a)
    fa, fb = _fields(tmp_path / "whole"), _fields(out)
    assert [n for n, _ in fa] == [n for n, _ in fb] and all(np.array_equal(x, y) for (_, x), (_, y) in zip(fa, fb))
