"""decks/underwater_explosion_3d_ale.yaml: a TNT sphere in water, 3D ALE (hex8), one eighth.

The peak pressure at the probes falls with distance and is compared with Cole's similitude P = 52.4
(W^(1/3)/R)^1.13 MPa (Cole 1948, "Underwater Explosions"; W the charge in kg TNT as filled, R in m; the
constants read from tests/data/underwater_explosion_free_field.yaml). Measured on the deck's 10 mm mesh (two
elements per charge radius), Q2 = 0.3: 0.87, 0.81, 0.65, 0.64 of Cole at R = 0.06, 0.10, 0.14, 0.18 m: the
coarse mesh smears the shock and the farther probes under-predict (with the default Q2 0.06: 1.00, 0.97, 0.80,
0.81, lifted by the linear viscosity's post-shock overshoot, which does not refine away). The converged
comparison with Cole is the 1D spherical reference's (tests/verification/spherical_blast_reference.py,
docs/studies/underwater_explosion.md "The Cole excess"): this is a plausibility band for a 10 mm mesh, not a
validation.

The r-z twin (decks/underwater_explosion_free_field_axisymmetric_ale.yaml, issue 15) is compared with the
octant at equal element size. A probe reads the element whose centre is nearest, and no r-z centre lies at
a 3D diagonal centre's distance, so the twin is sampled along a dense ray (every 5 mm, same direction) and
its peaks interpolated log-log to the 3D probes' centre distances R_c. Measured (histories every 0.2 us,
docs/studies/underwater_explosion_axi_vs_3d.py): with Q2 0.06, r-z / 3D = 1.050-1.061 at 10 mm, 1.010-1.024
at 5 mm over R_c = 0.043-0.20 m; the gap is discretisation error and closes at about second order (5.5 % ->
1.6 % mean). Arrival times agree within 1.4 us at 10 mm, 0.8 us at 5 mm. Both decks use Q2 = 0.3 since
December 2026 (the decks' headers): 1.023-1.036 at 10 mm.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

from sphfem_cli import api
from sphfem_cli.cli import main
from tests.verification.spherical_blast_reference import cole_peak

DECK = Path(__file__).parents[2] / "decks" / "underwater_explosion_3d_ale.yaml"
TWIN = Path(__file__).parents[2] / "decks" / "underwater_explosion_free_field_axisymmetric_ale.yaml"
RADII = (0.06, 0.10, 0.14, 0.18)
RAY = np.array([np.sqrt(2.0 / 3.0), np.sqrt(1.0 / 3.0)])  # (r, z) of the direction (1, 1, 1) / sqrt(3)


def centre_distance(point, h: float) -> float:
    """Distance from the charge of the centre of the element (of size h) a probe at ``point`` reads."""
    return float(np.linalg.norm((np.floor(np.asarray(point) / h) + 0.5) * h))


def twin_peaks(folder: Path, h: float, **overrides) -> tuple[np.ndarray, np.ndarray]:
    """Run the r-z twin at element size h with probes every 5 mm along the ray; (R_c, peak) sorted by R_c."""
    radii = np.arange(0.04, 0.2001, 0.005)
    probes = [{"name": f"ray_{round(r * 1000):03d}", "type": "pressure", "point": list(r * RAY)} for r in radii]
    result = api.run(TWIN, folder, {"parts.pool.geometry.box.element_size": h, "output.probes": probes,
                                    "output.interval": 1.0, **overrides}, threads=1)
    assert result.completed, result.message
    hist = result.histories()
    samples = {centre_distance(p["point"], h): hist[p["name"]]["pressure"].max() for p in probes}
    r_c = np.array(sorted(samples))
    return r_c, np.array([samples[r] for r in r_c])


def twin_over_solid(solid: Path, twin: tuple, h: float, names, points) -> np.ndarray:
    """Peak ratio r-z / 3D at the 3D probes' centre distances (r-z interpolated log-log in R_c)."""
    r_c = np.array([centre_distance(p, h) for p in points])
    peak_3d = np.array([np.genfromtxt(solid / f"{name}.csv", delimiter=",", names=True)["pressure"].max()
                        for name in names])
    peak_rz = np.exp(np.interp(np.log(r_c), np.log(twin[0]), np.log(twin[1])))
    return peak_rz / peak_3d


# heavy (9 s, the whole deck): test_ale_3d.py checks the hex8 ALE in the default suite, and the regression runs
# this deck's first 13 steps
pytestmark = pytest.mark.heavy


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    out = tmp_path_factory.mktemp("undex3d") / "out"
    result = CliRunner().invoke(main, ["run", str(DECK), "-o", str(out), "-q"])
    assert result.exit_code == 0, result.output
    return out / "histories"


def test_peak_pressure_falls_with_distance_and_follows_cole(run):
    mat = np.genfromtxt(run / "ale_materials.csv", delimiter=",", names=True)
    charge = 8.0 * mat["mass_tnt"][0]  # the octant's charge, whole
    assert charge == pytest.approx(1630.0 * 4.0 / 3.0 * np.pi * 0.02 ** 3, rel=0.02)
    peaks = []
    for r in RADII:
        table = np.genfromtxt(run / f"p_r{round(r * 1000):03d}.csv", delimiter=",", names=True)
        peaks.append(table["pressure"].max())
    peaks = np.array(peaks)
    assert np.all(np.diff(peaks) < 0.0), peaks
    cole = cole_peak(charge, np.array(RADII))  # Cole / Swisdak, tests/data/underwater_explosion_free_field.yaml
    ratio = peaks / cole
    assert np.all((ratio > 0.55) & (ratio < 1.1)), ratio


def test_stable_and_conservative_before_the_shock_leaves(run):
    """Energy is conserved to round-off until the wave's foot reaches the transmitting sides (0.24 m) at about
    0.09 ms (measured 1 - 3e-10 at 0.09 ms, 9e-8 at 0.1 ms); after it, energy and water leave through them:
    at 0.12 ms 2.5e-4 of the energy and 7.3e-5 of the water (Q2 = 0.3 smears the foot over more elements
    than the default 0.06 did: 3.4e-6 of the water then)."""
    glstat = np.genfromtxt(run / "glstat.csv", delimiter=",", names=True)
    early = glstat["time"] <= 0.09e-3
    assert np.all(np.abs(glstat["energy_ratio"][early] - 1.0) < 1e-8)
    assert 0.999 < glstat["energy_ratio"][-1] <= 1.0 + 1e-12
    mat = np.genfromtxt(run / "ale_materials.csv", delimiter=",", names=True)
    assert -1e-3 < mat["mass_water"][-1] / mat["mass_water"][0] - 1.0 <= 1e-12
    assert abs(mat["mass_tnt"][-1] / mat["mass_tnt"][0] - 1.0) < 1e-12


def test_axisymmetric_twin_matches_the_octant_at_10mm(run, tmp_path):
    """Equal element size (10 mm, the shipped decks), histories every 1 us in both. Measured (Q2 0.3): r-z / 3D
    1.028, 1.036, 1.029, 1.023 at R_c = 0.061, 0.095, 0.147, 0.182 m (Q2 0.06: 1.048, 1.061, 1.049, 1.053).
    Tolerance: issue 15's 5 % at every probe (was 7 % while the decks had Q2 0.06, whose 10 mm gap was just over it)."""
    ratio = twin_over_solid(run, twin_peaks(tmp_path / "rz", 0.01), 0.01,
                            [f"p_r{round(r * 1000):03d}" for r in RADII], [[r / np.sqrt(3.0)] * 3 for r in RADII])
    print("r-z / 3D at 10 mm:", np.round(ratio, 4))
    assert np.all(ratio > 1.0) and np.all(ratio < 1.05), ratio


@pytest.mark.validation
def test_axisymmetric_twin_matches_the_octant_at_5mm(tmp_path):
    """Both at 5 mm (the 3D run is about 260 s CPU), probes on the diagonal element centres. Measured
    r-z / 3D 0.992-1.001 over R_c = 0.048-0.195 m with Q2 0.3 (6 December 2026, 559 s wall at load 6; with the
    default Q2 0.06: 1.010-1.024). Tolerance 3 % at every probe (issue 15 asks 5 %)."""
    h, names, points = 0.005, [], []
    for i in range(int(0.2 / (np.sqrt(3.0) * h)) + 1):
        c = (i + 0.5) * h
        if 0.045 <= np.sqrt(3.0) * c <= 0.2:
            names.append(f"d_{i:03d}")
            points.append([c, c, c])
    probes = [{"name": n, "type": "pressure", "point": p} for n, p in zip(names, points)]
    solid = api.run(DECK, tmp_path / "solid", {"parts.pool.geometry.box.element_size": h, "output.probes": probes,
                                               "output.history_interval": 2.0e-7, "output.interval": 1.0}, threads=1)
    assert solid.completed, solid.message
    twin = twin_peaks(tmp_path / "rz", h, **{"output.history_interval": 2.0e-7})
    ratio = twin_over_solid(solid.folder / "histories", twin, h, names, points)
    print("r-z / 3D at 5 mm:", np.round(ratio, 4))
    assert np.all(np.abs(ratio - 1.0) < 0.03), ratio
