"""What a run writes: field steps to XDMF/HDF5 and the history tables, on their own intervals.

histories/glstat.csv   global energies (LS-DYNA glstat)
histories/matsum.csv   kinetic, internal, hourglass energy per part (LS-DYNA matsum)
histories/<name>.csv   each requested history (LS-DYNA nodout/elout)
histories/<table>.csv  the tables each domain adds (solver.domain `history_tables`), e.g. ale_materials:
                       mass, internal and kinetic energy per material of the ALE part
The same tables are mirrored in results.h5 under /histories. The grids, fields, extra tables and
probes come from the simulation's domains (solver.domain); the settings from `model.options.output`.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

from ..materials.slots import H_EPS
from ..solver.domain import domain_tables
from ..solver.explicit import EnergyRow, Simulation
from ..solver.solid_domain import von_mises
from .filters import FILTERED, low_pass
from .history import HistoryWriter
from .revolve import (REVOLVED_SUFFIX, angles, revolve_cell_field, revolve_connectivity, revolve_point_field,
                      revolve_points)
from .xdmf import GridStep, XdmfWriter

XML_BUDGET = 0.05  # the XDMF index is rewritten at a field step whenever that costs under 5 % of the wall time
_PROBE_COLUMN = {"pressure": "pressure", "surface_height": "height", "front": "front"}


def history_tables(model) -> list[str]:
    """The history tables a run of `model` writes (histories/<name>.csv), in RunOutput's order."""
    out = model.options.output
    return ["glstat", "matsum", *domain_tables(model), *(h.name for h in out.histories), *(p.name for p in out.probes),
            *(f"{p.name}{FILTERED}" for p in out.probes if p.filter is not None)]


def output_grids(model) -> list[str]:
    """The grids a run of `model` writes, each with its results.<grid>.xdmf: the parts, and with
    output.revolve (axisymmetric decks) each part's <part>.revolved view."""
    names = [p.name for p in model.parts]
    if model.axisymmetric and model.options.output.revolve is not None:
        names += [n + REVOLVED_SUFFIX for n in names]
    return names


class RunOutput:
    """Field and history output of one simulation into `directory`."""

    def __init__(self, sim: Simulation, directory: Path, resume: dict | None = None):
        """``resume``: a :meth:`state` from a checkpoint; the files in ``directory`` are continued
        after the rows and steps it lists (what was written after it is dropped)."""
        self.sim = sim
        model = sim.model
        out = model.options.output
        self.field_interval = out.interval
        self.history_interval = out.history_interval
        self.fields = set(out.fields)
        self._selectable = out.selectable
        self.directory = Path(directory)
        (self.directory / "histories").mkdir(parents=True, exist_ok=True)
        self.xdmf = XdmfWriter(self.directory, "results", resume=None if resume is None else resume["xdmf"],
                               xml_budget=XML_BUDGET)
        rows = {} if resume is None else resume["rows"]
        self._owner = {i: d for d in sim.domains for i in d.parts}
        rev = out.revolve if model.axisymmetric else None
        self._revolve = None if rev is None else (rev[0], *angles(*rev))
        for i, p in enumerate(model.parts) if resume is None else ():
            topology, conn, n_points = self._owner[i].grid(i)
            self.xdmf.add_grid(p.name, topology, conn, n_points)
            if self._revolve is not None:
                segments, a, closed = self._revolve
                self.xdmf.add_grid(p.name + REVOLVED_SUFFIX,
                                   *revolve_connectivity(topology, conn, n_points, segments, closed),
                                   n_points * len(a))
        group = self.xdmf.h5  # HistoryWriter mirrors each table in /histories/<name>
        hist_dir = self.directory / "histories"
        self.glstat = HistoryWriter(hist_dir, "glstat", EnergyRow.COLUMNS, h5=group, resume_rows=rows.get("glstat"))
        if model.axisymmetric:
            self.glstat.note("basis", "axisymmetric: energies and work for the full 2 pi (the whole body of revolution)")
        part_cols = ["time"] + [f"{p.name}_{k}" for p in model.parts for k in ("kinetic", "internal", "hourglass")]
        self.matsum = HistoryWriter(hist_dir, "matsum", part_cols, h5=group, resume_rows=rows.get("matsum"))
        self.domain_tables = [(d, [HistoryWriter(hist_dir, name, ["time", *columns], h5=group,
                                                 resume_rows=rows.get(name)) for name, columns in d.history_tables()])
                              for d in sim.domains]
        self.requests = [_HistoryProbe(sim, h, hist_dir, group, rows.get(h.name)) for h in out.histories]
        self.probes = [(probe, next(d for d in sim.domains if d.owns_probe(probe)),
                        HistoryWriter(hist_dir, probe.name, ["time", _PROBE_COLUMN[probe.type]], h5=group,
                                      resume_rows=rows.get(probe.name)))
                       for probe in out.probes]
        self.warnings: list[str] = []
        self._next_field = 0.0 if resume is None else resume["next_field"]
        self._next_history = 0.0 if resume is None else resume["next_history"]
        last = None if resume is None else resume["last_energy"]
        self.last_energy: EnergyRow | None = None if last is None else EnergyRow(*(float(v) for v in last))

    def _writers(self) -> list[HistoryWriter]:
        tables = [w for _, writers in self.domain_tables for w in writers]
        return [self.glstat, self.matsum, *tables, *(p.writer for p in self.requests), *(w for _, _, w in self.probes)]

    def flush(self) -> None:
        """Every history row appended so far onto disk (CSV and HDF5)."""
        for writer in self._writers():
            writer.flush()

    def state(self) -> dict:
        """Everything needed to continue these files after a restart, as plain JSON-able data
        (flushes the histories first)."""
        self.flush()
        last = None if self.last_energy is None else [float(v) for v in self.last_energy.values()]
        return {"next_field": float(self._next_field), "next_history": float(self._next_history),
                "last_energy": last, "xdmf": self.xdmf.state(),
                "rows": {w.name: w.n_rows for w in self._writers()}}

    def __call__(self, force: bool = False) -> None:
        """Write whatever is due at the current state (everything not yet written at this time when `force`)."""
        t = self.sim.state.time
        history_done = self.last_energy is not None and self.last_energy.time == t
        if (force and not history_done) or _due(t, self._next_history, self.history_interval):
            self.write_histories()
            self._next_history = _next_after(t, self.history_interval)
        if (force and self.xdmf.last_time != t) or _due(t, self._next_field, self.field_interval):
            self.write_fields()
            self._next_field = _next_after(t, self.field_interval)

    def write_final_state(self) -> None:
        """The state at the end of a completed run as a field step, when the interval did not land on it
        (end_time not a multiple of output.interval), as LS-DYNA writes a d3plot state at termination."""
        if self.xdmf.last_time != self.sim.state.time:
            self.write_fields()

    def next_field_time(self) -> float:
        """The next field-output time; the solver lands on it exactly."""
        return self._next_field

    def write_histories(self) -> None:
        row = self.sim.energy_row()
        self.last_energy = row
        self.glstat.append(row.values())
        self.matsum.append([row.time, *self.sim.part_energies().ravel()])
        for domain, writers in self.domain_tables:
            if writers:
                for writer, values in zip(writers, domain.history_rows()):
                    writer.append([row.time, *values])
        for probe in self.requests:
            probe.append()
        for probe, domain, writer in self.probes:
            writer.append([row.time, domain.probe(probe)])

    def write_fields(self) -> None:
        sim, model = self.sim, self.sim.model

        def wanted(name: str) -> bool:
            return name in self.fields or name not in self._selectable

        steps = {}
        for d in sim.domains:
            steps.update(d.field_data(wanted))
        data = {}
        for i, p in enumerate(model.parts):
            coords, point, cell = steps[i]
            data[p.name] = GridStep(coordinates=coords, point_data=point, cell_data=cell)
            if self._revolve is not None:
                data[p.name + REVOLVED_SUFFIX] = revolved_step(coords, point, cell, *self._revolve)
        self.flush()  # histories up to this field step are on disk with it
        self.xdmf.write_step(sim.state.time, data)

    def close(self) -> None:
        try:
            for writer in self._writers():
                writer.close()
            self.write_filtered()
        finally:
            self.xdmf.close()

    def write_filtered(self) -> None:
        """histories/<name>_filtered.csv (and its HDF5 mirror) for each probe with a filter: the whole
        raw series as written, low-passed (output/filters.py); the raw table stays as it is. A series
        too short or too coarse for its filter gets no filtered table and a line in warnings."""
        for probe, _, writer in self.probes:
            if probe.filter is None:
                continue
            raw = np.loadtxt(writer.path, delimiter=",", skiprows=1, ndmin=2)
            f = probe.filter
            settings = {"kind": f.kind, "cutoff": f.cutoff, "order": f.order or 2, "window": f.window}
            try:
                values = low_pass(raw[:, 0], raw[:, 1], **settings) if len(raw) else raw[:, 1]
            except ValueError as err:
                self.warnings.append(f"{probe.name}: no filtered table ({err})")
                continue
            with HistoryWriter(writer.path.parent, f"{probe.name}{FILTERED}", writer.columns, h5=self.xdmf.h5) as out:
                for t, v in zip(raw[:, 0], values):
                    out.append([t, v])


def revolved_step(coords, point: dict, cell: dict, segments: int, a: np.ndarray, closed: bool) -> GridStep:
    """The revolved view (output/revolve.py) of one meridian grid step."""
    return GridStep(coordinates=revolve_points(coords, a),
                    point_data={k: revolve_point_field(v, a) for k, v in point.items()},
                    cell_data={k: revolve_cell_field(v, a, segments) for k, v in cell.items()})


def _due(t: float, next_time: float, interval: float) -> bool:
    """t has reached next_time, within round-off of the interval."""
    return t >= next_time - 1e-9 * interval


def _next_after(t: float, interval: float) -> float:
    """The first multiple of interval after t (t itself counting as reached within round-off); t itself when
    the multiple overflows (an interval below float resolution: due at every step)."""
    following = (np.floor((t + 1e-9 * interval) / interval) + 1) * interval
    return following if np.isfinite(following) else t


class _HistoryProbe:
    """One requested history: mean over nodes of a part/set, or the node/element nearest a point."""

    def __init__(self, sim: Simulation, request, directory: Path, group, resume_rows: int | None = None):
        self.sim = sim
        model = sim.model
        dim = model.dim
        if request.point is not None:
            point = np.array(request.point)
            self.nodes = np.array([int(np.argmin(np.linalg.norm(model.coordinates - point, axis=1)))])
            centres = model.coordinates[model.connectivity].mean(axis=1)
            nearest = int(np.argmin(np.linalg.norm(centres - point, axis=1)))
            self.element_rows = slice(nearest, nearest + 1)
        else:
            self.nodes = model.target_nodes(request.part, request.set)
            self.element_rows = (model.parts[model.part_index(request.part)].elements if request.part is not None
                                 else slice(0, model.n_elements))
        self.quantities = list(request.quantities)
        columns = ["time"]
        axes = "xyz"[:dim]
        for q in self.quantities:
            if q in ("displacement", "velocity", "acceleration", "coordinates", "contact_force"):
                columns += [f"{q}_{a}" for a in axes]
            elif q == "stress":
                columns += [f"stress_{c}" for c in ("xx", "yy", "zz", "xy", "yz", "zx")]
            else:
                columns.append(q)
        self.writer = HistoryWriter(directory, request.name, columns, h5=group, resume_rows=resume_rows)

    def _element_values(self, q: str) -> list[float]:
        st = self.sim.state
        rows = self.element_rows
        stress = st.stress[rows]
        if q == "stress":
            return list(stress.mean(axis=0))
        if q == "von_mises":
            return [float(von_mises(stress).max())]
        if q == "pressure":
            return [float(-stress[:, :3].mean())]
        return [float(st.hist[rows, H_EPS].max())]

    def append(self) -> None:
        sim, st = self.sim, self.sim.state
        x0 = sim.model.coordinates[self.nodes]
        row = [st.time]
        for q in self.quantities:
            if q == "displacement":
                row += list((st.x[self.nodes] - x0).mean(axis=0))
            elif q == "coordinates":
                row += list(st.x[self.nodes].mean(axis=0))
            elif q == "velocity":
                row += list(st.v[self.nodes].mean(axis=0))
            elif q == "acceleration":
                f = st.f_int[self.nodes] + st.f_ext[self.nodes]
                row += list((f * sim.inv_mass[self.nodes, None]).mean(axis=0))
            elif q == "contact_force":
                row += list(st.f_contact[self.nodes].sum(axis=0))
            else:
                row += self._element_values(q)
        self.writer.append(row)
