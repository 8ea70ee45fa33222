"""Restart checkpoints: the whole mutable state of a run in one file, and the deck it belongs to.

A checkpoint is a pickle (protocol 5) of a dict

    format        CHECKPOINT_FORMAT, refused when it differs
    version       the sphfem version that wrote it
    deck_hash     `deck_hash` of the deck and model it was written for
    time, step    where the run was
    simulation    the `Simulation` itself: every domain (solid `State`, the SPH `ParticleSystem`, the ALE
                  `AleSystem`), the contact and coupling objects with their histories, rigid bodies,
                  the first step, eroded elements, and the `Model` (erosion mutates element_active)
    output        `RunOutput.state()`: next output times, rows per history table, the XDMF step list

Pickling the simulation as a whole is what makes a restart bit-identical: nothing is rebuilt, so
no array is recomputed in another order. Interaction objects therefore keep plain attributes
(numpy arrays, numbers, references to the simulation); a pickle refers to classes by their import
path, so a checkpoint is for the sphfem version that wrote it.

The file is written to a temporary name and renamed over the previous checkpoint, so a kill at any
moment leaves either the old or the new one, never half of one. Checkpoints are trusted input,
as pickles are: load only ones your own runs wrote.
"""
from __future__ import annotations

import hashlib
import json
import os
import pickle
import tempfile
from pathlib import Path

import numpy as np

from .. import __version__

CHECKPOINT_FORMAT = 1
CHECKPOINT_NAME = "checkpoint.pkl"


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


def write_checkpoint(path: Path, sim, output_state: dict, digest: str) -> None:
    """Write the checkpoint of `sim` atomically to `path`."""
    path = Path(path)
    payload = {
        "format": CHECKPOINT_FORMAT, "version": __version__, "deck_hash": digest,
        "time": sim.state.time, "step": sim.state.step, "simulation": sim, "output": output_state,
    }
    fd, tmp = tempfile.mkstemp(prefix=".checkpoint.", suffix=".tmp", dir=path.parent)
    try:
        with os.fdopen(fd, "wb") as fh:
            pickle.dump(payload, fh, protocol=5)
            fh.flush()
            os.fsync(fh.fileno())
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise


def read_checkpoint(path: Path, digest: str) -> dict:
    """The checkpoint dict of `path`, refused (CheckpointError) unless it was written for this deck."""
    path = Path(path)
    try:
        with path.open("rb") as fh:
            payload = pickle.load(fh)
    except FileNotFoundError:
        raise CheckpointError(f"{path}: no such checkpoint file") from None
    except Exception as err:  # noqa: BLE001 - any unpickling failure means the file is not usable
        raise CheckpointError(f"{path}: not a readable sphfem checkpoint ({type(err).__name__}: {err})") from None
    if not isinstance(payload, dict) or payload.get("format") != CHECKPOINT_FORMAT:
        raise CheckpointError(f"{path}: not a sphfem checkpoint of format {CHECKPOINT_FORMAT}")
    if payload.get("version") != __version__:
        raise CheckpointError(f"{path}: written by sphfem {payload.get('version')}, this is {__version__}")
    if payload.get("deck_hash") != digest:
        raise CheckpointError(
            f"{path}: written for another deck (hash {str(payload.get('deck_hash'))[:12]}, this deck "
            f"{digest[:12]}); restart with the deck the run started from, unchanged"
        )
    return payload
