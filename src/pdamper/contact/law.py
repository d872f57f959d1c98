"""Parameters of the DEM contact law (paper Sect. 3, "Discrete element method").

This module imports no numba, so that damper models and scenario files can describe the
contact law without loading the kernels. The law itself (Hertz with a COR-calibrated
nonlinear damping, tanh-regularised friction) is in :mod:`pdamper.contact.forces`.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field

from pdamper.contact.restitution import RestitutionCurve
from pdamper.errors import InputError, check_range

#: Damping laws of the normal force: ``"exact"`` (pdamper's closed form of the COR of
#: ``K delta^1.5 (1 + d delta_dot)``, default), ``"gonthier"`` (the paper's approximation of
#: it), ``"tsuji"`` (``K delta^1.5 + c delta^0.25 delta_dot``, LIGGGHTS' and EDEM's "Hertz
#: with COR"); see :mod:`pdamper.contact.damping`.
DAMPING_MODELS = ("exact", "gonthier", "tsuji")

#: Tangential (friction) laws: ``"regularised"`` (the paper's tanh-regularised Coulomb
#: friction, default) or ``"spring"`` (a tangential spring with a Coulomb limit on a
#: per-contact elastic tangential displacement: LIGGGHTS' ``tangential history`` with its
#: Hertz ``k_t = 8 G* sqrt(R* delta)`` and damping, Yade's Mindlin without the latter);
#: see :mod:`pdamper.contact.forces`.
FRICTION_MODELS = ("regularised", "spring")


def check_integrator_for(friction_model: str, integrator: str, field: str = "integrator"
                         ) -> None:
    """The one rule between a friction law and an integrator: the Gear kernel has no
    tangential displacement history (its corrector would need it per accepted step), so
    ``"spring"`` runs with ``"verlet"`` or ``"auto"`` (Verlet throughout); an
    :class:`~pdamper.errors.InputError` naming ``field`` otherwise."""
    if friction_model == "spring" and integrator == "gear":
        raise InputError(field, "must be verlet or auto with friction_model = spring (Gear "
                         "has no tangential spring), got 'gear'")

#: Default regularisation velocity of the tanh friction law [m/s]: below it friction acts
#: as a viscous damper of coefficient mu |F_n| / v_reg, above ~2 v_reg it is Coulomb
#: sliding to within 4 %.
DEFAULT_REGULARISATION_VELOCITY = 0.01
#: Default lower bound of the onset speed used to set the damping parameter [m/s]; contacts
#: that form more gently are damped as if they had hit at this speed (keeps d finite).
DEFAULT_MIN_IMPACT_VELOCITY = 1e-2
#: Default re-impact factor: a persisting contact approached faster than this factor times
#: its stored impact speed is treated as a new impact (see :mod:`pdamper.dem.kernels`).
DEFAULT_REIMPACT_FACTOR = 1.25


@dataclass(frozen=True)
class ContactParameters:
    """Contact law parameters (paper Sect. 3).

    Parameters
    ----------
    restitution_pp, restitution_pw
        COR curves ``e(v_impact)`` of sphere-sphere and sphere-wall contacts.
    friction_pp, friction_pw
        Coulomb friction coefficients mu [-] (paper: 0.1 everywhere).
    pairs
        Optional per-material-pair curves, keyed by a pair of material names (order does
        not matter; the wall material name for sphere-wall pairs); they override the two
        defaults above.
    damping_model
        ``"exact"`` (default): damping from the exact closed-form COR relation;
        ``"gonthier"``: Gonthier's approximation ``(1 - e^2)/e`` (the paper's choice);
        ``"tsuji"``: the viscoelastic law of LIGGGHTS and EDEM ("Hertz with COR").
    friction_model
        ``"regularised"`` (default): the paper's tanh-regularised Coulomb friction;
        ``"spring"``: a tangential spring with a Coulomb limit (LIGGGHTS' ``tangential
        history``).
    regularisation_velocity
        v_reg of the tanh friction law [m/s] (default 0.01 m/s).
    min_impact_velocity
        Floor of the onset speed that sets the damping parameter [m/s] (default 0.01 m/s).
    reimpact_factor
        A persisting contact whose approach speed exceeds this factor times its stored impact
        speed is treated as a new impact (``d`` reset from the current speed); default 1.25,
        ``math.inf`` keeps the onset value for the whole contact (see
        :mod:`pdamper.dem.kernels`).
    """

    restitution_pp: RestitutionCurve
    restitution_pw: RestitutionCurve
    friction_pp: float
    friction_pw: float
    pairs: Mapping[tuple[str, str], RestitutionCurve] = field(default_factory=dict)
    damping_model: str = "exact"
    regularisation_velocity: float = DEFAULT_REGULARISATION_VELOCITY
    min_impact_velocity: float = DEFAULT_MIN_IMPACT_VELOCITY
    reimpact_factor: float = DEFAULT_REIMPACT_FACTOR
    friction_model: str = "regularised"

    def __post_init__(self) -> None:
        check_range("reimpact_factor", self.reimpact_factor, low=1.0, low_inclusive=False)
        check_range("friction_pp", self.friction_pp, low=0.0)
        check_range("friction_pw", self.friction_pw, low=0.0)
        check_range("regularisation_velocity", self.regularisation_velocity, low=0.0,
                    low_inclusive=False, unit="m/s")
        check_range("min_impact_velocity", self.min_impact_velocity, low=0.0,
                    low_inclusive=False, unit="m/s")
        if self.damping_model not in DAMPING_MODELS:
            raise InputError("damping_model", f"must be one of {', '.join(DAMPING_MODELS)}, "
                             f"got {self.damping_model!r}")
        if self.friction_model not in FRICTION_MODELS:
            raise InputError("friction_model", f"must be one of {', '.join(FRICTION_MODELS)}, "
                             f"got {self.friction_model!r}")
        for name in ("restitution_pp", "restitution_pw"):
            if not isinstance(getattr(self, name), RestitutionCurve):
                raise InputError(name, "must be a RestitutionCurve (e.g. ConstantRestitution)")

    def curve(self, a: str, b: str, wall: bool) -> RestitutionCurve:
        """COR curve of the material pair (a, b)."""
        for key, c in self.pairs.items():
            if {str(key[0]).lower(), str(key[1]).lower()} == {a.lower(), b.lower()}:
                return c
        return self.restitution_pw if wall else self.restitution_pp


