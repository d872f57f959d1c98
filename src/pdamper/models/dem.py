"""The DEM damper model (the paper's model 1, Sects. 3 and 4.1).

Level II: :meth:`DEMDamper.response` runs the DEM under harmonic container motion until the
loss factor is steady (or for the paper's fixed eight cycles), applies the complex power
method (Eqs. 1-4) over the averaged window and classifies the motion mode; the runs travel
in the response's ``details``, the steady-state evidence and the modes in its
``diagnostics``. Level III: the ``"co_simulation"`` strategy of :mod:`pdamper.coupling`
integrates the structure together with the particles through :meth:`DEMDamper.engine`.
"""

from __future__ import annotations

import dataclasses
import inspect
import logging
import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from pdamper import resources
from pdamper.analysis.dem_modes import BedSignals, ModeClassification, classify_motion
from pdamper.analysis.modes import MotionMode
from pdamper.analysis.stationarity import (
    Stationarity,
    cycle_loss_factors,
    cycle_symmetry,
    whole_cycles,
)
from pdamper.constants import STANDARD_GRAVITY
from pdamper.contact.law import ContactParameters, check_integrator_for
from pdamper.damper import ParticleDamper
from pdamper.dem.settings import (  # noqa: F401 - the lattice's rule, importable from here too
    LATTICE_GEAR_TOLERANCE,
    EngineSettings,
    gear_tolerance_for,
)
from pdamper.errors import InputError, check_range
from pdamper.models.base import DamperModel, DamperResponse
from pdamper.models.settings import (  # noqa: F401 - the defaults, importable from here too
    AUTO,
    DEFAULT_ACCURACY,
    DEFAULT_CYCLES,
    DEFAULT_MAX_CYCLES,
    DEFAULT_MAX_REFINEMENTS,
    DEFAULT_SAMPLE_RATE,
    DEFAULT_SKIP_CYCLES,
    DEFAULT_TRANSIENT_TOLERANCE,
    PACKINGS,
    PAPER_CYCLES,
    AccuracyTarget,
    ContactLaw,
    DEMSettings,
    FlatSettings,
    RunPlan,
    SteadyState,
)

if TYPE_CHECKING:
    from pdamper.analysis.complex_power import ComplexPowerResult
    from pdamper.dem.result import DEMResult

logger = logging.getLogger(__name__)
#: Share of the lattice's count up to which ``packing = "auto"`` starts from a random bed
#: (dense random beds grow for every seed tried at 90 % of it in tall, flat and cubic boxes;
#: docs/dem.md), the lattice above.
AUTO_RANDOM_SHARE = 0.9

#: Motion-mode code of a point without a mode (kept for callers of the first DEM model).
UNCLASSIFIED = -1



#: Loss factor below which the accuracy is absolute: solid-like points have eta ~ 0 [-].
LOSS_FACTOR_FLOOR = 0.05
#: The refined companion run of the error estimate: Gear's tolerance divided by 10 (its
#: error-per-unit-step control makes the global error proportional to the tolerance), or
#: Verlet's safety factor halved (second order: a quarter of the error); "auto" refines the
#: integrator that ran most of the excitation (Verlet once Gear handed over).
REFINEMENT = {"gear": ("gear_tolerance", 10.0), "verlet": ("safety", 2.0)}
#: Error estimate = |default - refined| / (1 - ERROR_REDUCTION). The asymptotic reductions
#: are 0.1 (Gear) and 0.25 (Verlet); 0.5 assumes only that the refined run's error is at
#: most half the default's, which holds outside the asymptotic range too (the verification
#: table of docs/verification.md checks the bound against converged runs).
ERROR_REDUCTION = 0.5
#: Largest move of each sphere of the settled bed [m] of the error estimate's realisation
#: companion (vertical, uniform, seeded by the run's seed; made after the settling, which
#: would undo it in the lattice): far below any integration error,
#: it changes a reproducible point by < 0.2 % and a chaotic one by 3-40 % (docs/verification.md).
REALISATION_MOVE = 1e-9

#: Settled beds a process keeps, the least recently used dropped first: a map's model and
#: the refined companions of its error estimate, a particle-count axis.
MAX_BEDS = 8
#: The cache itself: a memo of a deterministic function of the key (not state: a model
#: pickled to a sweep's worker finds the bed its process settled for an earlier point).
_BEDS: dict = {}
#: Keys of the kept beds whose settling a run has counted as its own
#: (:meth:`DEMDamper.claim_settling`): a later run of this process from the same bed
#: reused it. A command starts it afresh (:func:`reset_settling_claims`).
_COUNTED: set = set()


def reset_settling_claims() -> None:
    """Start the counting of settlings afresh: a command's first run from a kept bed then
    counts its settling, as the same command in a process of its own would (its output
    does not depend on the commands run before it in the process)."""
    _COUNTED.clear()
#: Level II runs settle for the free fall over the container height plus this [s] (the
#: engine's default adds SETTLE_EXTRA, 0.05 s). After the default, a random bed of the paper's damper still
#: moves at ~6 cm/s (kinetic energy 2.8e-4 J, 32 spheres) and creeps down through the
#: averaged window of solid-like cells (8 Hz / 2 mm: eta -1.1e-3, bed height range 0.5 mm,
#: classified scattering although A = 0.26 g; 2 Hz / 1 mm: eta -7.9e-4). Settling 0.25 /
#: 0.45 / 0.85 s longer leaves 2.6e-6 / 1.1e-7 / 4.6e-11 J and eta 8.6e-6 / -1.2e-4 /
#: -1.0e-5 there (solid-like). Over packings (seeds 0-5, friction-cap floor 5) the
#: default leaves 2.9e-4 - 5.6e-4 J and this 1e-20 - 4.7e-7 J; a bed at rest can still
#: compact under the shaking through the regularised friction (one packing of five: eta
#: -1.1e-3, lift 0.2 mm at 8 Hz / 2 mm, solid-like all the same). The bed is settled once
#: per process and shared by every point (SettledBed, _BEDS): ~1.4 s of CPU per worker.
LEVEL2_SETTLE_EXTRA = 1.0


#: Fewest cycles in each half of an averaged window whose motion modes must agree.
MIN_HALF_WINDOW = 3


@dataclass(frozen=True)
class SteadyRun:
    """One Level II DEM run with what Eqs. (1)-(4) and the classifier made of it.

    Attributes
    ----------
    result
        The :class:`~pdamper.dem.DEMResult`, covering the cycles the run needed.
    stationarity
        The steady-state verdict on the averaged window.
    motion
        The motion mode over the same window.
    power
        :class:`~pdamper.analysis.complex_power.ComplexPowerResult` over the window.
    packing
        The initial packing the run started from (``"lattice"`` or ``"random"``).
    accuracy
        The :class:`AccuracyEstimate` (None unless the model estimates it).
    """

    result: DEMResult
    stationarity: Stationarity
    motion: ModeClassification
    power: ComplexPowerResult
    packing: str = "lattice"
    accuracy: AccuracyEstimate | None = None

    @property
    def skip_cycles(self) -> int:
        """Cycles before the averaged window [-]."""
        return self.stationarity.first_cycle - 1

    @property
    def window_cycles(self) -> int:
        """Cycles in the averaged window [-]."""
        return self.stationarity.last_cycle - self.stationarity.first_cycle + 1


def error_bound(value: float, refined: float, reduction: float = ERROR_REDUCTION) -> float:
    """Bound of the integration error of ``value`` from a refined run's ``refined``:
    ``|value - refined| / (1 - reduction)``, valid where the refined run's error is at most
    ``reduction`` times the default's (:data:`ERROR_REDUCTION`).

    >>> error_bound(1.02, 1.01)
    0.02...
    """
    if not 0.0 <= reduction < 1.0:
        raise InputError("reduction", f"must be in [0, 1), got {reduction!r}")
    return abs(value - refined) / (1.0 - reduction)


@dataclass(frozen=True)
class AccuracyEstimate:
    """Estimated integration error of a Level II DEM run, from a refined companion run over
    the same cycles and averaged window (Richardson's idea: the difference of two runs whose
    errors differ by a known factor bounds the larger error, :func:`error_bound`).

    Attributes
    ----------
    loss_factor_error, effective_mass_ratio_error
        Bounds of the absolute errors of eta and m_eff / m_bed [-].
    relative_error
        The larger of ``loss_factor_error / max(|eta|, LOSS_FACTOR_FLOOR)`` and
        ``effective_mass_ratio_error / |m_eff / m_bed|`` [-].
    target
        The accuracy asked for [-]; ``met``: ``relative_error <= target``.
    setting, value, reference
        The refined setting (``"gear_tolerance"`` or ``"safety"``), its value in the
        reported run and in the companion run [-].
    refinements
        How many times the run was redone refined because the estimate missed the target.
    reference_loss_factor, reference_effective_mass_ratio
        The companion run's values [-].

    loss_factor_spread, effective_mass_ratio_spread
        How far the run moves when every sphere of the settled bed is moved up or down by
        up to :data:`REALISATION_MOVE` (1e-9 m), at the same settings [-]: the spread of the
        realisations of the point, next to the integration error. Where it exceeds the
        target (``realisation_dependent``) the state the run ends in depends on the
        transient or the realisation, not on the step: a converged run of the same inputs
        may end in another state, so ``met`` is false and the run is not refined (a finer
        step would not make it an answer to the target; an ensemble of random packings
        does, ``pdamper dem --realisations N``).

    The refined companion refines the whole run, the start from rest included (no transient
    tolerance), so the error covers the state the transient chose.
    """

    loss_factor_error: float
    effective_mass_ratio_error: float
    relative_error: float
    target: float
    met: bool
    setting: str
    value: float
    reference: float
    refinements: int
    reference_loss_factor: float
    reference_effective_mass_ratio: float
    loss_factor_spread: float = 0.0
    effective_mass_ratio_spread: float = 0.0
    realisation_dependent: bool = False


def _relative(eta: float, ratio: float, d_eta: float, d_mass: float) -> float:
    """The larger of ``d_eta / max(|eta|, LOSS_FACTOR_FLOOR)`` and ``d_mass / |ratio|``."""
    return max(d_eta / max(abs(eta), LOSS_FACTOR_FLOOR),
               d_mass / abs(ratio) if ratio != 0 else math.inf)


def truncate_result(result, cycles: int):
    """The first ``cycles`` whole cycles of a harmonic :class:`~pdamper.dem.DEMResult`
    (counters such as ``steps`` and ``wall_seconds`` still describe the whole run)."""
    t_end = cycles / result.frequency
    n = int(np.searchsorted(result.time, t_end * (1.0 + 1e-12) + 1e-12, side="right"))
    q = int(np.searchsorted(result.snapshot_time, t_end * (1.0 + 1e-12) + 1e-12, side="right"))
    series = {f.name: getattr(result, f.name)[:n] for f in dataclasses.fields(result)
              if isinstance(getattr(result, f.name), np.ndarray)
              and not f.name.startswith("snapshot") and f.name not in ("radius", "masses")}
    snaps = {f.name: getattr(result, f.name)[:q] for f in dataclasses.fields(result)
             if f.name.startswith("snapshot")}
    return dataclasses.replace(result, **series, **snaps)


class DEMDamper(FlatSettings, DamperModel):
    """Particle damper simulated by the discrete element method.

    Parameters
    ----------
    damper
        Container, spheres and materials; its ``friction`` and COR curves
        (``restitution_pp``, ``restitution_pw``) set the contact law.
    settings
        :class:`~pdamper.models.settings.DEMSettings` (default: its defaults): all five
        concerns in one object.
    plan, steady, accuracy, contact, engine
        The concerns (:class:`~pdamper.models.settings.RunPlan`,
        :class:`~pdamper.models.settings.SteadyState`,
        :class:`~pdamper.models.settings.AccuracyTarget`,
        :class:`~pdamper.models.settings.ContactLaw`,
        :class:`~pdamper.dem.settings.EngineSettings`), each declared once in
        :mod:`pdamper.models.settings` and :mod:`pdamper.dem.settings` with its unit, range
        and meaning; the model's typed attributes of the same names (``model.engine.
        gear_tolerance``). ``accuracy`` given as a number is the target
        (``AccuracyTarget.accuracy``).
    **changes
        Settings by flat name (``cycles=8``, ``integrator="verlet"``: aliases of
        ``plan.cycles``, ``engine.integrator``) or as ``concern__name``
        (``engine__gear_tolerance=1e-6``), replacing those of ``settings``; read back through
        the concern (``model.plan.cycles``) or the typed read-only ``model.cycles``.

    A Level II run goes on until the loss factor is steady (``cycles = "auto"``, at most
    ``max_cycles``) or runs ``cycles`` cycles (the paper: 8) and still records whether the
    averaged window was steady; ``error_estimate`` adds a refined companion run
    (:class:`AccuracyEstimate`); ``transient_tolerance`` is the Gear tolerance of the
    cycles every averaged window skips (the first ``min(skip_cycles,
    quiet_skip_cycles)``, :data:`DEFAULT_TRANSIENT_TOLERANCE`); ``settle_time`` None
    settles for the free fall over the container height plus
    :data:`LEVEL2_SETTLE_EXTRA`.

    Examples
    --------
    >>> from pdamper.parameters import PAPER_DAMPER
    >>> DEMDamper(PAPER_DAMPER, integrator="verlet", cycles=3, skip_cycles=1)
    DEMDamper(count=32, integrator='verlet', packing='lattice')
    """

    fidelity = "dem"
    takes_gravity = True
    coupling = "co_simulation"
    expensive = True
    contact_law = True

    def __init__(self, damper: ParticleDamper, settings: DEMSettings | None = None, *,
                 plan: RunPlan | None = None, steady: SteadyState | None = None,
                 accuracy: AccuracyTarget | float | None = None,
                 contact: ContactLaw | None = None, engine: EngineSettings | None = None,
                 **changes: Any):
        super().__init__(damper)
        given = {"plan": plan, "steady": steady, "accuracy": accuracy, "contact": contact,
                 "engine": engine}
        changes = {**{k: v for k, v in given.items() if v is not None}, **changes}
        unknown = sorted(k for k in changes if k not in _KEYWORDS and "__" not in k)
        if unknown:
            raise TypeError(f"DEMDamper() got an unexpected keyword argument {unknown[0]!r}")
        if settings is None:
            settings = DEMSettings(**changes)
        elif not isinstance(settings, DEMSettings):
            raise InputError("settings", f"must be a DEMSettings, got {type(settings).__name__}")
        elif changes:
            settings = settings.clone(**changes)
        #: The settings (checked on their construction), by concern below.
        self.settings = settings
        s = settings
        self.plan = s.plan
        self.steady = s.steady
        self.accuracy = s.accuracy
        self.contact = s.contact
        self.engine = s.engine
        #: The steady-state criterion of the runs (:meth:`SteadyState.criterion`).
        self.criterion = s.steady.criterion(s.skip_cycles)
        if s.cycles == AUTO:
            if s.max_cycles < self.criterion.full_cycles:
                raise InputError("dem.max_cycles", f"must be >= skip_cycles + steady_windows x "
                                 f"window_cycles = {self.criterion.full_cycles}, got "
                                 f"{s.max_cycles}")
        elif s.skip_cycles >= int(s.cycles):  # a whole number here (not AUTO)
            raise InputError("dem.skip_cycles", f"must be in [0, {int(s.cycles) - 1}] for "
                             f"{s.cycles} cycles, got {s.skip_cycles}")
        friction, cor_pp, cor_pw = damper.friction, damper.restitution_pp, damper.restitution_pw
        if friction is None or cor_pp is None or cor_pw is None:
            name = ("friction" if friction is None
                    else "restitution_pp" if cor_pp is None else "restitution_pw")
            raise InputError(f"particles.{name}", "the DEM needs the friction coefficient "
                             "and the COR curves of the damper (ParticleDamper.friction, "
                             ".restitution_pp, .restitution_pw)")
        try:
            #: The contact law of the engine (the damper's CORs and friction with ``contact``).
            self.contact_parameters = ContactParameters(restitution_pp=cor_pp, restitution_pw=cor_pw,
                                             friction_pp=friction, friction_pw=friction,
                                             damping_model=s.damping_model,
                                             min_impact_velocity=s.min_impact_velocity,
                                             friction_model=s.friction_model)
        except InputError as exc:  # name the field as the [dem] section does
            raise InputError(f"dem.{exc.field}", exc.message) from None
        check_integrator_for(s.friction_model, s.integrator, "dem.integrator")

    def get_params(self, deep: bool = False) -> dict[str, Any]:
        """The damper and the five concerns by name; ``deep``: also every setting as
        ``concern__name`` (scikit-learn's ``engine__gear_tolerance``)."""
        return {"damper": self.damper, **self.settings.get_params(deep)}

    def set_params(self, **changes: Any) -> DEMDamper:
        """The settings replaced by ``changes`` (concerns, flat names or ``concern__name``),
        in place as scikit-learn's ``set_params``; returns the model."""
        new = self.clone(**changes)
        self.__dict__.update(new.__dict__)
        return self

    def clone(self, **changes: Any) -> DEMDamper:
        """A copy with ``changes`` (``damper`` and settings by name), checked as at
        construction."""
        damper = changes.pop("damper", self.damper)
        return type(self)(damper, self.settings.clone(**changes) if changes else self.settings)

    # ------------------------------------------------------------------ cost
    @staticmethod
    def _run_bound(settings) -> tuple[int, str]:
        """Cycles a Level II run lasts at most, and the setting that says so."""
        if settings.cycles == AUTO:
            return settings.max_cycles, "dem.max_cycles"
        return settings.cycles, "dem.cycles"

    @staticmethod
    def settings_drivers(settings) -> list[tuple]:
        """The settings that drive a run's cost, and their ratios to their defaults."""
        d = DEMSettings()
        return [("dem.safety", d.safety / settings.safety, True),
                ("dem.sample_rate", settings.sample_rate / d.sample_rate),
                ("dem.snapshot_rate", (settings.snapshot_rate or 0.0) / d.sample_rate)]

    @classmethod
    def excitation_cost(cls, damper, frequency, amplitude, settings=None, *,
                        gravity=STANDARD_GRAVITY, usual=(10.0, 0.032),
                        fields=("excitation.frequency", "excitation.amplitude"),
                        damper_drivers=()):
        """One Level II run (at most ``max_cycles`` cycles until steady, else ``cycles``),
        its settling included; refuses impacts beyond Hertz's law."""
        settings = DEMSettings() if settings is None else settings
        imp = resources.check_motion(damper, frequency, amplitude, fields=fields, usual=usual,
                                     contact_law=cls.contact_law, gravity=gravity)
        cycles, field = cls._run_bound(settings)
        # (name, ratio to its usual value[, whether lowering it raises the cost])
        drivers: list[tuple] = [(field, cycles / cls._run_bound(DEMSettings())[0]),
                                (fields[0], usual[0] / frequency, True), *damper_drivers,
                                *cls.settings_drivers(settings)]
        return resources.dem_cost(
            damper, cycles / frequency, imp.speed, sample_rate=settings.sample_rate,
            safety=settings.safety, snapshot_rate=settings.snapshot_rate, frequency=frequency,
            gravity=gravity, drivers=drivers)

    @classmethod
    def map_cost(cls, damper, frequency, amplitude, points, settings=None, *,
                 gravity=STANDARD_GRAVITY, usual=(10.0, 0.032), axes=(), damper_drivers=()):
        """A DEM run per point: the mean over a sample of the grid (a point costs more at low
        frequency, more time per cycle), scaled to ``points``; refuses a grid beyond
        Hertz's law."""
        (f0, f1, nf), (x0, x1, nx) = frequency, amplitude
        resources.check_grid(damper, (f0, f1), (x0, x1), usual=usual,
                             contact_law=cls.contact_law, gravity=gravity)
        fs, xs = np.linspace(f0, f1, min(nf, 8)), np.linspace(x0, x1, min(nx, 8))
        costs = [cls.excitation_cost(damper, f, x, settings, gravity=gravity, usual=usual,
                                     fields=("map.frequency", "map.amplitude"),
                                     damper_drivers=damper_drivers)
                 for f in fs for x in xs]
        seconds = float(np.mean([c.seconds for c in costs])) * points
        worst = max(costs, key=lambda c: (c.seconds, c.memory))
        rest = tuple(d for d in worst.drivers if not d[0].startswith("map."))
        return resources.Cost(
            "the DEM map", seconds, max(c.memory for c in costs),
            f"{points:.3g} DEM runs, the longest {worst.detail}", tuple(axes) + rest,
            runs=int(min(points, 2**62)), longest=worst.seconds)

    @classmethod
    def free_vibration_cost(cls, damper, duration, sample_rate, natural_frequency,
                            settings=None, *, x0=0.0, drivers=(), damper_drivers=(),
                            count=None):
        """The DEM integrated with the structure (co-simulation) over ``duration``, its
        time growing with the particle count; refuses a release whose impacts are beyond
        Hertz's law."""
        settings = DEMSettings() if settings is None else settings
        imp = resources.check_release(damper, natural_frequency, x0,
                                      contact_law=cls.contact_law)
        return resources.dem_cost(
            damper if count is None else damper.with_count(count), duration, imp.speed,
            sample_rate=sample_rate, safety=settings.safety,
            drivers=[*drivers, *damper_drivers, *cls.settings_drivers(settings)],
            what="the DEM free vibration")

    @property
    def run_until_steady(self) -> bool:
        """Whether Level II runs go on until the loss factor is steady."""
        return self.cycles == AUTO

    # ------------------------------------------------------------------ set-up
    def build_engine(self, motion, **override):
        """The :class:`pdamper.dem.DEMEngine` of this damper under ``motion``; ``override``:
        engine settings that replace the model's (e.g. ``reference_velocity``)."""

        return self._engine(self._particles()[1], motion, **override)

    def _engine(self, particles, motion, **override):
        """The engine; ``override``: engine settings that replace the model's (the refined
        companion runs of the error estimate, the settling and start of Level II runs)."""
        from pdamper.dem import Container, DEMEngine

        d = self.damper
        return DEMEngine(particles, Container(d.box, d.wall_material, d.container_mass),
                         self.contact_parameters, motion,
                         self.engine.clone(seed=self.seed, **override))

    def gear_tolerance_for(self, packing: str) -> float:
        """The Gear tolerance of a Level II run from ``packing``: ``engine.gear_tolerance``,
        or where that is None (the default) the declaration's rule by the start
        (:func:`~pdamper.dem.settings.gear_tolerance_for`: 1e-9 from the lattice, 1e-5 from
        a random bed)."""
        return gear_tolerance_for(self.engine.gear_tolerance, packing)

    def _transient(self, packing: str) -> dict:
        """Engine options of the start from rest of a Level II run from ``packing``: from a
        random bed ``transient_tolerance`` over the cycles every averaged window skips; from
        the lattice no transient tolerance, and Gear's tolerance of the start where
        ``engine.gear_tolerance`` is left to the declaration (None; the engine resolves
        None itself for every other start: :meth:`gear_tolerance_for`)."""
        if packing == "lattice":
            # the lattice is integrated converged throughout (LATTICE_GEAR_TOLERANCE)
            return ({"gear_tolerance": self.gear_tolerance_for(packing)}
                    if self.engine.gear_tolerance is None else {})
        tol: dict = {}
        # the same cycles however the run is judged: a run of the paper's 8 cycles, one
        # until steady and one with the rule for quiet beds off follow the same trajectory
        skip = min(self.skip_cycles, self.criterion.quiet_skip_cycles)
        if self.transient_tolerance is None or skip == 0:
            return tol
        return {**tol, "transient_cycles": skip,
                "gear_transient_tolerance": self.transient_tolerance}

    def protocol(self, packing: str | None = None) -> dict:
        """What a Level II run from ``packing`` (default :meth:`initial_packing`) does: the
        start (``"lattice"`` or ``"random"``, with the seed of a random one), the integrator,
        Gear's tolerance, the transient tolerance and its cycles (0: none), the safety
        factor and whether Gear's free flights are on (``pdamper dem --json``'s
        ``protocol``). ``gear_tolerance`` is the tolerance the declaration gives this start
        (:meth:`gear_tolerance_for`). A setting that does not act in this run is null, and
        ``not_applicable`` says why: the seed of a lattice start, Gear's tolerance under
        ``integrator = "verlet"`` (fixed steps), a transient tolerance where there is none."""
        packing = packing or self.initial_packing()
        opts = {"gear_tolerance": self.gear_tolerance_for(packing), **self._transient(packing)}
        gear = self.integrator != "verlet"
        transient = (float(opts["gear_transient_tolerance"])
                     if gear and "gear_transient_tolerance" in opts else None)
        why = {}
        if packing != "random":
            why["seed"] = "the lattice start draws no random numbers"
        if not gear:
            why["gear_tolerance"] = "integrator verlet takes fixed steps: no Gear step control"
        if transient is None:
            why["transient_tolerance"] = (
                "integrator verlet takes fixed steps" if not gear else
                "from the lattice Gear keeps one tolerance throughout (no transient)"
                if packing != "random" else "no transient tolerance set")
        return {"start": packing, "seed": self.seed if packing == "random" else None,
                "integrator": self.integrator,
                "gear_tolerance": float(opts["gear_tolerance"]) if gear else None,
                "not_applicable": why,
                "transient_tolerance": transient,
                "transient_cycles": int(opts.get("transient_cycles", 0)) if gear else 0,
                "safety": float(self.safety),
                "free_flight": bool(self.gear_free_flight) if gear else False}

    def _level2_settling(self) -> dict:
        """The settling of Level II runs (:data:`LEVEL2_SETTLE_EXTRA`), unless the settings
        give ``settle_time``."""
        from pdamper.dem.simulation import free_fall_settling

        if self.settle_time is not None:
            return {}
        return {"settle_time": free_fall_settling(self.damper.box[2], self.gravity,
                                                  LEVEL2_SETTLE_EXTRA)}

    @staticmethod
    def _settled(engine):
        """The settled bed ``engine`` starts from: settled once per process for its
        particles, container, contact law and step settings (the key), then shared by every
        frequency and amplitude (the settling does not depend on them; a run from the bed is
        bit-identical to one that settles by itself: :class:`pdamper.dem.SettledBed`)."""
        key = engine.settle_key
        bed = _BEDS.pop(key, None)
        if bed is None:
            bed = engine.settle()
            _COUNTED.discard(key)  # settled now: no run has counted it yet
        _BEDS[key] = bed  # most recent last
        while len(_BEDS) > MAX_BEDS:
            _BEDS.pop(next(iter(_BEDS)))
        return bed

    def initial_packing(self) -> str:
        """The packing the runs start from: ``"lattice"`` or ``"random"`` (``"auto"``
        resolved for this damper and seed)."""
        return self._particles()[0]

    def _particles(self):
        from pdamper.dem import ParticleSet

        d = self.damper
        if d.count < 1:
            raise InputError("particles.count", "the DEM model needs at least 1 particle")
        # "auto" starts from the lattice beyond AUTO_RANDOM_SHARE of its count: below it
        # the dense random bed packs for every seed tried (docs/dem.md), above it a growth
        # that jams costs seconds before its refusal, and seeds of one damper could start
        # some random and some from the lattice
        auto_random = d.count <= AUTO_RANDOM_SHARE * d.max_count
        if self.packing == "random" or (self.packing == "auto" and auto_random):
            try:
                return "random", ParticleSet.random(d.count, d.box, d.particle_radius,
                                                    d.particle_material, seed=self.seed)
            except InputError as exc:
                if self.packing == "random" or exc.field != "particles.count":
                    raise
                logger.info("packing auto: %s; starting from the lattice", exc.message)
        return "lattice", ParticleSet.lattice(d.count, d.box, d.particle_radius,
                                              d.particle_material)

    # ------------------------------------------------------------------ Level II
    def run(self, frequency: float, amplitude: float):
        """One DEM run at f [Hz], X [m]: ``cycles`` cycles, or until steady (``"auto"``);
        the :class:`~pdamper.dem.DEMResult`."""
        return self.steady_run(frequency, amplitude).result

    def steady_run(self, frequency: float, amplitude: float) -> SteadyRun:
        """One Level II run at f [Hz], X [m] with its stationarity, motion mode and complex
        power over the averaged window (:class:`SteadyRun`)."""
        f = check_range("frequency", frequency, low=0.0, low_inclusive=False, unit="Hz")
        x = check_range("amplitude", amplitude, low=0.0, low_inclusive=False, unit="m")
        # what no run can do (more memory than the machine has, months of computing); the
        # edges (scenario, command line) hold runs to the lower limits unless forced
        d = self.damper
        cycles = self.max_cycles if self.run_until_steady else int(self.cycles)
        drivers: tuple[tuple, ...] = (
            ("dem.max_cycles" if self.run_until_steady else "dem.cycles", cycles),
            ("frequency", 1.0 / f, True), ("dem.sample_rate", self.sample_rate / f))
        resources.require(resources.dem_cost(
            d, cycles / f, resources.impact_speed(x, f, d.length), frequency=f,
            sample_rate=self.sample_rate, safety=self.safety, snapshot_rate=self.snapshot_rate,
            drivers=drivers), force=True)
        packing, particles, engine = self._point_engine(f, x)
        if self.run_until_steady:
            need = self.criterion.min_cycles

            def steady(part) -> bool:
                return (whole_cycles(part.time, f) >= need
                        and self.assess(part)[0].stationary)

            # the engine asks after every whole cycle: the run ends at the first steady one
            res = engine.run(self.max_cycles / f, sample_rate=self.sample_rate,
                             snapshot_rate=self.snapshot_rate, stop=steady,
                             start=self._settled(engine))
        else:
            res = engine.run(int(self.cycles) / f, sample_rate=self.sample_rate,
                             snapshot_rate=self.snapshot_rate, start=self._settled(engine))
        st, motion = self.assess(res)
        power = res.complex_power(st.first_cycle - 1, st.last_cycle - st.first_cycle + 1)
        run = SteadyRun(res, st, motion, power, packing)
        return self._estimate(run, particles, f, x) if self.error_estimate else run

    def _point_engine(self, f: float, x: float):
        """``(packing, particles, engine)`` of the Level II run at f [Hz], X [m]."""
        from pdamper.dem import HarmonicMotion

        packing, particles = self._particles()
        engine = self._engine(particles, HarmonicMotion(amplitude=x, frequency=f),
                              **self._level2_settling(), **self._transient(packing))
        return packing, particles, engine

    def settled_bed(self, frequency: float, amplitude: float):
        """The :class:`~pdamper.dem.SettledBed` the run at f [Hz], X [m] started from, as
        this process keeps it (None when it is not kept): its ``steps`` and ``seconds``
        [s] are what settling it cost, which a run that started from the kept bed
        (``settle_reused``) did not count in its own."""
        return _BEDS.get(self._point_engine(float(frequency), float(amplitude))[2].settle_key)

    def claim_settling(self, frequency: float, amplitude: float):
        """The kept bed the run at f [Hz], X [m] started from, if no earlier run of this
        process counted its settling (the bed was settled for this run; the claim marks
        it counted), else None (the run reused a bed an earlier run settled)."""
        key = self._point_engine(float(frequency), float(amplitude))[2].settle_key
        bed = _BEDS.get(key)
        if bed is None or key in _COUNTED:
            return None
        _COUNTED.add(key)
        return bed

    def _estimate(self, run: SteadyRun, particles, f: float, x: float) -> SteadyRun:
        """:class:`AccuracyEstimate` of ``run``: a realisation companion (the spheres of the
        settled bed moved up or down by up to :data:`REALISATION_MOVE`, same settings) gives
        the spread of the point; refined companion runs over the same cycles, refined from
        the start (no transient tolerance), give the integration error; a run missing the
        target on the latter alone is replaced by its refined companion, at most
        ``max_refinements`` times."""
        from pdamper.dem import HarmonicMotion

        kernel = self.integrator
        if kernel == "auto":
            res = run.result
            kernel = "verlet" if res.verlet_time > 0.5 * res.simulated_time else "gear"
        setting, factor = REFINEMENT[kernel]
        start = self._transient(run.packing)
        value = (self.safety if setting == "safety" else self.gear_tolerance_for(run.packing))
        # the refined companions refine the start from rest too: the transient tolerance
        # would otherwise steer both runs into the same state (8 Hz / 80 mm from the
        # lattice: error 0.001 reported where converged runs differ by 0.3)
        refined = {k: v for k, v in start.items()
                   if k not in ("transient_cycles", "gear_transient_tolerance")}
        motion = HarmonicMotion(amplitude=x, frequency=f)
        st = run.stationarity
        skip, span = st.first_cycle - 1, st.last_cycle - st.first_cycle + 1
        # the realisation companion: same settings, every sphere of the settled bed moved up
        # or down by up to 1e-9 m. After the settling: a move before it is undone by it where
        # the bed settles into one state (the lattice's 16 columns settle back to the same
        # heights, and the companion repeated the run: 10 Hz / 10 mm, Tsuji's law, eta spread
        # 0.0006 where a 1e-9 m move of the settled bed gives 0.259-0.278 against 0.299).
        # Vertical only: a sideways move of the settled lattice pushes spheres that touch
        # their neighbours and the walls at zero overlap 1e-9 m into them, a kick of ~1 mN
        # each, which broke the ordered state of 10 Hz / 32 mm (exact law, eta 0.938 and
        # m_eff/m_bed 1.924 moved by 0.12-0.14 and 0.56-0.70 over three seeds), which a
        # vertical move leaves as it is (spread < 1e-4)
        rng = np.random.default_rng(self.seed)
        move = np.zeros(particles.positions.shape)
        move[:, 2] = rng.uniform(-REALISATION_MOVE, REALISATION_MOVE, len(move))
        engine = self._engine(particles, motion, **self._level2_settling(), **start)
        alt = engine.run(st.cycles / f, sample_rate=self.sample_rate,
                         snapshot_rate=self.snapshot_rate,
                         start=self._settled(engine).moved(move))
        cp_alt = alt.complex_power(skip, span)
        eta0, ratio0 = run.power.loss_factor, run.power.effective_mass_ratio
        s_eta = abs(eta0 - cp_alt.loss_factor)
        s_mass = abs(ratio0 - cp_alt.effective_mass_ratio)
        dependent = bool(_relative(eta0, ratio0, s_eta, s_mass) > self.accuracy.accuracy)
        for k in range(self.max_refinements + 1):
            st = run.stationarity
            skip, span = st.first_cycle - 1, st.last_cycle - st.first_cycle + 1
            reference = value / factor
            engine = self._engine(particles, motion, **self._level2_settling(),
                                  **{**refined, setting: reference})
            comp = engine.run(st.cycles / f, sample_rate=self.sample_rate,
                              snapshot_rate=self.snapshot_rate, start=self._settled(engine))
            cp = comp.complex_power(skip, span)
            eta, ratio = run.power.loss_factor, run.power.effective_mass_ratio
            e_eta = error_bound(eta, cp.loss_factor)
            e_mass = error_bound(ratio, cp.effective_mass_ratio)
            rel = _relative(eta, ratio, e_eta, e_mass)
            met = bool(rel <= self.accuracy.accuracy) and not dependent
            est = AccuracyEstimate(e_eta, e_mass, rel, self.accuracy.accuracy, met, setting, value,
                                   reference, k, cp.loss_factor, cp.effective_mass_ratio,
                                   s_eta, s_mass, dependent)
            # a realisation-dependent point is no integration problem: a finer step would
            # only pick another realisation
            if met or dependent or k == self.max_refinements:
                return dataclasses.replace(run, accuracy=est)
            logger.info("DEM f=%.3g Hz X=%.3g m: estimated error %.2g > %.2g; redone with "
                        "%s = %.3g", f, x, rel, self.accuracy.accuracy, setting, reference)
            st2, motion2 = self.assess(comp)
            power2 = comp.complex_power(st2.first_cycle - 1, st2.last_cycle - st2.first_cycle + 1)
            run = SteadyRun(comp, st2, motion2, power2, run.packing)
            value = reference
        raise AssertionError("unreachable")  # pragma: no cover

    def assess(self, result) -> tuple[Stationarity, ModeClassification]:
        """Stationarity and motion mode of the run ``result`` so far.

        Running until steady, the averaged window is the last ``steady_windows x
        window_cycles`` cycles, or for a quiet bed the last ``quiet_windows x
        quiet_window_cycles``; with a fixed number of cycles it is every cycle after
        ``skip_cycles`` (the paper's procedure), split into ``steady_windows`` windows.
        Besides the loss-factor criterion, a window of at least ``2 x MIN_HALF_WINDOW``
        cycles is steady only if its two halves show the same motion mode; the motion mode
        is that of the averaged window.
        """
        f = float(result.frequency)
        eta = cycle_loss_factors(result.time, -result.force[:, 2], result.container_velocity,
                                 f, result.bed_mass)
        n = eta.size
        if n < 1:
            raise InputError("cycles", "the run holds no whole excitation cycle")
        if self.run_until_steady:
            crit = self.criterion
            length = min(crit.span, max(n - self.skip_cycles, 1))
        else:  # the paper's averaged window, split into the criterion's windows
            length = max(n - self.skip_cycles, 1)
            m = max(1, length // self.criterion.windows)
            crit = dataclasses.replace(self.criterion, window_cycles=m, windows=max(2, length // m),
                                       quiet_window_cycles=0)
        signals = BedSignals.from_dem(result)
        motion = classify_motion(signals, n - length + 1, n)
        st = crit.evaluate(eta, cycle_symmetry(result.time, result.force, f),
                           resting=motion.mode is MotionMode.SOLID)
        if st.quiet:
            # a quiet bed's window: its motion there (a resting bed may stay symmetric)
            length = st.last_cycle - st.first_cycle + 1
            motion = classify_motion(signals, n - length + 1, n)
            if st.symmetric and motion.mode is not MotionMode.SOLID:
                st = dataclasses.replace(st, stationary=False, reason="symmetric lattice state")
        if st.stationary and length >= 2 * MIN_HALF_WINDOW:
            # the motion must have settled too: both halves of the window in one mode
            half = length // 2
            a = classify_motion(signals, n - length + 1, n - length + half).mode
            b = classify_motion(signals, n - half + 1, n).mode
            if a is not b:
                st = dataclasses.replace(st, stationary=False,
                                         reason=f"motion mode changes ({a.label} -> {b.label})")
        if st.first_cycle != n - length + 1:  # report the whole averaged window
            st = dataclasses.replace(st, first_cycle=n - length + 1,
                                     loss_factor=float(np.mean(eta[n - length:])))
        return st, motion

    def response(self, frequency, amplitude) -> DamperResponse:
        """Run the DEM at every (f, X) point (:meth:`steady_run`) and apply Eqs. (1)-(4)
        over each run's averaged window.

        ``details`` holds the :class:`~pdamper.dem.DEMResult` of every point,
        ``stationary`` the steady-state verdicts, ``mode`` the classified motion modes
        (:mod:`pdamper.analysis.dem_modes`) and ``diagnostics`` the run diagnostics.
        """
        f, x = np.broadcast_arrays(np.asarray(frequency, float), np.asarray(amplitude, float))
        shape = f.shape
        eta, e_tilde, ratio = np.empty(shape), np.empty(shape), np.empty(shape)
        mode, order = np.empty(shape, int), np.empty(shape, int)
        steady = np.empty(shape, bool)
        runs = np.empty(shape, dtype=object)
        diag: dict[str, np.ndarray] = {}
        for idx in np.ndindex(shape):
            sr = self.steady_run(float(f[idx]), float(x[idx]))
            res, st, mo, cp = sr.result, sr.stationarity, sr.motion, sr.power
            eta[idx], e_tilde[idx], ratio[idx] = (cp.loss_factor, cp.dissipated_energy_per_cycle,
                                                  cp.effective_mass_ratio)
            mode[idx], order[idx], steady[idx] = int(mo.mode), mo.subharmonic_order, st.stationary
            runs[idx] = res
            for name, value in point_diagnostics(sr).items():
                if name not in diag:
                    diag[name] = np.empty(shape, dtype=object if not isinstance(
                        value, int | float | bool | np.number) else type(value))
                diag[name][idx] = value
            logger.info("DEM f=%.3g Hz X=%.3g m: eta=%.3f over cycles %d-%d (%s), %s "
                        "(%d steps, %.2f s)", f[idx], x[idx], cp.loss_factor, st.first_cycle,
                        st.last_cycle, "steady" if st.stationary else f"not steady: {st.reason}",
                        mo.mode.label, res.steps, res.wall_seconds)
        return DamperResponse(frequency=f, amplitude=x, mode=mode, loss_factor=eta,
                              dissipated_energy_per_cycle=e_tilde, effective_mass_ratio=ratio,
                              bed_mass=self.bed_mass, details=runs, stationary=steady,
                              subharmonic_order=order, diagnostics=diag)

    def __repr__(self) -> str:
        return (f"DEMDamper(count={self.damper.count}, integrator={self.integrator!r}, "
                f"packing={self.packing!r})")


#: The keyword arguments of :class:`DEMDamper`: the concerns and every setting by flat name.
_KEYWORDS = frozenset(DEMSettings.flat_fields()) | frozenset(
    ("plan", "steady", "accuracy", "contact", "engine"))

# the signature lists the concerns and every setting as a keyword (help, inspection), from
# the declarations
DEMDamper.__init__.__signature__ = inspect.Signature([  # type: ignore[attr-defined]
    *list(inspect.signature(DEMDamper.__init__).parameters.values())[:8],
    *(inspect.Parameter(name, inspect.Parameter.KEYWORD_ONLY, default=info.default,
                        annotation=info.annotation)
      for name, info in DEMSettings.flat_fields().items() if name != "accuracy")])


#: The keys of :meth:`DEMResult.summary <pdamper.dem.DEMResult.summary>` among a point's
#: diagnostics (besides ``wall_seconds`` and ``steps``: the whole run, as in the summary).
#: (The wall times beside ``wall_seconds`` stay out: a map's points are compared and
#: reused without their timings.)
RUN_KEYS = ("total_steps", "excitation_steps", "settle_steps", "energy_balance_error",
            "max_overlap_ratio", "max_impact_velocity", "stepped_fraction")


def point_diagnostics(run: SteadyRun) -> dict:
    """The per-point diagnostics of a Level II run, as plain values (SI units).

    The run's keys come from :meth:`DEMResult.summary <pdamper.dem.DEMResult.summary>`:
    ``wall_seconds`` [s] and ``steps`` are the point's whole run, settling included (as in
    ``pdamper dem --json``; the same as ``total_wall_seconds`` and ``total_steps``),
    ``total_steps``, ``excitation_steps``,
    ``settle_steps`` (0 for a point that started from a bed settled once for the map),
    ``energy_balance_error`` [-],
    ``max_overlap_ratio`` [-] (largest overlap / radius), ``max_impact_velocity`` [m/s]
    (fastest impact), ``stepped_fraction`` [-] (mean share of the spheres a Gear step
    integrated, the others in free flight),
    ``random_packing`` (1: the run started from a random packing, 0: from the lattice),
    ``cycles`` (simulated), ``first_cycle``/``last_cycle`` (the averaged window),
    ``loss_factor_stderr``, ``loss_factor_spread``, ``loss_factor_drift``
    [-] (:class:`~pdamper.analysis.stationarity.Stationarity`), ``symmetric_state`` (0/1),
    ``quiet_window`` (0/1: judged by the rule for quiet beds),
    ``period`` [cycles], ``periodicity_residual``, ``lift`` [m], ``contact_fraction``,
    ``lid_contacts_per_cycle`` [-] (:class:`~pdamper.analysis.dem_modes.ModeClassification`),
    with an error estimate also ``loss_factor_error``, ``effective_mass_ratio_error`` [-],
    ``accuracy_met`` (0/1), ``accuracy_refinements``, ``realisation_loss_factor_spread``,
    ``realisation_effective_mass_ratio_spread`` [-] and ``realisation_dependent`` (0/1)
    (:class:`AccuracyEstimate`),
    ``stationarity`` and ``motion`` (the records themselves, not numbers).
    """
    res, st, mo = run.result, run.stationarity, run.motion
    s = res.summary()
    return {
        # a map point's work, settling included (the summary's meaning of the two keys)
        "wall_seconds": s["wall_seconds"],
        "steps": s["steps"],
        **{k: s[k] for k in RUN_KEYS},
        "random_packing": int(run.packing == "random"),
        "cycles": int(st.cycles),
        "first_cycle": int(st.first_cycle),
        "last_cycle": int(st.last_cycle),
        "loss_factor_stderr": float(st.stderr),
        "loss_factor_spread": float(st.spread),
        "loss_factor_drift": float(st.drift),
        "symmetric_state": int(st.symmetric),
        "quiet_window": int(st.quiet),
        "period": int(mo.period),
        "periodicity_residual": float(mo.periodicity_residual),
        "lift": float(mo.lift),
        "contact_fraction": float(mo.contact_fraction),
        "lid_contacts_per_cycle": float(mo.lid_contacts_per_cycle),
        **({} if run.accuracy is None else {
            "loss_factor_error": float(run.accuracy.loss_factor_error),
            "effective_mass_ratio_error": float(run.accuracy.effective_mass_ratio_error),
            "accuracy_met": int(run.accuracy.met),
            "accuracy_refinements": int(run.accuracy.refinements),
            "realisation_loss_factor_spread": float(run.accuracy.loss_factor_spread),
            "realisation_effective_mass_ratio_spread": float(
                run.accuracy.effective_mass_ratio_spread),
            "realisation_dependent": int(run.accuracy.realisation_dependent)}),
        "stationarity": st,
        "motion": mo,
    }
