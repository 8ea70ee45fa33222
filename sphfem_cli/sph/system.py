"""``SphSystem``: the SPH fluid as plain arrays plus the calls into the kernel modules of ``sph/``.

One step, as the explicit loop drives it (see ``step`` for the integrator)::

    ps.compute_rates()            # neighbour search + all rates at the current state
    ps.f_ext[:] = ...             # contact/coupling forces (force units), optional
    dt = ps.stable_dt(scale)      # CFL, force and viscous criteria times timestep_scale
    ps.step(dt)                   # kick-drift-kick leapfrog, walls, domain

Arrays are public and owned by the system: ``x``, ``v`` (N, dim); ``rho``, ``e`` (specific
internal energy), ``m``, ``h``, ``p``, ``c`` (N,); ``mat`` (N,) material index into the table;
``active`` (N,) bool; rates ``acc`` (N, dim, without gravity and f_ext), ``drho``, ``de``,
``xsph``; ``alpha`` (N,) the artificial viscosity's alpha_i (the section's alpha unless the shock switch,
``sph/switch.py``, moves it) and ``conv`` (N,) -div v of the last evaluation;
``f_ext`` (N, dim, force units, applied in the next ``step``; the system never clears
it, so a coupling overwrites it every step). At the second evaluation and then every ``reorder_every``
evaluations ``compute_rates`` permutes all per-particle arrays in place into cell order for memory
locality (``ids`` holds each slot's original particle number; ``reorder_every=0`` keeps the order fixed). Counters: ``time``,
``nsteps``, ``lost`` (deactivated particles), ``lost_mass``, ``lost_energy``, ``wall_crossings``,
``external_work`` (work of ``f_ext``).
"""
from __future__ import annotations

from dataclasses import replace
from typing import Callable

import numpy as np

from ..materials import kernels as mk
from ..materials import slots as ms
from . import diffusion, eos, expansion, integration, open_sides, rates, search, switch, walls
from .options import SphOptions, WallParticles
from .walls import Wall
from . import slots as sl
from .kernel_functions import CUBIC_SPLINE, WENDLAND_C2

KERNELS = {"cubic_spline": CUBIC_SPLINE, "wendland_c2": WENDLAND_C2}


class SphSystem:
    """An SPH fluid: particles, optional dummy wall particles, ghost walls, and their time stepping.

    Parameters
    ----------
    x, v : (N, dim) positions and velocities (dim 2 or 3: a deck's ``dimension``).
    mass, density : (N,) particle masses and densities.
    material : (N,) int index into ``materials``.
    materials : ``(type ids (M,), rows (M, NPARAM))`` as ``materials.tables.pack_material``
        gives them (see ``material_table``); every type must be ``fluid``.
    options : ``SphOptions``.
    energy : (N,) specific internal energy; default e0/rho0 of each particle's EOS.
    wall_particles : optional ``WallParticles``.
    """

    def __init__(self, x, v, mass, density, material, materials, options: SphOptions | None = None,
                 energy=None, wall_particles: WallParticles | None = None):
        self.options = opt = options or SphOptions()
        self.x = np.array(x, dtype=np.float64, order="C")
        if self.x.ndim != 2 or self.x.shape[1] not in (2, 3):
            raise ValueError(f"positions must be (N, dim) with dim 2 or 3, got shape {self.x.shape}")
        n, dim = self.x.shape
        self.dim = dim
        self.v = np.array(v, dtype=np.float64, order="C").reshape(n, dim)
        self.m = np.array(mass, dtype=np.float64).reshape(n).copy()
        self.rho = np.array(density, dtype=np.float64).reshape(n).copy()
        self.mat = np.array(material, dtype=np.int64).reshape(n).copy()
        types, rows = materials
        self.material_types = np.asarray(types, dtype=np.int64).reshape(-1)
        self.params = np.ascontiguousarray(rows, dtype=np.float64).reshape(len(self.material_types), mk.NPARAM)
        if np.any(self.material_types != mk.FLUID):
            raise ValueError("SPH particles need materials of type 'fluid'")
        if n and (self.mat.min() < 0 or self.mat.max() >= len(self.material_types)):
            raise ValueError("particle material index out of range of the material table")
        if np.any(self.params[:, mk.P_EOS_TYPE] < 0):
            raise ValueError("every SPH fluid material needs an equation of state")
        if energy is None:
            self.e = self.params[self.mat, mk.EOS_OFFSET + ms.Q_E0] / self.params[self.mat, mk.P_RHO0]
        else:
            self.e = np.array(energy, dtype=np.float64).reshape(n).copy()
        if opt.kernel not in KERNELS:
            raise ValueError(f"unknown kernel {opt.kernel!r} (expected one of {sorted(KERNELS)})")

        self.n = n
        self.active = np.ones(n, dtype=np.bool_)
        self.ids = np.arange(n, dtype=np.int64)
        self.h = np.zeros(n)
        self.p = np.zeros(n)
        self.c = np.zeros(n)
        self.acc = np.zeros((n, dim))
        self.drho = np.zeros(n)
        self.de = np.zeros(n)
        self.xsph = np.zeros((n, dim))
        self.f_ext = np.zeros((n, dim))
        self.wall_power = np.zeros(n)
        self.wall_energy = 0.0
        self.v_half = self.v.copy()
        self.rho_half = self.rho.copy()
        self.e_half = self.e.copy()
        # the shock switch (sph/switch.py): alpha_i, its half-step value and rate; conv = -(div v)_i of the
        # last evaluation (written by the rates with or without the switch)
        self.shock_switch = opt.switch_alpha_max is not None
        if self.shock_switch:
            if not opt.alpha > 0.0:
                raise ValueError("the viscosity switch needs alpha > 0 (its floor alpha_min, and beta/alpha)")
            if not opt.switch_alpha_max > opt.alpha:
                raise ValueError(f"the viscosity switch's alpha_max {opt.switch_alpha_max} must exceed alpha {opt.alpha}")
            if not opt.switch_decay > 0.0:
                raise ValueError(f"the viscosity switch's decay must be > 0, got {opt.switch_decay}")
        self.alpha = np.full(n, float(opt.alpha))
        self.alpha_half = self.alpha.copy()
        self.dalpha = np.zeros(n)
        self.conv = np.zeros(n)
        self._salpha = switch.empty_slots()

        self.axisymmetric = bool(opt.axisymmetric)
        if self.axisymmetric:
            self._check_axisymmetric(wall_particles)
            if not any(w.axis == 0 and w.position == 0.0 and w.side == 1 for w in opt.walls):
                # the axis: reflected ghosts r -> -r (a copy of the options: the caller's stay as given)
                self.options = opt = replace(opt, walls=(Wall(0, 0.0, 1, "slip"), *opt.walls))
        self.gravity = np.zeros(3)
        if opt.gravity is not None:
            g = np.asarray(opt.gravity, dtype=np.float64).reshape(-1)
            self.gravity[: len(g)] = g
        # ghost planes (walls.make_ghosts; open_sides.ghost_planes); self.walls: the walls among them, which
        # mirror back the particles that cross them; the open sides move with the water and delete nothing
        self._planes = open_sides.ghost_planes(opt.walls, dim)
        is_open = self._planes[:, 3] == sl.PLANE_OPEN
        self.walls = np.ascontiguousarray(self._planes[~is_open, :4])
        self._open_planes = self._planes[is_open]
        self.wall_function_walls = np.array([[w.axis, w.position, w.side] for w in opt.walls
                                             if w.condition == "wall_function"], dtype=np.float64).reshape(-1, 3)
        nsub = 1 << len(self._planes)
        self._valid = np.zeros(nsub, dtype=np.bool_)
        for s in range(1, nsub):
            axes = [int(self._planes[w, 0]) for w in range(len(self._planes)) if s >> w & 1]
            self._valid[s] = len(axes) == len(set(axes))
        # the domain box (particles leaving it are deactivated): the section's, if any
        self._use_domain = opt.domain is not None
        self._dom_lo, self._dom_hi = ((np.array(b, dtype=np.float64).reshape(dim) for b in opt.domain)
                                      if self._use_domain else (np.zeros(dim), np.zeros(dim)))
        # open sides: each particle's distance from each ghost plane at t = 0 (N, planes; read for the open
        # sides only, whose images it places: sph.open_sides; (N, 0) without open sides), its far pressure
        # (its pressure at the first evaluation) and the impulse int (p - p_far) dt of the Bayliss-Turkel
        # term; the power of their ghosts
        self.open_d0 = open_sides.initial_distances(self.x, self._planes)
        self.p_far = np.zeros(n)
        self.impulse = np.zeros(n)
        self.open_power = np.zeros(n)
        self.open_energy = 0.0
        self._k_wave = {1: 0.0, 2: 0.5, 3: 1.0}[dim]

        wp = wall_particles
        if wp is not None:
            self.wall_x = np.array(wp.positions, dtype=np.float64).reshape(-1, dim)
            nw = len(self.wall_x)
            self.wall_v = (np.zeros((nw, 3)) if wp.velocities is None else
                           np.pad(np.asarray(wp.velocities, dtype=np.float64).reshape(nw, dim), ((0, 0), (0, 3 - dim))))
            rho0 = self.params[wp.material, mk.P_RHO0]
            self.wall_rho = np.full(nw, rho0)
            self.wall_m = np.full(nw, rho0 * wp.spacing**dim)
            self.wall_h = np.full(nw, opt.smoothing_ratio * wp.spacing)
            self.wall_mat = np.full(nw, wp.material, dtype=np.int64)
        else:
            self.wall_x = np.zeros((0, dim))
            self.wall_v = np.zeros((0, 3))
            self.wall_rho = self.wall_m = self.wall_h = np.zeros(0)
            self.wall_mat = np.zeros(0, dtype=np.int64)

        self._wall_hmax = float(self.wall_h.max()) if len(self.wall_h) else 0.0
        self._no_ghosts = (np.zeros((0, 3)), np.zeros((0, 3)), np.zeros((0, 3)), np.zeros(0, dtype=np.int64),
                           np.zeros(0, dtype=np.int64), np.zeros(0), np.zeros(0))
        self._no_flips = np.ones((1, 3))
        self._no_stress = np.zeros((1, 6))
        self.viscous = bool(np.any(self.params[:, ms.P_VISCOSITY] > 0.0) or opt.dilatational_viscosity > 0.0)
        # the kernels' settings (fixed) and cell grid (rewritten by every search); slots in sph/slots.py
        self.settings_f = np.zeros(sl.N_SF)
        self.settings_f[[sl.SF_ALPHA, sl.SF_BETA, sl.SF_EPS, sl.SF_DELTA, sl.SF_XSPH]] = [
            opt.alpha, opt.beta, opt.eps, opt.delta, opt.xsph]
        self.settings_f[[sl.SF_GX, sl.SF_GY, sl.SF_GZ]] = self.gravity
        self.settings_f[sl.SF_DILATATIONAL_VISCOSITY] = opt.dilatational_viscosity
        self.settings_f[sl.SF_PRESSURE_CUTOFF] = opt.pressure_cutoff
        self.settings_f[sl.SF_BETA_PER_ALPHA] = opt.beta / opt.alpha if opt.alpha > 0.0 else 0.0
        self.settings_i = np.zeros(sl.N_SI, dtype=np.int64)
        self.settings_i[sl.SI_DIM] = dim
        self.settings_i[sl.SI_KERNEL] = KERNELS[opt.kernel]
        self.settings_i[sl.SI_VISCOUS] = int(self.viscous)
        if opt.density_diffusion_form not in ("molteni_colagrossi", "delta_plus"):
            raise ValueError(f"density_diffusion_form must be molteni_colagrossi or delta_plus, got {opt.density_diffusion_form!r}")
        if opt.density_diffusion_form == "delta_plus" and opt.axisymmetric:
            raise ValueError("density_diffusion_form delta_plus is 2D and 3D only (not axisymmetric)")
        self.delta_plus = opt.density_diffusion_form == "delta_plus" and opt.delta > 0.0
        # delta_plus removes every linear density field, the hydrostatic one included: no second correction
        self.settings_i[sl.SI_DELTA_HYDROSTATIC] = int(opt.delta_hydrostatic and not self.delta_plus)
        self.settings_i[sl.SI_NWALL] = len(self.wall_x)
        if opt.continuity not in sl.CONTINUITY_FORMS:
            raise ValueError(f"continuity must be one of {sorted(sl.CONTINUITY_FORMS)}, got {opt.continuity!r}")
        self.settings_i[sl.SI_CONTINUITY] = sl.CONTINUITY_FORMS[opt.continuity]
        self.settings_i[sl.SI_NMAT] = len(self.material_types)
        self.grid_f = np.zeros(sl.N_GF)
        self.grid_i = np.zeros(sl.N_GI, dtype=np.int64)

        self.time = 0.0
        self.nsteps = 0
        self.lost = 0
        self.lost_mass = 0.0
        self.lost_energy = 0.0
        self.wall_crossings = 0
        self.external_work = 0.0
        self._dt_prev = 0.0
        # scratch of integration.stable_time_step and advance_particles (2D); zeroed, not empty: a checkpoint
        # holds it, and uninitialised memory made two checkpoints of the same 3D run differ
        self._dt_work = np.zeros((3, n))
        self._evaluations = 0
        self._rates_valid = False
        self._sorted = None  # last evaluation's point set (layout in the sph/search.py docstring)
        self._update_state()

    def _check_axisymmetric(self, wall_particles) -> None:
        """What the axisymmetric rates (``sph.axisymmetric``) do not model; particles must lie at r > 0."""
        opt = self.options
        if self.dim != 2:
            raise ValueError("axisymmetric SPH needs 2D points (r, z)")
        if self.n and not np.all(self.x[:, 0] > 0.0):
            raise ValueError("axisymmetric SPH particles must lie at r = x > 0")
        if wall_particles is not None:
            raise ValueError("axisymmetric SPH has no dummy wall particles (use ghost walls)")
        if np.any(self.params[:, ms.P_VISCOSITY] > 0.0) or opt.dilatational_viscosity > 0.0:
            raise ValueError("axisymmetric SPH has no physical viscosity yet (inviscid fluids only)")
        if any(w.condition != "slip" for w in opt.walls):
            raise ValueError("axisymmetric SPH supports slip ghost walls only")

    # ------------------------------------------------------------------ evaluation

    def set_burn(self, detonations) -> None:
        """Programmed burn (``materials.burn``) of every particle whose material has a detonation
        velocity (a ``high_explosive``): lighting time at its current position from ``detonations``
        [(point, time), ...], size delta its spacing (m / rho)^(1/dim) now (axisymmetric: sqrt(A), A =
        m / (2 pi r rho) its area in the meridian plane, and every detonation point on the axis r = 0,
        where it is a point: off it, it would be a ring). Kept per particle id."""
        from ..materials.burn import lighting_time

        if self.axisymmetric:
            off = [tuple(p) for p, _ in detonations if float(np.asarray(p, dtype=float).reshape(-1)[0]) != 0.0]
            if off:
                raise ValueError(f"axisymmetric SPH: a detonation point must lie on the axis (x = r = 0), got {off}")

        d = self.params[self.mat, ms.P_DETONATION_VELOCITY]
        self.burn_light = np.full(self.n, np.inf)
        self.burn_velocity = np.zeros(self.n)
        self.burn_delta = np.ones(self.n)
        he = d > 0.0
        if not he.any():
            self.burn_light = None
            return
        ids = self.ids[he]
        for dv in np.unique(d[he]):
            sel = he & (d == dv)
            self.burn_light[self.ids[sel]] = lighting_time(self.x[sel], detonations, float(dv))
        self.burn_velocity[ids] = d[he]
        if self.axisymmetric:  # the spacing of the ring's section, not of its volume
            self.burn_delta[ids] = np.sqrt(self.m[he] / (2.0 * np.pi * self.x[he, 0] * self.rho[he]))
        else:
            self.burn_delta[ids] = (self.m[he] / self.rho[he]) ** (1.0 / self.dim)
        self._update_state()

    def _update_state(self) -> float:
        """p, c, h of the active particles; returns the largest h."""
        hmax = eos.update_particle_state(self.rho, self.e, self.m, self.mat, self.active, self.params,
                                         float(self.options.smoothing_ratio), self.dim,
                                         float(self.options.pressure_cutoff), self.p, self.c, self.h)
        if self.axisymmetric:  # the plane h of the ring's area, not of its volume
            from .axisymmetric import ring_smoothing_lengths

            hmax = ring_smoothing_lengths(self.x, self.rho, self.m, self.active,
                                          float(self.options.smoothing_ratio), self.h)
        if getattr(self, "burn_light", None) is not None:
            from ..materials.burn import burn_fraction

            he = np.isfinite(self.burn_light[self.ids])
            i = self.ids[he]
            self.p[he] *= burn_fraction(self.time, self.burn_light[i], self.burn_velocity[i], self.burn_delta[i])
        return hmax

    def _reorder(self) -> None:
        """Permute every per-particle array into the cell order of the last evaluation."""
        perm = self._sorted["perm"]
        order = perm[perm < self.n]
        if len(order) < self.n:
            seen = np.zeros(self.n, dtype=bool)
            seen[order] = True
            order = np.concatenate([order, np.flatnonzero(~seen)])
        if np.array_equal(order, np.arange(self.n)):
            return
        for name in ("x", "v", "v_half", "m", "rho", "rho_half", "e", "e_half", "mat", "active", "ids",
                     "h", "p", "c", "acc", "drho", "de", "xsph", "f_ext", "p_far", "impulse", "open_d0",
                     "open_power", "alpha", "alpha_half", "dalpha", "conv"):
            arr = getattr(self, name)
            arr[...] = arr[order]  # in place: references held by callers stay valid

    def _sort_storage(self) -> tuple[np.ndarray, np.ndarray]:
        """The last evaluation's ``sx`` and ``sd``, reused by the next sort (empty ones before the first)."""
        if self._sorted is None:
            return np.zeros((0, 0)), np.zeros((0, 0))
        return self._sorted["sx"], self._sorted["sd"]

    def _build_points(self, hmax: float) -> dict:
        """Ghosts, cell sort and the sorted point set of one evaluation."""
        opt = self.options
        if len(self.wall_h):
            hmax = max(hmax, self._wall_hmax)
        if len(self._planes):
            gpos, gvel, gflip, gsrc, gsub, gdp, gdr = walls.make_ghosts(
                self.x, self.v, self.rho, self.c, self.open_d0, self.active, self._planes, self._valid, 2.0 * hmax,
                self.gravity, bool(opt.ghost_hydrostatic))
        else:
            gpos, gvel, gflip, gsrc, gsub, gdp, gdr = self._no_ghosts
        ghost_open = np.zeros(len(gsrc), dtype=np.bool_)
        if len(self._open_planes):
            open_sides.open_ghost_state(self.x, self.p, self.rho, self.c, self.p_far, self.impulse, gpos, gvel, gsrc,
                                        gsub, gdp, gdr, self._planes, self._k_wave, self.gravity,
                                        float(opt.pressure_cutoff), ghost_open)
        if self.axisymmetric:  # the ghosts' source radius, read by sph.axisymmetric (third column unused in 2D)
            gvel[:, 2] = self.x[gsrc, 0]
        # the last sx and sd, reused (search.sort_points); a checkpoint holds them, so a restart reuses them too
        perm, cell_start, sreach, sx, sd = search.sort_points(
            self.x, self.v, self.rho, self.m, self.p, self.c, self.h, self.mat, self.active, gpos, gvel, gsrc,
            gdp, gdr, self.wall_x, self.wall_v, self.wall_rho, self.wall_m, self.wall_h, self.wall_mat,
            int(opt.max_cells_per_point), self.grid_f, self.grid_i, *self._sort_storage())
        # no-slip ghosts: per-slot velocity factors (fill_ghosts) and the fluid slots next to them
        svf, friction_slots = self._no_flips, np.zeros(0, dtype=np.int64)
        stuck = np.flatnonzero((gflip != 1.0).any(axis=1))
        if stuck.size:
            n = self.n
            svf = np.ones((len(perm) + 1, 3))
            slot_of = np.empty(n + len(gsrc) + len(self.wall_x), dtype=np.int64)  # point id -> slot (active points)
            slot_of[perm] = np.arange(len(perm))
            svf[slot_of[n + stuck]] = gflip[stuck]
            friction_slots = np.sort(slot_of[np.unique(gsrc[stuck])])
        return {"perm": perm, "cell_start": cell_start, "sx": sx, "sd": sd, "sreach": sreach, "n_ghost": len(gsrc),
                "ghost_source": gsrc, "grid_f": self.grid_f.copy(), "grid_i": self.grid_i.copy(),
                "svf": svf, "friction_slots": friction_slots, "ghost_open": ghost_open}

    def compute_rates(self) -> None:
        """Neighbour search and every rate at the current state (x, v, rho, e).

        Updates p, c, h; builds ghosts, the cell list and the sorted point set; extrapolates the
        dummy-wall pressures; computes the viscous stress (if any material is viscous) and then
        ``acc``, ``drho``, ``de``, ``xsph`` of every active particle (0 for inactive ones).
        Reorders the particle arrays first at the second evaluation and every ``reorder_every`` evaluations.
        """
        opt = self.options
        # also at the second evaluation: the particles come in the order their generator gave (a lattice
        # is x-major, the cells are y-major), read out of sequence by the copy into cell order and the
        # rates' writes until the first reordering; at 5e5 particles the step took 1.2 times as long
        # before it as after (issue 17: the growth of the cost per particle-step with N)
        if opt.reorder_every and self._sorted is not None and (
                self._evaluations % opt.reorder_every == 0 or self._evaluations == 1):
            self._reorder()
        hmax = self._update_state()
        if self._evaluations == 0:
            self.p_far[:] = self.p  # the open sides' far field: the state the run starts from
        pts = self._build_points(hmax)
        sx, sd, perm, cs, sr = pts["sx"], pts["sd"], pts["perm"], pts["cell_start"], pts["sreach"]
        sf, si, gf, gi = self.settings_f, self.settings_i, self.grid_f, self.grid_i
        if len(self.wall_x):
            walls.wall_pressure(sx, sd, cs, sr, sf, si, gf, gi, self.params)
        if self.viscous:
            stau = np.zeros((len(perm) + 1, 6))
            rates.viscous_stress(sx, sd, pts["svf"], cs, sr, sf, si, gf, gi, self.params, stau)
        else:
            stau = self._no_stress
        pts["stau"] = stau
        self.wall_power[:] = 0.0
        salpha = self._slot_alpha(pts)
        if self.axisymmetric:
            from .axisymmetric import axisymmetric_rates  # compiled only for axisymmetric systems

            axisymmetric_rates(sx, sd, perm, cs, sr, sf, si, gf, gi, self.acc, self.drho, self.de, self.xsph,
                               self.conv, salpha, self.shock_switch)
            if getattr(self, "burn_light", None) is not None:  # explosive products: renormalised r-z continuity
                from .axisymmetric import renormalise_ring_continuity

                he = np.isfinite(self.burn_light[self.ids]) & self.active
                renormalise_ring_continuity(sx, sd, perm, cs, sr, si, gf, gi, he, self.drho)
        else:
            rates.fluid_rates(sx, sd, stau, perm, cs, sr, sf, si, gf, gi, self.acc, self.drho, self.de, self.xsph,
                              self.wall_power, self.conv, salpha, self.shock_switch)
            if self.delta_plus:  # Antuono et al. 2010's correction of the Molteni-Colagrossi term
                grad = np.zeros((3, sx.shape[1]))
                diffusion.density_gradient(sx, sd, cs, sr, si, gf, gi, grad)
                diffusion.delta_plus_correction(sx, sd, perm, cs, sr, sf, si, gf, gi, grad, self.drho)
            if getattr(self, "burn_light", None) is not None:  # explosive products: renormalised continuity
                he = np.isfinite(self.burn_light[self.ids]) & self.active
                expansion.renormalise_continuity(sx, sd, perm, cs, sr, si, gf, gi, he, self.drho)
        if pts["friction_slots"].size and (self.options.alpha or self.options.beta):
            walls.ghost_friction(sx, sd, pts["svf"], pts["friction_slots"], perm, cs, sr, sf, si, gf, gi, self.acc,
                                 self.de, salpha)
        if len(self._open_planes):
            self.open_power[:] = 0.0
            sopen, slots = open_sides.open_slots(perm, self.n, pts["ghost_open"], pts["ghost_source"])
            if slots.size:
                open_sides.open_side_power(sx, sd, sopen, slots, perm, cs, sr, sf, si, gf, gi, self.open_power)
        if len(self.wall_function_walls):
            walls.wall_shear(self.x, self.v, self.rho, self.m, self.mat, self.active, self.params,
                             self.wall_function_walls, self.acc, self.de)
        if self.shock_switch:
            switch.switch_rates(self.conv, self.h, self.c, self.alpha, self.active, float(opt.alpha),
                                float(opt.switch_alpha_max), float(opt.switch_decay), self.dalpha)
        self._sorted = pts
        self._evaluations += 1
        self._rates_valid = True

    def _slot_alpha(self, pts: dict) -> np.ndarray:
        """The shock switch's alpha of every slot of this evaluation (``switch.slot_alpha``); a dummy without it."""
        if not self.shock_switch:
            return self._salpha
        width = pts["sx"].shape[1]
        if self._salpha.shape[0] < width:
            self._salpha = np.empty(width)
        switch.slot_alpha(pts["perm"], self.n, pts["ghost_source"], self.alpha, float(self.options.alpha), width,
                          self._salpha)
        return self._salpha

    # ------------------------------------------------------------------ stepping

    def stable_dt(self, scale: float = 1.0) -> float:
        """scale x min over active particles of cfl h/(c+|v|), force_factor sqrt(h/|a|) and
        viscous_factor rho h^2/mu, with a = acc + g + f_ext/m, and for an axisymmetric system r/(c+|v|)
        (``axisymmetric.axis_time_step``) (call after ``compute_rates``)."""
        opt = self.options
        dt = integration.stable_time_step(self.h, self.c, self.v, self.acc, self.f_ext, self.m, self.rho, self.mat,
                                self.active, self.params, self.gravity, float(opt.cfl), float(opt.force_factor),
                                float(opt.viscous_factor), self._dt_work)
        if self.axisymmetric:  # the hoop terms' Courant condition (sph.axisymmetric.axis_time_step)
            from .axisymmetric import axis_time_step

            dt = min(dt, axis_time_step(self.x, self.c, self.v, self.active))
        return scale * float(dt)

    def step(self, dt: float) -> None:
        """Advance by ``dt`` with the rates of the last ``compute_rates`` (kick-drift-kick leapfrog).

        With a^n = acc + g + f_ext/m evaluated at step n (and drho, de likewise):
        v^n = v^{n-1/2} + dt_prev/2 a^n closes the previous step, v^{n+1/2} = v^n + dt/2 a^n,
        x^{n+1} = x^n + dt (v^{n+1/2} + xsph); rho and e are kicked the same way. Afterwards ``v``,
        ``rho``, ``e`` hold the predictions v^{n+1/2} + dt/2 a^n (the state the next rates are
        evaluated at); the next step replaces them by the corrected values. Over two steps this is
        v^{n+1/2} = v^{n-1/2} + (dt_prev + dt)/2 a^n, the FEM central difference. Then particles
        behind a wall are mirrored back (counted in ``wall_crossings``) and particles outside
        ``domain`` are deactivated (counted in ``lost``).
        """
        if not self._rates_valid:
            raise RuntimeError("step() needs the rates of the current state: call compute_rates() first")
        dt = float(dt)
        work, nref, nlost, lost_mass, lost_energy = integration.advance_particles(
            self.x, self.v, self.v_half, self.rho, self.rho_half, self.e, self.e_half, self.acc, self.drho,
            self.de, self.xsph, self.f_ext, self.m, self.active, self.gravity, dt, self._dt_prev, self.walls,
            self._dom_lo, self._dom_hi, self._use_domain, self._dt_work[0])
        if self.shock_switch:  # alpha_i in the density's leapfrog (sph/switch.py)
            switch.advance_switch(self.alpha, self.alpha_half, self.dalpha, self.active, dt, self._dt_prev,
                                  float(self.options.alpha), float(self.options.switch_alpha_max))
        self.external_work += work
        if len(self.wall_x):  # the dummy walls' share of the pair work, weighted as the kicks weigh de
            self.wall_energy += 0.5 * (self._dt_prev + dt) * float(np.sum(self.wall_power))
        if len(self._open_planes):  # radiated through the open sides, weighted as the kicks weigh the rates
            self.open_energy -= 0.5 * (self._dt_prev + dt) * float(np.sum(self.open_power))
            if not np.all(np.isnan(self._open_planes[:, 4])):  # the Bayliss-Turkel impulse, p at step n
                a = self.active
                self.impulse[a] += dt * (self.p[a] - self.p_far[a])
        self.wall_crossings += nref
        if nlost:
            self.lost += nlost
            self.lost_mass += lost_mass
            self.lost_energy += lost_energy
        self._dt_prev = dt
        self.time += dt
        self.nsteps += 1
        self._rates_valid = False

    def advance(self, scale: float = 1.0, dt_max: float | None = None) -> float:
        """``compute_rates()``, ``stable_dt(scale)`` (capped by dt_max), ``step(dt)``; returns dt."""
        self.compute_rates()
        dt = self.stable_dt(scale)
        if dt_max is not None:
            dt = min(dt, dt_max)
        if not np.isfinite(dt) or dt <= 0.0:
            raise RuntimeError(f"no usable time step (dt = {dt}) at t = {self.time:.6e}")
        self.step(dt)
        return dt

    def run(self, end_time: float, scale: float = 1.0, every: Callable[["SphSystem"], None] | None = None,
            max_steps: int | None = None) -> None:
        """Step until ``end_time`` (the last step is shortened to land on it); ``every(self)`` after each step."""
        while self.time < end_time * (1.0 - 1e-12):
            if max_steps is not None and self.nsteps >= max_steps:
                break
            self.advance(scale, dt_max=end_time - self.time)
            if every is not None:
                every(self)

    # ------------------------------------------------------------------ diagnostics

    def energies(self) -> dict:
        """Kinetic, internal and gravitational potential energy of the active particles, the external
        work of ``f_ext``, the energy carried away by deactivated particles and the energy the dummy
        walls absorbed (``wall``: their half of the fluid-wall pair work, see ``rates.fluid_rates``) and the
        energy radiated through non-reflecting open sides (``open``: minus the work of their ghosts,
        ``open_sides.open_side_power``)."""
        a = self.active
        m = self.m[a]
        ke = 0.5 * float(np.sum(m * np.sum(self.v[a] ** 2, axis=1)))
        ie = float(np.sum(m * self.e[a]))
        pe = -float(np.sum(m * (self.x[a] @ self.gravity[: self.dim])))
        return {"kinetic": ke, "internal": ie, "potential": pe, "external_work": self.external_work,
                "lost": self.lost_energy, "wall": self.wall_energy, "open": self.open_energy,
                "total": ke + ie + pe}

    def momentum(self) -> np.ndarray:
        """Total linear momentum of the active particles."""
        return (self.m[self.active, None] * self.v[self.active]).sum(axis=0)

    def _pad(self, points) -> np.ndarray:
        pts = np.atleast_2d(np.asarray(points, dtype=np.float64))
        out = np.zeros((len(pts), 3))
        out[:, : pts.shape[1]] = pts
        return out

    def interpolate(self, points, quantity: str = "pressure", include_walls: bool = True) -> np.ndarray:
        """Shepard-normalised SPH interpolation of ``quantity`` ("pressure", "density", "vx", "vy",
        "vz", "sound_speed") at ``points`` (P, dim), from the point set of the last evaluation
        (fluid, ghosts and, with ``include_walls``, dummy walls). NaN where no particle is near."""
        if self._sorted is None:
            self.compute_rates()
        cols = {"pressure": -1, "density": sl.D_RHO, "vx": sl.D_VX, "vy": sl.D_VY, "vz": sl.D_VZ,
                "sound_speed": sl.D_C}
        pts = self._sorted
        return rates.interpolate_points(self._pad(points), pts["sx"], pts["sd"], pts["cell_start"], self.settings_i,
                                        pts["grid_f"], pts["grid_i"], cols[quantity], include_walls)

    def front(self, axis: int = 0, material: int | None = None) -> float:
        """Largest coordinate along ``axis`` of the active particles (of ``material`` if given)."""
        sel = self.active if material is None else self.active & (self.mat == material)
        return float(self.x[sel, axis].max()) if sel.any() else float("nan")

    def surface_height(self, gauge: float, axis: int = 0, up: int = 1, width: float | None = None) -> float:
        """Free-surface height at ``x[axis] = gauge``: the highest particle (along ``up``) within
        ``width`` (default the smoothing length) of the gauge line, plus half a particle spacing."""
        w = float(np.median(self.h[self.active])) if width is None else width
        sel = self.active & (np.abs(self.x[:, axis] - gauge) < w)
        if not sel.any():
            return float("nan")
        top = np.argmax(np.where(sel, self.x[:, up], -np.inf))
        vol = self.m[top] / self.rho[top]
        if self.axisymmetric:  # the particle's area in the meridian plane
            vol /= 2.0 * np.pi * self.x[top, 0]
        return float(self.x[top, up] + 0.5 * vol ** (1.0 / self.dim))

    def neighbour_lists(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Neighbour lists of the last evaluation: ``(offsets, neighbours, point_ids)`` in slot
        numbering; slot k's neighbours are ``neighbours[offsets[k]:offsets[k+1]]`` and
        ``point_ids[slot]`` is the point id (particle index < N, then ghosts, then walls)."""
        pts = self._sorted
        counts = np.empty(len(pts["perm"]), dtype=np.int64)
        search.count_neighbours(pts["sx"], pts["cell_start"], pts["sreach"], pts["grid_f"], pts["grid_i"], counts)
        offsets = np.zeros(len(counts) + 1, dtype=np.int64)
        np.cumsum(counts, out=offsets[1:])
        out = np.empty(offsets[-1], dtype=np.int64)
        search.fill_neighbours(pts["sx"], pts["cell_start"], pts["sreach"], pts["grid_f"], pts["grid_i"], offsets, out)
        return offsets, out, pts["perm"]

    def memory_bytes(self) -> int:
        """Bytes held by the per-particle arrays and the last evaluation's point set."""
        total = sum(a.nbytes for a in vars(self).values() if isinstance(a, np.ndarray))
        if self._sorted is not None:
            held = {id(a.base if a.base is not None else a): (a.base if a.base is not None else a)
                    for a in self._sorted.values() if isinstance(a, np.ndarray)}  # views counted once, by their base
            total += sum(getattr(a, "nbytes", 0) for a in held.values())
        return int(total)
