"""Soft-constraint contact on the three SPH-on-plate decks whose masters are deformable plates (7 December 2026):
decks/bird_strike_axisymmetric_plate_sph.yaml, decks/underwater_explosion_axisymmetric_sph.yaml and
decks/underwater_explosion_sph.yaml, run as shipped and with the contacts' soft_scale changed, with the
penetration of the particles into the plate measured at every step.

    PYTHONPATH=. NUMBA_NUM_THREADS=1 python docs/studies/soft_contact_plates.py DECK --soft-scale 0.1 0.3 [-o DIR]

The soft constraint's spring (contact.kernels.point_forces) is k = s m / dt0^2 on the reduced mass
m = m_p / (1 + m_p max_j 1/m_j) of the particle and the master segment's lightest node; a particle with gap g
to the segment is pushed out when its penetration d = t - g > 0 (t the contact thickness, dx / 2 for
particles), and is released (no force) once g <= -depth, the segment's depth limit (the element's depth
through the plate, meridian area / length). Recorded per contact, after every force pass:
  - ``pen_max``: the largest d / t over the contacting particles (d / t = 1: the particle's centre on the
    segment; 1 + depth / t: the release depth), with its time;
  - ``behind``: particles whose centre lies more than the depth limit behind the wet face (the face taken
    as the master nodes on the plate's initial wet plane y = FACE_Y, piecewise linear in x at their current
    positions, the side of the slaves at t = 0 the outside): the largest number at one step and the number
    of distinct particles ever so, i.e. particles the contact let through;
  - ``gap_min``: the smallest signed distance (m) of a slave's centre from that face.
Per run also the deck's compared quantities (``measure``) and the CPU seconds (process time).
"""
from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

import numpy as np
import yaml

from sphfem_cli import api
from sphfem_cli.contact.system import NodesToSurfaceContact


class PenetrationLog:
    """Wraps NodesToSurfaceContact.forces to record the figures of the module docstring per contact."""

    def __init__(self, face_y: float):
        self.face_y = face_y
        self.rows: dict[str, dict] = {}
        self._original = NodesToSurfaceContact.forces

    def install(self) -> None:
        log = self

        def forces(contact, st):
            log._original(contact, st)
            log.record(contact, st)

        NodesToSurfaceContact.forces = forces

    def remove(self) -> None:
        NodesToSurfaceContact.forces = self._original

    def record(self, contact, st) -> None:
        name = contact.name
        xp, _, _, mask, thickness = contact._slaves()
        row = self.rows.get(name)
        if row is None:
            x0 = contact.sim.model.coordinates
            nodes = np.asarray(contact.master_nodes)
            face = nodes[np.abs(x0[nodes, 1] - self.face_y) < 1e-9]
            face = face[np.argsort(x0[face, 0])]
            side = 1.0 if float(np.mean(xp[mask, 1])) > self.face_y else -1.0
            row = self.rows[name] = {"pen_max": 0.0, "t_pen_max": 0.0, "gap_min": np.inf, "t_gap_min": 0.0,
                                     "behind_step_max": 0, "behind_ids": set(), "_face": face, "_side": side,
                                     "depth_min": float(np.min(contact.seg_depth)),
                                     "depth_max": float(np.max(contact.seg_depth)),
                                     "thickness": float(np.median(thickness[mask]))}
        t = float(st.time)
        touching = (contact._seg_of >= 0) & mask
        if touching.any():
            ratio = (thickness[touching] - contact._gap[touching]) / thickness[touching]
            j = float(ratio.max())
            if j > row["pen_max"]:
                row["pen_max"], row["t_pen_max"] = j, t
        face = row["_face"]
        xf = st.x[face]
        sel = mask & (xp[:, 0] >= xf[0, 0]) & (xp[:, 0] <= xf[-1, 0])
        if sel.any():
            gap = row["_side"] * (xp[sel, 1] - np.interp(xp[sel, 0], xf[:, 0], xf[:, 1]))
            g = float(gap.min())
            if g < row["gap_min"]:
                row["gap_min"], row["t_gap_min"] = g, t
            behind = gap < -row["depth_min"]
            if behind.any():
                row["behind_step_max"] = max(row["behind_step_max"], int(behind.sum()))
                idx = np.flatnonzero(sel)[behind]
                ids = contact.sim.particles.system.ids[idx] if contact.particle_slaves else idx
                row["behind_ids"].update(int(i) for i in ids)

    def summary(self) -> dict:
        out = {}
        for name, row in self.rows.items():
            out[name] = {k: v for k, v in row.items() if not k.startswith("_") and k != "behind_ids"}
            out[name]["behind_ever"] = len(row["behind_ids"])
        return out


def measure(hist: dict) -> dict:
    """Plate centre (history 'centre'): largest |u_y| and its time, u_y at 0.1 / 0.2 / 0.5 ms, largest |v_y|,
    largest von Mises or the final plastic strain; the plate's contact force history ('plate') where there is
    one: its value at 0.1 / 0.3 ms, peak and impulse; the pressure probes' peaks; the largest energy-ratio error."""
    c = hist["centre"]
    t, u, v = c["time"], c["displacement_y"], c["velocity_y"]
    i = int(np.argmax(np.abs(u)))
    out = {"u_max_mm": 1e3 * float(abs(u[i])), "t_u_max_ms": 1e3 * float(t[i]),
           "u_end_mm": 1e3 * float(abs(u[-1]))}
    for tq in (1e-4, 2e-4, 3e-4, 5e-4):
        if t[-1] >= tq:
            out[f"u_{tq * 1e3:g}ms_mm"] = 1e3 * float(abs(np.interp(tq, t, u)))
            out[f"v_{tq * 1e3:g}ms"] = float(np.interp(tq, t, v))
    j = int(np.argmax(np.abs(v)))
    out.update({"v_peak": float(abs(v[j])), "t_v_peak_ms": 1e3 * float(t[j])})
    if "von_mises" in c:
        k = int(np.argmax(c["von_mises"]))
        out.update({"vm_peak_MPa": float(c["von_mises"][k]) / 1e6, "t_vm_peak_ms": 1e3 * float(t[k])})
    if "plastic_strain" in c:
        out["eps_p_centre_end"] = float(c["plastic_strain"][-1])
        out["eps_p_centre_max"] = float(np.max(c["plastic_strain"]))
    if "plate" in hist and "contact_force_y" in hist["plate"]:
        tf, f = hist["plate"]["time"], hist["plate"]["contact_force_y"]
        out.update({"F_0.1ms": float(np.interp(1e-4, tf, f)), "F_0.3ms": float(np.interp(3e-4, tf, f)),
                    "F_peak": float(f[np.argmax(np.abs(f))]), "impulse": float(np.trapezoid(f, tf))})
    for name, table in hist.items():
        if "pressure" in table and name != "centre":
            p = np.nan_to_num(table["pressure"])
            m = int(np.argmax(p))
            out[f"{name}_MPa"] = float(p[m]) / 1e6
            out[f"t_{name}_us"] = 1e6 * float(table["time"][m])
    out["energy_err"] = float(np.abs(hist["glstat"]["energy_ratio"] - 1.0).max())
    out["energy_ratio_end"] = float(hist["glstat"]["energy_ratio"][-1])
    return out


def run(deck: Path, scale: float, out: Path, end_time: float | None, face_y: float) -> dict:
    overrides = {f"contacts.{k}.soft_scale": scale for k in range(len(yaml.safe_load(deck.read_text())["contacts"]))}
    if end_time:
        overrides["control.end_time"] = end_time
    log = PenetrationLog(face_y)
    log.install()
    try:
        cpu = time.process_time()
        result = api.run(deck, out, overrides, overwrite=True, threads=1)
        cpu = time.process_time() - cpu
    finally:
        log.remove()
    row = {"deck": deck.name, "soft_scale": scale, "completed": bool(result.completed), "message": result.message,
           "steps": result.steps, "cpu_s": cpu, "contacts": log.summary()}
    if result.completed:
        row.update(measure(result.histories()))
    (out / "soft_contact.json").write_text(json.dumps(row, indent=1, default=float))
    return row


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("deck", type=Path)
    ap.add_argument("--soft-scale", type=float, nargs="+", default=[0.1])
    ap.add_argument("--end-time", type=float, default=None)
    ap.add_argument("--face-y", type=float, default=0.0, help="the plate's wet plane at t = 0 (m)")
    ap.add_argument("-o", type=Path, default=Path("soft_contact_plates"))
    args = ap.parse_args()
    for s in args.soft_scale:
        row = run(args.deck, s, args.o / f"{args.deck.stem}_s{s:g}", args.end_time, args.face_y)
        print(json.dumps(row, default=float), flush=True)


if __name__ == "__main__":
    main()
