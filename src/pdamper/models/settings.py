"""Level II settings of the DEM damper, each declared once (:mod:`pdamper.dem.settings`).

Per concern: :class:`RunPlan` (how long and how a Level II run samples, its start),
:class:`SteadyState` (the steady-state criterion of a run until steady), :class:`AccuracyTarget`
(the integration error estimate) and :class:`ContactLaw` (the damping law of the contact);
the engine's own are :class:`~pdamper.dem.settings.EngineSettings`. :class:`DEMSettings`
holds them all under their flat names, as :class:`~pdamper.models.DEMDamper` takes them and
as the scenario's ``[dem]`` section and the ``dem`` command's options write them; it is
derived from the concerns' declarations, not written again.

To add a setting: declare it (one :func:`~pdamper.dem.settings.setting` in its concern),
use it where it acts, and, for a command-line flag, add one row to
:data:`pdamper.cli.dem.FLAGS`. The scenario key follows from the declaration.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any, ClassVar, TypeVar

from pydantic import create_model

from pdamper.analysis.stationarity import SteadyStateCriterion
from pdamper.contact.law import DAMPING_MODELS, DEFAULT_MIN_IMPACT_VELOCITY, FRICTION_MODELS
from pdamper.dem.settings import EngineSettings, Settings, setting

#: ``cycles`` value that runs until the loss factor is steady (the default).
AUTO = "auto"
DEFAULT_CYCLES = AUTO
#: The paper's procedure (Sect. 3.1.2): eight cycles, the first two cut off.
PAPER_CYCLES = 8
DEFAULT_SKIP_CYCLES = 2
#: Upper bound of a run until steady [cycles]. The symmetric state of the benchmark lattice
#: bed lasts up to ~30 cycles, the averaged window takes 12 more (docs/fields.md).
DEFAULT_MAX_CYCLES = 60
#: Samples per second of the force and container series of a Level II run [Hz].
DEFAULT_SAMPLE_RATE = 4000.0

#: Initial packings: the paper's square-lattice layers, random (seeded), or "auto": random
#: where random sequential addition can place every sphere, else the lattice. Random
#: addition jams near a solid fraction of 0.35 (about 103 spheres in the benchmark box, whose
#: lattice holds 192), so a denser bed can only start from the lattice: "auto" lets a map
#: or a particle-count sweep span 16-192 spheres; each run records the packing it used.
PACKINGS = ("lattice", "random", "auto")

#: Accuracy the error estimate is held to by default: 1 % of the loss factor (relative to
#: ``max(|eta|, LOSS_FACTOR_FLOOR)``) and of the effective mass ratio.
DEFAULT_ACCURACY = 0.01

#: Default number of times a run whose estimate misses the target is redone refined.
DEFAULT_MAX_REFINEMENTS = 2

#: Gear tolerance of the start from rest of a Level II run: the cycles that every averaged
#: window skips (the first, running until steady) run at this tolerance instead of
#: ``gear_tolerance`` (1e-5). No value is taken from them; the window starts from a
#: slightly different state, i.e. another realisation of a chaotic bed. On the 14 x 24 map
#: (docs/fields.md, section 6): 9.5 % fewer steps, 7.5 % less wall time; the cells' loss
#: factors differ from the map without it as much as two realisations do (median 0.5 %,
#: 90th percentile 2.1 %; quiet cells' mean 0.4705 against 0.4707), the same quiet cells
#: (282 / 281), the ledger within 1.1e-3 (whole run). Gear's first cycle took 53 % of its
#: steps at 1e-3 and 68 % at 1e-4 (eight points, 2-20 Hz).
DEFAULT_TRANSIENT_TOLERANCE = 1e-3

#: The steady-state criterion's defaults (one home: the criterion itself).
_STEADY = SteadyStateCriterion()


class RunPlan(Settings):
    """The plan of a Level II run: cycles, averaging, packing, sampling, the start from
    rest."""

    cycles: int | str = setting(
        DEFAULT_CYCLES, "``auto``: run until the loss factor is steady (at most "
        "``max_cycles``); a whole number: run that many excitation cycles (the paper: 8) and "
        "still record whether the averaged window was steady.", kind="cycles")
    skip_cycles: int = setting(DEFAULT_SKIP_CYCLES, "Cycles never averaged (the paper: the "
                               "first 2).", low=0)
    max_cycles: int = setting(DEFAULT_MAX_CYCLES, "Upper bound of a run until steady "
                              "[cycles].", low=1)
    packing: str = setting(
        "lattice", "Initial packing: ``lattice`` (the paper's 4 x 4 layers), ``random`` "
        "(seeded by ``seed``) or ``auto`` (random where every sphere can be placed at random, "
        "else the lattice).", choices=PACKINGS)
    seed: int = setting(0, "Seed of the random packing (recorded always).", low=0)
    sample_rate: float = setting(
        DEFAULT_SAMPLE_RATE, "Samples per second of the force and container time series.",
        unit="Hz", low=0.0, low_inclusive=False)
    snapshot_rate: float | None = setting(
        None, "Particle snapshots per second.", unit="Hz", low=0.0, low_inclusive=False,
        kind="number", none="the first and last only")
    transient_tolerance: float | None = setting(
        DEFAULT_TRANSIENT_TOLERANCE, "Gear tolerance of the cycles that every averaged "
        "window skips (the first ``min(skip_cycles, quiet_skip_cycles)``): the start from "
        "rest, a transient no value is taken from.", low=0.0, low_inclusive=False,
        kind="number", none="gear_tolerance throughout")


class SteadyState(Settings):
    """The steady-state criterion of a run until steady
    (:class:`~pdamper.analysis.stationarity.SteadyStateCriterion`, docs/fields.md)."""

    window_cycles: int = setting(_STEADY.window_cycles, "Cycles per window of the "
                                 "criterion.", low=1)
    steady_windows: int = setting(_STEADY.windows, "Windows whose loss factors must agree.",
                                  low=2)
    steady_rtol: float = setting(_STEADY.rtol, "Relative tolerance of the agreement: "
                                 "``max(steady_rtol |eta|, steady_atol)``.", low=0.0)
    steady_atol: float = setting(_STEADY.atol, "Absolute tolerance of the agreement.",
                                 low=0.0)
    quiet_window_cycles: int = setting(
        _STEADY.quiet_window_cycles, "Cycles per window of a quiet bed (cycle-to-cycle "
        "scatter at most ``quiet_scatter`` x the tolerance; 0: no rule for quiet beds).",
        low=0)
    quiet_scatter: float = setting(_STEADY.quiet_scatter, "Scatter (in tolerances) below "
                                   "which a bed is quiet.", low=0.0)
    quiet_windows: int = setting(_STEADY.quiet_windows, "Windows of a quiet bed.", low=2)
    quiet_skip_cycles: int = setting(
        _STEADY.quiet_skip_cycles, "Cycles a quiet bed's window skips (at most "
        "``skip_cycles``).", low=0)

    def criterion(self, skip_cycles: int) -> SteadyStateCriterion:
        """The criterion of these settings for runs that skip ``skip_cycles``."""
        return SteadyStateCriterion(
            window_cycles=self.window_cycles, windows=self.steady_windows,
            rtol=self.steady_rtol, atol=self.steady_atol,
            quiet_window_cycles=self.quiet_window_cycles, quiet_scatter=self.quiet_scatter,
            quiet_windows=self.quiet_windows, quiet_skip_cycles=self.quiet_skip_cycles,
            skip_cycles=skip_cycles)


class AccuracyTarget(Settings):
    """The integration error estimate of a Level II run (a refined companion run;
    :class:`~pdamper.models.dem.AccuracyEstimate`)."""

    error_estimate: bool = setting(
        False, "Estimate the integration error of eta and m_eff / m_bed from a refined "
        "companion run over the same cycles (about twice the cost); redo refined where it "
        "misses ``accuracy``.")
    accuracy: float = setting(DEFAULT_ACCURACY, "Target of the estimate, relative.",
                              low=0.0, high=1.0, low_inclusive=False)
    max_refinements: int = setting(DEFAULT_MAX_REFINEMENTS, "Upper bound of the "
                                   "refinements.", low=0)


class ContactLaw(Settings):
    """The contact law's damping and friction law (the COR curves and the friction
    coefficient come from the damper)."""

    damping_model: str = setting(
        "exact", "Damping law of the normal force: ``exact``, ``gonthier`` (the paper's) or "
        "``tsuji`` (LIGGGHTS/EDEM 'Hertz with COR').", choices=DAMPING_MODELS)
    min_impact_velocity: float = setting(
        DEFAULT_MIN_IMPACT_VELOCITY, "Floor of the onset speed that sets the damping of the "
        "exact and Gonthier laws (docs/dem.md on rattling columns).", unit="m/s", low=0.0,
        low_inclusive=False)
    friction_model: str = setting(
        "regularised", "Tangential law: ``regularised`` (the paper's tanh-regularised Coulomb "
        "friction) or ``spring`` (a tangential spring with a Coulomb limit, LIGGGHTS' "
        "'tangential history'; runs with ``integrator`` verlet or auto).",
        choices=FRICTION_MODELS)


#: The concerns whose settings a DEM damper takes, in the order of :class:`DEMSettings`.
CONCERNS: tuple[type[Settings], ...] = (RunPlan, SteadyState, AccuracyTarget, ContactLaw,
                                        EngineSettings)
#: Engine settings that a Level II run sets itself: the seed is the plan's, the start from
#: rest follows ``transient_tolerance`` and ``skip_cycles``.
ENGINE_SET_BY_RUN = ("seed", "transient_cycles", "gear_transient_tolerance")
#: Defaults of a DEM damper that differ from its concern's (the engine's default integrator
#: is Verlet; a damper's runs use the paper's Gear).
DAMPER_DEFAULTS: dict[str, Any] = {"integrator": "gear"}


def _fields() -> dict[str, tuple]:
    out: dict[str, tuple] = {}
    for concern in CONCERNS:
        for name, info in concern.model_fields.items():
            if concern is EngineSettings and name in ENGINE_SET_BY_RUN:
                continue
            if name in out:  # pragma: no cover - checked by the tests too
                raise TypeError(f"setting {name!r} declared twice")
            if name in DAMPER_DEFAULTS:
                info = info.merge_field_infos(info, default=DAMPER_DEFAULTS[name])
            out[name] = (info.annotation, info)
    return out


_S = TypeVar("_S", bound=Settings)


class _DEMSettingsBase(Settings):
    prefix: ClassVar[str] = "dem."

    def engine_settings(self, **changes: Any) -> EngineSettings:
        """The :class:`EngineSettings` of these settings, with ``changes``."""
        names = EngineSettings.model_fields
        return EngineSettings(**{**{k: v for k, v in self.get_params().items() if k in names},
                                 **changes})

    def concern(self, cls: type[_S]) -> _S:
        """The settings of one concern (``RunPlan``, ``SteadyState``, ...)."""
        params = self.get_params()
        return cls(**{k: params[k] for k in cls.model_fields if k in params})


#: Every setting of the DEM damper under its flat name (errors name ``dem.<name>``).
if TYPE_CHECKING:  # built from the concerns' fields at run time: a type checker sees a class
    class DEMSettings(_DEMSettingsBase):
        def __getattr__(self, name: str) -> Any: ...
else:
    DEMSettings = create_model("DEMSettings", __base__=_DEMSettingsBase,
                               __module__=__name__, **_fields())
DEMSettings.__doc__ = ("Every setting of :class:`~pdamper.models.DEMDamper`, flat: the fields "
                       "of " + ", ".join(c.__name__ for c in CONCERNS) + " (the engine's "
                       "less " + ", ".join(ENGINE_SET_BY_RUN) + ").")
