"""LS-DYNA keyword meshes (``.k``, ``.key``, ``.dyn``) as a meshio mesh, read with ``dynakw``.

``dynakw`` (PyPI, MIT, numpy only; W. Roux, github.com/WillemJR/dynakw) parses the keyword cards in
fixed or free format. It was chosen over ``lsdyna-mesh-reader``, whose C++ parser was measured to loop
forever on a malformed ``*NODE`` line; ``dynakw`` is young (2025, releases 1.0 to 1.7 within the year,
one author), so what we take from it is checked here.

Read: ``*NODE`` (ids, x, y, z), ``*ELEMENT_SOLID`` (8-node hexahedra), ``*ELEMENT_SHELL`` (4-node
quadrilaterals: the 2D plane-strain mesh of an LS-DYNA model lies in shells), ``*PART`` (its heading
names the part's cell set, else ``part_<pid>``), ``*SET_NODE_LIST`` (point set ``set_<sid>``).
Node ids become 0-based indices in file order. A solid or shell written with repeated nodes
(tetrahedra, wedges, triangles in LS-DYNA's degenerate form) is refused by name: sphfem's
elements are hex8 and quad4. Every other keyword (materials, sections, loads) is ignored: the
deck says those.
"""
from __future__ import annotations

import logging
import re
from pathlib import Path

import numpy as np

SUFFIXES = (".k", ".key", ".dyn")


def _cards(keyword) -> dict:
    return getattr(keyword, "cards", None) or {}


def _column(card: dict, name: str) -> np.ndarray:
    return np.asarray(card[name]).ravel()


def read_keyword_mesh(path: str | Path):
    """The mesh of an LS-DYNA keyword file as ``meshio.Mesh`` (points, hexahedron and quad blocks,
    cell sets per part, point sets per node set). ValueError naming what is wrong."""
    import meshio
    from dynakw import DynaKeywordReader, KeywordType

    nids, xyz, solids, shells, parts, node_sets = [], [], [], [], {}, {}
    logged = _Collect()
    log = logging.getLogger("dynakw")
    propagate, log.propagate = log.propagate, False  # its parse errors become ours, not stray stderr lines
    log.addHandler(logged)
    try:
        with DynaKeywordReader(str(path)) as reader:
            keywords = list(reader.keywords())
    except Exception as exc:  # noqa: BLE001 - a third-party parser: any failure is the file's
        raise ValueError(f"{path}: cannot read the LS-DYNA keyword file: {type(exc).__name__}: {exc}") from None
    finally:
        log.removeHandler(logged)
        log.propagate = propagate
    if logged.errors:
        raise ValueError(f"{path}: the LS-DYNA keyword file has a card that cannot be read: {logged.errors[0]}")
    for kw in keywords:
        cards = _cards(kw)
        if not cards:
            continue  # a keyword without cards, or one dynakw keeps as text (materials, loads...)
        try:
            if kw.type == KeywordType.NODE:
                c = cards["Card 1"]
                nids.append(_column(c, "NID").astype(np.int64))
                xyz.append(np.column_stack([_column(c, a).astype(float) for a in ("X", "Y", "Z")]))
            elif kw.type == KeywordType.ELEMENT_SOLID:
                c, n = cards["Card 1"], cards["nodes"]
                conn = np.column_stack([_column(n, f"N{i}").astype(np.int64) for i in range(1, 9)])
                solids.append((_column(c, "EID").astype(np.int64), _column(c, "PID").astype(np.int64), conn))
            elif kw.type == KeywordType.ELEMENT_SHELL:
                c = cards["Card 1"]
                conn = np.column_stack([_column(c, f"N{i}").astype(np.int64) for i in range(1, 5)])
                shells.append((_column(c, "EID").astype(np.int64), _column(c, "PID").astype(np.int64), conn))
            elif kw.type == KeywordType.PART:
                heads, ids = _column(cards["Card 1"], "HEADING"), _column(cards["Card 2"], "PID")
                for head, pid in zip(heads, ids):
                    parts[int(pid)] = str(head).strip()
            elif kw.type == KeywordType.SET_NODE:
                sid = int(_column(cards["Card 1"], "SID")[0])
                ids = np.concatenate([_column(card, k).astype(np.int64) for name, card in cards.items()
                                      if name != "Card 1" for k in card if k.startswith("NID")])
                node_sets[f"set_{sid}"] = ids[ids > 0]
        except (KeyError, IndexError, TypeError, ValueError) as exc:
            raise ValueError(f"{path}: a {kw.type.name} keyword could not be read ({type(exc).__name__}: {exc})") from None
    if not nids:
        raise ValueError(f"{path}: no *NODE keyword with nodes (an LS-DYNA keyword mesh needs *NODE and "
                         "*ELEMENT_SOLID or *ELEMENT_SHELL)")
    nid = np.concatenate(nids)
    points = np.concatenate(xyz)
    if len(np.unique(nid)) != len(nid):
        raise ValueError(f"{path}: a node id appears twice in *NODE")
    order = np.argsort(nid)

    def index(ids: np.ndarray, what: str) -> np.ndarray:
        at = np.searchsorted(nid, ids, sorter=order)
        at = np.minimum(at, len(nid) - 1)
        found = order[at]
        missing = nid[found] != ids
        if np.any(missing):
            raise ValueError(f"{path}: {what} names node {int(ids[missing].ravel()[0])}, which *NODE does not define")
        return found

    cells, cell_sets = [], {}
    blocks = (("hexahedron", solids, "*ELEMENT_SOLID"), ("quad", shells, "*ELEMENT_SHELL"))
    for kind, groups, keyword in blocks:
        if not groups:
            continue
        eid = np.concatenate([g[0] for g in groups])
        pid = np.concatenate([g[1] for g in groups])
        conn = np.concatenate([g[2] for g in groups])
        degenerate = np.any(np.diff(np.sort(conn, axis=1), axis=1) == 0, axis=1)
        if np.any(degenerate):
            raise ValueError(f"{path}: {keyword} element {int(eid[degenerate][0])} repeats a node (a "
                             f"{'tetrahedron or wedge' if kind == 'hexahedron' else 'triangle'} in LS-DYNA's "
                             f"degenerate form); only 8-node hexahedra and 4-node quadrilaterals are read")
        cells.append((kind, index(conn, f"{keyword} element")))
        for p in np.unique(pid):
            name = _set_name(parts.get(int(p)), int(p))
            cell_sets.setdefault(name, {})[len(cells) - 1] = np.flatnonzero(pid == p)
    if not cells:
        raise ValueError(f"{path}: no *ELEMENT_SOLID or *ELEMENT_SHELL elements")
    per_block = {name: [blocks_of.get(i, np.zeros(0, np.int64)) for i in range(len(cells))]
                 for name, blocks_of in cell_sets.items()}
    point_sets = {name: index(ids, f"*SET_NODE_LIST {name[4:]}") for name, ids in node_sets.items()}
    return meshio.Mesh(points, cells, point_sets=point_sets, cell_sets=per_block)


def _set_name(heading: str | None, pid: int) -> str:
    """A part's cell-set name: its *PART heading as a set name (letters, digits, _ . -), else part_<pid>."""
    name = re.sub(r"[^A-Za-z0-9_.-]+", "_", heading or "").strip("_")
    return name or f"part_{pid}"


class _Collect(logging.Handler):
    """The messages of dynakw's errors while it reads."""

    def __init__(self):
        super().__init__(logging.ERROR)
        self.errors: list[str] = []

    def emit(self, record: logging.LogRecord) -> None:
        self.errors.append(" ".join(record.getMessage().split()))
