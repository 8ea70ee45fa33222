"""Issue 15: the axisymmetric Taylor rod against the 3D deck at matched element sizes, both refined by 2
in every direction (figures and conclusions in docs/studies/taylor_convergence.md).

    python docs/studies/taylor_convergence.py run CASE [CASE ...]   # from the repository root, one process each
    python docs/studies/taylor_convergence.py summary               # tables of the cases that have run
    python docs/studies/taylor_convergence.py list                  # the case names

Decks: decks/taylor_bar.yaml (3D O-grid cylinder, 16 around, 3 through, 32 along) and
decks/taylor_bar_axisymmetric.yaml (r-z quads, 5 x 32), both to 80 us. Level k multiplies every count by
2^(k-1): 3D ``elements_around``, ``elements_through``, ``elements_along``; r-z both ``divisions``.

Matched sizes. Along the axis both have L / n_along. Across, the r-z quads are R / n_r; the O-grid's ray
through the rim node at angle 0 (the deck's "rim" history; the ring nodes sit at -pi/4 + 2 pi i / n_around,
so one is at angle 0 when n_around is a multiple of 8) crosses m / 2 core elements (m = n_around / 4, core
half-width a = R / (1.2 + 2 n_through / m) = R / 2.7 at every level here) and n_through ring layers, so
n_r = m / 2 + n_through (5, 10, 20): mean radial size R / n_r on both (3D: 0.185 R core, 0.210 R ring at
level 1). The 3D section has no r-z counterpart around: 2 pi R / n_around at the rim (0.39 R at level 1).

Quarter models. The O-grid is symmetric about x = 0 and y = 0 (core grid lines and ring nodes lie on both
axes when n_around is a multiple of 8), so ``q3d`` cases run the quadrant x, y >= 0 of the same mesh (written
as a VTU) with symmetry conditions on x = 0 and y = 0: a quarter of the cost; ``f3d`` cases run the deck as
shipped, to check that the quarter gives the full model's numbers. Areas and perimeters of a quarter are
multiplied by 4.

Measured per case, at 80 us (the rod has stopped at about 66 us):
- length: the axis node of the rear face (history far_end);
- D_rim: 2 x the largest radius of the impact face's rim nodes (those at r = R at t = 0). In 3D they are the
  vertices of the section polygon, on the circle; in r-z the one rim node. Also the smallest rim radius (3D:
  how round the foot stays) and 2 x the largest radius of any node (whether the foot is widest at the face);
- D_area = 2 sqrt(A / pi), A the impact face's area: 3D the sum of the bottom faces of the first element layer
  (shoelace, in the wall plane z = 0); r-z the revolved face, pi r_rim^2, so D_area = D_rim there;
- caliper widths of the 3D face polygon: its width between two parallel jaws, over 3600 directions (min,
  max; the mean width of a convex polygon is its perimeter / pi, Cauchy);
- the final plastic strain at the impact centre (history impact_centre: the element nearest the axis point
  of the face), CPU seconds of the run (process time, one thread, after a warm-up run that loads the numba
  cache), steps, energy ratio and hourglass energy over internal at the end.
Convergence per method: observed order, Richardson value and GCI (Fs 1.25) of each three consecutive levels run,
sphfem_cli.study.metrics.three_grid / describe, with h = 2^(1-k).
"""
from __future__ import annotations

import json
import math
import sys
import time
from pathlib import Path

import numpy as np
import yaml

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))
from sphfem_cli import api  # noqa: E402
from sphfem_cli.model.mesh import cylinder_mesh  # noqa: E402
from sphfem_cli.study.metrics import describe, three_grid  # noqa: E402

DECK_3D = ROOT / "decks/taylor_bar.yaml"
DECK_RZ = ROOT / "decks/taylor_bar_axisymmetric.yaml"
WORK = Path("study_taylor")
R, L = 0.00381, 0.0254
BASE_3D = (16, 3, 32)  # around, through, along
BASE_RZ = (5, 32)
# name: (model, level); model "rz", "q3d" (quarter 3D) or "f3d" (full 3D deck)
CASES = {f"rz_{k}": ("rz", k) for k in (1, 2, 3, 4)}
CASES.update({f"q3d_{k}": ("q3d", k) for k in (1, 2, 3)})
CASES.update({f"f3d_{k}": ("f3d", k) for k in (1, 2)})


def counts(model: str, level: int) -> tuple[int, ...]:
    base = BASE_RZ if model == "rz" else BASE_3D
    return tuple(c * 2 ** (level - 1) for c in base)


def elements(model: str, level: int) -> int:
    c = counts(model, level)
    if model == "rz":
        return c[0] * c[1]
    full = ((c[0] // 4) ** 2 + c[0] * c[1]) * c[2]
    return full // 4 if model == "q3d" else full


def quarter_mesh(level: int, path: Path) -> int:
    """Write the quadrant x, y >= 0 of the level's O-grid cylinder as a VTU; returns its element count."""
    import meshio

    around, through, along = counts("q3d", level)
    mesh = cylinder_mesh((0.0, 0.0, 0.5 * L), "z", 0.0, R, L, around, through, along)
    nodes = mesh.nodes.copy()
    nodes[np.abs(nodes) < 1e-12 * R] = 0.0  # the axes' nodes exactly on the symmetry planes
    centroid = nodes[mesh.elements].mean(axis=1)
    keep = mesh.elements[(centroid[:, 0] > 0.0) & (centroid[:, 1] > 0.0)]
    used = np.unique(keep)
    new = np.full(nodes.shape[0], -1, dtype=np.int64)
    new[used] = np.arange(used.size)
    meshio.write(path, meshio.Mesh(nodes[used], [("hexahedron", new[keep])]))
    return int(keep.shape[0])


def deck_for(name: str) -> dict:
    model, level = CASES[name]
    deck = yaml.safe_load((DECK_RZ if model == "rz" else DECK_3D).read_text())
    geometry = deck["parts"]["rod"]["geometry"]
    if model == "rz":
        geometry["box"]["divisions"] = list(counts(model, level))
    elif model == "f3d":
        around, through, along = counts(model, level)
        geometry["cylinder"].update(elements_around=around, elements_through=through, elements_along=along)
    else:
        vtu = (WORK / f"quarter_{level}.vtu").resolve()
        quarter_mesh(level, vtu)
        deck["parts"]["rod"]["geometry"] = {"file": {"file": str(vtu)}}
        deck["sets"]["sym_x"] = {"type": "node", "part": "rod", "plane": {"point": [0, 0, 0], "normal": [1, 0, 0]}}
        deck["sets"]["sym_y"] = {"type": "node", "part": "rod", "plane": {"point": [0, 0, 0], "normal": [0, 1, 0]}}
        deck["boundaries"] += [{"type": "symmetry", "set": "sym_x", "normal": "x"},
                               {"type": "symmetry", "set": "sym_y", "normal": "y"}]
    deck["output"]["interval"] = deck["control"]["end_time"]  # fields at 0 and at the end only
    deck["output"]["fields"] = ["displacement", "plastic_strain"]
    return deck


def shoelace(xy: np.ndarray) -> np.ndarray:
    """Areas of polygons (..., k, 2), corners in order."""
    x, y = xy[..., 0], xy[..., 1]
    return 0.5 * np.abs(np.sum(x * np.roll(y, -1, axis=-1) - np.roll(x, -1, axis=-1) * y, axis=-1))


def face_measures(folder: Path, model: str) -> dict:
    """Diameters of the impact face at the last field step (see the module docstring)."""
    import h5py

    with h5py.File(folder / "results.h5", "r") as f:
        steps = sorted(k for k in f["rod"] if k.startswith("step_"))
        x0 = f[f"rod/{steps[0]}/coordinates"][...]
        x1 = f[f"rod/{steps[-1]}/coordinates"][...]
        conn = f["rod/connectivity"][...]
    tol = 1e-9 * L
    if model == "rz":
        face = np.abs(x0[:, 1]) < tol
        rim = face & (x0[:, 0] > R - tol)
        r_rim = float(x1[rim, 0].max())
        area = math.pi * r_rim**2
        out = {"r_rim_max": r_rim, "r_rim_min": float(x1[rim, 0].min()), "r_all_max": float(x1[:, 0].max()),
               "area": area}
        return out
    mult = 4 if model == "q3d" else 1
    r0 = np.hypot(x0[:, 0], x0[:, 1])
    face = np.abs(x0[:, 2]) < tol
    rim = face & (r0 > R * (1 - 1e-9))
    r1 = np.hypot(x1[:, 0], x1[:, 1])
    bottom = conn[:, :4]
    on_face = face[bottom].all(axis=1)
    area = mult * float(shoelace(x1[bottom[on_face]][..., :2]).sum())
    pts = x1[face][:, :2]
    if model == "q3d":  # the whole face by the two symmetry planes
        pts = np.concatenate([pts * s for s in ((1, 1), (-1, 1), (1, -1), (-1, -1))])
    phi = np.linspace(0.0, math.pi, 3600, endpoint=False)
    proj = pts @ np.stack([np.cos(phi), np.sin(phi)])
    width = proj.max(axis=0) - proj.min(axis=0)
    return {"r_rim_max": float(r1[rim].max()), "r_rim_min": float(r1[rim].min()), "r_all_max": float(r1.max()),
            "area": area, "caliper_min": float(width.min()), "caliper_max": float(width.max()),
            "caliper_mean": float(width.mean()), "area_t0": mult * float(shoelace(x0[bottom[on_face]][..., :2]).sum())}


def last(table: dict, column: str) -> float:
    return float(table[column][-1])


def run(name: str) -> dict:
    model, level = CASES[name]
    WORK.mkdir(exist_ok=True)
    deck = deck_for(name)
    warm = dict(deck, control=dict(deck["control"], end_time=2.0e-7))
    warm["output"] = dict(deck["output"], interval=2.0e-7)
    api.run(warm, WORK / f"warmup_{name}", overwrite=True, threads=1)
    t0, w0 = time.process_time(), time.time()
    result = api.run(deck, WORK / name, overwrite=True, threads=1)
    cpu, wall = time.process_time() - t0, time.time() - w0
    if not result.completed:
        raise SystemExit(f"{name}: {result.status}: {result.message}")
    h = result.histories()
    axial = "coordinates_y" if model == "rz" else "coordinates_z"
    glstat = h["glstat"]
    row = {"name": name, "model": model, "level": level, "counts": counts(model, level),
           "elements": elements(model, level),
           "length": last(h["far_end"], axial), "plastic_strain_centre": last(h["impact_centre"], "plastic_strain"),
           "cpu_s": cpu, "wall_s": wall, "steps": result.steps, "energy_ratio": last(glstat, "energy_ratio"),
           "hourglass_over_internal": last(glstat, "hourglass") / last(glstat, "internal"),
           "rim_history_x": last(h["rim"], "coordinates_x")}
    row.update(face_measures(WORK / name, model))
    row["D_rim"], row["D_area"] = 2 * row["r_rim_max"], 2 * math.sqrt(row["area"] / math.pi)
    (WORK / f"{name}.json").write_text(json.dumps(row, indent=1))
    return row


def load(name: str) -> dict | None:
    path = WORK / f"{name}.json"
    return json.loads(path.read_text()) if path.exists() else None


QUANTITIES = (("length", "length [mm]", 1e3), ("D_rim", "D_rim [mm]", 1e3), ("D_area", "D_area [mm]", 1e3),
              ("plastic_strain_centre", "plastic strain at the centre", 1.0))


def summary() -> None:
    rows = {n: r for n in CASES if (r := load(n)) is not None}
    print("| case | counts | length [mm] | D_rim [mm] | D_area [mm] | rim min / all-node max r [mm] | "
          "caliper min / mean / max [mm] | plastic strain, centre | steps | CPU [s] | energy ratio | HG / IE |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    for n, r in rows.items():
        cal = (f"{1e3 * r['caliper_min']:.3f} / {1e3 * r['caliper_mean']:.3f} / {1e3 * r['caliper_max']:.3f}"
               if "caliper_min" in r else "-")
        print(f"| {n} | {' x '.join(map(str, r['counts']))} | {1e3 * r['length']:.3f} | {1e3 * r['D_rim']:.3f} | "
              f"{1e3 * r['D_area']:.3f} | {1e3 * r['r_rim_min']:.3f} / {1e3 * r['r_all_max']:.3f} | {cal} | "
              f"{r['plastic_strain_centre']:.3f} | {r['steps']} | {r['cpu_s']:.1f} | {r['energy_ratio']:.4f} | "
              f"{100 * r['hourglass_over_internal']:.2f} % |")
    print("\n| method | quantity | levels | values (fine, medium, coarse) | convergence | Richardson | "
          "GCI fine |")
    print("|---|---|---|---|---|---|---|")
    for model in ("rz", "q3d"):
        levels = sorted(r["level"] for r in rows.values() if r["model"] == model)
        for top in range(len(levels), 2, -1):
            use = levels[top - 3:top]
            h = [2.0 ** (1 - k) for k in use]
            for key, label, scale in QUANTITIES:
                phi = [rows[f"{model}_{k}"][key] for k in use]
                c = three_grid(h, phi)
                ext = f"{scale * c.extrapolated:.3f}" if math.isfinite(c.extrapolated) else "-"
                band = f"{100 * c.gci_fine:.2f} %" if math.isfinite(c.gci_fine) else "-"
                vals = " / ".join(f"{scale * v:.3f}" for v in c.phi)
                print(f"| {model} | {label} | {use[-1]},{use[1]},{use[0]} | {vals} | {describe(c)} | {ext} | {band} |")
    print("\n| case | D_area at t = 0 [mm] | D_area / D_rim at t = 0 | at 80 us | D_rim / 2R | D_area / D_area(0) |"
          "\n|---|---|---|---|---|---|")
    for n, r in rows.items():
        if "area_t0" in r:
            d0 = 2 * math.sqrt(r["area_t0"] / math.pi)
            print(f"| {n} | {1e3 * d0:.4f} | {d0 / (2 * R):.5f} | {r['D_area'] / r['D_rim']:.5f} | "
                  f"{r['D_rim'] / (2 * R):.4f} | {r['D_area'] / d0:.4f} |")
        elif r["model"] == "rz":
            print(f"| ({n}, r-z) | {2e3 * R:.4f} | 1 | 1 | {r['D_rim'] / (2 * R):.4f} | {r['D_rim'] / (2 * R):.4f} |")
    print("\n| level | length r-z / 3D - 1 | D_rim r-z / 3D - 1 | D_area r-z / 3D - 1 |\n|---|---|---|---|")
    for k in (1, 2, 3, 4):
        a, b = rows.get(f"rz_{k}"), rows.get(f"q3d_{k}")
        if a and b:
            print(f"| {k} | {100 * (a['length'] / b['length'] - 1):+.2f} % | {100 * (a['D_rim'] / b['D_rim'] - 1):+.2f} % "
                  f"| {100 * (a['D_area'] / b['D_area'] - 1):+.2f} % |")


if __name__ == "__main__":
    command, names = (sys.argv[1], sys.argv[2:]) if len(sys.argv) > 1 else ("summary", [])
    if command == "run":
        for name in names:
            print(json.dumps(run(name)))
    elif command == "list":
        print(" ".join(CASES))
    else:
        summary()
