"""The damper interface shared by every fidelity, and its response type."""

from __future__ import annotations

import copy
import inspect
from abc import ABC, abstractmethod
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any, ClassVar

import numpy as np

from pdamper import resources
from pdamper.constants import STANDARD_GRAVITY
from pdamper.damper import ParticleDamper
from pdamper.errors import InputError


@dataclass(frozen=True)
class DamperResponse:
    """Response of a damper under harmonic vertical excitation ``x_c = X sin(2 pi f t)``.

    Attributes
    ----------
    frequency, amplitude
        f [Hz] and X [m], broadcast to the shape of the results.
    mode
        :class:`~pdamper.analysis.modes.MotionMode` codes [-] (-1: not classified).
    loss_factor
        Effective loss factor eta [-] (Eq. 3).
    dissipated_energy_per_cycle
        E~_diss [J] (Eq. 2).
    effective_mass_ratio
        Effective particle mass over bed mass [-] (Eq. 4 or Eq. 22).
    bed_mass
        m_bed [kg].
    details
        What the model computed on the way: the analytical
        :class:`~pdamper.analysis.analytical.BedResponse`, or for the DEM an object array of
        :class:`~pdamper.dem.DEMResult`, one per point (``details.item()`` for one point).
    stationary
        Whether each value is a steady state [-] (None: not assessed). The analytical
        formulas are steady by construction; a DEM run is steady when its averaged window
        passes :class:`~pdamper.analysis.stationarity.SteadyStateCriterion`.
    subharmonic_order
        ``n_s`` of Eqs. (12)/(18) [-] (-1 where undefined; None: not given).
    diagnostics
        Further per-point arrays of the shape of the results, by name (the DEM: wall time,
        steps, ledger error, largest overlap, cycles run, the averaged window, ...; object
        arrays hold the stationarity and mode-classification records).
    """

    frequency: np.ndarray
    amplitude: np.ndarray
    mode: np.ndarray
    loss_factor: np.ndarray
    dissipated_energy_per_cycle: np.ndarray
    effective_mass_ratio: np.ndarray
    bed_mass: float
    details: Any = field(default=None, repr=False, compare=False)
    stationary: np.ndarray | None = None
    subharmonic_order: np.ndarray | None = None
    diagnostics: dict[str, np.ndarray] = field(default_factory=dict, repr=False, compare=False)

    @property
    def effective_mass(self) -> np.ndarray:
        """Effective particle mass [kg]."""
        return self.effective_mass_ratio * self.bed_mass


#: The inputs that enter only through a contact law (friction and the coefficients of
#: restitution): a fidelity whose bed is one perfectly plastic block declares them unused.
CONTACT_LAW_INPUTS = ("particles.friction", "dem.restitution_pp", "dem.restitution_pw",
                      "restitution.particle_particle", "restitution.particle_wall")


class DamperModel(ABC):
    """A particle damper model of some fidelity.

    Subclasses implement :meth:`response` (Level II); ``coupling`` names the Level III
    strategy of :mod:`pdamper.coupling` that puts the model on a structure
    (``"pseudo_force"``: Sect. 4.1 models 2 and 3; ``"co_simulation"``: model 1).

    Parameters
    ----------
    damper
        The physical damper (container, spheres, materials).
    """

    #: Name of the fidelity (``"analytic"``, ``"fields"``, ``"dem"``).
    fidelity: ClassVar[str] = ""
    #: Name of the Level III coupling strategy.
    coupling: ClassVar[str] = "pseudo_force"
    #: Whether one ``response`` call evaluates a whole grid cheaply (closed forms); maps of
    #: other models run point by point on the sweep engine (:mod:`pdamper.sweep`).
    vectorised: ClassVar[bool] = False
    #: Whether one Level III run costs seconds or more (design studies then evaluate
    #: designs on parallel workers by default).
    expensive: ClassVar[bool] = False
    #: Whether the model resolves the contacts with the contact law (Hertz): its runs must
    #: also keep the Hertz contact radius below half the sphere radius
    #: (:data:`pdamper.resources.MAX_CONTACT_RADIUS_RATIO`).
    contact_law: ClassVar[bool] = False

    #: Whether the model takes ``gravity`` [m/s^2] as a keyword (a scenario passes its
    #: ``[excitation] gravity``).
    takes_gravity: ClassVar[bool] = False

    #: Inputs of a scenario this fidelity's answers do not depend on: field (as in
    #: ``--uncertain``, e.g. ``"particles.friction"``; a fitted COR curve by its field,
    #: ``"restitution.particle_wall"``) -> why. An uncertainty propagation reports them as
    #: not used by this fidelity, with the fidelities that do use them
    #: (:func:`pdamper.models.registry.input_users`), instead of a zero sensitivity.
    unused_inputs: ClassVar[Mapping[str, str]] = {}

    def __init__(self, damper: ParticleDamper):
        if not isinstance(damper, ParticleDamper):
            raise InputError("damper", f"must be a ParticleDamper (e.g. "
                             f"pdamper.parameters.PAPER_DAMPER), got {type(damper).__name__}")
        # spheres below 0.1 mm are a cohesive powder in every model: refused wherever a
        # model of any fidelity is made (a design study's candidate, the API)
        resources.check_particles(damper)
        self.damper = damper

    @property
    def bed_mass(self) -> float:
        """m_bed [kg]."""
        return self.damper.bed_mass

    def with_damper(self, damper: ParticleDamper) -> DamperModel:
        """The same model (same options) for another physical damper, e.g.
        ``model.with_damper(model.damper.with_count(64))`` for a particle-count sweep."""
        if not isinstance(damper, ParticleDamper):
            raise InputError("damper", f"must be a ParticleDamper, got {type(damper).__name__}")
        resources.check_particles(damper)
        new = copy.copy(self)
        new.damper = damper
        return new

    def check_excitation(self, frequency, amplitude) -> None:
        """Refuse harmonic excitations ``X sin(2 pi f t)`` outside the physics limits of a
        run of this model (:func:`pdamper.resources.check_grid`: strokes, impact speeds,
        the contact frequency and, with :attr:`contact_law`, Hertz's law), judged at the
        fastest frequency with the largest and smallest stroke of the arrays given; what is
        not a positive finite number is left to the model's own checks."""
        f = np.asarray(frequency, float).ravel()
        x = np.abs(np.asarray(amplitude, float).ravel())
        f, x = f[np.isfinite(f) & (f > 0)], x[np.isfinite(x) & (x > 0)]
        if f.size and x.size:
            resources.check_grid(self.damper, (float(f.min()), float(f.max())),
                                 (float(x.min()), float(x.max())),
                                 fields=("frequency", "amplitude"),
                                 contact_law=self.contact_law,
                                 gravity=getattr(self, "gravity", STANDARD_GRAVITY))

    # -- parameters, scikit-learn style -------------------------------------------------
    def get_params(self) -> dict[str, Any]:
        """The parameters of the model by name (those of its constructor), e.g. to rebuild
        it: ``type(m)(**m.get_params())``."""
        names = [p for p in inspect.signature(type(self).__init__).parameters
                 if p != "self"]
        return {name: getattr(self, name) for name in names}

    def clone(self, **changes: Any) -> DamperModel:
        """A new model of the same fidelity with ``changes`` to :meth:`get_params`,
        checked as at construction."""
        return type(self)(**{**self.get_params(), **changes})

    # -- what a run costs and needs: asked of the fidelity, never branched on its name ----
    @classmethod
    def excitation_cost(cls, damper: ParticleDamper, frequency: float, amplitude: float,
                        settings: Any = None, *, gravity: float = STANDARD_GRAVITY,
                        usual: tuple[float, float] = (10.0, 0.032),
                        fields: tuple[str, str] = ("excitation.frequency",
                                                   "excitation.amplitude"),
                        damper_drivers: Sequence[tuple] = ()) -> resources.Cost | None:
        """What one Level II response at f [Hz], X [m] costs with ``settings`` (the
        fidelity's section of a scenario, or its settings object); None where it is not
        worth judging (closed forms). Refuses what the fidelity's physics cannot run
        (e.g. the DEM's contact law). ``usual``: the usual (f, X); ``damper_drivers``: the
        damper's inputs and their ratios to their usual values, counted where the
        fidelity's cost depends on them (:class:`pdamper.resources.Cost`)."""
        return None

    @classmethod
    def map_cost(cls, damper: ParticleDamper, frequency: tuple[float, float, int],
                 amplitude: tuple[float, float, int], points: float, settings: Any = None, *,
                 gravity: float = STANDARD_GRAVITY, usual: tuple[float, float] = (10.0, 0.032),
                 axes: Sequence[tuple] = (),
                 damper_drivers: Sequence[tuple] = ()) -> resources.Cost:
        """What a Level II map over ``frequency`` and ``amplitude`` (``(start, stop,
        count)``, [Hz] and [m]) of ``points`` points costs (``axes``: the grid's drivers);
        by default a vectorised evaluation of the grid."""
        return resources.analytic_map_cost(points, axes)

    @classmethod
    def free_vibration_cost(cls, damper: ParticleDamper, duration: float, sample_rate: float,
                            natural_frequency: float, settings: Any = None, *,
                            x0: float = 0.0, drivers: Sequence[tuple] = (),
                            damper_drivers: Sequence[tuple] = (),
                            count: int | None = None) -> resources.Cost:
        """What a Level III free vibration of ``duration`` [s] sampled at ``sample_rate``
        [Hz] of a structure of ``natural_frequency`` [Hz] released from ``x0`` [m] costs
        (``drivers``: the run's inputs; ``count``: judged at this particle count, e.g. the
        mean of a design study's candidates); by default a pseudo-force run (one damper
        update per cycle, whatever the damper)."""
        return resources.pseudo_force_cost(duration, sample_rate, natural_frequency, drivers)

    @abstractmethod
    def response(self, frequency, amplitude) -> DamperResponse:
        """Response under harmonic excitation with frequency f [Hz] and stroke X [m]."""

    def __repr__(self) -> str:
        return f"{type(self).__name__}(count={self.damper.count})"
