"""Level II settings of the DEM damper, each declared once (:mod:`pdamper.dem.settings`).

Per concern: :class:`RunPlan` (how long and how a Level II run samples, its start),
:class:`SteadyState` (the steady-state criterion of a run until steady), :class:`AccuracyTarget`
(the integration error estimate) and :class:`ContactLaw` (the damping law of the contact);
the engine's own are :class:`~pdamper.dem.settings.EngineSettings`. :class:`DEMSettings`
holds the five as typed fields (``plan``, ``steady``, ``accuracy``, ``contact``,
``engine``), as :class:`~pdamper.models.DEMDamper` takes them; the flat names
(:data:`FLAT`: ``cycles`` is ``plan.cycles``) are aliases, as the scenario's flat ``[dem]``
keys and the ``dem`` command's options write them, and read back typed through
:class:`FlatSettings`.

To add a setting: declare it (one :func:`~pdamper.dem.settings.setting` in its concern),
use it where it acts (through its concern; a typed flat read is a property of
:class:`FlatSettings`), and, for a command-line flag, add one row to
:data:`pdamper.cli.dem.FLAGS`. The scenario key follows from the declaration.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import TYPE_CHECKING, Any, ClassVar, Self, TypeVar

from pydantic import Field
from pydantic.fields import FieldInfo

from pdamper.analysis.stationarity import SteadyStateCriterion
from pdamper.contact.law import DAMPING_MODELS, DEFAULT_MIN_IMPACT_VELOCITY, FRICTION_MODELS
from pdamper.dem.settings import EngineSettings, Settings, redeclare, setting
from pdamper.errors import InputError

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
    # the seed and the transient tolerance are the engine's settings (their range declared
    # there), which a Level II run sets from these
    seed: int = redeclare(EngineSettings, "seed", 0, "Seed of the random packing (recorded "
                          "always; the engine's ``seed``).", none="")
    sample_rate: float = setting(
        DEFAULT_SAMPLE_RATE, "Samples per second of the force and container time series.",
        unit="Hz", low=0.0, low_inclusive=False)
    snapshot_rate: float | None = setting(
        None, "Particle snapshots per second.", unit="Hz", low=0.0, low_inclusive=False,
        kind="number", none="the first and last only")
    transient_tolerance: float | None = redeclare(
        EngineSettings, "gear_transient_tolerance", DEFAULT_TRANSIENT_TOLERANCE,
        "Gear tolerance of the cycles that every averaged window skips (the first "
        "``min(skip_cycles, quiet_skip_cycles)``): the start from rest, a transient no value "
        "is taken from (the engine's ``gear_transient_tolerance`` over its "
        "``transient_cycles``).", none="gear_tolerance throughout")


class SteadyState(Settings):
    """The steady-state criterion of a run until steady
    (:class:`~pdamper.analysis.stationarity.SteadyStateCriterion`, docs/fields.md)."""

    #: The flat names of the fields whose names alone would not say they are the
    #: criterion's (``DEMDamper(steady_windows=3)``, flat ``[dem]`` keys, errors).
    flat_names: ClassVar[dict[str, str]] = {"windows": "steady_windows", "rtol": "steady_rtol",
                                            "atol": "steady_atol"}

    window_cycles: int = setting(_STEADY.window_cycles, "Cycles per window of the "
                                 "criterion.", low=1)
    windows: int = setting(_STEADY.windows, "Windows whose loss factors must agree.", low=2)
    rtol: float = setting(_STEADY.rtol, "Relative tolerance of the agreement: "
                          "``max(rtol |eta|, atol)``.", low=0.0)
    atol: float = setting(_STEADY.atol, "Absolute tolerance of the agreement.", low=0.0)
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

    def __init__(self, **data: Any) -> None:
        flat = {v: k for k, v in self.flat_names.items()}
        super().__init__(**{flat.get(k, k): v for k, v in data.items()})

    @property
    def steady_windows(self) -> int:
        """``windows`` under its flat name."""
        return self.windows

    @property
    def steady_rtol(self) -> float:
        """``rtol`` under its flat name."""
        return self.rtol

    @property
    def steady_atol(self) -> float:
        """``atol`` under its flat name."""
        return self.atol

    def criterion(self, skip_cycles: int) -> SteadyStateCriterion:
        """The criterion of these settings for runs that skip ``skip_cycles``: the fields are
        the criterion's parameters, by the same names."""
        return SteadyStateCriterion(**self.get_params(), skip_cycles=skip_cycles)


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
#: The name of each concern in :class:`DEMSettings`, :class:`~pdamper.models.DEMDamper`
#: (``model.plan``), ``get_params(deep=True)`` (``plan__cycles``) and the scenario's
#: ``[dem.<name>]`` tables.
CONCERN_NAMES: dict[str, type[Settings]] = {
    "plan": RunPlan, "steady": SteadyState, "accuracy": AccuracyTarget,
    "contact": ContactLaw, "engine": EngineSettings}
#: Engine settings that a Level II run sets itself: the seed is the plan's, the start from
#: rest follows ``transient_tolerance`` and ``skip_cycles``.
ENGINE_SET_BY_RUN = ("seed", "transient_cycles", "gear_transient_tolerance")
#: Defaults of a DEM damper that differ from its concern's (the engine's default integrator
#: is Verlet; a damper's runs use the paper's Gear).
DAMPER_DEFAULTS: dict[str, Any] = {"integrator": "gear"}


def _flat() -> dict[str, tuple[str, str]]:
    out: dict[str, tuple[str, str]] = {}
    for concern_name, concern in CONCERN_NAMES.items():
        names: dict[str, str] = getattr(concern, "flat_names", {})
        for field in concern.model_fields:
            if concern is EngineSettings and field in ENGINE_SET_BY_RUN:
                continue
            name = names.get(field, field)
            if name in out:  # pragma: no cover - checked by the tests too
                raise TypeError(f"setting {name!r} declared twice")
            out[name] = (concern_name, field)
    return out


#: Every setting of the DEM damper by its flat name (``cycles``, ``gear_tolerance``) ->
#: the concern that declares it (``plan``, ``engine``): the flat keyword arguments of
#: :class:`~pdamper.models.DEMDamper` and flat ``[dem]`` keys are aliases of
#: ``<concern>.<name>``.
FLAT: dict[str, str] = {name: c for name, (c, _) in _flat().items()}
#: The field of each flat name in its concern (the same name but ``steady_windows``,
#: ``steady_rtol``, ``steady_atol``: ``SteadyState``'s ``windows``, ``rtol``, ``atol``, the
#: criterion's names).
FIELD: dict[str, str] = {name: f for name, (_, f) in _flat().items()}
#: The flat name of each ``(concern, field)``.
FLAT_NAME: dict[tuple[str, str], str] = {(c, f): n for n, (c, f) in _flat().items()}


def default_concern(name: str) -> Settings:
    """The default settings of concern ``name`` for a DEM damper (:data:`DAMPER_DEFAULTS`
    applied)."""
    cls = CONCERN_NAMES[name]
    return cls(**{k: v for k, v in DAMPER_DEFAULTS.items() if k in cls.model_fields})


def _is_concern_value(name: str, value: Any) -> bool:
    # ``accuracy`` is both a concern and a setting of it: a table or a Settings object is
    # the concern, a number the setting
    return isinstance(value, dict | Settings) or name != "accuracy"


def route(data: dict[str, Any], prefix: str = "dem.") -> dict[str, dict[str, Any]]:
    """The settings ``data`` by concern: ``{"plan": {...}, "engine": {...}}``.

    ``data`` holds concerns (a :class:`Settings` object or a dict of its settings, under
    :data:`CONCERN_NAMES`), flat names (:data:`FLAT`) and ``concern__name`` keys
    (scikit-learn's nesting); each setting may be given once. A concern given as an object
    contributes the values set on it (its defaults stay the damper's), which the keys given
    beside it replace."""
    out: dict[str, dict[str, Any]] = {name: {} for name in CONCERN_NAMES}
    base: dict[str, dict[str, Any]] = {}
    where: dict[str, str] = {}

    def put(concern: str, name: str, value: Any, given: str) -> None:
        cls = CONCERN_NAMES[concern]
        if name not in cls.model_fields and FLAT.get(name) == concern:
            name = FIELD[name]  # a flat name in its table (the old tables' keys)
        if name not in cls.model_fields or (cls is EngineSettings
                                            and name in ENGINE_SET_BY_RUN):
            field = prefix.rstrip(".") if "." in given else prefix + given
            raise InputError(field, f"{cls.__name__} ({concern}) has no setting "
                             f"{name!r} a DEM damper takes; its settings: "
                             f"{', '.join(n for n, c in FLAT.items() if c == concern)}")
        key = f"{concern}.{name}"
        if key in where:
            raise InputError(prefix.rstrip("."), f"{name} given twice, as {where[key]} and "
                             f"as {given}")
        where[key] = given
        out[concern][name] = value

    for key, value in data.items():
        concern, sep, name = key.partition("__")
        if sep:
            if concern not in CONCERN_NAMES:
                raise InputError(prefix + key, f"unknown concern {concern!r}; known: "
                                 f"{', '.join(CONCERN_NAMES)}")
            put(concern, name, value, f"{concern}.{name}")
        elif key in CONCERN_NAMES and _is_concern_value(key, value):
            if isinstance(value, Settings):
                if not isinstance(value, CONCERN_NAMES[key]):
                    raise InputError(prefix + key, f"must be a {CONCERN_NAMES[key].__name__}, "
                                     f"got {type(value).__name__}")
                # an object is the base of its concern: keys given beside it replace its values
                base[key] = {k: getattr(value, k) for k in value.model_fields_set
                             if not (key == "engine" and k in ENGINE_SET_BY_RUN)}
                continue
            if not isinstance(value, dict):
                raise InputError(prefix + key, f"must be a {CONCERN_NAMES[key].__name__} or a "
                                 f"table of its settings, got {value!r}")
            for name, v in value.items():
                put(key, name, v, f"{key}.{name}")
        elif key in FLAT:
            put(FLAT[key], FIELD[key], value, key)
        else:
            raise InputError(prefix + key, "unknown setting of the DEM damper; known: "
                             f"{', '.join(FLAT)}")
    return {name: {**base.get(name, {}), **values} for name, values in out.items()}


class FlatSettings:
    """Every setting of the DEM damper read by its flat name (``model.cycles`` is
    ``model.plan.cycles``), typed; read-only: a change goes through the concern (``clone``).
    ``accuracy`` is the concern :class:`AccuracyTarget` (its target: ``accuracy.accuracy``)."""

    if TYPE_CHECKING:
        plan: RunPlan
        steady: SteadyState
        accuracy: AccuracyTarget
        contact: ContactLaw
        engine: EngineSettings

    @property
    def cycles(self) -> int | str:
        return self.plan.cycles

    @property
    def skip_cycles(self) -> int:
        return self.plan.skip_cycles

    @property
    def max_cycles(self) -> int:
        return self.plan.max_cycles

    @property
    def packing(self) -> str:
        return self.plan.packing

    @property
    def seed(self) -> int:
        return self.plan.seed

    @property
    def sample_rate(self) -> float:
        return self.plan.sample_rate

    @property
    def snapshot_rate(self) -> float | None:
        return self.plan.snapshot_rate

    @property
    def transient_tolerance(self) -> float | None:
        return self.plan.transient_tolerance

    @property
    def window_cycles(self) -> int:
        return self.steady.window_cycles

    @property
    def steady_windows(self) -> int:
        return self.steady.windows

    @property
    def steady_rtol(self) -> float:
        return self.steady.rtol

    @property
    def steady_atol(self) -> float:
        return self.steady.atol

    @property
    def quiet_window_cycles(self) -> int:
        return self.steady.quiet_window_cycles

    @property
    def quiet_scatter(self) -> float:
        return self.steady.quiet_scatter

    @property
    def quiet_windows(self) -> int:
        return self.steady.quiet_windows

    @property
    def quiet_skip_cycles(self) -> int:
        return self.steady.quiet_skip_cycles

    @property
    def error_estimate(self) -> bool:
        return self.accuracy.error_estimate

    @property
    def max_refinements(self) -> int:
        return self.accuracy.max_refinements

    @property
    def damping_model(self) -> str:
        return self.contact.damping_model

    @property
    def min_impact_velocity(self) -> float:
        return self.contact.min_impact_velocity

    @property
    def friction_model(self) -> str:
        return self.contact.friction_model

    @property
    def integrator(self) -> str:
        return self.engine.integrator

    @property
    def safety(self) -> float:
        return self.engine.safety

    @property
    def gravity(self) -> float:
        return self.engine.gravity

    @property
    def gear_tolerance(self) -> float | None:
        return self.engine.gear_tolerance

    @property
    def gear_velocity_scale(self) -> float:
        return self.engine.gear_velocity_scale

    @property
    def gear_adaptive(self) -> bool:
        return self.engine.gear_adaptive

    @property
    def max_step(self) -> float:
        return self.engine.max_step

    @property
    def skin(self) -> float | None:
        return self.engine.skin

    @property
    def settle_time(self) -> float | None:
        return self.engine.settle_time

    @property
    def settle_rest_speed(self) -> float | None:
        return self.engine.settle_rest_speed

    @property
    def settle_rest_time(self) -> float:
        return self.engine.settle_rest_time

    @property
    def max_overlap(self) -> float | None:
        return self.engine.max_overlap

    @property
    def reference_velocity(self) -> float | None:
        return self.engine.reference_velocity

    @property
    def gear_contact_bound(self) -> bool:
        return self.engine.gear_contact_bound

    @property
    def auto_cost_ratio(self) -> float:
        return self.engine.auto_cost_ratio

    @property
    def gear_free_flight(self) -> bool:
        return self.engine.gear_free_flight


class DEMSettings(FlatSettings, Settings):
    """Every setting of :class:`~pdamper.models.DEMDamper`, by concern: ``plan``
    (:class:`RunPlan`), ``steady`` (:class:`SteadyState`), ``accuracy``
    (:class:`AccuracyTarget`), ``contact`` (:class:`ContactLaw`) and ``engine``
    (:class:`~pdamper.dem.settings.EngineSettings`, the integrator defaulting to the paper's
    Gear; ``seed``, ``transient_cycles`` and ``gear_transient_tolerance`` are the run's).

    Constructed from concerns, flat names (aliases: ``DEMSettings(cycles=8)`` is
    ``DEMSettings(plan=RunPlan(cycles=8))``) or ``concern__name`` keys; a setting given twice
    is an error. Errors name the flat setting (``dem.cycles``), as the scenario's ``[dem]``
    section does.
    """

    prefix: ClassVar[str] = "dem."

    plan: RunPlan = Field(default_factory=lambda: default_concern("plan"))  # type: ignore[assignment]
    steady: SteadyState = Field(default_factory=lambda: default_concern("steady"))  # type: ignore[assignment]
    accuracy: AccuracyTarget = Field(  # type: ignore[assignment]
        default_factory=lambda: default_concern("accuracy"))
    contact: ContactLaw = Field(default_factory=lambda: default_concern("contact"))  # type: ignore[assignment]
    engine: EngineSettings = Field(default_factory=lambda: default_concern("engine"))  # type: ignore[assignment]

    def __init__(self, **data: Any) -> None:
        super().__init__(**self.concerns_of(data))

    @classmethod
    def _edge_concern(cls, concern: str, values: dict[str, Any]) -> dict[str, Any]:
        """The values of one concern as given at the edge, made values of their settings
        (the scenario parses quantities with units here); identity for the Python API."""
        return values

    @classmethod
    def concerns_of(cls, data: dict[str, Any]) -> dict[str, Any]:
        """``data`` (concerns, flat names, ``concern__name`` keys: :func:`route`) as the
        five concern objects, each checked against its declarations (errors name
        ``dem.<setting>``)."""
        routed = route({k: v for k, v in data.items() if k in FLAT or k in CONCERN_NAMES
                        or "__" in k}, cls.prefix)
        out: dict[str, Any] = {k: v for k, v in data.items()
                               if not (k in FLAT or k in CONCERN_NAMES or "__" in k)}
        for name, values in routed.items():
            concern = CONCERN_NAMES[name]
            defaults = {k: v for k, v in DAMPER_DEFAULTS.items() if k in concern.model_fields}
            try:
                obj = concern(**{**defaults, **cls._edge_concern(name, values)})
            except InputError as exc:  # named by its flat name, as the [dem] keys
                raise InputError(cls.prefix + FLAT_NAME.get((name, exc.field), exc.field),
                                 exc.message) from None
            # what was given, not the damper's defaults (model_fields_set)
            object.__setattr__(obj, "__pydantic_fields_set__", set(values))
            out[name] = obj
        return out

    @property
    def model_fields_set(self) -> set[str]:
        """The settings given (by flat name, whichever form they were given in) and the
        other fields given; a setting left at its default is not in it."""
        out = {k for k in self.__pydantic_fields_set__ if k not in CONCERN_NAMES}
        for name in CONCERN_NAMES:
            out |= {FLAT_NAME[(name, k)] for k in getattr(self, name).model_fields_set
                    if (name, k) in FLAT_NAME}
        return out

    def get_params(self, deep: bool = False) -> dict[str, Any]:
        """The concerns by name; ``deep``: also every setting as ``concern__name``
        (scikit-learn's convention: ``engine__gear_tolerance``)."""
        out: dict[str, Any] = {name: getattr(self, name) for name in CONCERN_NAMES}
        if deep:
            for name in CONCERN_NAMES:
                for key, value in getattr(self, name).get_params().items():
                    if not (name == "engine" and key in ENGINE_SET_BY_RUN):
                        out[f"{name}__{key}"] = value
        return out

    def clone(self, **changes: Any) -> Self:
        """A copy with ``changes`` (concerns, flat names or ``concern__name`` keys), checked
        as at construction."""
        if not changes:
            return self
        routed = route(changes, self.prefix)
        keep = {k: getattr(self, k) for k in type(self).model_fields if k not in CONCERN_NAMES}
        merged = {name: {**getattr(self, name).get_params(), **routed[name]}
                  for name in CONCERN_NAMES}
        merged["engine"] = {k: v for k, v in merged["engine"].items()
                            if k not in ENGINE_SET_BY_RUN}
        new = type(self)(**keep, **{k: v for k, v in changes.items() if k not in FLAT
                                    and k not in CONCERN_NAMES and "__" not in k},
                         **{f"{c}__{k}": v for c, vals in merged.items()
                            for k, v in vals.items()})
        # the copy was given what this was given and the changes (as pydantic's model_copy)
        object.__setattr__(new, "__pydantic_fields_set__", set(self.__pydantic_fields_set__)
                           | {k for k in changes if k not in FLAT and k not in CONCERN_NAMES
                              and "__" not in k})
        for name in CONCERN_NAMES:
            obj = getattr(new, name)
            object.__setattr__(obj, "__pydantic_fields_set__", getattr(
                self, name).model_fields_set | set(routed[name]))
        return new

    def model_copy(self, *, update: Mapping[str, Any] | None = None,
                   deep: bool = False) -> Self:
        """A copy; ``update`` may name settings by flat name or ``concern__name`` (routed to
        their concern and checked, as :meth:`clone`)."""
        if update and any(k in FLAT or k in CONCERN_NAMES or "__" in k for k in update):
            return self.clone(**update)
        return super().model_copy(update=update, deep=deep)

    def engine_settings(self, **changes: Any) -> EngineSettings:
        """The :class:`EngineSettings` of these settings, with ``changes``."""
        return self.engine.clone(**changes) if changes else self.engine

    def concern(self, cls: type[_S]) -> _S:
        """The settings of one concern (``RunPlan``, ``SteadyState``, ...)."""
        return next(getattr(self, n) for n, c in CONCERN_NAMES.items() if c is cls)

    @classmethod
    def flat_fields(cls) -> dict[str, FieldInfo]:
        """Every setting by its flat name: the declaration of its concern, with the damper's
        default (:data:`DAMPER_DEFAULTS`)."""
        out: dict[str, FieldInfo] = {}
        for name, concern in FLAT.items():
            info = CONCERN_NAMES[concern].model_fields[FIELD[name]]
            if name in DAMPER_DEFAULTS:
                info = FieldInfo.merge_field_infos(info, default=DAMPER_DEFAULTS[name])
            out[name] = info
        return out

    @classmethod
    def declarations(cls) -> dict[str, dict]:
        """Every setting under its canonical dotted name (``"engine.gear_tolerance"``):
        ``unit``, ``kind``, range, ``choices``, ``doc``, ``default`` (the damper's) and
        ``concern``; :meth:`aliases` maps the other names to these."""
        out: dict[str, dict] = {}
        for name, concern in FLAT.items():
            decl = CONCERN_NAMES[concern].declarations()[FIELD[name]]
            out[f"{concern}.{FIELD[name]}"] = {**decl, "default": DAMPER_DEFAULTS.get(
                name, decl["default"]), "concern": concern, "name": name}
        return out

    @classmethod
    def aliases(cls) -> dict[str, str]:
        """Alias -> canonical dotted name: the flat names (``cycles`` -> ``plan.cycles``)
        and scikit-learn's ``plan__cycles``."""
        out = {name: f"{concern}.{FIELD[name]}" for name, concern in FLAT.items()}
        out.update({f"{concern}__{FIELD[name]}": f"{concern}.{FIELD[name]}"
                    for name, concern in FLAT.items()})
        out.update({f"{concern}.{name}": f"{concern}.{FIELD[name]}"
                    for name, concern in FLAT.items() if FIELD[name] != name})
        return out


_S = TypeVar("_S", bound=Settings)
