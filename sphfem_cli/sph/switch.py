"""The shock switch of the artificial viscosity: a per-particle coefficient alpha_i that rises where the
fluid is compressed and decays back to its floor behind (``artificial_viscosity.switch`` of an SPH section).

Morris & Monaghan (1997), J. Comput. Phys. 136, 41-50, "A switch to reduce SPH viscosity",
with the source limited as Rosswog, Davies, Thielemann & Piran (2000), A&A 360, 171:

    d alpha_i/dt = -(alpha_i - alpha_min) / tau_i + S_i,
    tau_i = h_i / (l c_i),                          (l = ``decay``, 0.1-0.2 in Morris & Monaghan)
    S_i   = max(-(div v)_i, 0) (alpha_max - alpha_i).

alpha_min is the section's ``alpha`` (the floor every particle starts at and relaxes to: in a region at rest
alpha_i = alpha_min exactly, S = 0 and the decay term 0); the factor (alpha_max - alpha_i) keeps alpha_i
below alpha_max without a clip and makes the rise at a strong shock fast (the source is then close to
alpha_max |div v|). Across a shock (rho1 -> rho2, no decay) alpha_max - alpha falls by the factor rho1/rho2:
alpha_2 = alpha_min + (alpha_max - alpha_min)(1 - rho1/rho2) = alpha_min + (alpha_max - alpha_min) up/Us, small
at a water shock (docs/theory/sph.md, "Shock switch": 0.18 at up 150 m/s). The pair
uses alpha_ij = (alpha_i + alpha_j)/2 in Monaghan's Pi_ij (``rates._pair_terms``,
``axisymmetric._pair_terms``), and beta_ij = (beta/alpha) alpha_ij: the deck's beta/alpha ratio is kept at
every alpha, so a section with alpha 0.1, beta 0.2 has Monaghan's shock setting alpha 1, beta 2 (Morris &
Monaghan: beta = 2 alpha) where alpha_i has reached 1.

(div v)_i is the continuity equation's own estimate (``rates._fluid_rates``: -sum_j V_j v_ij.grad_i W_ij,
in r-z plus v_r/r; ``axisymmetric._axisymmetric_rates``), without the delta-SPH diffusion and without the
renormalisation of explosive products (the products expand: S = 0 there either way).

alpha_i is integrated by the kick-drift-kick leapfrog of the density (``integration.advance_particles``):
d alpha/dt is evaluated with the rates at step n and kicked by (dt_prev + dt)/2 like drho. The decay term's
explicit step is stable and does not overshoot for dt / tau = l c dt / h < 1 (the CFL step gives about
0.25 l: 0.025 at l = 0.1), the source's for dt |div v| < 1 (the density changes by that fraction in a
step). Round-off aside alpha_i stays within [alpha_min, alpha_max]; it is clamped there after each kick so
that a particle never carries a value outside the switch's range.
"""
from __future__ import annotations

import numpy as np
from numba import njit


@njit(cache=True, inline="always")
def pair_coefficients(ashape, ai, salpha, j, bpa, alpha, beta):
    """(alpha_ij, beta_ij) of Monaghan's Pi_ij for the pair (i, j): with the switch (``ashape.ndim`` 2, a
    compile-time choice) alpha_ij = (``ai`` + ``salpha[j]``)/2 and beta_ij = ``bpa`` alpha_ij (module
    docstring); without it (``ashape.ndim`` 1) the section's ``alpha`` and ``beta``, ``salpha`` not read."""
    if ashape.ndim == 2:
        aij = 0.5 * (ai + salpha[j])
        return aij, bpa * aij
    return alpha, beta


@njit(cache=True, error_model="numpy")
def switch_rates(conv, h, c, alpha, active, alpha_min, alpha_max, decay, dalpha):
    """d alpha_i/dt of every active particle (module docstring); ``conv`` = -(div v)_i [1/time], h_i the
    smoothing length, c_i the sound speed. 0 for inactive particles and where c_i = 0 has no decay."""
    for i in range(alpha.shape[0]):
        if not active[i]:
            dalpha[i] = 0.0
            continue
        decay_rate = decay * c[i] / h[i]  # 1 / tau_i
        dalpha[i] = -(alpha[i] - alpha_min) * decay_rate + max(conv[i], 0.0) * (alpha_max - alpha[i])


@njit(cache=True, error_model="numpy")
def advance_switch(alpha, alpha_half, dalpha, active, dt, dt_prev, alpha_min, alpha_max):
    """The leapfrog step of alpha_i, as ``integration.advance_particles`` steps rho_i:

      alpha^n       = alpha^{n-1/2} + dt_prev/2 dalpha^n   (closes the previous step; skipped if dt_prev = 0)
      alpha^{n+1/2} = alpha^n + dt/2 dalpha^n
      alpha        <- alpha^{n+1/2} + dt/2 dalpha^n        (the prediction the next rates use)

    each clamped to [alpha_min, alpha_max]."""
    hp = 0.5 * dt_prev
    hn = 0.5 * dt
    closing = dt_prev > 0.0
    for i in range(alpha.shape[0]):
        if not active[i]:
            continue
        an = alpha_half[i] + hp * dalpha[i] if closing else alpha[i]
        ah = min(max(an + hn * dalpha[i], alpha_min), alpha_max)
        alpha_half[i] = ah
        alpha[i] = min(max(ah + hn * dalpha[i], alpha_min), alpha_max)


@njit(cache=True)
def slot_alpha(perm, n, ghost_source, alpha, alpha_wall, width, out):
    """alpha of every slot of an evaluation (``search.sort_points``' layout) into ``out[:width]``: a particle's
    own, a ghost its source particle's (a mirror image carries the state of its source), a dummy wall point and
    the sentinel columns ``alpha_wall`` (the floor alpha_min: a wall is never compressed)."""
    npts = perm.shape[0]
    ng = ghost_source.shape[0]
    for k in range(npts):
        pid = perm[k]
        if pid < n:
            out[k] = alpha[pid]
        elif pid < n + ng:
            out[k] = alpha[ghost_source[pid - n]]
        else:
            out[k] = alpha_wall
    for k in range(npts, width):
        out[k] = alpha_wall


def empty_slots() -> np.ndarray:
    """The per-slot alpha passed to the rates when the switch is off (never read: see ``rates._pair_terms``)."""
    return np.zeros(1)
