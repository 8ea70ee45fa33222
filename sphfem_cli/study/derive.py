"""Deck derivation for the mesh study: SPH variants of an ALE scene, and ALE decks at other element sizes.

Works on the loaded YAML data (plain dicts and lists) and returns new data; the validated
:class:`~sphfem_cli.deck.schema.Deck` is used only to read defaults. Rules (docs/mesh-study.md):

- particle spacing = ALE element size / ratio; particles at the element sub-centres (ratio 1: one
  at each element centre; ratio 2: 2 x 2 per element; ...). Each fill region (box, ball, polygon,
  half_space; later fills win, as in the ALE part) becomes an SPH part of its material; the part's
  base material fills the rest; void gives no particles. The sub-centres inside each region are
  computed with the ALE's own region tests, then written as a lattice-aligned ``box`` (a full
  rectangle) or ``polygon`` (anything else) whose lattice reproduces exactly those centres.
- the ``sph`` section already in the deck, as it is (the scene's SPH settings), else one (cubic
  spline, h/dx 1.2, alpha 0.1, beta 0; the ALE section's ``pressure_cutoff``, if any);
- ``ale_boundary`` slip / fixed sides -> ``wall`` slip / no_slip; transmit sides -> the section's
  ``domain`` (particles leaving it are deactivated);
- ``lagrange_in_solid`` -> one ``nodes_to_surface`` per coupled SPH part, soft-constraint stiffness
  (soft_scale at its default 0.1, damping kept, thickness left at its default): the penalty form's
  stiffness comes from the structure's bulk modulus and can shorten the step; the soft form never does
  (measured on decks/structure_in_water_ale.yaml, docs/mesh-study.md). The coupling's pfac is not
  carried over: it scales a spring from the fluid's bulk modulus, soft_scale the spring's frequency
  against the step (omega dt0 = sqrt(soft_scale)); soft_scale 1.0 was unstable on the §4.1 scene;
- a fill's ``pressure`` (and ``density``) becomes a copy of its material whose EOS ``e0`` gives that
  pressure; a fill's ``velocity`` becomes an initial velocity of its SPH part.
"""
from __future__ import annotations

import copy
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..deck.schema.interaction import LagrangeInSolid, NodesToSurface

SOFT_SCALE = NodesToSurface.model_fields["soft_scale"].default  # the contact's own default, written out
NQUAD_DEFAULT = LagrangeInSolid.model_fields["nquad"].default
NQUAD_MAX = 5  # the schema's bound on lagrange_in_solid.nquad


class StudyError(Exception):
    """A deck the study cannot derive from (one line, shown to the user)."""


@dataclass
class AleInfo:
    """The ALE part of a deck, as the study needs it."""

    name: str
    section: str
    lo: np.ndarray
    hi: np.ndarray
    divisions: np.ndarray  # elements per direction

    @property
    def element_size(self) -> float:
        return float(np.mean((self.hi - self.lo) / self.divisions))

    @property
    def n_elements(self) -> int:
        return int(np.prod(self.divisions))


@dataclass
class Derived:
    """A derived deck and what the derivation did."""

    data: dict
    spacing: float | None = None
    parts: dict[str, int] = field(default_factory=dict)  # SPH part -> particle count
    notes: list[str] = field(default_factory=list)


def validated(data: dict):
    """The :class:`Deck` of YAML data (raises StudyError with pydantic's first message)."""
    from pydantic import ValidationError

    from ..deck.schema import Deck

    try:
        return Deck.model_validate(data)
    except ValidationError as err:
        first = err.errors()[0]
        where = ".".join(str(p) for p in first["loc"])
        raise StudyError(f"derived deck is not valid: {where}: {first['msg']}") from None


def ale_info(deck) -> AleInfo:
    """The deck's one ALE part: a 2D box mesh with square elements."""
    names = [n for n, p in deck.parts.items() if deck.sections[p.section].type == "ale_multi_material"]
    if len(names) != 1:
        raise StudyError(f"the mesh study needs a deck with exactly one ALE part (found {len(names)})")
    name = names[0]
    part = deck.parts[name]
    box = part.geometry.box
    if box is None:
        raise StudyError(f"parts.{name}.geometry: the mesh study needs the ALE part meshed as a box")
    lo, hi = np.asarray(box.min, float), np.asarray(box.max, float)
    if box.divisions is not None:
        n = np.asarray(box.divisions, dtype=np.int64)
        n = np.broadcast_to(n, lo.shape).copy() if n.size == 1 else n
    else:
        n = np.maximum(1, np.round((hi - lo) / box.element_size)).astype(np.int64)
    size = (hi - lo) / n
    if abs(size[0] - size[1]) > 1e-6 * size.max():
        raise StudyError(f"parts.{name}.geometry.box: the ALE elements are {size[0]:g} x {size[1]:g}; "
                         "the SPH lattice needs square elements")
    return AleInfo(name, part.section, lo, hi, n)


def ale_variant(data: dict, element_size: float) -> Derived:
    """The deck with its ALE part meshed at ``element_size`` (divisions = round(length / size))."""
    deck = validated(data)
    info = ale_info(deck)
    out = copy.deepcopy(data)
    n = np.maximum(1, np.round((info.hi - info.lo) / element_size)).astype(int)
    box = out["parts"][info.name]["geometry"]["box"]
    box.pop("element_size", None)
    box["divisions"] = [int(v) for v in n]
    size = (info.hi - info.lo) / n
    if abs(size[0] - size[1]) > 1e-6 * size.max():
        raise StudyError(f"ALE element size {element_size:g} gives {size[0]:g} x {size[1]:g} elements on the "
                         f"{info.hi[0] - info.lo[0]:g} x {info.hi[1] - info.lo[1]:g} box (not square)")
    notes = [f"ALE part {info.name}: {n[0]} x {n[1]} elements of {size[0]:g}"]
    notes += _coupling_points(out, info.element_size / float(size[0]))
    return Derived(out, notes=notes)


def _coupling_points(data: dict, refinement: float) -> list[str]:
    """Scale each lagrange_in_solid's ``nquad`` by the ALE refinement (deck size / this size), in place.

    The coupling acts at nquad points per structure segment; the structure is not refined with the
    fluid, so at fixed nquad the points end up farther apart than the fluid elements and water
    passes between them (LS-DYNA's guidance for *CONSTRAINED_LAGRANGE_IN_SOLID: two or more coupling
    points per fluid element along the structure). Measured on decks/underwater_explosion_ale.yaml
    at h/2 (1.25 mm, 5 mm plate segments): plate centre at 0.1 ms 0.80 mm with nquad 2, 3.63 mm with
    nquad 4 (3.12 mm at h). Returns the notes; the schema caps nquad at NQUAD_MAX.

    The penalty's extra fluid layer L_c = n h / pfac (n = h / l, l = segment length / nquad;
    docs/theory/coupling.md, "Stiffness") therefore stays the same fraction of the fluid element:
    at refinement r, h / r and nquad r give n and L_c / h unchanged with pfac kept. ceil() can only
    raise nquad and the cap only lowers it: at the cap (e.g. nquad 2 at h / 4 wants 8, gets 5) n
    falls to 5/8 of the deck's and L_c / h with it (a stiffer coupling, never a softer one), while
    the points sit farther apart than the deck's spacing per element (said in the note).
    """
    notes = []
    for j, c in enumerate(data.get("couplings") or []):
        if c.get("type") != "lagrange_in_solid" or refinement <= 1.0 + 1e-9:
            continue
        base = int(c.get("nquad", NQUAD_DEFAULT))
        want = int(np.ceil(base * refinement - 1e-9))
        c["nquad"] = min(NQUAD_MAX, want)
        capped = f" (capped at {NQUAD_MAX}: {want} would keep the deck's point spacing per element)" \
            if want > NQUAD_MAX else ""
        notes.append(f"couplings[{j}]: nquad {base} -> {c['nquad']}, the coupling points refined with the "
                     f"fluid mesh{capped}")
    return notes


# ------------------------------------------------------------------------------------ particles


def sub_centres(info: AleInfo, ratio: int) -> tuple[np.ndarray, np.ndarray, float]:
    """x (nx,) and y (ny,) coordinates of the element sub-centres at ``ratio``, and the spacing."""
    m = info.divisions * ratio
    dx = (info.hi - info.lo) / m
    xs = info.lo[0] + (np.arange(m[0]) + 0.5) * dx[0]
    ys = info.lo[1] + (np.arange(m[1]) + 0.5) * dx[1]
    return xs, ys, float(dx.mean())


def source_labels(deck, info: AleInfo, xs: np.ndarray, ys: np.ndarray) -> np.ndarray:
    """(ny, nx) int: 0 where the base material is, j + 1 where fill j is (later fills win)."""
    from ..model.ale_build import fill_region

    X, Y = np.meshgrid(xs, ys)
    labels = np.zeros(X.shape, dtype=np.int64)
    for j, fill in enumerate(deck.parts[info.name].fill):
        labels[np.asarray(fill_region(fill)(X, Y), dtype=bool)] = j + 1
    return labels


def mask_geometry(mask: np.ndarray, x0: float, y0: float, dx: float) -> dict:
    """A deck geometry whose SPH lattice (sph.lattice) is exactly the cells of ``mask`` (ny, nx).

    A full rectangle becomes a ``box`` (the lattice anchors at its lower corner). Anything else
    becomes a ``polygon`` read with the even-odd rule: only the vertical edges count for a point
    (the ray test is horizontal), so the walk goes up a spine on the grid's left line x0 (to the
    left of every centre, never counted) and, for each band of rows with the same runs, out and
    round each run [a, b) and back. All vertices are on grid lines, so the lattice anchored at the
    polygon's lower-left corner is the sub-centre lattice, and no centre lies on an edge.
    """
    rows = np.flatnonzero(mask.any(axis=1))
    if len(rows) == 0:
        raise ValueError("empty mask")
    cols = np.flatnonzero(mask.any(axis=0))
    r0, r1, c0, c1 = rows[0], rows[-1] + 1, cols[0], cols[-1] + 1
    if mask[r0:r1, c0:c1].all() and mask.sum() == (r1 - r0) * (c1 - c0):
        return {"box": {"min": [x0 + c0 * dx, y0 + r0 * dx], "max": [x0 + c1 * dx, y0 + r1 * dx]}}

    def runs(row: np.ndarray) -> tuple[tuple[int, int], ...]:
        padded = np.concatenate([[False], row, [False]]).astype(np.int8)
        edges = np.flatnonzero(np.diff(padded))
        return tuple(zip(edges[0::2].tolist(), edges[1::2].tolist()))

    bands: list[list] = []  # [row_lo, row_hi, runs]
    for j in range(mask.shape[0]):
        rj = runs(mask[j])
        if bands and bands[-1][1] == j and bands[-1][2] == rj:
            bands[-1][1] = j + 1
        else:
            bands.append([j, j + 1, rj])
    vertices: list[list[float]] = []
    for lo, hi, rj in bands:
        if not rj:
            continue
        ylo, yhi = y0 + lo * dx, y0 + hi * dx
        vertices.append([x0, ylo])
        for a, b in rj:
            xa, xb = x0 + a * dx, x0 + b * dx
            vertices += [[xa, ylo], [xa, yhi], [xb, yhi], [xb, ylo]]
        vertices.append([x0, ylo])
    return {"polygon": {"vertices": vertices}}


def _lattice_points(geometry: dict, dx: float) -> np.ndarray:
    from ..sph import lattice

    if "box" in geometry:
        return lattice.box(geometry["box"]["min"], geometry["box"]["max"], dx)
    return lattice.polygon(geometry["polygon"]["vertices"], dx)


def _energy_for_pressure(deck, material: str, pressure: float, density_ratio: float = 1.0) -> float | None:
    """E0 [pressure] at which the material's EOS gives ``pressure`` at rho/rho0 = density_ratio
    (every EOS here is linear in E); None when the pressure does not depend on E (Tait)."""
    from ..materials.kernels import eos_pressure
    from ..materials.slots import EOS_OFFSET, P_EOS_TYPE
    from ..materials.tables import pack_material

    mat = deck.materials[material]
    _, row = pack_material(mat, deck.equations_of_state.get(mat.eos))
    kind, q = int(row[P_EOS_TYPE]), row[EOS_OFFSET:]
    p0 = float(eos_pressure(kind, q, density_ratio, 0.0))
    p1 = float(eos_pressure(kind, q, density_ratio, 1.0))
    if abs(p1 - p0) < 1e-300:
        return None
    return (pressure - p0) / (p1 - p0)


def sph_variant(data: dict, ratio: int, deck_dir: Path | None = None) -> Derived:
    """The SPH deck at particle spacing = ALE element size / ``ratio`` (see the module's rules)."""
    if int(ratio) != ratio or ratio < 1:
        raise StudyError(f"ratio {ratio!r}: ratios are whole numbers >= 1 (particles at element sub-centres)")
    ratio = int(ratio)
    deck = validated(data)
    info = ale_info(deck)
    out = copy.deepcopy(data)
    derived = Derived(out)
    xs, ys, dx = sub_centres(info, ratio)
    derived.spacing = dx
    labels = source_labels(deck, info, xs, ys)
    ale_part = deck.parts[info.name]
    sources = [(info.name, ale_part.material, None)] + [
        (f"{info.name}_fill{j}", f.material, f) for j, f in enumerate(ale_part.fill)]

    parts = out["parts"]
    ale_raw = parts.pop(info.name)
    if not any(p.get("section") == info.section for p in parts.values()):
        out["sections"].pop(info.section, None)
    section_name = next((n for n, s in deck.sections.items() if s.type == "sph"), None)
    if section_name is None:
        section_name = "sph" if "sph" not in out["sections"] else f"{info.section}_sph"
        out["sections"][section_name] = {
            "type": "sph", "kernel": "cubic_spline", "smoothing_ratio": 1.2,
            "artificial_viscosity": {"alpha": 0.1, "beta": 0.0},
        }
        cutoff = deck.sections[info.section].pressure_cutoff  # the ALE fluids' cavitation pressure
        if cutoff is not None:
            out["sections"][section_name]["pressure_cutoff"] = cutoff
    del ale_raw

    sph_parts: dict[str, str] = {}  # part -> material
    for label, (pname, material, fill) in enumerate(sources):
        if deck.materials[material].type == "void":
            continue
        mask = labels == label
        if not mask.any():
            if fill is not None:
                derived.notes.append(f"{pname}: no sub-centre of fill {label - 1} is left at ratio {ratio}")
            continue
        geometry = mask_geometry(mask, info.lo[0], info.lo[1], dx)
        pts = _lattice_points(geometry, dx)
        if len(pts) != int(mask.sum()):  # the lattice must reproduce the mask exactly
            raise StudyError(f"{pname}: the derived geometry gives {len(pts)} particles, expected {int(mask.sum())}")
        name = pname if pname not in parts else f"{pname}_sph"
        mat_name = material
        if fill is not None and (fill.pressure is not None or fill.density is not None):
            mat_name = _state_material(out, deck, material, fill, name, derived)
        parts[name] = {"material": mat_name, "section": section_name, "geometry": geometry, "spacing": dx}
        if ale_part.hydrostatic:
            parts[name]["hydrostatic"] = True
        sph_parts[name] = material
        derived.parts[name] = len(pts)
        if fill is not None and fill.velocity is not None:
            out.setdefault("initial", []).append({"type": "velocity", "part": name, "velocity": list(fill.velocity)})
    if not sph_parts:
        raise StudyError("the ALE part holds no fluid to turn into particles")

    for load in out.get("loads", []):  # loads that name the ALE part act on its particles
        if load.get("type") == "gravity" and info.name in (load.get("parts") or []):
            load["parts"] = [p for p in load["parts"] if p != info.name] + list(sph_parts)
    _boundaries(out, info, section_name, dx)
    _couplings(out, deck, info, sph_parts, derived)
    derived.data = plain(out)
    return derived


def plain(v):
    """numpy scalars as Python numbers, tuples as lists: data yaml.safe_dump can write."""
    if isinstance(v, dict):
        return {k: plain(x) for k, x in v.items()}
    if isinstance(v, (list, tuple)):
        return [plain(x) for x in v]
    if isinstance(v, np.generic):
        return v.item()
    return v


def _state_material(out: dict, deck, material: str, fill, part: str, derived: Derived) -> str:
    """A copy of ``material`` (and its EOS) whose default state is the fill's density and pressure."""
    mat = deck.materials[material]
    new_mat = f"{material}_{part}"
    raw_mat = copy.deepcopy(out["materials"][material])
    rho = fill.density if fill.density is not None else mat.density
    raw_mat["density"] = rho
    if fill.density is not None and fill.density != mat.density:
        derived.notes.append(f"{part}: fill density {rho:g} becomes the reference density of material {new_mat}")
    if fill.pressure is not None:
        probe = copy.deepcopy(deck)
        probe.materials[material] = mat.model_copy(update={"density": rho})
        e0 = _energy_for_pressure(probe, material, fill.pressure)
        if e0 is None:
            derived.notes.append(f"{part}: EOS '{mat.eos}' does not depend on energy; fill pressure "
                                 f"{fill.pressure:g} not carried")
        else:
            new_eos = f"{mat.eos}_{part}"
            raw_eos = copy.deepcopy(out["equations_of_state"][mat.eos])
            raw_eos["e0"] = float(e0)
            out["equations_of_state"][new_eos] = raw_eos
            raw_mat["eos"] = new_eos
    out["materials"][new_mat] = raw_mat
    return new_mat


_FACES = {"left": (0, 0), "right": (0, 1), "bottom": (1, 0), "top": (1, 1)}


def _boundaries(out: dict, info: AleInfo, section: str, dx: float) -> None:
    """ale_boundary -> SPH walls (slip / no_slip), non_reflecting sides -> SPH non_reflecting sides (their
    `source` kept: the same impedance condition, sph/open_sides.py) and transmit sides -> the section's
    domain (particles leaving it are deactivated: a free surface, as before; the ALE transmit side's zero
    gradient has no SPH counterpart)."""
    kept, transmit, walls = [], set(), {"slip": [], "no_slip": []}
    open_sides: list[tuple[list[str], list | None]] = []
    for bc in out.get("boundaries", []):
        if bc.get("type") != "ale_boundary" or bc.get("part") != info.name:
            kept.append(bc)
            continue
        condition = bc.get("condition", "slip")
        if condition == "transmit":
            transmit.update(bc["sides"])
        elif condition == "non_reflecting":
            open_sides.append((list(bc["sides"]), bc.get("source")))
        else:
            walls["slip" if condition == "slip" else "no_slip"] += [s for s in bc["sides"] if s not in walls["slip"]
                                                                     and s not in walls["no_slip"]]
    lo, hi = [float(v) for v in info.lo], [float(v) for v in info.hi]
    for condition, sides in walls.items():
        if sides:
            kept.append({"type": "wall", "min": lo, "max": hi, "sides": sides, "condition": condition})
    for sides, source in open_sides:
        side = {"type": "wall", "min": lo, "max": hi, "sides": sides, "condition": "non_reflecting"}
        if source is not None:
            side["source"] = [float(v) for v in source]
        kept.append(side)
    out["boundaries"] = kept
    if transmit:
        # Deactivate particles leaving through transmitting sides; elsewhere leave room for the walls, and
        # beyond a non_reflecting side, which moves with the water by its displacement there and deletes
        # nothing, the tank's own extent (a bound that only a runaway particle reaches)
        nonref = {s for sides, _ in open_sides for s in sides}
        dlo, dhi = list(lo), list(hi)
        for side, (axis, which) in _FACES.items():
            if side in transmit:
                continue
            margin = hi[axis] - lo[axis] if side in nonref else 3 * dx
            if which == 0:
                dlo[axis] -= margin
            else:
                dhi[axis] += margin
        out["sections"][section]["domain"] = {"min": dlo, "max": dhi}


def _couplings(out: dict, deck, info: AleInfo, sph_parts: dict[str, str], derived: Derived) -> None:
    """lagrange_in_solid couplings -> nodes_to_surface contacts, one per coupled SPH part."""
    couplings = out.pop("couplings", []) or []
    for c in couplings:
        if c.get("fluid") != info.name:
            raise StudyError(f"coupling to '{c.get('fluid')}' is not the ALE part '{info.name}'")
        model = next(m for m in deck.couplings if m.structure == c["structure"] and m.fluid == c["fluid"])
        coupled = set(model.materials) if model.materials else {
            m for m in sph_parts.values() if deck.materials[m].type != "void"}
        for part, material in sph_parts.items():
            if material not in coupled:
                continue
            out.setdefault("contacts", []).append({
                "type": "nodes_to_surface", "nodes": part, "surface": c["structure"],
                "stiffness": "soft_constraint", "soft_scale": SOFT_SCALE, "damping": model.damping,
            })
        derived.notes.append(f"coupling {c['structure']} <- {info.name} (pfac {model.pfac}, damping "
                             f"{model.damping:g}) became soft-constraint nodes_to_surface contacts "
                             f"(soft_scale {SOFT_SCALE:g}) for "
                             f"{', '.join(p for p, m in sph_parts.items() if m in coupled) or 'no part'}")


def absolute_files(data: dict, deck_dir: Path) -> dict:
    """Geometry file paths made absolute, so a derived deck can live in another folder."""
    out = copy.deepcopy(data)
    for part in out.get("parts", {}).values():
        f = part.get("geometry", {}).get("file")
        if isinstance(f, dict) and "file" in f and not Path(f["file"]).is_absolute():
            f["file"] = str((deck_dir / f["file"]).resolve())
    return out
