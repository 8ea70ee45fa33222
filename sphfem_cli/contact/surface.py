"""Master segments of a contact or coupling: outward-oriented exterior faces with their owners.

Orientation follows model.sets: in 2D a segment (a, b) has its outward normal to the right of
a -> b (counter-clockwise elements); in 3D a quad (a, b, c, d) has its outward normal by the
right-hand rule. In an axisymmetric model a face on the axis (every node at r = x = 0, where
model.checks.radii puts near-axis nodes) is no surface: it sweeps no ring, and a point near the
axis that passed below a body's top face found it the nearest face (gap ~ r) and was pushed only
radially, so it sank through (an r-z Taylor rod's axis node fell 1 mm into a rigid anvil).
"""
from __future__ import annotations

import numpy as np

from ..model import sets as selection
from ..model.build import Model


def master_segments(model: Model, name: str) -> tuple[np.ndarray, np.ndarray]:
    """(faces, owner) of a solid part's outer faces, or of a segment set's faces.

    ``faces`` int64 (S, 2|4) global node ids, ``owner`` int64 (S,) global element ids.
    """
    faces_all, owner_all = [], []
    is_part = any(p.name == name for p in model.parts)
    for p in model.parts:
        if p.kind != "solid" or p.elements.stop == p.elements.start:
            continue
        if is_part and p.name != name:
            continue
        faces, owner = selection.boundary_faces(model.connectivity[p.elements], model.dim)
        faces_all.append(faces)
        owner_all.append(owner + p.elements.start)
    if not faces_all:
        width = 2 if model.dim == 2 else 4
        return np.zeros((0, width), dtype=np.int64), np.zeros(0, dtype=np.int64)
    faces, owner = np.vstack(faces_all), np.concatenate(owner_all)
    if model.axisymmetric:
        on_axis = np.all(model.coordinates[faces, 0] == 0.0, axis=1)
        faces, owner = faces[~on_axis], owner[~on_axis]
    if name in model.segment_sets:
        wanted = {tuple(sorted(f)) for f in model.segment_sets[name].tolist()}
        keep = np.array([tuple(sorted(f)) in wanted for f in faces.tolist()], dtype=bool)
        faces, owner = faces[keep], owner[keep]
    return faces, owner
