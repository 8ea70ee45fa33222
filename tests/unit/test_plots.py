"""`sphfem plot` of a run folder: glstat on three panels (energies with their unit, the energy ratio
with the deck's band, dt on a log axis), one panel per quantity, reference curves read with their
series and scales, and an unknown quantity as a usage error that lists the known ones."""
from __future__ import annotations

import numpy as np
import pytest
from click.testing import CliRunner
from matplotlib.image import imread

from sphfem_cli.cli import main
from sphfem_cli.output import plots


def _run(tmp_path, deck_dir=None, references=""):
    run = tmp_path / "run"
    (run / "histories").mkdir(parents=True)
    t = np.linspace(0.0, 1e-3, 11)
    ke, ie = 1e3 * t, 2e3 * t
    rows = np.column_stack([t, ke, ie, 0 * t, 0 * t, 3e3 * t, ke + ie, 1 + 0 * t, 1e-6 + 0 * t])
    np.savetxt(run / "histories" / "glstat.csv", rows, delimiter=",", comments="",
               header="time,kinetic,internal,hourglass,contact,external_work,total,energy_ratio,dt")
    rows = np.column_stack([t, 1e-4 * t, 2e-4 * t, t, 2 * t])
    np.savetxt(run / "histories" / "tip.csv", rows, delimiter=",", comments="",
               header="time,displacement_x,displacement_y,velocity_x,velocity_y")
    np.savetxt(run / "histories" / "matsum.csv", np.column_stack([t, ke]), delimiter=",", comments="",
               header="time,plate_kinetic")
    head = f"# {(deck_dir or tmp_path) / 'deck.yaml'} with every default filled in (sphfem test)\n"
    (run / "deck.effective.yaml").write_text(head + "units: {length: mm, mass: t, time: s}\ndimension: 3\n"
                                             "control: {energy_band: [0.95, 1.05]}\n" + references)
    return run


def _capture(monkeypatch):
    figures = []
    save = plots._save

    def keep(fig, path, plt):
        figures.append([(ax.get_ylabel(), ax.get_yscale(), ax.get_title()) for ax in fig.axes])
        return save(fig, path, plt)

    monkeypatch.setattr(plots, "_save", keep)
    return figures


def test_glstat_has_energy_ratio_and_log_dt_panels(tmp_path, monkeypatch):
    figures = _capture(monkeypatch)
    written = plots.plot_run(_run(tmp_path))
    assert [p.name for p in written] == ["glstat.png", "matsum.png", "tip.png"]
    glstat = figures[0]
    assert glstat[0][0] == "energy [N*mm]"  # mm-t-s: force N, energy N mm (3D: not per length)
    assert glstat[1][0] == "energy ratio [-]"
    assert glstat[2][0].startswith("dt [s]") and glstat[2][1] == "log"
    assert "energies, energy ratio, time step" in glstat[0][2]
    tip = figures[2]
    assert [a[0] for a in tip] == ["displacement [mm]", "velocity [mm/s]"]
    for path in written:
        image = imread(path)
        assert image.shape[0] > 300 and image.std() > 0.01  # drawn, not blank


def test_unknown_quantity_is_a_usage_error_listing_the_known(tmp_path):
    run = _run(tmp_path)
    result = CliRunner().invoke(main, ["plot", str(run), "--quantity", "displacement_z"])
    assert result.exit_code == 2
    assert "unknown quantity 'displacement_z'" in result.output and "tip.displacement_y" in result.output
    result = CliRunner().invoke(main, ["plot", str(run), "--quantity", "displacement_y"])
    assert result.exit_code == 0, result.output
    assert (run / "plots" / "tip.displacement_y.png").exists()
    assert plots.resolve_quantity(run / "histories", "kinetic") == "glstat.kinetic"
    assert plots.resolve_quantity(run / "histories", "tip.velocity") == "tip.velocity"


def test_reference_series_and_scales(tmp_path):
    csv = tmp_path / "front.csv"
    csv.write_text("# a comment\nseries,T,Z\nA,1.0,2.0\nA,2.0,3.0\nB,1.0,5.0\n")
    a, b = plots.read_reference(csv, "front.front", time_scale=0.5, value_scale=0.1)
    assert a.label == "front A" and b.label == "front B"
    assert np.allclose(a.time, [0.5, 1.0]) and np.allclose(a.value, [0.2, 0.3])
    (only,) = plots.read_reference(csv, "front.front", series="B", name="Martin & Moyce")
    assert only.label == "Martin & Moyce" and np.allclose(only.value, [5.0])
    with pytest.raises(ValueError, match="no rows"):
        plots.read_reference(csv, "front.front", series="C")


def test_deck_references_resolve_beside_the_deck_and_are_drawn(tmp_path, monkeypatch):
    deck_dir = tmp_path / "decks"
    deck_dir.mkdir()
    (deck_dir / "exp.csv").write_text("0.0,0.0\n0.001,0.0002\n")
    refs = ("output:\n  references:\n    - {file: exp.csv, quantity: tip.displacement_y, label: experiment}\n"
            "    - {file: gone.csv, quantity: tip.displacement_y}\n")
    run = _run(tmp_path, deck_dir, refs)
    warnings = []
    curves = plots.deck_references(run, warnings.append)
    assert [c.label for c in curves] == ["experiment"] and "gone.csv not found" in warnings[0]
    figures = _capture(monkeypatch)
    result = CliRunner().invoke(main, ["plot", str(run), "--quantity", "tip.displacement_y",
                                       "--reference", str(deck_dir / "exp.csv")])
    assert result.exit_code == 0, result.output
    assert figures[0][0][2].endswith("against the reference")
    result = CliRunner().invoke(main, ["plot", str(run), "--reference", str(deck_dir / "exp.csv")])
    assert result.exit_code == 2 and "--reference needs --quantity" in result.output


def test_a_deck_reference_names_a_history_table(tmp_path):
    from pathlib import Path

    from sphfem_cli import api

    deck = Path(__file__).resolve().parents[2] / "decks" / "dam_break_2d.yaml"
    loaded = api.load(deck)
    (ref,) = loaded.deck.output.references
    assert ref.quantity == "front.front" and ref.series == "MM_a2.25in"
    bad = [{"file": "x.csv", "quantity": "nowhere.front"}]
    with pytest.raises(api.DeckProblem, match=r"output.references\[0\].quantity: no history table 'nowhere'"):
        api.load(deck, {"output.references": bad})
    with pytest.raises(api.DeckProblem, match="TABLE.COLUMN"):
        api.load(deck, {"output.references": [{"file": "x.csv", "quantity": "front"}]})


def test_a_filtered_probe_is_drawn_over_its_raw_table_and_a_dense_reference_as_a_line(tmp_path, monkeypatch):
    deck_dir = tmp_path / "decks"
    deck_dir.mkdir()
    t = np.linspace(0.0, 1e-3, 201)
    np.savetxt(deck_dir / "record.csv", np.column_stack([t, np.sin(2e4 * t)]), delimiter=",")
    run = _run(tmp_path, deck_dir, "output:\n  references:\n    - {file: record.csv, quantity: wall.pressure, "
                                   "label: record}\n")
    raw = np.column_stack([t, np.sin(2e4 * t) + 0.3 * np.sin(3e5 * t)])
    for name, rows in (("wall", raw), ("wall_filtered", np.column_stack([t, np.sin(2e4 * t)]))):
        np.savetxt(run / "histories" / f"{name}.csv", rows, delimiter=",", comments="", header="time,pressure")
    lines = []
    save = plots._save

    def keep(fig, path, plt):
        lines.append({ln.get_label(): (ln.get_linestyle(), ln.get_marker()) for ax in fig.axes for ln in ax.get_lines()})
        return save(fig, path, plt)

    monkeypatch.setattr(plots, "_save", keep)
    written = plots.plot_run(run)
    assert [p.name for p in written] == ["glstat.png", "matsum.png", "tip.png", "wall.png"]  # no wall_filtered.png
    wall = lines[-1]
    assert set(wall) == {"pressure", "pressure, filtered", "record"}
    assert wall["record"] == ("-", "None")  # 201 points: a line, not 201 circles


def test_a_reference_outside_the_runs_window_is_not_drawn_and_says_why(tmp_path, monkeypatch):
    """A dimensionless CSV (Martin & Moyce's T, Z) given to a run in seconds: no legend entry without points."""
    run = _run(tmp_path)
    (tmp_path / "mm.csv").write_text("T,Z\n0.83,1.2\n1.9,2.6\n")
    (tmp_path / "near.csv").write_text("0.0005,0.0001\n0.002,0.0004\n")
    legends = []
    save = plots._save

    def keep(fig, path, plt):
        legends.append([t.get_text() for t in fig.axes[0].get_legend().get_texts()])
        return save(fig, path, plt)

    monkeypatch.setattr(plots, "_save", keep)
    result = CliRunner().invoke(main, ["plot", str(run), "--quantity", "tip.displacement_y",
                                       "--reference", str(tmp_path / "mm.csv"), "--reference", str(tmp_path / "near.csv")])
    assert result.exit_code == 0, result.output
    assert [entries[1:] for entries in legends] == [["near"]]  # after the run itself; the in-window reference is drawn (its point beyond 1.05 t_end cut)
    assert "reference 'mm' not drawn: none of its 2 points lies in the run's time window" in result.output
    assert "from 0.83 to 1.9" in result.output
