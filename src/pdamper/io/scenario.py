"""Scenario files: declarative TOML inputs with units, validated by pydantic.

Every quantity is written with its unit (``"120 mm"``, ``"7900 kg/m^3"``) and converted to
an SI float on load; a bare number is taken as SI. :func:`load_scenario` turns every
problem (malformed TOML, unknown unit, out-of-range value, unknown key, an error inside an
inline material table) into a one-line :class:`~pdamper.errors.InputError` naming the field.
Every section is validated on load, whichever command reads the scenario, by building the
objects it describes and by the physical checks of :mod:`pdamper.resources` (a ``[map]``
that is malformed or physically meaningless is an error for ``pdamper analytic`` too).
What a run implies (memory, time steps, grid points) is checked by
:func:`pdamper.runs.resources.check_resources` for the runs a command makes, before it
makes them.

The defaults are the reference paper's case (:mod:`pdamper.parameters`) and the models' own
defaults; nothing here restates a number.
"""

from __future__ import annotations

import functools
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
    model_validator,
)

from pdamper.constants import STANDARD_GRAVITY
from pdamper.damper import QUANTITIES, ParticleDamper
from pdamper.errors import InputError
from pdamper.io.damper_sections import ContainerSpec, MaterialSpec, ParticlesSpec
from pdamper.io.damper_sections import material as _material
from pdamper.io.dem_section import (  # noqa: F401  (importable from here)
    DEM_SCENARIO_ONLY,
    DEM_SET_ELSEWHERE,
    DEM_TABLE_ALIASES,
    DEM_TABLES,
    DEMSpec,
)
from pdamper.io.grids import _grid, _range_text, count_grid, grid, parse_axis
from pdamper.io.loads import FRFSpec, LoadSpec
from pdamper.io.quantities import (
    Count,
    Damping,
    Density,
    Duration,
    Frequency,
    Gravity,
    Length,  # noqa: F401  (a type of the schema, importable from here)
    Mass,
    Modulus,
    PositiveLength,
    PositiveMass,
    Stiffness,
    _q,
    _scheduler,
    _tolerance,
)
from pdamper.io.restitution import RestitutionSpec
from pdamper.parameters import vertical_dampers_paper as paper
from pdamper.resources import DEFAULT_MAX_EVALUATIONS, DEFAULT_MAX_GRID, DEFAULT_TOLERANCE
from pdamper.settings import setting

if TYPE_CHECKING:  # pragma: no cover
    import numpy as np

    from pdamper.contact.restitution import RestitutionCurve
    from pdamper.design.study import DesignVariable
    from pdamper.materials import Material
    from pdamper.models.base import DamperModel
    from pdamper.structure import SingleDOFStructure
    from pdamper.structure.modal import ModalStructure


_D = paper.PAPER_DAMPER


class _Section(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True, populate_by_name=True)


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
    #: where a force on the beam acts (a harmonic force, an unbalance, a force history),
    #: from the clamp; default the damper's point
    load_position: PositiveLength | None = None
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
        ``damper_position``, results at ``observation_position`` (both default the tip;
        :func:`pdamper.io.structure.beam_structure`)."""
        from pdamper.io.structure import beam_structure

        return beam_structure(self)

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
    includes_container_mass: bool | None = setting(
        None, "Whether the structure's data already include the container's mass "
        "([container] mass); where they do not, it is added at the damper point (1-DOF: "
        "M + m_c; modes and beam: the mass-modified eigenproblem, docs/structure.md). "
        "Unset: true for the 1-DOF and the beam, false for a modes file.",
        kind="flag", none="true for the 1-DOF of Eq. 23 and the beam (the paper's M and tip "
        "mass include the container), false for a modes file (a user's modes of the bare "
        "structure)")

    @model_validator(mode="after")
    def _one_structure(self):
        given = [k for k in ("modes", "beam") if getattr(self, k) is not None]
        if len(given) == 2:
            raise ValueError("give the structure as modes (a CSV file) or as a beam, not both")
        single = sorted({"mass", "stiffness", "damping"} & self.model_fields_set)
        if given and single:
            raise ValueError(f"{given[0]} describes the whole structure: leave out "
                             f"{', '.join(single)} (the 1-DOF of Eq. 23); a mode's "
                             "uncertain damping or frequency is mode<k>.damping_ratio or "
                             "mode<k>.frequency, e.g. mode1.damping_ratio")
        return self


class SimulationSpec(_Section):
    #: the damper's fidelity (:data:`pdamper.models.registry.DAMPER_MODELS`)
    model: str = Field(default="analytic", validation_alias=AliasChoices("model", "damper"),
                       json_schema_extra={"choices": ["analytic", "fields", "dem", "plastic"]})
    duration: Duration = paper.PAPER_DURATION
    sample_rate: Frequency = 2000.0


class OptimizationSpec(_Section):
    """The design study (:mod:`pdamper.design.study`); without ``vary``, the paper's
    particle-count study (Sect. 4.2.2)."""

    at: Duration = paper.PAPER_OBJECTIVE_TIME
    step: Annotated[int, Field(ge=1, strict=True)] | None = None
    objective: Literal["amplitude-at", "settling-time", "mean-damping",
                       "peak", "rms", "peak-frf", "rms-frf"] = "amplitude-at"
    #: frequencies of peak-frf and rms-frf, "start:stop:count" (default every mode of the
    #: structure, each resonance resolved for its damping: [frf] frequency's default)
    band: str | None = None
    #: harmonic load of peak-frf and rms-frf: a force ("2 N", the default), an unbalance
    #: ("1.76 kg*mm") or a base motion ("1 mm", "0.3 g")
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
    tolerance: Annotated[float, BeforeValidator(_tolerance), Field(json_schema_extra={
        "allowed": '>= 0, < 1 (a fraction, or a percentage: "5%")'})] = DEFAULT_TOLERANCE
    max_mass: float | None = setting(
        None, "Largest mass of a design, its bed and its container (container.mass) "
        "together, e.g. \"0.5 kg\"; a heavier design is infeasible, and the best and the "
        "lightest designs are chosen among the others.", unit="kg", low=0.0,
        low_inclusive=False, kind="number", none="no mass limit")
    #: response limits at the observation point, "QUANTITY<=VALUE" (or >=): the quantities
    #: the objective's runs compute, e.g. "peak-acceleration<=10g", "peak<=3mm"
    #: (pdamper.design.study.LIMIT_QUANTITIES); a design that violates one is infeasible
    require: Annotated[list[str], Field(json_schema_extra={
        "allowed": 'texts "QUANTITY<=VALUE" or "QUANTITY>=VALUE"'})] = []

    @field_validator("max_mass", mode="before")
    @classmethod
    def _declared_quantity(cls, value: Any, info) -> Any:
        """A quantity declared with :func:`pdamper.settings.setting`, read with its unit
        and checked against its declaration."""
        from pdamper.settings import check_setting, declaration
        from pdamper.units import parse_quantity

        decl = declaration(cls, info.field_name)
        try:
            if value is not None:
                value = parse_quantity(value, decl["unit"], info.field_name)
            return check_setting(info.field_name, value, decl)
        except InputError as exc:  # pydantic adds the location
            raise ValueError(exc.message) from None

    @field_validator("require", mode="after")
    @classmethod
    def _limits(cls, value: list[str]) -> list[str]:
        if value:  # no import of Level III for a scenario without limits
            from pdamper.design.study import parse_limit

            for text in value:
                try:
                    parse_limit(text)
                except InputError as exc:
                    raise ValueError(exc.message) from None
        return value

    @model_validator(mode="after")
    def _limits_of_the_objective(self):
        """A limit bounds what the objective's runs compute: judged on load, before any
        run of any command."""
        if self.require:
            from pdamper.design.study import LIMIT_QUANTITIES, parse_limit

            for text in self.require:
                lim = parse_limit(text)
                where = LIMIT_QUANTITIES[lim.quantity][2]
                if lim.quantity != "mass" and self.objective not in where:
                    raise InputError("optimization.require", f"{text!r}: {lim.quantity} is "
                                     f"computed by the objective(s) {', '.join(where)}, not "
                                     f"by {self.objective!r} (the limits bound what the "
                                     "objective's runs compute)")
        return self

    def variables(self) -> list[DesignVariable]:
        """The parsed :class:`~pdamper.design.DesignVariable` objects of ``vary`` (judge
        their sizes first: :func:`pdamper.runs.resources.check_resources` with
        ``"optimization"``)."""
        if not self.vary:  # no import of Level III for the commands that do not optimise
            return []
        from pdamper.design.study import parse_variable

        return [parse_variable(v) for v in self.vary]

    def sizes(self) -> list[tuple[str, float]]:
        """``(name, number of values)`` of each ``vary`` entry, every entry checked,
        nothing built (:func:`pdamper.design.study.variable_size`)."""
        from pdamper.design.study import variable_size

        return [variable_size(v) for v in self.vary]


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
    particles: Annotated[str | Count | None, Field(json_schema_extra={
        "allowed": '>= 1 (one count) or a grid "start:stop:count"'})] = None
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
    frf: FRFSpec = FRFSpec()
    #: inputs given as "value +- sd" (field -> UncertainInput; pdamper.io.uncertain)
    _uncertain: dict = PrivateAttr(default_factory=dict)
    #: modal parameters of a sample of the uncertain inputs (pdamper.io.uncertain)
    _modal: dict = PrivateAttr(default_factory=dict)

    def uncertain_inputs(self) -> tuple:
        """The :class:`~pdamper.design.uncertainty.UncertainInput` of every value given
        as ``"value +- sd"`` (:mod:`pdamper.io.uncertain`), in the file's order, after
        those its modes file writes (:func:`~pdamper.io.modes.file_inputs`)."""
        from pdamper.io.modes import file_inputs

        return tuple({**file_inputs(self), **self._uncertain}.values())

    # -- builders of the domain objects ------------------------------------------------
    def damper(self) -> ParticleDamper:
        """The :class:`~pdamper.damper.ParticleDamper` this scenario describes: every
        ``[container]`` and ``[particles]`` key is a quantity of the damper, given to the
        field its declaration names (:data:`~pdamper.damper.QUANTITIES`)."""
        values = {attribute: getattr(getattr(self, section), name)
                  for key, attribute in QUANTITIES.items()
                  for section, _, name in [key.partition(".")]
                  if section in ("container", "particles")}
        sphere = _material(values.pop("particle_material"), "particles.material")
        wall = _material(values.pop("wall_material"), "container.material")
        pp, pw = self.restitution_curves(sphere, wall, self.particles.radius)
        return ParticleDamper(**values, particle_material=sphere, wall_material=wall,
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
        """The structure of ``[structure]`` (:func:`pdamper.io.structure.structure_model`)."""
        from pdamper.io.structure import structure_model
        from pdamper.io.uncertain import modal_values, with_modes

        # the uncertain modal parameters (mode1.damping_ratio, ...) at their nominal value
        # or a sample's
        return with_modes(structure_model(self), modal_values(self))

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
        size first: :func:`pdamper.runs.resources.check_resources` with ``"map"``)."""
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

    def settings_of(self, cls: type[DamperModel]) -> Any:
        """The section of the scenario that holds the settings of fidelity ``cls`` (None:
        it has none)."""
        return getattr(self, cls.fidelity, None)


def scenario_from_dict(data: dict) -> Scenario:
    """Validate a dict (parsed TOML) into a :class:`Scenario`; a value ``"value +- sd"``
    is validated as its nominal value and kept as an uncertain input
    (:meth:`Scenario.uncertain_inputs`, :mod:`pdamper.io.uncertain`)."""
    import copy

    from pdamper.io.reading import first_error
    from pdamper.io.uncertain import extract_uncertain
    from pdamper.io.validation import validate

    data = copy.deepcopy(data)  # the caller's dict stays as given
    uncertain = extract_uncertain(data)
    try:
        sc = Scenario.model_validate(data)
    except ValidationError as exc:
        raise first_error(exc) from None
    sc._uncertain = uncertain
    validate(sc)
    return sc


def load_scenario(path: str | Path | None, overrides: dict | None = None) -> Scenario:
    """Load a scenario TOML file (or the defaults when ``path`` is None) and apply
    ``overrides`` given as ``{"section.key": value}`` (None values are skipped). What the
    runs of a command imply is judged apart, before they start
    (:func:`pdamper.runs.resources.check_runs`).

    Examples
    --------
    >>> s = load_scenario(None, {"particles.count": 64, "excitation.frequency": "5 Hz"})
    >>> s.particles.count, s.excitation.frequency
    (64, 5.0)
    """
    from pdamper.io.reading import read_toml, resolve_paths

    data: dict = {}
    if path is not None:
        p = Path(path)
        data = read_toml(p)
        resolve_paths(data, p.parent)  # the files it names, relative to it
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
    return scenario_from_dict(data)


@functools.cache
def _example_text() -> str:
    from pdamper.io.example import example_text

    return example_text(Scenario(), BeamSpec())


@functools.cache
def example_scenario() -> Scenario:
    """The example scenario (:data:`EXAMPLE_SCENARIO`) parsed; it equals the defaults."""
    import tomllib

    return scenario_from_dict(tomllib.loads(_example_text()))


def __getattr__(name: str) -> Any:
    # the example scenario's text (pdamper.io.example writes it from the defaults), written
    # when first asked for: it formats every quantity with the unit registry
    if name == "EXAMPLE_SCENARIO":
        return _example_text()
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
