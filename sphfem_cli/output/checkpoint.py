"""Restart checkpoints: the mutable state of a run as named arrays and plain data, never code.

A checkpoint (``checkpoint.npz`` in the output folder) is a zip archive of stored (uncompressed)
members, readable with ``numpy.load(path, allow_pickle=False)``:

    arrays/000000.npy ...   every numpy array of the run's state (`snapshot.capture`), .npy format
    state.json              {"simulation": the snapshot tree naming each array by its place in the
                            object graph, "output": `RunOutput.state()`}, plain JSON
    meta.json               format, format_version, sphfem (the version that wrote it), deck_sha256
                            (`deck_hash`), time, step, members (the other members in order) and
                            content_sha256: sha256 of the canonical JSON of the other meta fields
                            followed by each member's name and the sha256 of its bytes

Loading parses JSON and .npy headers only (arrays of object dtype are refused), so it never runs
code. A restart builds the `Simulation` from the deck as a fresh run does, then restores every
saved value into it by name (`snapshot.restore`): the deck's settings (guards, intervals, materials)
come from the deck, never from the file, and the restart is bit-identical to an uninterrupted run.

A checkpoint is refused (CheckpointError, one line) when it is not such an archive (a pickle, from
earlier versions, is refused unread: unpickling can run code), when its format or sphfem version
differs from this one, when it was written for another deck, when its content hash does not match
its bytes (a changed file), or when its state does not fit the model the deck builds. The content
hash detects a file changed after sphfem wrote it; it is not a signature (whoever can write the file
can write a consistent one), which is why nothing that decides what the run does is read from it.

The file is written to a temporary name and renamed over the previous checkpoint, so a kill at any
moment leaves either the old or the new one, never half of one.
"""
from __future__ import annotations

import hashlib
import io
import json
import os
import tempfile
import zipfile
from pathlib import Path

import numpy as np

from .. import __version__
from .snapshot import SnapshotMismatch, capture, restore

CHECKPOINT_FORMAT = 2  # 1: the pickled Simulation of earlier versions, no longer read
CHECKPOINT_NAME = "checkpoint.npz"
LEGACY_NAME = "checkpoint.pkl"
_KIND = "sphfem checkpoint"
_META = "meta.json"
_STATE = "state.json"
_META_LIMIT = 1 << 20
_ZIP_MAGIC = b"PK\x03\x04"


class CheckpointError(Exception):
    """A checkpoint that cannot be used; the message is one line."""


def deck_hash(deck, model) -> str:
    """sha256 of the validated deck (every default filled in) and of the model's geometry.

    The geometry covers mesh files the deck imports: a changed mesh changes the hash even when the
    deck's text does not.
    """
    h = hashlib.sha256()
    h.update(json.dumps(deck.model_dump(mode="json"), sort_keys=True, default=str).encode())
    arrays = [model.coordinates, model.connectivity]
    if model.particles is not None:
        arrays.append(model.particles.x)
    if model.ale is not None:
        arrays += [model.ale.nodes, model.ale.elements]
    for a in arrays:
        a = np.ascontiguousarray(a)
        h.update(str((a.dtype.str, a.shape)).encode())
        h.update(a.tobytes())
    return h.hexdigest()


def _content_hash(meta: dict, digests: list[tuple[str, str]]) -> str:
    core = {k: v for k, v in meta.items() if k != "content_sha256"}
    h = hashlib.sha256(json.dumps(core, sort_keys=True).encode())
    for name, digest in digests:
        h.update(name.encode() + b"\0" + digest.encode())
    return h.hexdigest()


class _HashingWriter:
    """A write-only stream that hashes what passes through it."""

    def __init__(self, fh):
        self.fh = fh
        self.sha = hashlib.sha256()

    def write(self, data) -> int:
        self.sha.update(data)
        return self.fh.write(data)


def write_checkpoint(path: Path, sim, output_state: dict, digest: str) -> None:
    """Write the checkpoint of `sim` and of the output state atomically to `path`."""
    path = Path(path)
    tree, arrays = capture(sim)
    state = json.dumps({"simulation": tree, "output": output_state}, allow_nan=True).encode()
    fd, tmp = tempfile.mkstemp(prefix=".checkpoint.", suffix=".tmp", dir=path.parent)
    try:
        with os.fdopen(fd, "wb") as raw, zipfile.ZipFile(raw, "w", zipfile.ZIP_STORED, allowZip64=True) as zf:
            digests = []
            for i, a in enumerate(arrays):
                name = f"arrays/{i:06d}.npy"
                with zf.open(name, "w", force_zip64=True) as fh:
                    w = _HashingWriter(fh)
                    np.lib.format.write_array(w, a, allow_pickle=False)
                digests.append((name, w.sha.hexdigest()))
            zf.writestr(_STATE, state)
            digests.append((_STATE, hashlib.sha256(state).hexdigest()))
            meta = {"format": _KIND, "format_version": CHECKPOINT_FORMAT, "sphfem": __version__,
                    "deck_sha256": digest, "time": float(sim.state.time), "step": int(sim.state.step),
                    "members": [name for name, _ in digests]}
            meta["content_sha256"] = _content_hash(meta, digests)
            zf.writestr(_META, json.dumps(meta))
            zf.close()
            raw.flush()
            os.fsync(raw.fileno())
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise


def _refuse(path: Path, why: str) -> CheckpointError:
    return CheckpointError(f"{path}: not a readable sphfem checkpoint ({why})")


def read_checkpoint(path: Path, digest: str) -> dict:
    """The checkpoint of `path` as {time, step, version, deck_hash, output, tree, arrays}; refused
    (CheckpointError) unless it is a checkpoint of this format and sphfem version, written for the
    deck of `digest`, with every byte as written. Only JSON and .npy members are parsed."""
    path = Path(path)
    try:
        if path.exists() and not path.is_file():
            raise CheckpointError(f"{path}: not a regular file (a checkpoint is a file sphfem wrote)")
        with path.open("rb") as fh:
            head = fh.read(4)
    except FileNotFoundError:
        raise CheckpointError(f"{path}: no such checkpoint file") from None
    except OSError as err:
        raise CheckpointError(f"{path}: cannot read the checkpoint ({err.strerror or err})") from None
    if head[:1] == b"\x80" or path.suffix in (".pkl", ".pickle"):
        raise _refuse(path, "a pickle, the checkpoint format of earlier sphfem versions: loading a pickle can run "
                            "code, so it is never read; rerun the deck from the start")
    if head != _ZIP_MAGIC:
        raise _refuse(path, f"not the zip archive of a {CHECKPOINT_NAME}")
    try:
        with zipfile.ZipFile(path) as zf:
            return _read_archive(path, zf, digest)
    except CheckpointError:
        raise
    except Exception as err:  # noqa: BLE001 - a damaged archive, in whatever way, is not usable
        raise _refuse(path, f"damaged: {type(err).__name__}: {err}") from None


def _read_archive(path: Path, zf: zipfile.ZipFile, digest: str) -> dict:
    infos = {info.filename: info for info in zf.infolist()}
    if any(info.compress_type != zipfile.ZIP_STORED for info in infos.values()):
        raise _refuse(path, "compressed members; sphfem writes them stored")
    meta_info = infos.get(_META)
    if meta_info is None or meta_info.file_size > _META_LIMIT:
        raise _refuse(path, f"no {_META}")
    meta = json.loads(zf.read(_META))
    if not isinstance(meta, dict) or meta.get("format") != _KIND:
        raise _refuse(path, f"{_META} does not describe a sphfem checkpoint")
    if meta.get("format_version") != CHECKPOINT_FORMAT:
        raise CheckpointError(f"{path}: a checkpoint of format {meta.get('format_version')!r}; this sphfem reads "
                              f"format {CHECKPOINT_FORMAT} only; rerun the deck from the start")
    if meta.get("sphfem") != __version__:
        raise CheckpointError(f"{path}: written by sphfem {meta.get('sphfem')}, this is {__version__}; a checkpoint "
                              f"continues only under the version that wrote it (restart with sphfem "
                              f"{meta.get('sphfem')}, or rerun the deck from the start)")
    if meta.get("deck_sha256") != digest:
        raise CheckpointError(
            f"{path}: written for another deck (hash {str(meta.get('deck_sha256'))[:12]}, this deck "
            f"{digest[:12]}); restart with the deck the run started from, unchanged"
        )
    members = meta.get("members")
    if not isinstance(members, list) or sorted(members) != sorted(set(infos) - {_META}) or _STATE not in members:
        raise _refuse(path, "its members differ from the list in meta.json")
    names = [n for n in members if n != _STATE]
    if names != [f"arrays/{i:06d}.npy" for i in range(len(names))]:
        raise _refuse(path, "unexpected member names")
    digests, arrays, state_bytes = [], [], b""
    for name in members:  # one member's bytes at a time; nothing is used before the content hash matches
        data = zf.read(name)
        digests.append((name, hashlib.sha256(data).hexdigest()))
        if name == _STATE:
            state_bytes = data
        else:
            arrays.append(_npy(path, name, data))
        del data
    if _content_hash(meta, digests) != meta.get("content_sha256"):
        raise CheckpointError(f"{path}: content hash mismatch: the file was changed after sphfem wrote it; "
                              "it is not used (rerun, or restart from an unchanged checkpoint)")
    state = json.loads(state_bytes)
    if not isinstance(state, dict) or not isinstance(state.get("output"), dict):
        raise _refuse(path, f"{_STATE} is malformed")
    return {"format": CHECKPOINT_FORMAT, "version": meta["sphfem"], "deck_hash": meta["deck_sha256"],
            "time": meta.get("time"), "step": meta.get("step"), "output": state["output"],
            "tree": state.get("simulation"), "arrays": arrays}


def _npy(path: Path, name: str, data: bytes) -> np.ndarray:
    """The array of one .npy member, read from its header without unpickling anything."""
    f = io.BytesIO(data)
    version = np.lib.format.read_magic(f)
    if version == (1, 0):
        shape, fortran, dtype = np.lib.format.read_array_header_1_0(f)
    elif version == (2, 0):
        shape, fortran, dtype = np.lib.format.read_array_header_2_0(f)
    else:
        raise _refuse(path, f"{name}: .npy version {version}")
    if dtype.hasobject:
        raise _refuse(path, f"{name}: an array of objects")
    count = int(np.prod(shape, dtype=np.int64))
    offset = f.tell()
    if len(data) - offset != count * dtype.itemsize:
        raise _refuse(path, f"{name}: {len(data) - offset} data bytes for shape {shape} of {dtype}")
    flat = np.frombuffer(data, dtype=dtype, count=count, offset=offset)
    return flat.reshape(shape, order="F" if fortran else "C").copy(order="K")


def restore_simulation(sim, payload: dict, path: Path) -> None:
    """Overwrite the state of `sim`, freshly built from the deck, with the checkpoint's."""
    try:
        restore(payload["tree"], payload["arrays"], sim)
    except SnapshotMismatch as err:
        raise CheckpointError(f"{path}: its state does not fit the model this deck builds ({err})") from None


def load_simulation(path: Path, deck, model):
    """The `Simulation` of checkpoint `path`, built from `deck` and `model` (a `cli.load_model` of the
    run's deck) and restored, for inspection or for continuing it in Python."""
    from ..solver.explicit import Simulation

    payload = read_checkpoint(path, deck_hash(deck, model))
    sim = Simulation(model)
    restore_simulation(sim, payload, path)
    return sim
