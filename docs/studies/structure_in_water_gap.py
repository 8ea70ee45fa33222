"""Issue 12 on the paper's section 4.1 scene: is the flow round the plate's bottom end what separates SPH from ALE?
(figures in docs/studies/structure_in_water.md, "The flow under the plate").

    python docs/studies/structure_in_water_gap.py [CASE ...]   # run from the repository root
    python docs/studies/structure_in_water_gap.py --summary
    python docs/studies/structure_in_water_gap.py --corner-figure
    python docs/studies/structure_in_water_gap.py --pairs av0 sb0 sbm   # deck drive against a tenth, ratio 4
    python docs/studies/structure_in_water_gap.py --corners sbm_r4_gap sbma01c01_r4_gap   # the corner layer's speed

Each case writes a variant of decks/structure_in_water_{ale,sph}.yaml into study_siw_gap/ (plate 4 x 60, 2 ms,
the code-to-code settings of the study: ALE Lagrangian mesh with L_c = h / 2, i.e. pfac 16 / 16 / 10 at nquad
2 / 4 / 5 for 10 / 5 / 2.5 mm; SPH at ratios 2 / 3 / 4 of the 10 mm ALE size), runs it on one thread and appends
its CPU seconds to study_siw_gap/log.txt. "gap" is the shipped scene (water under the plate's driven bottom
end, 0 < y < 0.05, joining the two sides); "sb" is the SPH variant with the sph_boundary coupling (boundary
particles carried by the plate) in place of the penalty contact; "av" and "av0" are the SPH variants with the
artificial viscosity's alpha at AV_ALPHA (0.01 and 0) instead of the deck's 0.1 (Monaghan's term is a shear
viscosity nu = alpha c h / 8 in 2D, Monaghan 2005, Rep. Prog. Phys. 68, 1703, sec. 4.2: 0.11 / 0.074 / 0.056
m^2/s at ratios 2 / 3 / 4, a Reynolds number v d / nu of about 1 for the flow under the plate). "nogap" raises
the tank floor to the plate's bottom (y = 0.05), so the two sides are closed chambers and no water flows round
the plate's end (the bottom nodes slide on the slip floor).
The SPH-gap candidates ("SPH's gap: ..." in the study) are the av0 deck with one change: "d0" / "d05" the
density diffusion 0 / 0.05 (deck 0.1), "dp" its delta-plus form (Antuono et al. 2010), "ts" timestep_scale
0.45 (deck 0.9), "wc2" the Wendland C2 kernel at h/dx 2, "c2" / "c3" the water's ambient pressure C0 2 / 3 MPa
(deck 1 MPa); "alec3" is the ALE deck at 3 MPa, the control (linear water: no dependence expected).
The amplitude variants (section "SPH's gap grows with the drive's amplitude"): "a01" / "alea01" the SPH (alpha 0)
/ ALE decks with the drive's velocity scaled by 0.1, "a01c01" / "a03c03" the SPH deck with the drive and the
ambient pressure C0 both scaled by 0.1 / 0.3 (the same pressure ratios, particle displacements 0.1 / 0.3 of the
deck's), "a0" no drive; "xs05" XSPH 0.5 (energy band off: the XSPH drift is not a force the contact's work books);
"alesm" / "alesma01" the ALE deck with a smoothed mesh and a remap (equipotential, sliding sides) at drive 1 / 0.1
(ALE levels 10 / 5 / 2.5 / 1.25 / 0.625 mm; 0.625 mm runs to 1.6 ms).
The wall-treatment variants (section "Where the amplitude effect sits"), each at the deck's drive and as "...a01c01"
at a tenth of drive and ambient pressure, all alpha 0: "cd0" contact damping 0, "ss03" the contact's soft_scale
0.3, "sb0" boundary particles on the plate (sph_boundary); "av1" alpha 0.01 and "sw" alpha 0.01 with the shock
switch {alpha_max 1, decay 0.1}; "hr15" the cubic spline at h/dx 1.5, "wc2a01c01" Wendland C2 at h/dx 2 at a tenth;
"sb0hr15" boundary particles at h/dx 1.5, "hr15dp" / "hr15d05" h/dx 1.5 with the delta-plus form / delta 0.05, "d02" /
"d01" the deck's kernel with delta 0.02 / 0.01 ("d05" and these also as a01c01 twins).
The convex-corner candidates (section "Convex corners"), each with its "...a01c01" twin: "sbc" the sb0 deck with
sph_boundary's corner_particles: once; "tt" / "ttc0" the av0 deck (penalty contact) with structure_in_water_corner_truncation.py's
corner correction at each particle's pressure / at the water's ambient C0, run through
structure_in_water_corner_run.py (energy guard off for these: the correction's work is negative contact energy).
The mDBC candidates (section "mDBC at the corners"), each with its "...a01c01" twin: "sbm" the sb0 deck with
sph_boundary's extrapolation: mdbc (English et al. 2022), "sbmc" the same with corner_particles: once; "sbs" the sb0
deck with particle shifting restricted to the water next to the plate's lower corners
(structure_in_water_corner_shift.py, A 2, within 4 spacings; energy guard off: the shift is no force).
The last SPH wall candidates (section "mDBC's velocity and a first-order pressure gradient"), each with its
"...a01c01" twin: "sbmn" / "sbmf" the sbm deck with the boundary particles' velocity extrapolated from the ghost nodes
(structure_in_water_mdbc_velocity.py, no-slip / slip; energy guard off), "sbk" the sb0 deck with the
kernel-gradient-corrected pressure gradient and continuity for the water next to the plate (structure_in_water_kgc.py;
energy guard off), "sbka" the same for every water point with a nearly full support ("sbkan": with the boundary
pairs' gradient left plain).
The ratio-5 diagnosis (section "The boundary particles at ratio 5"), each with its "...a01c01" twin, energy guard off:
"sb0n" the sb0 deck (the control sb0_r5 stops at step 10 on the guard), "sb0nts" / "sbkats" the sb0 / sbka decks at
half the deck's time step (timestep_scale 0.45), "sb0d" the sb0 deck with twice the boundary particles along the
plate's faces at ratio 5 (structure_in_water_kgc.py "plain dense"); `--steps [r4] KIND ...` prints their peaks and
energy at ratio 5 (or the one named).
The series at one step (section "The corrected gradient as a series at one step"): "sbkat8" and its "...a01c01"
twin, sbka at 0.8 of the deck's step (timestep_scale 0.72, as "sb0nt8") at ratios 3-6; `--series KIND ...` prints
their peaks (a KIND "A,B" takes per ratio B's run where it was made, else A's), energy, gauges and CPU, Celik's three_grid on the finest three ratios and the comparison with ALE's limit.
`--corners` prints u(t) on
the rise and the water's speed next to the plate's lower corners.
`--corner-figure` draws the water's speed round the plate's end
(structure_in_water_corner_flow.png) from cd0_r4_gap, cd0a01c01_r4_gap and ale_2.5_gap.
Every variant records the x force of the contact / coupling on three bands of each face of the plate
(y 0.05-0.10, 0.10-0.15, 0.15-0.20) and on its bottom face; `--summary` prints the mid-height peaks and the
net band impulses over the drive (0-0.75 ms) and the rebound (0.75-1.6 ms).
"""
import copy, os, resource, subprocess, sys
from pathlib import Path

import numpy as np
import yaml

ROOT = Path(__file__).resolve().parents[2]
WORK = Path("study_siw_gap")
LEVELS = {"ale": {"10": (0.01, 2, 16.0), "5": (0.005, 4, 16.0), "2.5": (0.0025, 5, 10.0),  # size, nquad, pfac
                  "1.25": (0.00125, 5, 5.0),  # 2.5 coupling points per 1.25 mm face: pfac 2 n = 5
                  "0.625": (0.000625, 5, 2.5)},  # 1.25 per 0.625 mm face; run to 1.6 ms only (the peak is at 1.3-1.5 ms)
          "sph": {"r2": 0.005, "r3": 0.01 / 3.0, "r4": 0.0025},
          "sb": {"r2": 0.005, "r3": 0.01 / 3.0, "r4": 0.0025},  # SPH with the sph_boundary coupling
          "av": {"r2": 0.005, "r3": 0.01 / 3.0, "r4": 0.0025},  # SPH (contact) with alpha 0.01 instead of 0.1
          "av0": {"r2": 0.005, "r3": 0.01 / 3.0, "r4": 0.0025,  # the same without artificial viscosity
                  "r5": 0.002, "r6": 0.01 / 6.0}}
AV_ALPHA = {"av": 0.01, "av0": 0.0}
# issue 12's SPH-gap candidates, each the av0 deck (alpha 0) with one setting of its sph section changed
SPH_VARIANTS = {"d0": {"density_diffusion": 0.0}, "d05": {"density_diffusion": 0.05},
                "wc2": {"kernel": "wendland_c2", "smoothing_ratio": 2.0},
                "dp": {"density_diffusion_form": "delta_plus"}, "c2": {}, "c3": {}, "ts": {}, "a01": {}, "a01c01": {}, "a0": {}, "xs05": {"xsph": 0.5}, "a03c03": {},
                "cd0": {}, "ss03": {}, "sb0": {}, "av1": {}, "hr15": {"smoothing_ratio": 1.5},
                "sb0hr15": {"smoothing_ratio": 1.5},
                "hr15dp": {"smoothing_ratio": 1.5, "density_diffusion_form": "delta_plus"},
                "hr15d05": {"smoothing_ratio": 1.5, "density_diffusion": 0.05},
                "d02": {"density_diffusion": 0.02}, "d01": {"density_diffusion": 0.01}, "sbc": {}, "tt": {}, "ttc0": {},
                "sbm": {}, "sbmc": {}, "sbs": {}, "sbmn": {}, "sbmf": {}, "sbk": {}, "sbka": {}, "sbkan": {},
                "sb0d": {}, "sb0n": {}, "sb0nts": {}, "sbkats": {}, "sbkat8": {}, "sb0nt8": {}, "sb0nm4": {}, "sb0ncb": {}, "sb0nt9": {},
                "sbal8": {}, "sbal45": {}, "sbkal8": {}, "sbkal45": {},
                "sw": {"artificial_viscosity": {"alpha": 0.01, "beta": 0.0, "switch": {"alpha_max": 1.0, "decay": 0.1}}}}
# the penalty contact's settings changed (deck: soft_scale 0.1, damping 0.1), at the deck's drive and at a tenth
CONTACT = {"cd0": {"damping": 0.0}, "ss03": {"soft_scale": 0.3},
           }
# the deck's contact with structure_in_water_corner_truncation.py's corner correction (section "Convex corners"), run through
# structure_in_water_corner_run.py: "tt" with each particle's pressure, "ttc0" with the water's ambient C0 (1 MPa;
# 0.1 MPa in the a01c01 twin)
CORNER_CORRECTION = {"tt": "particle", "ttc0": "ambient"}
SPH_BOUNDARY = {"sb", "sb0", "sb0hr15", "sbc", "sbm", "sbmc", "sbs", "sbmn", "sbmf", "sbk", "sbka", "sbkan",
                "sb0d", "sb0n", "sb0nts", "sbkats", "sbkat8", "sb0nt8", "sb0nm4", "sb0ncb", "sb0nt9",
                "sbal8", "sbal45", "sbkal8", "sbkal45"}
# the sb0 deck with particle shifting restricted to the water within CORNER_SHIFT[kind][1] spacings of the plate's lower
# corners (A = CORNER_SHIFT[kind][0]), run through structure_in_water_corner_shift.py (section "mDBC at the corners")
CORNER_SHIFT = {"sbs": ("2", "4")}  # boundary particles carried by the plate instead of the penalty contact
# issue 12's convex-corner candidates (section "Convex corners"): "sbc" the sb0 deck with the corner squares counted
# once (sph_boundary corner_particles: once)
BOUNDARY_OPTIONS = {"sbc": {"corner_particles": "once"},
                    # section "mDBC at the corners": the boundary particles' density from English et al. (2022)'s
                    # first-order extrapolation at ghost nodes (through the faces, through the vertex at a corner)
                    "sbm": {"extrapolation": "mdbc"}, "sbmc": {"extrapolation": "mdbc", "corner_particles": "once"},
                    # section "mDBC's velocity ...": the sbm deck with the boundary particles' velocity extrapolated
                    # from the ghost nodes too (structure_in_water_mdbc_velocity.py), no-slip / slip
                    "sbmn": {"extrapolation": "mdbc"}, "sbmf": {"extrapolation": "mdbc"},
                    # section "The wall's sampling refined with the water": the boundary particles every dx by arc
                    # length along the plate's outline (sph_boundary sampling: arc_length) instead of round(L / dx) per
                    # face; "sbal8" / "sbal45" the plain gradient at timestep_scale 0.72 / 0.45, "sbkal8" / "sbkal45"
                    # the corrected one
                    "sbal8": {"sampling": "arc_length"}, "sbal45": {"sampling": "arc_length"},
                    "sbkal8": {"sampling": "arc_length"}, "sbkal45": {"sampling": "arc_length"}}
MDBC_VELOCITY = {"sbmn": "no_slip", "sbmf": "slip"}
# the sb0 deck with the kernel-gradient-corrected pressure gradient and continuity next to the plate
# (structure_in_water_kgc.py)
KGC = {"sbk": [], "sbka": ["all"],  # "sbka": every water point with a nearly full support corrected
       "sbkan": ["all", "nowall"],  # "sbkan": the same with the boundary pairs' gradient plain
       # section "The boundary particles at ratio 5": "sb0d" the sb0 deck (through the wrapper, uncorrected) with the
       # plate's boundary particles at no more than the water's spacing along each face (ceil(L / dx) per face
       # instead of round(L / dx): 2 per 2.5 mm face at ratio 5, unchanged at ratios 3, 4, 6)
       "sb0d": ["plain", "dense"],
       "sbkats": ["all"],  # sbka at half the deck's time step (as "sb0nts" is sb0n's)
       "sbkat8": ["all"], "sbkal8": ["all"], "sbkal45": ["all"]}  # sbka at 0.8 of the deck's step (as "sb0nt8" is sb0n's): the series at one step rule
# the energy guard off: at a tenth the corners-once run stopped at 0.70 ms on the guard against negative contact
# energy (the boundary's share of the pair work -0.021 J, 10 % of the energy in play) with the energy ratio 1.0005
# and the tangential-only form of "tt" stopped at step 100 (34 us) on the same guard (contact -0.078 J of 0.40 J in
# play, energy ratio 1.0014): the corner correction's work is booked as contact energy and is negative
ENERGY_GUARD_OFF = {"sbca01c01", "tt", "tta01c01", "ttc0", "ttc0a01c01", "sbs", "sbsa01c01",
                    # the extrapolated boundary velocity's continuity and pair-work terms are not the nodes' work
                    "sbmn", "sbmna01c01", "sbmf", "sbmfa01c01", "sbk", "sbka01c01", "sbka", "sbkaa01c01", "sbkan", "sbkana01c01",
                    "sb0d", "sb0da01c01",
                    # "sb0n": sb0 with the guard off, the control of the corrected runs at ratio 5 (sb0_r5 stops at
                    # step 10 on the guard: the ambient preload's start, contact -2.8e-3 J against 7.3e-3 J in play)
                    "sb0n", "sb0na01c01", "sb0nts", "sb0ntsa01c01", "sbkats", "sbkatsa01c01", "sb0nt8", "sb0nm4", "sb0ncb", "sb0nt9",
                    "sbkat8", "sbkat8a01c01", "sbal8", "sbal45", "sbkal8", "sbkal45"}
# half the deck's time step: "ts" (section "SPH's gap: ..."), and the ratio-5 boundary-particle decks of section "The
# boundary particles at ratio 5" (the plain and the corrected gradient)
HALF_STEP = {"ts", "sb0nts", "sb0ntsa01c01", "sbkats", "sbkatsa01c01", "sbal45", "sbkal45"}
# section "A stable step for the coupling": sb0n at 0.8 of the deck's step (timestep_scale 0.72), where the water's
# c dt / h at ratio 5 is ratio 4's at the deck's step (0.169), and "sb0nt9" at 0.9 of it (timestep_scale 0.81)
STEP_SCALE = {"sb0nt8": 0.72, "sb0nt9": 0.81,
              # section "The corrected gradient as a series at one step": sbka at 0.72 at every ratio (3-6), both drives
              "sbkat8": 0.72, "sbkat8a01c01": 0.72,
              # section "The wall's sampling refined with the water"
              "sbal8": 0.72, "sbkal8": 0.72}
# and sb0n with the plate's density x 4 at the deck's step (dt_max 3.4174e-7 s, the plate's step of sb0n; the water's own
# limit 3.66e-7, the heavier plate's 6.8e-7): the face nodes' S_i / m_i a quarter at the same step (a diagnostic)
# "sb0ncb": the deck's plate at the combined Gershgorin step of plate and coupling, 0.9 (dt_p^-2 + dt_c^-2)^-1/2 =
# 3.3727e-7 s (dt_p = 3.4174e-7 / 0.9, dt_c = 2.0910e-6 / 0.9, SphBoundaryCoupling.stable_dt)
PLATE_DENSITY = {"sb0nm4": (4.0, 3.4174e-7), "sb0ncb": (1.0, 3.3727e-7)}
AMBIENT = {"c2": 2.0e6, "c3": 3.0e6, "alec3": 3.0e6, "a01c01": 1.0e5, "a03c03": 3.0e5}  # the water's ambient pressure C0 instead of the decks' 1 MPa
LEVELS["alec3"] = LEVELS["ale"]  # the ALE deck at 3 MPa ambient (the control: linear water, no kernel)
# the drive's velocity scaled (2 -> 0.2 m/s: the linear limit); "a01c01" / "a03c03" scale the ambient pressure with it
AMPLITUDE = {"a01": 0.1, "alea01": 0.1, "a01c01": 0.1, "a0": 0.0, "a03c03": 0.3, "alesma01": 0.1}
# the twins "<kind>a01c01" of these SPH kinds: the same change at a tenth of the drive and of the ambient pressure
for _kind in ("cd0", "ss03", "sb0", "av1", "sw", "wc2", "hr15", "sb0hr15", "hr15dp", "hr15d05", "d05", "d02", "d01",
              "sbc", "tt", "ttc0", "sbm", "sbmc", "sbs", "sbmn", "sbmf", "sbk", "sbka", "sbkan",
              "sb0d", "sb0n", "sb0nts", "sbkats", "sbkat8"):
    _twin = _kind + "a01c01"
    SPH_VARIANTS[_twin] = SPH_VARIANTS[_kind]
    if _kind in BOUNDARY_OPTIONS:
        BOUNDARY_OPTIONS[_twin] = BOUNDARY_OPTIONS[_kind]
    if _kind in CORNER_CORRECTION:
        CORNER_CORRECTION[_twin] = CORNER_CORRECTION[_kind]
    if _kind in CORNER_SHIFT:
        CORNER_SHIFT[_twin] = CORNER_SHIFT[_kind]
    if _kind in MDBC_VELOCITY:
        MDBC_VELOCITY[_twin] = MDBC_VELOCITY[_kind]
    if _kind in KGC:
        KGC[_twin] = KGC[_kind]
    if _kind in CONTACT:
        CONTACT[_twin] = CONTACT[_kind]
    if _kind in SPH_BOUNDARY:
        SPH_BOUNDARY.add(_twin)
    AMPLITUDE[_twin], AMBIENT[_twin] = AMPLITUDE["a01c01"], AMBIENT["a01c01"]
LEVELS["alea01"] = LEVELS["ale"]
# the ALE deck with a smoothed mesh and a remap (mesh_motion smoothed, equipotential, sliding sides) instead of
# the Lagrangian mesh: material may cross element faces, so the flow may separate at the plate's corners
SMOOTHED = {"alesm", "alesma01"}
LEVELS["alesm"] = LEVELS["alesma01"] = LEVELS["ale"]
for _kind in SPH_VARIANTS:
    LEVELS[_kind] = {"r2": 0.005, "r3": 0.01 / 3.0, "r4": 0.0025, "r5": 0.002, "r6": 0.01 / 6.0}
    AV_ALPHA[_kind] = 0.0
AV_ALPHA["av1"] = AV_ALPHA["av1a01c01"] = 0.01  # the switch's floor without the switch, the control of "sw"
CASES = [f"{kind}_{level}_{geo}" for geo in ("gap", "nogap") for kind in LEVELS for level in LEVELS[kind]]
BANDS = ((0.0499, 0.1001), (0.1002, 0.1501), (0.1502, 0.2001))  # node boxes: each face node in exactly one band
WINDOWS = {"drive": (0.0, 0.75e-3), "rebound": (0.75e-3, 1.6e-3)}
GAUGE_Y = (0.2, 0.175, 0.15)  # face nodes of every plate mesh: strain gauges over 0-25 and 25-50 mm under the clamp
E_PLANE = 7.0e10 / (1.0 - 0.33 ** 2)  # the plate's plane-strain modulus E / (1 - nu^2)


def variant(name: str) -> Path:
    kind, level, geo = name.split("_")
    base = "sph" if kind in ("sb", *AV_ALPHA) else "ale" if kind in ("alec3", "alea01", *SMOOTHED) else kind
    d = copy.deepcopy(yaml.safe_load(open(ROOT / f"decks/structure_in_water_{base}.yaml")))
    d["control"]["end_time"] = 0.0016 if level == "0.625" else 0.002
    d["parts"]["plate"]["geometry"]["box"]["divisions"] = [4, 60]
    sets, hist = d["sets"], d["output"]["histories"]
    for side, x in (("R", 0.21), ("L", 0.20)):
        for i, (y0, y1) in enumerate(BANDS):
            sets[f"{side}{i}"] = {"type": "node", "part": "plate", "box": {"min": [x - 1e-4, y0], "max": [x + 1e-4, y1]}}
            hist.append({"name": f"f{side}{i}", "set": f"{side}{i}", "quantities": ["contact_force"]})
    hist.append({"name": "fB", "set": "plate_bottom", "quantities": ["contact_force"]})
    for side, x in (("R", 0.21), ("L", 0.20)):
        for y in GAUGE_Y[1:]:
            sets[f"g{side}{y}"] = {"type": "node", "part": "plate", "box": {"min": [x - 1e-4, y - 1e-4], "max": [x + 1e-4, y + 1e-4]}}
            hist.append({"name": f"g{side}{y}", "set": f"g{side}{y}", "quantities": ["displacement"]})
    floor = 0.05 if geo == "nogap" else 0.0
    for b in d["boundaries"]:
        if b["type"] == "prescribed_velocity":
            b["velocity"] = [v * AMPLITUDE.get(kind, 1.0) if v is not None else None for v in b["velocity"]]
    if base == "ale":
        size, nquad, pfac = LEVELS["ale"][level]
        if kind in AMBIENT:
            d["equations_of_state"]["water"]["c0"] = AMBIENT[kind]
        box = d["parts"]["tank"]["geometry"]["box"]
        box.update(min=[0.0, floor], element_size=size)
        d["couplings"][0].update(nquad=nquad, pfac=pfac)
        if kind in SMOOTHED:
            d["sections"]["fluid"].update(mesh_motion="smoothed", smoothing="equipotential", smoothing_boundary="sliding")
    else:
        dx = LEVELS[kind][level]
        tank = d["parts"]["tank"]
        tank["spacing"] = dx
        d["boundaries"][-1]["min"] = [0.0, floor]
        if geo == "nogap":  # two closed chambers, each in contact with the plate
            left, right = copy.deepcopy(tank), copy.deepcopy(tank)
            left["geometry"] = {"polygon": {"vertices": [[0.0, 0.05], [0.2, 0.05], [0.2, 0.2], [0.0, 0.2], [0.0, 0.05]]}}
            right["geometry"] = {"polygon": {"vertices": [[0.21, 0.05], [0.4, 0.05], [0.4, 0.2], [0.21, 0.2], [0.21, 0.05]]}}
            d["parts"]["tank"], d["parts"]["tank_right"] = left, right
            d["contacts"].append(dict(d["contacts"][0], nodes="tank_right"))
        if kind in AV_ALPHA:
            d["sections"]["sph"]["artificial_viscosity"]["alpha"] = AV_ALPHA[kind]
        d["sections"]["sph"].update(SPH_VARIANTS.get(kind, {}))
        if kind in ENERGY_GUARD_OFF:
            d["control"]["energy_band"] = None
        if kind == "xs05":  # XSPH moves particles by a velocity the contact's work is not booked against
            d["control"]["energy_band"] = None
        if kind in HALF_STEP:  # half the deck's time step (timestep_scale 0.9 -> 0.45)
            d["control"]["timestep_scale"] = 0.45
        if kind in STEP_SCALE:
            d["control"]["timestep_scale"] = STEP_SCALE[kind]
        if kind in PLATE_DENSITY:
            d["materials"]["aluminium"]["density"] *= PLATE_DENSITY[kind][0]
            d["control"]["dt_max"] = PLATE_DENSITY[kind][1]
        if kind in AMBIENT:
            d["equations_of_state"]["water"]["c0"] = AMBIENT[kind]
        for contact in d["contacts"]:
            contact.update(CONTACT.get(kind, {}))
        if kind in SPH_BOUNDARY:  # boundary particles carried by the plate instead of the penalty contact
            d["couplings"] = [{"type": "sph_boundary", "structure": "plate", "fluid": c["nodes"],
                               **BOUNDARY_OPTIONS.get(kind, {})} for c in d["contacts"]]
            d["contacts"] = []
    WORK.mkdir(exist_ok=True)
    path = WORK / f"{name}.yaml"
    yaml.safe_dump(d, open(path, "w"), sort_keys=False)
    return path


def run(name: str) -> None:
    deck = variant(name)
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    kind = name.split("_")[0]
    command = [sys.executable, "-m", "sphfem_cli.cli"]  # this tree's package (PYTHONPATH = the repository root)
    if kind in CORNER_CORRECTION:
        pressure = CORNER_CORRECTION[kind]
        if pressure == "ambient":
            pressure = str(yaml.safe_load(open(deck))["equations_of_state"]["water"]["c0"])
        command = [sys.executable, str(ROOT / "docs/studies/structure_in_water_corner_run.py"), pressure]
    if kind in CORNER_SHIFT:
        command = [sys.executable, str(ROOT / "docs/studies/structure_in_water_corner_shift.py"), *CORNER_SHIFT[kind]]
    if kind in MDBC_VELOCITY:
        command = [sys.executable, str(ROOT / "docs/studies/structure_in_water_mdbc_velocity.py"), MDBC_VELOCITY[kind]]
    if kind in KGC:
        command = [sys.executable, str(ROOT / "docs/studies/structure_in_water_kgc.py"), *KGC[kind]]
    subprocess.run([*command, "run", str(deck), "-o", str(WORK / name), "-q", "--overwrite", "--threads", "1"],
                   check=True)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = after.ru_utime + after.ru_stime - before.ru_utime - before.ru_stime
    with open(WORK / "log.txt", "a") as log:
        log.write(f"{name} cpu {cpu:.1f} s load {os.getloadavg()[0]:.1f}\n")


def history(name: str, table: str) -> np.ndarray:
    return np.genfromtxt(WORK / name / "histories" / f"{table}.csv", delimiter=",", names=True)


def impulse(t: np.ndarray, f: np.ndarray, window: tuple[float, float]) -> float:
    m = (t >= window[0]) & (t <= window[1])
    return float(np.trapezoid(f[m], t[m]))


def gauges(name: str) -> list[float]:
    """Peak |bending stress| of the strain gauges over 0-25 and 25-50 mm under the clamp, MPa:
    E' (eps_right - eps_left) / 2 with eps = (u_y(y_upper) - u_y(y_lower)) / 25 mm on each face (the
    clamp's nodes y = 0.2 are fixed)."""
    uy = {}
    for side in "RL":
        uy[(side, GAUGE_Y[0])] = 0.0
        for y in GAUGE_Y[1:]:
            uy[(side, y)] = history(name, f"g{side}{y}")["displacement_y"]
    out = []
    for y_hi, y_lo in zip(GAUGE_Y[:-1], GAUGE_Y[1:]):
        eps = {side: (uy[(side, y_hi)] - uy[(side, y_lo)]) / (y_hi - y_lo) for side in "RL"}
        out.append(float(np.max(np.abs(0.5 * E_PLANE * (eps["R"] - eps["L"])))) / 1e6)
    return out


def summary() -> None:
    print("case | peak u mm (t ms) | peak v m/s | net x impulse N s/m, bands y 0.05-0.10 / 0.10-0.15 / 0.15-0.20: "
          "drive ; rebound")
    for name in CASES:
        if not (WORK / name / "histories" / "mid.csv").exists():
            continue
        mid = history(name, "mid")
        k = int(np.abs(mid["displacement_x"]).argmax())
        row = [f"{1e3 * abs(mid['displacement_x'][k]):.4f} ({1e3 * mid['time'][k]:.2f})",
               f"{np.abs(mid['velocity_x']).max():.3f}"]
        for window in WINDOWS.values():
            net = []
            for i in range(len(BANDS)):
                r, l = history(name, f"fR{i}"), history(name, f"fL{i}")
                net.append(impulse(r["time"], r["contact_force_x"] + l["contact_force_x"], window))
            row.append(" / ".join(f"{v:.2f}" for v in net))
        if (WORK / name / "histories" / f"gR{GAUGE_Y[1]}.csv").exists():
            g = gauges(name)
            row.append(f"gauges {g[0]:.2f} / {g[1]:.2f} MPa, clamp VM {history(name, 'clamp')['von_mises'].max() / 1e6:.2f} MPa")
        else:
            row.append("")
        if (WORK / name / "histories" / "glstat.csv").exists():  # the energy table at the end, and its ratio's range
            e = history(name, "glstat")
            row[-1] += (f"; energy ratio {e['energy_ratio'][-1]:.4f} ({e['energy_ratio'][1:].min():.4f}-"
                        f"{e['energy_ratio'][1:].max():.4f}), contact {e['contact'][-1]:.3f} J, external "
                        f"{e['external_work'][-1]:.3f} J")
        print(f"{name} | {row[0]} | {row[1]} | {row[2]} ; {row[3]} | {row[4]}")


REFERENCE_PEAK = 0.5734  # mm, the same-plate (4 x 60) independent reference ("An independent continuum reference")


def pairs(kinds: list[str]) -> None:
    """Each SPH kind at ratio 4 at the deck's drive and its twin at a tenth of drive and ambient pressure (peak x 10):
    the peak mid-height displacement against REFERENCE_PEAK and the amplitude effect (their difference in % of the
    reference). "av0" pairs with "a01c01" (the deck's penalty contact)."""
    print("kind | deck drive mm (vs ref) | a tenth x 10 | amplitude effect | energy ratio at 2 ms deck / tenth")
    for kind in kinds:
        out = []
        for name, scale in ((f"{kind}_r4_gap", 1.0), (f"{'a01c01' if kind == 'av0' else kind + 'a01c01'}_r4_gap", 10.0)):
            if not (WORK / name / "histories" / "mid.csv").exists():
                break
            u = scale * 1e3 * np.abs(history(name, "mid")["displacement_x"]).max()
            out.append((u, 100.0 * (u / REFERENCE_PEAK - 1.0), history(name, "glstat")["energy_ratio"][-1]))
        if len(out) == 2:
            print(f"{kind} | {out[0][0]:.4f} ({out[0][1]:+.2f} %) | {out[1][0]:.4f} ({out[1][1]:+.2f} %) | "
                  f"{out[0][1] - out[1][1]:+.2f} % | {out[0][2]:.4f} / {out[1][2]:.4f}")


def corners(names: list[str], scale: float = 1.0) -> None:
    """Per run: u at 0.8 / 1.0 / 1.2 ms (mm, x scale), and at each field output (0.5 / 1.0 / 1.5 / 2.0 ms) the fastest
    water particle within 10 mm of either lower corner of the plate (its bottom face's end nodes, moving) and the sum
    of v^2 within 5 mm of them (m/s, m^2/s^2, velocities x scale); "...a01c01" runs are scaled by 10."""
    import h5py
    for name in names:
        k = 10.0 if "a01c01" in name else scale
        mid = history(name, "mid")
        u = [k * 1e3 * float(np.interp(t, mid["time"], mid["displacement_x"])) for t in (0.8e-3, 1.0e-3, 1.2e-3)]
        fast, sum2 = [], []
        with h5py.File(WORK / name / "results.h5", "r") as f:
            for step in sorted(s for s in f["tank"] if s.startswith("step_"))[1:]:
                x, v = f[f"tank/{step}/coordinates"][:, :2], k * f[f"tank/{step}/point/velocity"][:, :2]
                plate = f[f"plate/{step}/coordinates"][:, :2]
                low = plate[np.abs(plate[:, 1] - plate[:, 1].min()) < 1e-4]
                ends = low[[low[:, 0].argmin(), low[:, 0].argmax()]]
                d = np.min(np.linalg.norm(x[:, None, :] - ends[None, :, :], axis=2), axis=1)
                speed = np.linalg.norm(v, axis=1)
                fast.append(speed[d < 0.01].max())
                sum2.append(float(np.sum(speed[d < 0.005] ** 2)))
        print(f"{name} | u(0.8/1.0/1.2 ms) {' / '.join(f'{a:.4f}' for a in u)} mm | fastest within 10 mm "
              f"{' / '.join(f'{a:.1f}' for a in fast)} m/s | sum v^2 within 5 mm "
              f"{' / '.join(f'{a:.0f}' for a in sum2)}")


def steps(kinds: list[str], level: str = "r5") -> None:
    """Per kind at `level` (deck drive and its a01c01 twin, peak x 10): the peak mid-height displacement against
    REFERENCE_PEAK, the energy ratio at 1.5 / 2.0 ms and its largest value after 0.1 ms, the first time after 0.1 ms
    it leaves 1 +- 0.01 (the start's preload excepted), and the contact energy at 2 ms."""
    print("case | peak mm (vs ref) | energy ratio 1.5 / 2.0 ms (max) | leaves 1 +- 0.01 at ms | contact J at 2 ms")
    for kind in kinds:
        for name, scale in ((f"{kind}_{level}_gap", 1.0), (f"{kind}a01c01_{level}_gap", 10.0)):
            if not (WORK / name / "histories" / "mid.csv").exists():
                continue
            u = scale * 1e3 * np.abs(history(name, "mid")["displacement_x"]).max()
            e = history(name, "glstat")
            late = e["time"] > 1.0e-4
            if not late.any():
                continue
            r = e["energy_ratio"]
            at = [float(np.interp(t, e["time"], r)) for t in (1.5e-3, 2.0e-3)]
            out = np.flatnonzero(late & (np.abs(r - 1.0) > 0.01))
            leave = f"{1e3 * e['time'][out[0]]:.2f}" if len(out) else "-"
            print(f"{name} | {u:.4f} ({100.0 * (u / REFERENCE_PEAK - 1.0):+.2f} %) | {at[0]:.4f} / {at[1]:.4f} "
                  f"({r[late].max():.4f}) | {leave} | {e['contact'][-1]:.3f}")


# ALE's Lagrangian limit on the same plate ("Converged with alpha 0", 5 / 2.5 / 1.25 mm): peak mid-height displacement
# (mm) and the 0-25 mm gauge (MPa), each with its GCI on the finest level (relative)
ALE_LIMIT = {"peak": (0.5735, 0.0032), "gauge": (121.5, 0.020)}


def series(kinds: list[str]) -> None:
    """Per kind over ratios 3-6 (the deck's drive and its a01c01 twin, peaks and gauges x 10): the peak mid-height
    displacement against REFERENCE_PEAK, the energy ratio at 2 ms and its largest value after 0.1 ms, the 0-25 / 25-50 mm
    gauges and the CPU s of log.txt; then Celik's three_grid (sphfem_cli.study.metrics) on the finest three ratios run
    (h = the water's spacing) for the peak and the 0-25 mm gauge, and whether the extrapolation agrees with ALE's limit
    within the combined uncertainty |SPH_ext - ALE_ext| <= GCI_SPH + GCI_ALE (absolute)."""
    from sphfem_cli.study.metrics import three_grid
    cpu = {}
    if (WORK / "log.txt").exists():
        for line in open(WORK / "log.txt"):
            words = line.split()
            cpu[words[0]] = f"{words[2]} (load {words[5]})"
    print("case | ratio | peak mm (vs ref) | energy ratio at 2 ms (max after 0.1 ms) | gauges 0-25 / 25-50 MPa | CPU s")
    for kind in kinds:
        for twin, scale in ((kind, 1.0), (kind.replace(",", "a01c01,") + "a01c01", 10.0)):
            h, peak, gauge = [], [], []
            for level in ("r3", "r4", "r5", "r6"):
                # "A,B": per ratio the last of the kinds run (e.g. "sbal8,sbal45": the 0.45 step where it was run)
                names = [f"{k}_{level}_gap" for k in twin.split(",")
                         if (WORK / f"{k}_{level}_gap" / "histories" / "glstat.csv").exists()]
                if not names:
                    continue
                name = names[-1]
                e = history(name, "glstat")
                if e["time"][-1] < 2.0e-3 - 1e-9:
                    print(f"{name} | stopped at {1e3 * e['time'][-1]:.3f} ms")
                    continue
                u = scale * 1e3 * np.abs(history(name, "mid")["displacement_x"]).max()
                g = [scale * v for v in gauges(name)]
                late = e["time"] > 1.0e-4
                print(f"{name} | {level[1:]} | {u:.4f} ({100.0 * (u / REFERENCE_PEAK - 1.0):+.2f} %) | "
                      f"{float(np.interp(2.0e-3, e['time'], e['energy_ratio'])):.4f} ({e['energy_ratio'][late].max():.4f})"
                      f" | {g[0]:.2f} / {g[1]:.2f} | {cpu.get(name, '-')}")
                h.append(LEVELS[name.split("_")[0]][level])
                peak.append(u)
                gauge.append(g[0])
            if len(h) < 3:
                continue
            for label, phi in (("peak", peak), ("gauge", gauge)):
                c = three_grid(h[-3:], phi[-3:])
                head = f"{twin} {label}, ratios {'/'.join(str(round(0.01 / x)) for x in h[-3:])}: monotone {c.monotone}"
                if c.diverging or not np.isfinite(c.extrapolated):
                    print(f"{head}, {'differences grow' if c.diverging else 'no order'}: no extrapolation")
                    continue
                ale, ale_gci = ALE_LIMIT[label]
                band = abs(c.extrapolated) * c.gci_fine + ale * ale_gci
                print(f"{head}, order {c.order:.2f}, extrapolated {c.extrapolated:.4f}, GCI fine {100 * c.gci_fine:.2f} %, "
                      f"asymptotic ratio {c.asymptotic:.2f}; ALE {ale} (GCI {100 * ale_gci:.2f} %): apart "
                      f"{abs(c.extrapolated - ale):.4f}, band {band:.4f}, agree {abs(c.extrapolated - ale) <= band}")


def corner_figure(path: str = "structure_in_water_corner_flow.png") -> None:
    """Water speed round the plate's lower end at 0.5 and 1.0 ms: SPH ratio 4 at the deck's drive and at a tenth
    (velocities x 10), and the Lagrangian ALE at 2.5 mm (its mesh nodes); runs cd0_r4_gap, cd0a01c01_r4_gap and
    ale_2.5_gap."""
    import h5py
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    runs = (("cd0_r4_gap", 1.0, "SPH ratio 4, deck drive"), ("cd0a01c01_r4_gap", 10.0, "SPH ratio 4, drive / 10 (v x 10)"),
            ("ale_2.5_gap", 1.0, "ALE 2.5 mm Lagrangian, deck drive"))
    fig, axes = plt.subplots(2, 3, figsize=(15, 9.5), constrained_layout=True)
    for row, step in zip(axes, ("step_000001", "step_000002")):
        for ax, (name, scale, title) in zip(row, runs):
            with h5py.File(WORK / name / "results.h5", "r") as f:
                x, v = f[f"tank/{step}/coordinates"][:], scale * f[f"tank/{step}/point/velocity"][:]
                plate = f[f"plate/{step}/coordinates"][:]
            m = (np.abs(x[:, 0] - 0.205) < 0.016) & (x[:, 1] > 0.035) & (x[:, 1] < 0.065)
            dots = ax.scatter(1e3 * x[m, 0], 1e3 * x[m, 1], c=np.linalg.norm(v[m], axis=1), s=30, vmin=0, vmax=10)
            ax.quiver(1e3 * x[m, 0], 1e3 * x[m, 1], v[m, 0], v[m, 1], scale=150, width=0.003)
            ax.plot(1e3 * plate[:, 0], 1e3 * plate[:, 1], "rs", ms=3)
            ax.set(title=f"{title}, t = {0.5 * int(step[-1]):.1f} ms", xlabel="x (mm)", ylabel="y (mm)",
                   xlim=(189, 221), ylim=(35, 65), aspect="equal")
    fig.colorbar(dots, ax=axes, label="water speed (m/s); red: plate nodes")
    fig.savefig(path, dpi=70)


if __name__ == "__main__":
    args = sys.argv[1:]
    if args == ["--summary"]:
        summary()
    elif args[:1] == ["--pairs"]:
        pairs(args[1:])
    elif args[:1] == ["--steps"]:  # --steps [rN] KIND ...: ratio N (default 5)
        if args[1:2] and args[1][0] == "r" and args[1][1:].isdigit():
            steps(args[2:], args[1])
        else:
            steps(args[1:])
    elif args[:1] == ["--series"]:  # --series KIND ...: ratios 3-6, three_grid, against ALE's limit
        series(args[1:])
    elif args[:1] == ["--corners"]:
        corners(args[1:])
    elif args == ["--corner-figure"]:
        corner_figure()
    else:
        for case in args or CASES:
            run(case)
        summary()
