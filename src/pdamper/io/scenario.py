"""Scenario files: declarative TOML inputs with units, validated by pydantic.

Every quantity is written with its unit (``"120 mm"``, ``"7900 kg/m^3"``) and converted to
an SI float on load; a bare number is taken as SI. :func:`load_scenario` turns every
problem (malformed TOML, unknown unit, out-of-range value, unknown key, an error inside an
inline material table) into a one-line :class:`~pdamper.errors.InputError` naming the field.
Every section is validated on load, whichever command reads the scenario, by building the
objects it describes and by the physical checks of :mod:`pdamper.resources` (a ``[map]``
that is malformed or physically meaningless is an error for ``pdamper analytic`` too).
What a run implies (memory, time steps, grid points) is checked by
:meth:`Scenario.check_resources` for the runs a command makes, before it makes them.

The defaults are the reference paper's case (:mod:`pdamper.parameters`) and the models' own
defaults; nothing here restates a number.
"""

from __future__ import annotations

import functools
import math
import tomllib
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Any, Literal

from pydantic import (
    AfterValidator,
    AliasChoices,
    BaseModel,
    BeforeValidator,
    ConfigDict,
    Field,
    PrivateAttr,
    ValidationError,
    field_validator,
    model_serializer,
    model_validator,
)
from pydantic.fields import FieldInfo

from pdamper import resources
from pdamper.constants import STANDARD_GRAVITY
from pdamper.contact.law import DAMPING_MODELS
from pdamper.dem.settings import Settings
from pdamper.errors import InputError
from pdamper.io.restitution import MODELS as COR_MODELS
from pdamper.io.restitution import RestitutionSpec, resolve_files
from pdamper.models.settings import (
    CONCERN_NAMES,
    FIELD,
    FLAT,
    FLAT_NAME,
    PAPER_CYCLES,
    DEMSettings,
)
from pdamper.parameters import vertical_dampers_paper as paper
from pdamper.resources import DEFAULT_MAX_EVALUATIONS, DEFAULT_MAX_GRID, DEFAULT_TOLERANCE
from pdamper.units import format_quantity, parse_quantity, parse_range

if TYPE_CHECKING:  # pragma: no cover
    import numpy as np

    from pdamper.contact.restitution import RestitutionCurve
    from pdamper.coupling.loads import LoadHistory
    from pdamper.damper import ParticleDamper
    from pdamper.design.study import DesignVariable
    from pdamper.materials import Material
    from pdamper.models.base import DamperModel
    from pdamper.structure import SingleDOFStructure
    from pdamper.structure.modal import ModalStructure


def _q(unit: str):
    def conv(v: Any) -> Any:
        try:
            return parse_quantity(v, unit, "value")
        except InputError as exc:  # pydantic adds the location
            raise ValueError(exc.message) from None

    return BeforeValidator(conv)


Length = Annotated[float, _q("m")]
PositiveLength = Annotated[float, _q("m"), Field(gt=0)]
Frequency = Annotated[float, _q("Hz"), Field(gt=0)]
Duration = Annotated[float, _q("s"), Field(gt=0)]
Mass = Annotated[float, _q("kg"), Field(ge=0)]
PositiveMass = Annotated[float, _q("kg"), Field(gt=0)]
Stiffness = Annotated[float, _q("N/m"), Field(gt=0)]
Damping = Annotated[float, _q("kg/s"), Field(ge=0)]
Density = Annotated[float, _q("kg/m^3"), Field(gt=0)]
Modulus = Annotated[float, _q("Pa"), Field(gt=0)]
Restitution = Annotated[float, Field(gt=0, le=1)]
Gravity = Annotated[float, _q("m/s^2"), Field(ge=0, allow_inf_nan=False)]
Count = Annotated[int, Field(strict=True)]


_D = paper.PAPER_DAMPER
#: Usual (f [Hz], X [m]) of a Level II run: the paper's benchmark point; of the two, the
#: one further above its usual value is named when a motion is too fast.
_USUAL_EXCITATION = paper.BENCHMARK_EXCITATION
#: Runs whose cost :meth:`Scenario.check_resources` judges.
_RUNS = ("excitation", "map", "simulation", "optimization", "case_study", "case_study_dem")


class _Section(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True, populate_by_name=True)


class MaterialSpec(_Section):
    """A material given by its constants instead of a library name."""

    name: str
    youngs_modulus: Modulus
    poisson_ratio: Annotated[float, Field(gt=-1, lt=0.5)]
    density: Density
    yield_strength: Modulus | None = None


class ContainerSpec(_Section):
    length: PositiveLength = _D.length
    width: PositiveLength = _D.width
    depth: PositiveLength = _D.depth
    material: str | MaterialSpec = _D.wall_material.name
    mass: Mass = _D.container_mass


class ParticlesSpec(_Section):
    count: Annotated[int, Field(ge=0, strict=True)] = _D.count
    radius: PositiveLength = _D.particle_radius
    material: str | MaterialSpec = _D.particle_material.name
    friction: Annotated[float, Field(ge=0)] = paper.PAPER_FRICTION  # (_D.friction)


class ExcitationSpec(_Section):
    frequency: Frequency = paper.BENCHMARK_EXCITATION[0]
    amplitude: PositiveLength = paper.BENCHMARK_EXCITATION[1]
    #: g [m/s^2] along -z; 0 for a structure in orbit (docs/analytical.md)
    gravity: Gravity = STANDARD_GRAVITY


_BEAM, _TIP = paper.paper_beam()
#: Most Timoshenko elements of ``[structure] beam``: the dense eigenproblem of 2 x 1000 DOFs
#: takes seconds; the paper's 100 elements converge its first modes to < 0.1 %.
MAX_BEAM_ELEMENTS = 1000


class BeamSpec(_Section):
    """The Timoshenko FE cantilever of Sect. 4.1 (:class:`~pdamper.structure.beam.
    TimoshenkoBeam`) with a tip mass, reduced to its first ``modes`` bending modes
    (:meth:`~pdamper.structure.modal.ModalStructure.from_beam`); defaults: the paper's beam."""

    length: PositiveLength = _BEAM.length
    width: PositiveLength = _BEAM.width
    height: PositiveLength = _BEAM.height
    material: str | MaterialSpec | None = None
    youngs_modulus: Modulus | None = None
    poisson_ratio: Annotated[float, Field(gt=-1, lt=0.5)] | None = None
    density: Density | None = None
    shear_coefficient: Annotated[float, Field(gt=0, le=1)] = _BEAM.shear_coefficient
    elements: Annotated[int, Field(ge=1, le=MAX_BEAM_ELEMENTS, strict=True)] \
        = _BEAM.elements
    tip_mass: Mass = _TIP.mass
    modes: Annotated[int, Field(ge=1, strict=True)] = 1
    damper_position: PositiveLength | None = None
    observation_position: PositiveLength | None = None
    damping_ratio: (Annotated[float, Field(ge=0)]
                    | list[Annotated[float, Field(ge=0)]]) = paper.PAPER_STRUCTURE.damping_ratio

    @model_validator(mode="after")
    def _one_material(self):
        given = [k for k in ("youngs_modulus", "poisson_ratio", "density")
                 if getattr(self, k) is not None]
        if self.material is not None and given:
            raise ValueError(f"give the beam's material as material or as its constants "
                             f"({', '.join(given)}), not both")
        return self

    def structure(self) -> ModalStructure:
        """The :class:`~pdamper.structure.modal.ModalStructure`: damper and release at
        ``damper_position``, results at ``observation_position`` (both default the tip)."""
        from pdamper.structure.beam import TimoshenkoBeam, TipMass
        from pdamper.structure.modal import ModalStructure

        if self.material is not None:
            m = _material(self.material, "structure.beam.material")
            e, nu, rho = m.youngs_modulus, m.poisson_ratio, m.density
        else:
            e, nu, rho = (_BEAM.youngs_modulus if self.youngs_modulus is None
                          else self.youngs_modulus,
                          _BEAM.poisson_ratio if self.poisson_ratio is None
                          else self.poisson_ratio,
                          _BEAM.density if self.density is None else self.density)
        zeta = self.damping_ratio
        if isinstance(zeta, list) and len(zeta) != self.modes:
            raise InputError("structure.beam.damping_ratio", f"must be one ratio or one per "
                             f"mode ({self.modes}), got {len(zeta)}")
        pos = {}
        for key in ("damper_position", "observation_position"):
            v = getattr(self, key)
            if v is not None and v > self.length * (1.0 + 1e-12):
                raise InputError(f"structure.beam.{key}", f"must be in (0, {self.length:g}] m "
                                 f"(the beam's length), got {v:g} m")
            # "700 mm" is 0.7000000000000001 m: the tip of a 0.7 m beam, not beyond it
            pos[key] = None if v is None else min(v, self.length)
        try:
            beam = TimoshenkoBeam(length=self.length, width=self.width, height=self.height,
                                  youngs_modulus=e, poisson_ratio=nu, density=rho,
                                  shear_coefficient=self.shear_coefficient,
                                  elements=self.elements)
            return ModalStructure.from_beam(
                beam, TipMass(self.tip_mass), self.modes,
                damper_position=pos["damper_position"],
                output_position=pos["observation_position"],
                release_position=pos["damper_position"], damping_ratio=zeta)
        except InputError as exc:
            field = exc.field.removeprefix("beam.").removeprefix("structure.")
            raise InputError(f"structure.beam.{field}", exc.message) from None


class StructureSpec(_Section):
    """The structure: the 1-DOF of Eq. (23) (``mass``, ``stiffness``, ``damping``; default
    the paper's), or N modes from a CSV file (``modes``, :mod:`pdamper.io.modes`; a relative
    path is taken relative to the scenario file) or from a Timoshenko beam (``beam``)."""

    mass: PositiveMass | None = None
    stiffness: Stiffness = paper.PAPER_STIFFNESS
    damping: Damping = paper.PAPER_DAMPING
    initial_displacement: Annotated[float, _q("m"), Field(lt=0)] = paper.PAPER_INITIAL_DISPLACEMENT
    modes: str | None = None
    beam: BeamSpec | None = None

    @model_validator(mode="after")
    def _one_structure(self):
        given = [k for k in ("modes", "beam") if getattr(self, k) is not None]
        if len(given) == 2:
            raise ValueError("give the structure as modes (a CSV file) or as a beam, not both")
        single = sorted({"mass", "stiffness", "damping"} & self.model_fields_set)
        if given and single:
            raise ValueError(f"{given[0]} describes the whole structure: leave out "
                             f"{', '.join(single)} (the 1-DOF of Eq. 23)")
        return self


class LoadSpec(_Section):
    """A load history on the structure (:mod:`pdamper.io.loads`, docs/forced.md): a force
    (``force``, a CSV file) or a base acceleration (``base_acceleration``), not both; a
    relative path is taken relative to the scenario file. The run lasts the record plus
    ``tail`` of free vibration."""

    force: str | None = None
    base_acceleration: str | None = None
    tail: Annotated[float, _q("s"), Field(ge=0, allow_inf_nan=False)] = 0.0

    @model_validator(mode="after")
    def _one_load(self):
        if self.force is not None and self.base_acceleration is not None:
            raise ValueError("give the load as force or as base_acceleration, not both")
        return self

    @property
    def given(self) -> bool:
        return self.force is not None or self.base_acceleration is not None

    def history(self) -> LoadHistory | None:
        """The :class:`~pdamper.coupling.loads.LoadHistory` (None: no load given)."""
        from pdamper.io.loads import read_load

        if self.force is not None:
            return read_load(self.force, "force")
        if self.base_acceleration is not None:
            return read_load(self.base_acceleration, "base_acceleration")
        return None


class SimulationSpec(_Section):
    model: str = Field(default="analytic", validation_alias=AliasChoices("model", "damper"))
    duration: Duration = paper.PAPER_DURATION
    sample_rate: Frequency = 2000.0


def _scheduler(v: str) -> str:
    """The address of a dask scheduler (:func:`pdamper.sweep.cluster.check_scheduler`)."""
    from pdamper.sweep.cluster import check_scheduler

    try:
        return check_scheduler(v)
    except InputError as exc:  # pydantic adds the location
        raise ValueError(exc.message) from None


def _tolerance(v: Any) -> float:
    from pdamper.design.study import parse_tolerance

    try:
        return parse_tolerance(v)
    except InputError as exc:  # pydantic adds the location
        raise ValueError(exc.message) from None


class OptimizationSpec(_Section):
    """The design study (:mod:`pdamper.design.study`); without ``vary``, the paper's
    particle-count study (Sect. 4.2.2)."""

    at: Duration = paper.PAPER_OBJECTIVE_TIME
    step: Annotated[int, Field(ge=1, strict=True)] | None = None
    objective: Literal["amplitude-at", "settling-time", "mean-damping",
                       "peak", "rms", "peak-frf", "rms-frf"] = "amplitude-at"
    #: frequencies of peak-frf and rms-frf, "start:stop:count" (default 0.5-1.5 times the
    #: first natural frequency in 41)
    band: str | None = None
    #: harmonic load of peak-frf and rms-frf: a force ("2 N", the default) or a base motion
    #: ("1 mm", "0.3 g")
    frf_load: str | None = None

    def frf_band(self):
        """The frequencies [Hz] of ``band`` (None: the objective's default)."""
        return None if self.band is None else grid(self.band, "Hz", "optimization.band")
    vary: list[str] = []
    method: Literal["auto", "grid", "optimize"] = "auto"
    threshold: PositiveLength | None = None
    workers: Annotated[int, Field(ge=0, strict=True)] | Literal["auto"] = "auto"
    scheduler: Annotated[str, AfterValidator(_scheduler)] | None = None
    max_evaluations: Annotated[int, Field(ge=4, strict=True)] = DEFAULT_MAX_EVALUATIONS
    max_grid: Annotated[int, Field(ge=1, strict=True)] = DEFAULT_MAX_GRID
    seed: Annotated[int, Field(ge=0, strict=True)] = 0
    tolerance: Annotated[float, BeforeValidator(_tolerance)] = DEFAULT_TOLERANCE

    def variables(self) -> list[DesignVariable]:
        """The parsed :class:`~pdamper.design.DesignVariable` objects of ``vary`` (judge
        their sizes first: :meth:`Scenario.check_resources` with ``"optimization"``)."""
        if not self.vary:  # no import of Level III for the commands that do not optimise
            return []
        from pdamper.design.study import parse_variable

        return [parse_variable(v) for v in self.vary]

    def sizes(self) -> list[tuple[str, float]]:
        """``(name, number of values)`` of each ``vary`` entry, every entry checked,
        nothing built (:func:`pdamper.design.study.variable_size`)."""
        from pdamper.design.study import variable_size

        return [variable_size(v) for v in self.vary]


def _range_text(spec: tuple[float, float, int], unit: str, scale: float) -> str:
    a, b, n = spec
    return f"{a * scale:g}{unit}:{b * scale:g}{unit}:{n}"


def _grid(unit: str):
    def check(v: str) -> str:
        try:
            parse_axis(v, unit, "value")
        except InputError as exc:  # pydantic adds the location
            raise ValueError(exc.message) from None
        return v

    return AfterValidator(check)


#: Grid of the DEM map of ``pdamper paper`` (5 x 7 points with X_opt = 32 mm on it: a few
#: minutes on two cores; the paper's 14 x 24 grid is ``pdamper map --model dem``).
CASE_STUDY_DEM_FREQUENCY = "4Hz:20Hz:5"
CASE_STUDY_DEM_AMPLITUDE = "log:2mm:128mm:7"
#: Initial packing of the DEM runs of a map: random where every sphere can be placed at
#: random ("auto"; denser beds start from the lattice, where random addition jams). The
#: paper's ideal lattice bed moves in an exact mirror symmetry for 10 to more than 60 cycles,
#: a state of the idealisation that a map cell must not show (docs/fields.md); a random bed
#: is steady after ~14 cycles.
MAP_DEM_PACKING = "auto"


class MapSpec(_Section):
    """Level II grids: ``"start:stop:count"``, ``"log:start:stop:count"`` (geometric
    spacing) or one value."""

    frequency: Annotated[str, _grid("Hz")] = _range_text(paper.PAPER_MAP_FREQUENCY, "Hz", 1.0)
    amplitude: Annotated[str, _grid("m")] = _range_text(paper.PAPER_MAP_AMPLITUDE, "mm", 1e3)
    particles: str | Count | None = None
    dem_frequency: Annotated[str, _grid("Hz")] = CASE_STUDY_DEM_FREQUENCY
    dem_amplitude: Annotated[str, _grid("m")] = CASE_STUDY_DEM_AMPLITUDE
    dem_packing: str | None = MAP_DEM_PACKING


class FieldsSpec(_Section):
    """Options of the effective-field model (:class:`pdamper.models.EffectiveFieldDamper`).

    A relative ``file`` in a scenario file is taken relative to that file's directory.
    """

    file: str | None = None
    extrapolation: Literal["error", "clamp", "analytic"] = "error"
    interpolate: Literal["loss_factor", "dissipated_energy"] = "loss_factor"
    nonstationary: Literal["mask", "use"] = "mask"
    strict: bool = True

    @field_validator("file")
    @classmethod
    def _exists(cls, v):
        if v is not None and not Path(v).is_file():
            raise ValueError(f"file not found: {v}")
        return v

    def options(self) -> dict:
        """Keyword arguments of :class:`pdamper.models.EffectiveFieldDamper`."""
        return self.model_dump()


#: Settings of the DEM damper that the scenario takes from another section.
DEM_SET_ELSEWHERE = {"gravity": "excitation.gravity"}
#: Keys of ``[dem]`` that are not settings of the DEM damper: the constant CORs of the damper
#: (or ``[restitution]``).
DEM_SCENARIO_ONLY = ("restitution_pp", "restitution_pw")
#: ``[dem.<table>]``: the settings of one concern in a table of its own, the canonical form
#: (:data:`~pdamper.models.settings.CONCERN_NAMES`); flat ``[dem]`` keys and the old table
#: names of :data:`DEM_TABLE_ALIASES` are aliases.
DEM_TABLES: dict[str, type[Settings]] = dict(CONCERN_NAMES)
#: Old names of the ``[dem.<table>]`` tables -> their canonical name.
DEM_TABLE_ALIASES = {"steady_state": "steady", "accuracy_target": "accuracy"}


def _elsewhere(name: str) -> str:
    section, _, key = DEM_SET_ELSEWHERE[name].partition(".")
    return f"is set by [{section}] {key}"


class DEMSpec(DEMSettings):
    """Options of the DEM model (``pdamper dem``, ``--model dem``), one table per concern:
    ``[dem.plan]``, ``[dem.steady]``, ``[dem.accuracy]``, ``[dem.contact]`` and
    ``[dem.engine]`` (:class:`~pdamper.models.settings.DEMSettings`; g is ``[excitation]
    gravity``, the seed and the transient tolerance are ``[dem.plan]``'s). Each key may
    also be written flat in ``[dem]`` (``cycles = 8`` is ``[dem.plan] cycles = 8``), the
    old tables ``[dem.steady_state]`` and ``[dem.accuracy_target]`` are
    ``[dem.steady]`` and ``[dem.accuracy]``; a key given twice is an error, a command-line
    option replaces the key in whichever form the file gives it. ``restitution_pp`` and
    ``restitution_pw``: constant CORs (or ``[restitution]``)."""

    model_config = ConfigDict(extra="forbid", frozen=True, validate_default=False)

    restitution_pp: Restitution = _D.restitution_pp.e  # type: ignore[union-attr]
    restitution_pw: Restitution = _D.restitution_pw.e  # type: ignore[union-attr]

    @classmethod
    def _edge_concern(cls, concern: str, values: dict[str, Any]) -> dict[str, Any]:
        decls = DEM_TABLES[concern].declarations()
        out = {}
        for name, value in values.items():
            unit = decls[name]["unit"] if name in decls else ""
            out[name] = (parse_quantity(value, unit, name)
                         if unit and value is not None else value)
        return out

    @classmethod
    def canonical(cls, data: dict[str, Any]) -> dict[str, Any]:
        """``data`` as given in the file with the old table names made canonical; refuses
        the settings another section sets (:data:`DEM_SET_ELSEWHERE`)."""
        out: dict[str, Any] = {}
        for key, value in data.items():
            table = DEM_TABLE_ALIASES.get(key, key)
            if table in DEM_TABLES and isinstance(value, dict):
                if table in out:
                    raise InputError("dem", f"[dem.{table}] given twice (also as [dem.{key}])")
                for name in value:
                    if name in DEM_SET_ELSEWHERE:
                        raise InputError(cls.prefix + name, _elsewhere(name))
                out[table] = value
            elif key not in FLAT and key not in DEM_SCENARIO_ONLY and "__" not in key \
                    and key not in DEM_TABLES:
                raise InputError(cls.prefix + key, "unknown key (check the spelling; `pdamper "
                                 "example-scenario` lists the keys)")
            elif key in DEM_SET_ELSEWHERE:
                raise InputError(cls.prefix + key, _elsewhere(key))
            else:
                out[key] = value
        return out

    @model_validator(mode="before")
    @classmethod
    def _tables(cls, data: Any) -> Any:
        if not isinstance(data, dict):
            return data
        return cls.concerns_of(cls.canonical(data))

    def __init__(self, **data: Any) -> None:
        try:
            BaseModel.__init__(self, **data)
        except ValidationError as exc:
            raise _first_error(exc) from None

    @classmethod
    def override(cls, section: dict[str, Any], name: str, value: Any) -> None:
        """Set setting ``name`` (a flat name, ``concern.name`` or ``concern__name``) to
        ``value`` in the ``[dem]`` table ``section`` as read from a file, replacing it in
        whichever form the file gives it (flat, ``[dem.<concern>]`` or an old table name):
        a command-line option overrides the file."""
        aliases = cls.aliases()
        canonical = aliases.get(name) or aliases.get(name.replace(".", "__")) or name
        if canonical not in DEMSettings.declarations():
            section[name] = value  # not a setting: validated (and refused) as given
            return
        concern, _, key = canonical.partition(".")
        flat = FLAT_NAME[(concern, key)]
        section.pop(flat, None)
        tables = [t for t in (concern, *(a for a, c in DEM_TABLE_ALIASES.items()
                                         if c == concern)) if isinstance(section.get(t), dict)]
        for table in tables:
            section[table].pop(key, None)
            section[table].pop(flat, None)
        # into the table the file writes the concern in (an old name stays the one table)
        target = tables[0] if tables else concern
        section.setdefault(target, {})
        if not isinstance(section[target], dict):
            raise InputError(f"dem.{target}", "must be a table")
        section[target][key] = value

    @classmethod
    def declarations(cls) -> dict[str, dict]:
        """Every key of the section under its canonical dotted name (``"engine.
        gear_tolerance"``, ``"restitution_pp"``) with ``unit``, ``kind``, range, ``doc`` and
        ``default``; the other names are in :meth:`aliases`."""
        out = {k: v for k, v in DEMSettings.declarations().items()
               if v["name"] not in DEM_SET_ELSEWHERE}
        for name in DEM_SCENARIO_ONLY:
            f = cls.model_fields[name]
            out[name] = {"unit": "", "kind": "number", "low": 0.0, "high": 1.0,
                         "low_inclusive": True, "high_inclusive": True, "choices": [],
                         "infinite": False, "none": "", "doc": f.description or
                         "Constant coefficient of restitution (or [restitution]).",
                         "default": f.default, "concern": "", "name": name}
        return out

    @classmethod
    def aliases(cls) -> dict[str, str]:
        """Alias -> canonical dotted name: flat keys (``cycles`` -> ``plan.cycles``), the old
        tables (``steady_state.steady_windows`` -> ``steady.windows``) and
        ``concern__name``."""
        decls = cls.declarations()
        out = {k: v for k, v in DEMSettings.aliases().items() if v in decls}
        for old, new in DEM_TABLE_ALIASES.items():
            for k, decl in decls.items():
                if k.startswith(new + "."):
                    out[f"{old}.{k.partition('.')[2]}"] = k
                    out[f"{old}.{decl['name']}"] = k  # the old tables' flat names
        return out

    @model_serializer(mode="wrap")
    def _flat_dump(self, handler: Any) -> dict[str, Any]:
        # the section's values written flat, under the keys the JSON outputs and the map
        # files' keys have always used
        data = handler(self)
        out = {name: data[name] for name in DEM_SCENARIO_ONLY}
        for name, concern in FLAT.items():
            if name not in DEM_SET_ELSEWHERE:
                out[name] = data[concern][FIELD[name]]
        return out

    @classmethod
    def flat_fields(cls) -> dict[str, FieldInfo]:
        """Every key of the section by its flat name (the constant CORs included)."""
        return {**{n: cls.model_fields[n] for n in DEM_SCENARIO_ONLY},
                **{n: f for n, f in DEMSettings.flat_fields().items()
                   if n not in DEM_SET_ELSEWHERE}}

    def options(self) -> dict:
        """Keyword arguments of :class:`pdamper.models.DEMDamper`: the five concerns."""
        return {name: getattr(self, name) for name in DEM_TABLES}


class Scenario(_Section):
    """A complete scenario; every section is optional and defaults to the paper's case.

    A section named after a damper fidelity (``[dem]``, ``[fields]``) holds that model's
    options.
    """

    title: str = "paper benchmark damper"
    container: ContainerSpec = ContainerSpec()
    particles: ParticlesSpec = ParticlesSpec()
    excitation: ExcitationSpec = ExcitationSpec()
    structure: StructureSpec = StructureSpec()
    simulation: SimulationSpec = SimulationSpec()
    optimization: OptimizationSpec = OptimizationSpec()
    map: MapSpec = MapSpec()
    fields: FieldsSpec = FieldsSpec()
    dem: DEMSpec = DEMSpec()
    restitution: RestitutionSpec = RestitutionSpec()
    load: LoadSpec = LoadSpec()
    #: inputs given as "value +- sd" (field -> UncertainInput; pdamper.io.uncertain)
    _uncertain: dict = PrivateAttr(default_factory=dict)

    def uncertain_inputs(self) -> tuple:
        """The :class:`~pdamper.design.uncertainty.UncertainInput` of every value given
        as ``"value +- sd"`` (:mod:`pdamper.io.uncertain`), in the file's order."""
        return tuple(self._uncertain.values())

    # -- builders of the domain objects ------------------------------------------------
    def damper(self) -> ParticleDamper:
        """The :class:`~pdamper.damper.ParticleDamper` this scenario describes."""
        from pdamper.damper import ParticleDamper

        c, p = self.container, self.particles
        sphere = _material(p.material, "particles.material")
        wall = _material(c.material, "container.material")
        pp, pw = self.restitution_curves(sphere, wall, p.radius)
        return ParticleDamper(length=c.length, width=c.width, depth=c.depth,
                              particle_radius=p.radius, count=p.count,
                              particle_material=sphere, wall_material=wall,
                              container_mass=c.mass, friction=p.friction,
                              restitution_pp=pp, restitution_pw=pw)

    def restitution_curves(self, sphere: Material, wall: Material,
                           radius: float) -> tuple[RestitutionCurve, ...]:
        """COR curves ``(sphere-sphere, sphere-wall)`` of spheres of ``sphere`` material and
        ``radius`` [m] in a container of ``wall`` material.

        Precedence: an entry of ``[restitution]``; else ``[dem] restitution_pp / _pw`` (a
        constant; default the benchmark's 0.6 / 0.85). Giving one pair in both places is an
        error (docs/restitution.md).
        """
        from pdamper.contact.restitution import ConstantRestitution
        from pdamper.io.restitution import build_curve

        curves: list[RestitutionCurve] = []
        for pair, legacy, partner in (("particle_particle", "restitution_pp", sphere),
                                      ("particle_wall", "restitution_pw", wall)):
            spec = getattr(self.restitution, pair)
            if spec is None:
                curves.append(ConstantRestitution(getattr(self.dem, legacy)))
                continue
            if legacy in self.dem.model_fields_set:
                raise InputError(f"restitution.{pair}", f"also given as dem.{legacy}; give "
                                 "the COR of a pair in one place ([restitution] for curves)")
            curves.append(build_curve(spec, pair, sphere, partner, radius))
        return tuple(curves)

    def structure_model(self) -> SingleDOFStructure | ModalStructure:
        """The :class:`~pdamper.structure.SingleDOFStructure` of Eq. (23) (M defaults to the
        paper's, see :mod:`pdamper.parameters.vertical_dampers_paper`), or the
        :class:`~pdamper.structure.modal.ModalStructure` of ``[structure] modes`` or
        ``beam``."""
        from pdamper.structure import SingleDOFStructure

        s = self.structure
        if s.modes is not None:
            from pdamper.io.modes import read_modes

            return read_modes(s.modes)
        if s.beam is not None:
            return s.beam.structure()
        return SingleDOFStructure(mass=paper.PAPER_MASS if s.mass is None else s.mass,
                                  damping=s.damping, stiffness=s.stiffness)

    def model(self, name: str | None = None,
              damper: ParticleDamper | None = None) -> DamperModel:
        """The damper model of fidelity ``name`` (default ``[simulation] model``) for
        ``damper`` (default :meth:`damper`), with the options of its section."""
        from pdamper.models import get_damper_model

        field = "model" if name is not None else "simulation.model"
        cls = get_damper_model(self.simulation.model if name is None else name, field)
        section: Any = getattr(self, cls.fidelity, None)
        options = section.options() if hasattr(section, "options") else {}
        if cls.takes_gravity:
            options["gravity"] = self.excitation.gravity
        return cls(self.damper() if damper is None else damper, **options)

    def for_map(self) -> Scenario:
        """This scenario as a map computes it: ``[dem] packing`` replaced by ``[map]
        dem_packing`` (unless that is None)."""
        if self.map.dem_packing is None:
            return self
        return self.model_copy(update={"dem": self.dem.clone(packing=self.map.dem_packing)})

    def map_model(self, name: str, damper: ParticleDamper | None = None) -> DamperModel:
        """The damper model of a map: :meth:`model` of :meth:`for_map`."""
        try:
            return self.for_map().model(name, damper)
        except InputError as exc:
            if exc.field == "dem.packing" and self.map.dem_packing is not None:
                raise InputError("map.dem_packing", exc.message) from None
            raise

    def map_ranges(self) -> tuple[tuple[float, float, int], tuple[float, float, int]]:
        """``(start, stop, count)`` of the frequency [Hz] and amplitude [m] axes of
        ``[map]``, without building the grid."""
        return (parse_axis(self.map.frequency, "Hz", "map.frequency")[:3],
                parse_axis(self.map.amplitude, "m", "map.amplitude")[:3])

    def map_grid(self) -> tuple[np.ndarray, np.ndarray]:
        """The Level II grid ``(frequency [Hz], amplitude [m])`` of ``[map]`` (check its
        size first: :meth:`check_resources` with ``"map"``)."""
        return (grid(self.map.frequency, "Hz", "map.frequency"),
                grid(self.map.amplitude, "m", "map.amplitude"))

    def map_particles(self) -> np.ndarray | None:
        """The particle-count axis of ``[map] particles`` (None: the one count of
        ``[particles]``)."""
        if self.map.particles is None:
            return None
        return count_grid(self.map.particles, "map.particles")

    def dem_map_grid(self) -> tuple[np.ndarray, np.ndarray]:
        """The grid of the case study's DEM map (``[map] dem_frequency, dem_amplitude``)."""
        return (grid(self.map.dem_frequency, "Hz", "map.dem_frequency"),
                grid(self.map.dem_amplitude, "m", "map.dem_amplitude"))


    # -- what the runs imply ------------------------------------------------------------
    def check_physics(self, damper: ParticleDamper | None = None) -> None:
        """Refuse what has no physical meaning in any model (:mod:`pdamper.resources`):
        spheres too small, strokes too long, impacts too fast, excitations faster than a
        contact, in ``[particles]``, ``[excitation]``, ``[structure]`` and ``[map]``."""
        d = self.damper() if damper is None else damper
        resources.check_particles(d)
        g = self.excitation.gravity
        resources.check_motion(d, self.excitation.frequency, self.excitation.amplitude,
                               usual=_USUAL_EXCITATION, gravity=g)
        resources.check_release(d, self.structure_model().natural_frequency,
                                self.structure.initial_displacement, gravity=g)
        (f0, f1, _), (x0, x1, _) = self.map_ranges()
        resources.check_grid(d, (f0, f1), (x0, x1), usual=_USUAL_EXCITATION, gravity=g)

    def check_resources(self, run: str, model: str | None = None, force: bool = False,
                        require: Callable[..., Any] | None = None) -> None:
        """Refuse a run whose implied memory or time is above the limits of
        :mod:`pdamper.resources` (``force``: up to the hard limits), or for which its
        model's physics does not hold (the DEM's contact law).

        Parameters
        ----------
        run
            ``"excitation"`` (Level II at ``[excitation]``), ``"map"`` (Level II over
            ``[map]``), ``"simulation"`` (Level III, ``[simulation]``), ``"optimization"``
            (``[optimization]``), ``"case_study"`` or ``"case_study_dem"`` (the paper's,
            without or with the DEM model 1 run).
        model
            Damper fidelity of ``excitation``, ``map`` and ``simulation`` (default
            ``"analytic"``; for ``simulation`` and ``optimization`` the ``[simulation]``
            model).
        force
            Allow more than the limits, up to what this machine can hold.
        require
            The judge of each cost, ``require(cost, force)`` (default
            :func:`pdamper.resources.require`; e.g. one that counts N realisations of a run).

        Examples
        --------
        >>> s = load_scenario(None, {"map.frequency": "2Hz:20Hz:10000"})
        >>> try:
        ...     s.check_resources("map")
        ... except InputError as exc:
        ...     print(exc.field, "--force" in exc.message)
        map.frequency True
        """
        from pdamper.models import get_damper_model

        if run not in _RUNS:
            raise InputError("run", f"must be one of {', '.join(_RUNS)}, got {run!r}")
        req = resources.require if require is None else require
        damper = self.damper()
        default = Scenario()
        field = "model" if model else "simulation.model"
        if run == "excitation":
            cost = self.excitation_cost(model or "analytic", damper)
            if cost is not None:
                req(cost, force)
        elif run == "map":
            self._check_map(damper, get_damper_model(model or "analytic", "model"), default,
                            force, req)
        elif run == "simulation":
            cls = get_damper_model(model or self.simulation.model, field)
            self._check_simulation(damper, cls, self.simulation.duration,
                                   self.simulation.sample_rate, default, force, req)
        elif run == "optimization":
            cls = get_damper_model(model or self.simulation.model, field)
            self._check_optimization(damper, cls, default, force, req)
        else:  # the paper's case study (pdamper.reports.paper_case_study)
            analytic = get_damper_model("analytic")
            self._check_map(damper, analytic, default, force, req)
            for duration in (self.simulation.duration,
                             max(self.simulation.duration, paper.PAPER_DURATION)):
                self._check_simulation(damper, analytic, duration,
                                       self.simulation.sample_rate, default, force, req)
            self._check_optimization(damper, analytic, default, force, req)
            if run == "case_study_dem":
                self._check_simulation(damper, get_damper_model("dem"),
                                       self.simulation.duration,
                                       self.simulation.sample_rate, default, force, req)

    def settings_of(self, cls: type[DamperModel]) -> Any:
        """The section of the scenario that holds the settings of fidelity ``cls`` (None:
        it has none)."""
        return getattr(self, cls.fidelity, None)

    def excitation_cost(self, model: str = "analytic",
                        damper: ParticleDamper | None = None) -> resources.Cost | None:
        """What one Level II response of fidelity ``model`` at ``[excitation]`` costs
        (:meth:`pdamper.models.DamperModel.excitation_cost`; None: not worth judging), for
        ``damper`` (default :meth:`damper`)."""
        from pdamper.models import get_damper_model

        cls = get_damper_model(model, "model")
        d = self.damper() if damper is None else damper
        return cls.excitation_cost(d, self.excitation.frequency, self.excitation.amplitude,
                                   self.settings_of(cls), gravity=self.excitation.gravity,
                                   usual=_USUAL_EXCITATION,
                                   damper_drivers=self._damper_drivers(d, Scenario()))

    @staticmethod
    def _damper_drivers(damper, default) -> list[tuple]:
        dm = default.damper()
        return [("particles.count", damper.count / dm.count),
                ("particles.radius", dm.particle_radius / damper.particle_radius, True)]

    def _check_map(self, damper, cls, default, force: bool, req: Callable[..., Any]) -> None:
        (f0, f1, nf), (x0, x1, nx) = self.map_ranges()
        (_, _, nf0), (_, _, nx0) = default.map_ranges()
        counts = self.map_particles()
        axes = (("map.frequency", nf / nf0), ("map.amplitude", nx / nx0),
                ("map.particles", 1.0 if counts is None else float(counts.size)))
        points = float(nf) * float(nx) * (1.0 if counts is None else float(counts.size))
        # the grid and the four result arrays, whichever the model
        req(resources.Cost("the map", 0.0, points * 40.0,
                                         f"{points:.3g} points", axes), force)
        req(cls.map_cost(damper, (f0, f1, nf), (x0, x1, nx), points,
                                       self.settings_of(cls), gravity=self.excitation.gravity,
                                       usual=_USUAL_EXCITATION, axes=axes,
                                       damper_drivers=self._damper_drivers(damper, default)),
                          force)

    def _check_simulation(self, damper, cls, duration: float, sample_rate: float,
                          default, force: bool, req: Callable[..., Any]) -> None:
        structure = self.structure_model()
        ds = default.simulation
        drivers = [("simulation.duration", duration / ds.duration),
                   ("simulation.sample_rate", sample_rate / ds.sample_rate),
                   ("structure.stiffness", structure.natural_frequency
                    / default.structure_model().natural_frequency)]
        req(cls.free_vibration_cost(
            damper, duration, sample_rate, structure.natural_frequency, self.settings_of(cls),
            x0=self.structure.initial_displacement, drivers=drivers,
            damper_drivers=self._damper_drivers(damper, default)), force)

    def _check_optimization(self, damper, cls, default, force: bool,
                            req: Callable[..., Any]) -> None:
        """Cost of the design study (:func:`pdamper.design.optimize_design`): one free
        vibration of ``at`` plus two periods, sampled at 200 Hz, per candidate (the
        particle counts of the paper's study, the grid of ``vary``, or the optimiser's
        budget), and the values of each varied variable, judged from their numbers before
        they are built."""
        from pdamper.design.study import USUAL_VALUES, values_cost, variable_field

        structure = self.structure_model()
        o = self.optimization
        at = o.at
        duration = at + 2.0 / structure.natural_frequency
        d0 = default.damper()
        step = o.step or damper.per_layer
        counts = range(0, damper.max_count, step)
        drivers: tuple = (("optimization.at", at / default.optimization.at),)
        if o.vary:
            sizes = o.sizes()
            for name, size in sizes:
                req(values_cost(name, size), force)
            grid = math.prod(size for _, size in sizes)
            method = o.method
            if method == "auto":
                method = "grid" if grid <= o.max_grid else "optimize"
            if method == "grid" and math.isfinite(grid):
                candidates = grid
                drivers += tuple((variable_field(name), size / USUAL_VALUES)
                                 for name, size in sizes)
            else:
                candidates = o.max_evaluations
                drivers += (("optimization.max_evaluations",
                             candidates / default.optimization.max_evaluations),)
        else:
            candidates = len(counts)
            drivers += (("optimization.step", (d0.per_layer / step)
                         * (damper.max_count / d0.max_count), True),)
        # one candidate; where the time grows with the count, the mean count stands for all
        one = cls.free_vibration_cost(damper, duration, 200.0, structure.natural_frequency,
                                      self.settings_of(cls),
                                      x0=self.structure.initial_displacement,
                                      count=max(1, round(counts[-1] / 2)) if counts else 1)
        req(resources.Cost(
            "the optimisation", one.seconds * candidates,
            one.memory + candidates * resources.BYTES_PER_CANDIDATE,
            f"{candidates:.3g} candidates, each {one.detail}", drivers,
            runs=int(min(candidates, 2**62)), longest=one.seconds), force)


def grid(text: str, unit: str, field: str) -> np.ndarray:
    """A grid from ``"start:stop:count"`` (linear), ``"log:start:stop:count"`` (geometric)
    or one quantity; values must be > 0.

    >>> grid("log:1mm:100mm:3", "m", "map.amplitude").round(4).tolist()
    [0.001, 0.01, 0.1]
    """
    import numpy as np

    a, b, n, log = parse_axis(text, unit, field)
    return np.geomspace(a, b, n) if log else np.linspace(a, b, n)


def parse_axis(text: str, unit: str, field: str) -> tuple[float, float, int, bool]:
    """``(start, stop, count, log)`` of a grid axis (see :func:`grid`), checked, without
    building it; values must be > 0."""
    log = isinstance(text, str) and text.strip().lower().startswith("log:")
    body = text.strip()[4:] if log else text
    a, b, n = parse_range(body, unit, field)
    if min(a, b) <= 0:
        raise InputError(field, f"grid values must be > 0, got {min(a, b):g}")
    return a, b, n, log


def count_grid(value: Any, field: str) -> np.ndarray:
    """Whole particle counts from ``N``, ``"start:stop:count"`` or ``"log:..."`` (rounded;
    counts must be >= 1 and distinct).

    >>> count_grid("16:96:6", "map.particles").tolist()
    [16, 32, 48, 64, 80, 96]
    """
    import numpy as np

    if isinstance(value, int) and not isinstance(value, bool):
        counts = np.array([value])
    else:
        text = str(value).strip()
        log = text.lower().startswith("log:")
        body = text[4:] if log else text
        parts = body.split(":")
        try:
            nums = [float(p) for p in parts]
        except ValueError:
            raise InputError(field, f"expected N, 'start:stop:count' or 'log:start:stop:count' "
                             f"of particle counts, got {value!r}") from None
        if len(parts) == 1:
            raw = np.array(nums)
        elif len(parts) == 3 and nums[2] == int(nums[2]) and 1 <= nums[2] <= 100_000:
            if min(nums[:2]) <= 0 and log:
                raise InputError(field, f"log spacing needs counts > 0, got {value!r}")
            raw = (np.geomspace if log else np.linspace)(nums[0], nums[1], int(nums[2]))
        else:
            raise InputError(field, f"expected N, 'start:stop:count' or 'log:start:stop:count' "
                             f"of particle counts, got {value!r}")
        counts = np.rint(raw)
        if not log and np.any(np.abs(raw - counts) > 1e-9):
            raise InputError(field, f"{value!r} gives counts that are not whole: "
                             f"{', '.join(f'{v:g}' for v in raw)}")
    counts = counts.astype(int)
    if np.any(counts < 1):
        raise InputError(field, f"particle counts must be >= 1, got {counts.min()}")
    if len(set(counts.tolist())) != counts.size:
        raise InputError(field, f"{value!r} gives repeated counts {counts.tolist()}")
    return counts


def _material(spec, field: str):
    from pdamper.materials import Material, get_material

    if isinstance(spec, MaterialSpec):
        return Material(spec.name, spec.youngs_modulus, spec.poisson_ratio, spec.density,
                        spec.yield_strength)
    return get_material(spec, field)


def _first_error(exc: ValidationError) -> InputError:
    errors = exc.errors()
    # a table where a union (``str | MaterialSpec``) allows a name or a table: the table's
    # own error names the sub-key, not "should be a valid string"
    err = next((e for e in errors if not (e["type"] == "string_type"
                                          and isinstance(e.get("input"), dict))), errors[0])
    cause = (err.get("ctx") or {}).get("error")
    if isinstance(cause, InputError):  # raised by a section's own checks: names its field
        return cause
    loc = ".".join(str(p) for p in err["loc"]
                   if str(p) not in ("str", "MaterialSpec", *COR_MODELS)
                   and not str(p).startswith("function-"))
    msg = err["msg"].removeprefix("Value error, ")
    union = [e for e in errors if e["loc"][:-1] == err["loc"][:-1]]
    if err["type"] == "string_type" and any(e["type"] == "model_type" for e in union):
        msg = (f"must be a name (e.g. \"S235\") or an inline table {{ name, youngs_modulus, "
               f"poisson_ratio, density }}, got {repr(err.get('input'))[:60]}")
    if err["type"] == "extra_forbidden":
        msg = "unknown key (check the spelling; `pdamper example-scenario` lists the keys)"
    elif "input" in err and err["type"] != "missing" and repr(err["input"]) not in msg \
            and "got" not in msg:
        got = repr(err["input"])
        msg = f"{msg} (got {got if len(got) <= 60 else got[:57] + '...'})"
    return InputError(loc or "scenario", msg)


def _validate(sc: Scenario) -> None:
    """Build what every section describes and check its physics (cheaply: no DEM run, no
    numba, no grid), so that its errors surface at load time whichever command reads the
    scenario."""
    damper = sc.damper()
    sc.structure_model()
    sc.map_ranges()
    parse_axis(sc.map.dem_frequency, "Hz", "map.dem_frequency")
    parse_axis(sc.map.dem_amplitude, "m", "map.dem_amplitude")
    counts = sc.map_particles()
    if counts is not None and counts.max() > damper.max_count:
        raise InputError("map.particles", f"counts must be in [1, {damper.max_count}] (n_max of "
                         f"this container), got {counts.max()}")
    sc.optimization.sizes()  # checked, not built: a range's size is judged by its run
    sc.map_model("dem", damper)
    sc.model(None, damper)
    sc.check_physics(damper)


def scenario_from_dict(data: dict) -> Scenario:
    """Validate a dict (parsed TOML) into a :class:`Scenario`; a value ``"value +- sd"``
    is validated as its nominal value and kept as an uncertain input
    (:meth:`Scenario.uncertain_inputs`, :mod:`pdamper.io.uncertain`)."""
    import copy

    from pdamper.io.uncertain import extract_uncertain

    data = copy.deepcopy(data)  # the caller's dict stays as given
    uncertain = extract_uncertain(data)
    try:
        sc = Scenario.model_validate(data)
    except ValidationError as exc:
        raise _first_error(exc) from None
    sc._uncertain = uncertain
    _validate(sc)
    return sc


def _read_toml(p: Path) -> dict:
    if not p.exists():
        raise InputError("scenario", f"file not found: {p}")
    if not p.is_file():
        raise InputError("scenario", f"{p} is not a regular file; give a scenario file")
    try:
        size = p.stat().st_size
        if size > resources.MAX_SCENARIO_BYTES:
            raise InputError("scenario", f"{p} has {size} bytes; a scenario file describes one "
                             f"damper in at most {resources.MAX_SCENARIO_BYTES} bytes")
        text = p.read_text(encoding="utf-8")
    except OSError as exc:
        raise InputError("scenario", f"cannot read {p}: {exc.strerror or exc}") from None
    except UnicodeDecodeError:
        raise InputError("scenario", f"{p} is not UTF-8 text") from None
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise InputError("scenario", f"malformed TOML in {p}: {exc}") from None
    except RecursionError:
        raise InputError("scenario", f"malformed TOML in {p}: tables or arrays nested too "
                         f"deeply") from None


def load_scenario(path: str | Path | None, overrides: dict | None = None, *,
                  runs: tuple[str, ...] = (), model: str | None = None,
                  force: bool = False) -> Scenario:
    """Load a scenario TOML file (or the defaults when ``path`` is None) and apply
    ``overrides`` given as ``{"section.key": value}`` (None values are skipped); then check
    what each of ``runs`` implies (:meth:`Scenario.check_resources` with ``model`` and
    ``force``).

    Examples
    --------
    >>> s = load_scenario(None, {"particles.count": 64, "excitation.frequency": "5 Hz"})
    >>> s.particles.count, s.excitation.frequency
    (64, 5.0)
    """
    data: dict = {}
    if path is not None:
        p = Path(path)
        data = _read_toml(p)
        resolve_files(data, p.parent)
        fields = data.get("fields")  # model 2's map, relative to the scenario file too
        if isinstance(fields, dict) and isinstance(fields.get("file"), str) \
                and not Path(fields["file"]).expanduser().is_absolute():
            fields["file"] = str((p.parent / fields["file"]).resolve())
        structure = data.get("structure")  # the modes file, relative to the scenario file
        if isinstance(structure, dict) and isinstance(structure.get("modes"), str) \
                and not Path(structure["modes"]).expanduser().is_absolute():
            structure["modes"] = str((p.parent / structure["modes"]).resolve())
        loads = data.get("load")  # the load history, relative to the scenario file
        if isinstance(loads, dict):
            for key in ("force", "base_acceleration"):
                if isinstance(loads.get(key), str) \
                        and not Path(loads[key]).expanduser().is_absolute():
                    loads[key] = str((p.parent / loads[key]).resolve())
    for key, value in (overrides or {}).items():
        if value is None:
            continue
        section, _, name = key.partition(".")
        node = data.setdefault(section, {})
        if not isinstance(node, dict):
            raise InputError(section, "must be a table")
        spec = Scenario.model_fields.get(section)
        override = getattr(spec.annotation if spec is not None else None, "override", None)
        if override is not None:  # the option wins over the key in whichever table form
            override(node, name, value)
        else:
            node[name] = value
    sc = scenario_from_dict(data)
    for run in runs:
        sc.check_resources(run, model, force)
    return sc


def _example() -> str:
    """The text of ``EXAMPLE_SCENARIO``: every section with its defaults, commented."""
    s = Scenario()
    return _example_levels(s) + _example_study(s) + _example_dem(s)


def _example_levels(s: Scenario) -> str:
    """The example's head and its Level II and III sections (damper, excitation,
    structure)."""
    c, p, x, st = s.container, s.particles, s.excitation, s.structure
    q = format_quantity
    return f"""\
# pdamper scenario: the reference paper's benchmark damper on its beam-like structure.
# Every quantity carries its unit ("120 mm", "10 Hz", "7900 kg/m^3"); bare numbers are SI.
# Every section and key is optional; what is left out takes the value shown here.
title = "{s.title}"

[container]                 # cuboid particle container, inner dimensions
length = "{q(c.length, 'mm')}"           # along the excitation (vertical), L in h = L (1 - n_p/n_max)
width = "{q(c.width, 'mm')}"
depth = "{q(c.depth, 'mm')}"
material = "{c.material}"            # a library name (docs/materials.md: "S235", "POM", ...) or inline:
# material = {{ name = "my PMMA", youngs_modulus = "3.2 GPa", poisson_ratio = 0.35,
#              density = "1190 kg/m^3", yield_strength = "70 MPa" }}   # (one line in TOML)
mass = "{q(c.mass, 'kg')}"               # m_con, subtracted in Eq. (4) when a driving force includes it

[particles]
count = {p.count}                  # n_p; at most n_max (16 per layer x 12 layers = 192 here)
radius = "{q(p.radius, 'mm')}"
material = "{p.material}"
friction = {p.friction}              # sliding friction coefficient mu of every contact (DEM)
# friction = "0.1 +- 0.03"  # a value with its standard deviation (also lengths, masses, ...):
#                           # --uncertainty N samples it (docs/design.md)

[excitation]                # Level II: x_c = X sin(2 pi f t)
frequency = "{q(x.frequency, 'Hz')}"
amplitude = "{q(x.amplitude, 'mm')}"         # stroke X
gravity = "{q(x.gravity, 'm/s^2')}"        # g; "0 m/s^2" for a structure in orbit (analytic and DEM)

[structure]                 # Level III: M x'' + D x' + K x = F (Eq. 23)
# mass = "{q(paper.PAPER_MASS, 'kg')}"       # default K / (2 pi {paper.PAPER_EIGENFREQUENCY} Hz)^2: \
the printed {paper.PAPER_PRINTED_MASS} kg is inconsistent
stiffness = "{q(st.stiffness, 'N/m')}"
damping = "{q(st.damping, 'kg/s')}"
initial_displacement = "{q(st.initial_displacement, 'mm')}"   # at the damper's point
# Instead of mass, stiffness and damping (leave those out), N modes (docs/structure.md):
# modes = "modes.csv"       # one row per mode, unit headers (relative to this file):
#                           # frequency [Hz], damping ratio [1], damper [kg^-0.5](, observation [kg^-0.5])
# or the Timoshenko cantilever of Sect. 4.1 (every key optional; defaults: the paper's beam):
# beam = {{ length = "{q(_BEAM.length, 'mm')}", width = "{q(_BEAM.width, 'mm')}", \
height = "{q(_BEAM.height, 'mm')}", youngs_modulus = "{q(_BEAM.youngs_modulus, 'GPa')}", \
poisson_ratio = {_BEAM.poisson_ratio}, density = "{q(_BEAM.density, 'kg/m^3')}", \
elements = {_BEAM.elements}, tip_mass = "{q(_TIP.mass, 'kg')}", modes = 3, \
damper_position = "{q(_BEAM.length, 'mm')}", observation_position = "{q(_BEAM.length, 'mm')}", \
damping_ratio = {BeamSpec().damping_ratio:.4g} }}
#   (material = "S235" instead of youngs_modulus, poisson_ratio, density; damping_ratio: one
#   for all modes or a list, one per mode; positions from the clamp, default the tip)

"""


def _example_study(s: Scenario) -> str:
    """The example's sections of the simulation, the design study, the fields and the map."""
    q = format_quantity
    return f"""\
[simulation]
model = "{s.simulation.model}"          # damper fidelity: "analytic" (model 3), "fields" (2), "dem" (1)
duration = "{q(s.simulation.duration, 's')}"
sample_rate = "{q(s.simulation.sample_rate, 'Hz')}"     # of the stored trajectory

[optimization]
at = "{q(s.optimization.at, 's')}"                # objective: amplitude at this time after release
# step = 16                 # particle-count increment; default one layer
objective = "{s.optimization.objective}"    # or "settling-time", "mean-damping" (maximised)
# vary = ["particles=16:176:16", "radius=3mm:6mm:4"]   # design study; default: the count
method = "{s.optimization.method}"             # "grid" (brute force), "optimize" (scipy), or by size
# threshold = "14.5 mm"     # settling-time threshold; default |x0| / 4
workers = "{s.optimization.workers}"            # dask workers; "auto": 0 (in-process) for cheap models
max_evaluations = {s.optimization.max_evaluations}     # budget of the optimiser
max_grid = {s.optimization.max_grid}            # largest grid "auto" evaluates by brute force
seed = {s.optimization.seed}                    # seed of the optimiser
tolerance = "{s.optimization.tolerance * 100:g}%"              # lightest design this close to the best

[fields]                    # options of the effective-field model ("--model fields")
# file = "map.nc"           # map from `pdamper map` (relative to this file)
extrapolation = "{s.fields.extrapolation}"     # outside the map: "error", "clamp" or "analytic"
interpolate = "{s.fields.interpolate}"   # or "dissipated_energy"
nonstationary = "{s.fields.nonstationary}"      # non-stationary cells: "mask" (holes) or "use"
strict = {str(s.fields.strict).lower()}               # a map of another geometry is an error

[map]                       # Level II grids: "start:stop:count", "log:start:stop:count" or one value
frequency = "{s.map.frequency}"
amplitude = "{s.map.amplitude}"
# particles = "16:96:6"     # a particle-count axis (default: the one count of [particles])
dem_frequency = "{s.map.dem_frequency}"      # grid of the DEM map in "pdamper paper"
dem_amplitude = "{s.map.dem_amplitude}"
dem_packing = "{s.map.dem_packing}"           # initial packing of a map's DEM runs ("lattice",
                            # "random", "auto": random where it fits, else the lattice;
                            # the lattice's symmetric states are artefacts)

"""


def _example_dem(s: Scenario) -> str:
    """The example's sections of the DEM and the COR models."""
    q = format_quantity
    dem = s.dem
    _MODELS = " or ".join(f'"{m}"' for m in DAMPING_MODELS)  # noqa: N806
    return f"""\
[dem]                       # options of the DEM model ("pdamper dem", "--model dem")
integrator = "{dem.integrator}"         # "gear" (variable step, the paper's), "verlet", or "auto"
                            # (gear, handing over to verlet in jammed beds; docs/dem.md)
cycles = "{dem.cycles}"               # Level II: "auto" runs until the loss factor is steady;
                            # a number runs that many cycles (the paper: {PAPER_CYCLES})
skip_cycles = {dem.skip_cycles}             # cycles never averaged (complex power, Eqs. 1-4)
max_cycles = {dem.max_cycles}             # upper bound of a run until steady
window_cycles = {dem.window_cycles}           # steady: steady_windows windows of window_cycles cycles
steady_windows = {dem.steady_windows}          # whose loss factors agree within max(steady_rtol |eta|,
steady_rtol = {dem.steady_rtol}           # steady_atol), no trend, no symmetric lattice state
                            # (docs/fields.md)
steady_atol = {dem.steady_atol}
quiet_window_cycles = {dem.quiet_window_cycles}     # a quiet bed (cycle-to-cycle scatter below
quiet_scatter = {dem.quiet_scatter}         # quiet_scatter x the tolerance) is judged on
quiet_windows = {dem.quiet_windows}           # quiet_windows windows of quiet_window_cycles cycles
quiet_skip_cycles = {dem.quiet_skip_cycles}       # after min(quiet_skip_cycles, skip_cycles) cycles
                            # (quiet_window_cycles = 0: never; docs/fields.md)
# restitution_pp = {dem.restitution_pp}      # constant sphere-sphere COR (default; or [restitution])
# restitution_pw = {dem.restitution_pw}     # constant sphere-wall COR (default; or [restitution])
damping_model = "{dem.damping_model}"     # damping law of the normal force: {_MODELS}
# min_impact_velocity = "0.01 m/s"  # onset-speed floor of the exact/gonthier damping
# friction_model = "regularised"  # or "spring" (tangential spring, Coulomb limit; verlet/auto)
packing = "{dem.packing}"         # "lattice" (the paper's 4 x 4 layers), "random" or "auto"
seed = {dem.seed}                    # seed of the random packing (recorded always)
safety = {dem.safety}               # time step / Hertz contact time
sample_rate = "{q(dem.sample_rate, 'Hz')}"     # of the force and container series
# snapshot_rate = "200 Hz"  # particle snapshots per second (default: first and last)
error_estimate = {str(dem.error_estimate).lower()}     # estimate the integration error of eta and m_eff
                            # from a refined companion run (~2x the cost; docs/dem.md)
accuracy = {dem.accuracy.accuracy}             # its target (relative); a run missing it is redone
max_refinements = {dem.max_refinements}         # refined, at most this many times
gear_free_flight = {str(dem.gear_free_flight).lower()}    # Gear steps only spheres that may touch something,
                            # the others fly their exact parabola (docs/dem.md)
transient_tolerance = {dem.transient_tolerance}  # Gear tolerance of the start from rest (the cycles no
                            # window averages; 1e-5, Gear's own: none; docs/fields.md)

[restitution]               # COR model of each pair (Level I, docs/restitution.md), instead of the
                            # [dem] constants above (a pair given in both places is an error)
# particle_particle = "paper"                  # the paper's Fig. 2 curve (reconstructed from its text)
# particle_wall = 0.85                         # a constant
# particle_wall = "thornton"                   # Thornton 1997 from the materials' yield strength
# particle_wall = {{ model = "table", file = "cor.csv" }}   # rows "velocity [m/s], cor [-], std [-]"
# particle_wall = {{ model = "table", file = "cor.csv", fit = "exponential" }}  # "thornton", "linear"
# particle_wall = {{ model = "paper", scale = 1.5 }}        # e -> 1 - 1.5 (1 - e)
"""


@functools.cache
def _example_text() -> str:
    return _example()


def __getattr__(name: str) -> Any:
    # ``EXAMPLE_SCENARIO``: a commented scenario file with every key and its default
    # (``pdamper example-scenario``), written when first asked for: it formats every
    # quantity with its unit, which needs the unit registry, and most commands never print it
    if name == "EXAMPLE_SCENARIO":
        return _example_text()
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


@functools.cache
def example_scenario() -> Scenario:
    """The example scenario, parsed (it must equal the defaults)."""
    return scenario_from_dict(tomllib.loads(_example_text()))
