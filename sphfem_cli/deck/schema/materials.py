"""Deck keyword families ``materials`` and ``equations_of_state``.

Every material and equation of state is a mapping with a ``type`` key that selects the model.
Values are in the deck's consistent unit system (see ``units``); "energy per unit reference
volume" is the internal energy divided by the element's or particle's initial volume, as in
LS-DYNA. The equations behind each model are in ``docs/theory/materials.md``.
"""
from __future__ import annotations

from typing import Annotated, Literal, Optional, Union

from pydantic import Field, model_validator

from .base import DeckModel, Vector

__all__ = [
    "Elastic",
    "ElasticPlastic",
    "JohnsonCook",
    "Rigid",
    "Fluid",
    "HighExplosive",
    "Detonation",
    "Material",
    "LinearPolynomial",
    "Gruneisen",
    "Tait",
    "IdealGas",
    "StiffenedGas",
    "JWL",
    "EquationOfState",
]


# --------------------------------------------------------------------------------------- materials


class _Solid(DeckModel):
    density: float = Field(gt=0, description="Reference (initial) mass density rho0 [mass/length^3].")
    youngs_modulus: float = Field(gt=0, description="Young's modulus E [pressure].")
    poisson_ratio: float = Field(ge=0, lt=0.5, description="Poisson ratio nu, 0 <= nu < 0.5 [-].")


class _EosSolid(_Solid):
    """A solid whose pressure may come from an equation of state, bounded below by a cut-off."""

    eos: Optional[str] = Field(
        None, description="Name of an equation of state for the pressure; without one the pressure is hypoelastic (bulk modulus)."
    )
    pressure_cutoff: Optional[float] = Field(
        None, le=0, description="Lowest pressure the equation of state may give (cavitation, spall; LS-DYNA "
        "*MAT_ELASTIC_PLASTIC_HYDRO PC), at most 0; needs `eos`. A water-like soft body (a Lagrangian bird) "
        "cavitates near -0.1 MPa instead of pulling the EOS's tension. Default none [pressure]."
    )

    @model_validator(mode="after")
    def _cutoff_needs_eos(self) -> "_EosSolid":
        if self.pressure_cutoff is not None and self.eos is None:
            raise ValueError("pressure_cutoff bounds an equation of state's pressure: give the material an `eos`")
        return self


class Elastic(_Solid):
    """Isotropic linear elastic solid (hypoelastic rate form)."""

    type: Literal["elastic"] = Field(description="Model selector: isotropic linear elastic.")


class ElasticPlastic(_EosSolid):
    """Bilinear elastic-plastic solid with combined isotropic/kinematic hardening (LS-DYNA MAT_003)."""

    type: Literal["elastic_plastic"] = Field(
        description="Model selector: bilinear von Mises plasticity (LS-DYNA *MAT_PLASTIC_KINEMATIC)."
    )
    yield_stress: float = Field(gt=0, description="Initial yield stress sigma_y0 [pressure].")
    tangent_modulus: float = Field(
        0.0, ge=0, description="Tangent modulus Et of the uniaxial stress-strain curve, 0 <= Et < E [pressure]. Default 0 (perfectly plastic)."
    )
    hardening_beta: float = Field(
        1.0, ge=0, le=1, description="Hardening mix beta: 0 kinematic, 1 isotropic, between combined [-]. Default 1."
    )

    @model_validator(mode="after")
    def _tangent_below_youngs(self) -> "ElasticPlastic":
        if self.tangent_modulus >= self.youngs_modulus:
            raise ValueError(
                f"tangent_modulus ({self.tangent_modulus:g}) must be smaller than youngs_modulus ({self.youngs_modulus:g})"
            )
        return self


class JohnsonCook(_EosSolid):
    """Johnson-Cook strain-rate and temperature dependent plasticity (Johnson & Cook 1983; LS-DYNA MAT_015)."""

    type: Literal["johnson_cook"] = Field(description="Model selector: Johnson-Cook plasticity.")
    A: float = Field(ge=0, description="Yield stress at zero plastic strain, reference rate and room temperature [pressure].")
    B: float = Field(ge=0, description="Strain-hardening coefficient B in (A + B*eps_p^n) [pressure].")
    n: float = Field(gt=0, description="Strain-hardening exponent n [-].")
    C: float = Field(0.0, ge=0, description="Strain-rate coefficient C in (1 + C*ln(rate/reference_rate)) [-]. Default 0.")
    m: float = Field(1.0, gt=0, description="Thermal-softening exponent m in (1 - T*^m) [-]. Default 1.")
    reference_strain_rate: float = Field(
        1.0, gt=0, description="Reference plastic strain rate [1/time]. Default 1.0."
    )
    melt_temperature: float = Field(description="Melting temperature Tm [temperature].")
    room_temperature: float = Field(description="Room (initial) temperature Tr, below melt_temperature [temperature].")
    specific_heat: Optional[float] = Field(
        None,
        gt=0,
        description="Specific heat cp [energy/(mass*temperature)]; if given, all plastic work heats the material adiabatically and softens it.",
    )

    @model_validator(mode="after")
    def _melt_above_room(self) -> "JohnsonCook":
        if self.melt_temperature <= self.room_temperature:
            raise ValueError(
                f"melt_temperature ({self.melt_temperature:g}) must be above room_temperature ({self.room_temperature:g})"
            )
        return self


class Rigid(_Solid):
    """Rigid body material; E and nu are used only for contact stiffness and the time step."""

    type: Literal["rigid"] = Field(description="Model selector: rigid body.")


class Fluid(DeckModel):
    """Newtonian fluid: pressure from an equation of state plus linear viscous deviatoric stress."""

    type: Literal["fluid"] = Field(description="Model selector: fluid (SPH and ALE).")
    density: float = Field(gt=0, description="Reference (initial) mass density rho0 [mass/length^3].")
    viscosity: float = Field(0.0, ge=0, description="Dynamic viscosity mu [pressure*time]. Default 0 (inviscid).")
    eos: str = Field(min_length=1, description="Name of the equation of state giving the pressure.")


class HighExplosive(DeckModel):
    """High explosive with programmed burn (LS-DYNA *MAT_HIGH_EXPLOSIVE_BURN): p = F p_eos, F the burn fraction."""

    type: Literal["high_explosive"] = Field(
        description="Model selector: high explosive, a fluid whose EOS pressure is scaled by the programmed-burn fraction "
                    "F = min(1, max(0, (t - t_L) D / (1.5 delta))), t_L from the deck's detonations (SPH and ALE)."
    )
    density: float = Field(gt=0, description="Reference (initial, unreacted) mass density rho0 [mass/length^3].")
    detonation_velocity: float = Field(gt=0, description="Detonation velocity D [length/time].")
    eos: str = Field(min_length=1, description="Name of the equation of state of the detonation products (e.g. jwl).")


class Detonation(DeckModel):
    """A detonation point (LS-DYNA *INITIAL_DETONATION): explosive at x lights at time + |x - point| / D."""

    point: Vector = Field(description="Detonation point [length]. In an axisymmetric deck with SPH explosives it lies "
                                      "on the axis (x = 0): a point off it would be a ring.")
    time: float = Field(0.0, ge=0, description="Time at which the point detonates [time]. Default 0.")


class Void(DeckModel):
    """Empty space in an ALE mesh: no mass, no pressure (LS-DYNA *MAT_VACUUM)."""

    type: Literal["void"] = Field(description="Model selector: void (ALE multi-material groups only).")


Material = Annotated[
    Union[Elastic, ElasticPlastic, JohnsonCook, Rigid, Fluid, HighExplosive, Void], Field(discriminator="type")
]
"""One entry of the ``materials`` mapping, selected by its ``type``."""


# ------------------------------------------------------------------------------ equations of state


class LinearPolynomial(DeckModel):
    """LS-DYNA *EOS_LINEAR_POLYNOMIAL: p = C0 + C1 mu + C2 mu^2 + C3 mu^3 + (C4 + C5 mu + C6 mu^2) E, mu = rho/rho0 - 1."""

    type: Literal["linear_polynomial"] = Field(description="Model selector: linear polynomial EOS.")
    c0: float = Field(0.0, description="Constant term C0 [pressure]. Default 0.")
    c1: float = Field(0.0, description="Linear coefficient C1 of mu (the bulk modulus) [pressure]. Default 0.")
    c2: float = Field(0.0, description="Coefficient C2 of mu^2, used in compression only [pressure]. Default 0.")
    c3: float = Field(0.0, description="Coefficient C3 of mu^3 [pressure]. Default 0.")
    c4: float = Field(0.0, description="Coefficient C4 of E [-]. Default 0.")
    c5: float = Field(0.0, description="Coefficient C5 of mu*E [-]. Default 0.")
    c6: float = Field(0.0, description="Coefficient C6 of mu^2*E, used in compression only [-]. Default 0.")
    e0: float = Field(0.0, description="Initial internal energy per unit reference volume E0 [pressure]. Default 0.")
    v0: float = Field(1.0, gt=0, description="Initial relative volume V0 = rho0/rho at time zero [-]. Default 1.")


class Gruneisen(DeckModel):
    """LS-DYNA *EOS_GRUNEISEN: shock Hugoniot us = c + s1 up (+ s2, s3 terms) with Gruneisen gamma."""

    type: Literal["gruneisen"] = Field(description="Model selector: Mie-Gruneisen EOS.")
    c: float = Field(gt=0, description="Intercept C of the shock-velocity/particle-velocity curve (bulk sound speed) [length/time].")
    s1: float = Field(ge=0, description="First slope coefficient S1 of the us-up curve [-].")
    s2: float = Field(0.0, description="Second slope coefficient S2 [-]. Default 0.")
    s3: float = Field(0.0, description="Third slope coefficient S3 [-]. Default 0.")
    gamma0: float = Field(ge=0, description="Gruneisen gamma gamma0 [-].")
    a: float = Field(0.0, description="First-order volume correction a to gamma0 [-]. Default 0.")
    e0: float = Field(0.0, description="Initial internal energy per unit reference volume E0 [pressure]. Default 0.")


class Tait(DeckModel):
    """Tait (Cole) equation for weakly compressible liquids: p = B((rho/rho_ref)^gamma - 1) + p_b, B = rho_ref c^2/gamma."""

    type: Literal["tait"] = Field(description="Model selector: Tait EOS (weakly compressible liquid).")
    reference_density: float = Field(gt=0, description="Density rho_ref at which p equals the background pressure [mass/length^3].")
    sound_speed: float = Field(gt=0, description="Sound speed c0 at the reference density [length/time].")
    gamma: float = Field(7.0, ge=1, description="Tait exponent gamma [-]. Default 7.")
    background_pressure: float = Field(0.0, description="Background pressure p_b added to the Tait pressure [pressure]. Default 0.")


class IdealGas(DeckModel):
    """Ideal gas with constant gamma: p = (gamma - 1) rho e."""

    type: Literal["ideal_gas"] = Field(description="Model selector: ideal gas EOS.")
    gamma: float = Field(gt=1, description="Ratio of specific heats gamma = cp/cv, > 1 [-].")
    e0: float = Field(0.0, ge=0, description="Initial internal energy per unit reference volume E0 [pressure]. Default 0.")


class StiffenedGas(DeckModel):
    """Stiffened gas: p = (gamma - 1) rho e - gamma p_inf."""

    type: Literal["stiffened_gas"] = Field(description="Model selector: stiffened gas EOS.")
    gamma: float = Field(gt=1, description="Stiffened-gas exponent gamma, > 1 [-].")
    p_inf: float = Field(ge=0, description="Stiffening pressure p_inf [pressure].")
    e0: float = Field(0.0, description="Initial internal energy per unit reference volume E0 [pressure]. Default 0.")


class JWL(DeckModel):
    """LS-DYNA *EOS_JWL for detonation products: p = A(1 - w/(R1 V))e^(-R1 V) + B(1 - w/(R2 V))e^(-R2 V) + w E/V."""

    type: Literal["jwl"] = Field(description="Model selector: Jones-Wilkins-Lee EOS.")
    A: float = Field(description="First pressure coefficient A [pressure].")
    B: float = Field(description="Second pressure coefficient B [pressure].")
    R1: float = Field(gt=0, description="First exponent R1 [-].")
    R2: float = Field(gt=0, description="Second exponent R2 [-].")
    omega: float = Field(ge=0, description="Gruneisen coefficient omega [-].")
    e0: float = Field(0.0, description="Initial internal energy per unit reference volume E0 (detonation energy) [pressure]. Default 0.")


EquationOfState = Annotated[
    Union[LinearPolynomial, Gruneisen, Tait, IdealGas, StiffenedGas, JWL], Field(discriminator="type")
]
"""One entry of the ``equations_of_state`` mapping, selected by its ``type``."""
