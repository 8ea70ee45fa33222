"""Checkpoints are data: loading one never runs code, and a checkpoint that is not exactly what this
sphfem wrote for this deck (a pickle, a changed byte, another deck, another version or format) is
refused with exit 65 and one line, before anything in the output folder is touched."""
from __future__ import annotations

import hashlib
import io
import json
import os
import pickle
import zipfile
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

from sphfem_cli.cli import main
from sphfem_cli.output import checkpoint as ckpt

from . import decks


def _run(*args) -> tuple[int, str]:
    result = CliRunner().invoke(main, ["run", "-q", *map(str, args)])
    return result.exit_code, result.output


class _RunsCode:
    """Unpickling this calls os.system: what a crafted checkpoint.pkl did to earlier versions."""

    def __init__(self, marker: Path):
        self.marker = marker

    def __reduce__(self):
        return os.system, (f"touch {self.marker}",)


def _one_line(text: str, *words: str) -> None:
    lines = text.strip().splitlines()
    assert len(lines) == 1, text
    for w in words:
        assert w in lines[0], text


@pytest.fixture(scope="module")
def finished(tmp_path_factory):
    """A finished run of the solid deck: (deck, output folder)."""
    tmp = tmp_path_factory.mktemp("finished")
    deck = decks.write(tmp, "solid")
    code, text = _run(deck, "-o", tmp / "out")
    assert code == 0, text
    return deck, tmp / "out"


def _copy(folder: Path, to: Path) -> Path:
    to.mkdir()
    for p in folder.rglob("*"):
        target = to / p.relative_to(folder)
        if p.is_dir():
            target.mkdir(exist_ok=True)
        else:
            target.write_bytes(p.read_bytes())
    return to


def _members(path: Path) -> dict[str, bytes]:
    with zipfile.ZipFile(path) as zf:
        return {info.filename: zf.read(info.filename) for info in zf.infolist()}


def _rewrite(path: Path, members: dict[str, bytes], rehash: bool) -> None:
    """Write `members` back as a checkpoint; `rehash`: recompute the content hash, as a forger would."""
    if rehash:
        meta = json.loads(members["meta.json"])
        digests = [(n, hashlib.sha256(members[n]).hexdigest()) for n in meta["members"]]
        meta["content_sha256"] = ckpt._content_hash(meta, digests)
        members["meta.json"] = json.dumps(meta).encode()
    with zipfile.ZipFile(path, "w", zipfile.ZIP_STORED) as zf:
        for name, data in members.items():
            zf.writestr(name, data)


def _array_index(members: dict[str, bytes], *path: str) -> int:
    node = json.loads(members["state.json"])["simulation"]
    for name in path:
        node = node["attrs"][name]
    assert node["t"] == "array"
    return node["a"]


@pytest.mark.parametrize("name", ["checkpoint.pkl", "checkpoint.npz"])
def test_a_crafted_pickle_runs_no_code_and_is_refused(tmp_path, finished, name):
    deck, out = finished
    folder = _copy(out, tmp_path / "run")
    before = {p: p.read_bytes() for p in folder.rglob("*") if p.is_file()}
    marker = tmp_path / "code_ran"
    crafted = folder / name
    crafted.write_bytes(pickle.dumps(_RunsCode(marker)))
    assert not marker.exists()
    code, text = _run(deck, "-o", folder, "--restart", crafted)
    assert code == 65, text
    _one_line(text, "not a readable sphfem checkpoint", "pickle", "can run code")
    assert not marker.exists()
    assert all(p.read_bytes() == data for p, data in before.items() if p != crafted)


def test_a_pickle_inside_an_npy_member_runs_no_code(tmp_path, finished):
    """An object array's .npy embeds a pickle; the member list and content hash are made consistent,
    so only the reader's refusal of object dtypes stands between the file and the code."""
    deck, out = finished
    folder = _copy(out, tmp_path / "run")
    path = folder / "checkpoint.npz"
    members = _members(path)
    marker = tmp_path / "code_ran"
    buf = io.BytesIO()
    np.lib.format.write_array(buf, np.array([_RunsCode(marker)], dtype=object), allow_pickle=True)
    members["arrays/000000.npy"] = buf.getvalue()
    _rewrite(path, members, rehash=True)
    code, text = _run(deck, "-o", folder, "--restart", path)
    assert code == 65, text
    _one_line(text, "an array of objects")
    assert not marker.exists()


def test_a_doctored_checkpoint_is_refused_by_its_content_hash(tmp_path, finished):
    """Velocities x 50 in a real checkpoint, as in the issue; the guards are not in the file at all."""
    deck, out = finished
    folder = _copy(out, tmp_path / "run")
    path = folder / "checkpoint.npz"
    members = _members(path)
    state = json.loads(members["state.json"])
    assert state["simulation"]["attrs"]["control"]["t"] == "skip"  # control (guards) comes from the deck
    name = f"arrays/{_array_index(members, 'state', 'v'):06d}.npy"
    v = np.load(io.BytesIO(members[name]), allow_pickle=False)
    assert np.abs(v).max() > 0
    buf = io.BytesIO()
    np.lib.format.write_array(buf, v * 50.0)
    members[name] = buf.getvalue()
    _rewrite(path, members, rehash=False)
    code, text = _run(deck, "-o", folder, "--restart", path)
    assert code == 65, text
    _one_line(text, "content hash mismatch")


@pytest.mark.parametrize("field, value, words", [
    ("sphfem", "0.0.1", ("written by sphfem 0.0.1", "the version that wrote it")),
    ("format_version", 1, ("format 1", "reads format 2 only")),
    ("deck_sha256", "0" * 64, ("written for another deck",)),
])
def test_a_checkpoint_of_another_version_format_or_deck_is_refused(tmp_path, finished, field, value, words):
    deck, out = finished
    folder = _copy(out, tmp_path / "run")
    path = folder / "checkpoint.npz"
    members = _members(path)
    meta = json.loads(members["meta.json"])
    meta[field] = value
    members["meta.json"] = json.dumps(meta).encode()
    _rewrite(path, members, rehash=True)
    code, text = _run(deck, "-o", folder, "--restart", path)
    assert code == 65, text
    _one_line(text, *words)


@pytest.mark.parametrize("damage", ["truncated", "zip_of_nothing", "compressed", "extra_member", "bad_json"])
def test_a_damaged_checkpoint_is_refused_in_one_line(tmp_path, finished, damage):
    deck, out = finished
    folder = _copy(out, tmp_path / "run")
    path = folder / "checkpoint.npz"
    data = path.read_bytes()
    if damage == "truncated":
        path.write_bytes(data[: len(data) // 2])
    elif damage == "zip_of_nothing":
        _rewrite(path, {}, rehash=False)
    elif damage == "compressed":
        members = _members(path)
        with zipfile.ZipFile(path, "w", zipfile.ZIP_DEFLATED) as zf:
            for name, blob in members.items():
                zf.writestr(name, blob)
    elif damage == "extra_member":
        members = _members(path)
        members["arrays/999999.npy"] = b"\x93NUMPY"
        _rewrite(path, members, rehash=True)
    else:
        members = _members(path)
        members["state.json"] = b"[" * 100_000
        _rewrite(path, members, rehash=True)
    code, text = _run(deck, "-o", folder, "--restart", path)
    assert code == 65, text
    _one_line(text, str(path))


def test_a_checkpoint_reads_with_numpy_without_pickle(finished):
    _, out = finished
    with np.load(out / "checkpoint.npz", allow_pickle=False) as npz:
        arrays = [npz[name] for name in npz.files if name.startswith("arrays/")]
    assert arrays and all(a.dtype != object for a in arrays)


def test_the_guard_settings_are_not_in_the_checkpoint(finished):
    """Whoever rewrites the content hash too can change the state, not the settings: control (the
    guards, intervals) and the deck are configuration, rebuilt from the deck at every restart."""
    _, out = finished
    members = _members(out / "checkpoint.npz")
    tree = json.loads(members["state.json"])["simulation"]
    skipped = {k for k, v in tree["attrs"].items() if isinstance(v, dict) and v.get("t") == "skip"}
    assert "control" in skipped
    decks_found = []

    def find(node):
        if isinstance(node, dict):
            if node.get("t") == "obj" and "deck" in node["attrs"]:
                decks_found.append(node["attrs"]["deck"])
            for v in node.values():
                find(v)
        elif isinstance(node, list):
            for v in node:
                find(v)

    find(tree)
    assert decks_found and all(d["t"] in ("skip", "ref") for d in decks_found)
    assert "energy_band" not in members["state.json"].decode()


def test_a_restart_into_the_folder_of_another_decks_run_touches_nothing(tmp_path, finished):
    deck, out = finished
    other = decks.write(tmp_path, "solid", end_time=1.0e-4)
    code, text = _run(other, "-o", tmp_path / "other")
    assert code == 0, text
    before = {p: p.read_bytes() for p in (tmp_path / "other").rglob("*") if p.is_file()}
    code, text = _run(deck, "-o", tmp_path / "other", "--restart", out / "checkpoint.npz")
    assert code == 65, text
    _one_line(text, "does not hold the run of this checkpoint", "another deck")
    assert {p: p.read_bytes() for p in (tmp_path / "other").rglob("*") if p.is_file()} == before


def test_a_fifo_given_as_checkpoint_is_refused_without_blocking(tmp_path, finished):
    deck, out = finished
    fifo = tmp_path / "checkpoint.npz"
    os.mkfifo(fifo)
    code, text = _run(deck, "-o", out, "--restart", fifo)
    assert code == 65, text
    _one_line(text, "not a regular file")
