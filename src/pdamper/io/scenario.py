"""Scenario files: declarative TOML inputs with units, validated by pydantic.

Every quantity is written with its unit (``"120 mm"``, ``"7900 kg/m^3"``) and converted to
an SI float on load; a bare number is taken as SI. :func:`load_scenario` turns every
problem (malformed TOML, unknown unit, out-of-range value, unknown key) into a one-line
:class:`~pdamper.errors.InputError` naming the field. Every section is validated on load,
whichever command reads the scenario, by building the objects it describes.

The defaults are the reference paper's case (:mod:`pdamper.parameters`) and the models' own
defaults; nothing here restates a number.
"""

from __future__ import annotations

import functools
import tomllib
from pathlib import Path
from typing import Annotated, Any

from pydantic import AliasChoices, BaseModel, BeforeValidator, ConfigDict, Field, ValidationError

from pdamper.contact.law import DAMPING_MODELS, DEFAULT_MIN_IMPACT_VELOCITY
from pdamper.dem.model import DEFAULT_SAFETY
from pdamper.errors import InputError
from pdamper.models.dem import DEFAULT_CYCLES, DEFAULT_SAMPLE_RATE, DEFAULT_SKIP_CYCLES
from pdamper.parameters import vertical_dampers_paper as paper
from pdamper.units import format_quantity, parse_quantity


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
Count = Annotated[int, Field(strict=True)]

_D = paper.PAPER_DAMPER


class _Section(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True, populate_by_name=True)


class MaterialSpec(_Section):
    """A material given by its constants instead of a built-in name."""

    name: str
    youngs_modulus: Modulus
    poisson_ratio: Annotated[float, Field(gt=-1, lt=0.5)]
    density: Density


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
    friction: Annotated[float, Field(ge=0)] = _D.friction


class ExcitationSpec(_Section):
    frequency: Frequency = paper.BENCHMARK_EXCITATION[0]
    amplitude: PositiveLength = paper.BENCHMARK_EXCITATION[1]


class StructureSpec(_Section):
    mass: PositiveMass | None = None
    stiffness: Stiffness = paper.PAPER_STIFFNESS
    damping: Damping = paper.PAPER_DAMPING
    initial_displacement: Annotated[float, _q("m"), Field(lt=0)] = paper.PAPER_INITIAL_DISPLACEMENT


class SimulationSpec(_Section):
    model: str = Field("analytic", validation_alias=AliasChoices("model", "damper"))
    duration: Duration = paper.PAPER_DURATION
    sample_rate: Frequency = 2000.0


class OptimizationSpec(_Section):
    at: Duration = paper.PAPER_OBJECTIVE_TIME
    step: Annotated[int, Field(ge=1, strict=True)] | None = None


def _range_text(spec: tuple[float, float, int], unit: str, scale: float) -> str:
    a, b, n = spec
    return f"{a * scale:g}{unit}:{b * scale:g}{unit}:{n}"


class MapSpec(_Section):
    frequency: str = _range_text(paper.PAPER_MAP_FREQUENCY, "Hz", 1.0)
    amplitude: str = _range_text(paper.PAPER_MAP_AMPLITUDE, "mm", 1e3)


class DEMSpec(_Section):
    """Options of the DEM damper model (:class:`pdamper.models.DEMDamper`)."""

    integrator: str = "gear"
    cycles: Count = DEFAULT_CYCLES
    skip_cycles: Count = DEFAULT_SKIP_CYCLES
    restitution_pp: Restitution = _D.restitution_pp.e
    restitution_pw: Restitution = _D.restitution_pw.e
    damping_model: str = "exact"
    min_impact_velocity: Annotated[float, _q("m/s")] = DEFAULT_MIN_IMPACT_VELOCITY
    packing: str = "lattice"
    seed: Count = 0
    safety: float = DEFAULT_SAFETY
    sample_rate: Frequency = DEFAULT_SAMPLE_RATE
    snapshot_rate: Frequency | None = None

    def options(self) -> dict:
        """Keyword arguments of :class:`pdamper.models.DEMDamper`."""
        return self.model_dump(exclude={"restitution_pp", "restitution_pw"})


class Scenario(_Section):
    """A complete scenario; every section is optional and defaults to the paper's case.

    A section named after a damper fidelity (``[dem]``) holds that model's options.
    """

    title: str = "paper benchmark damper"
    container: ContainerSpec = ContainerSpec()
    particles: ParticlesSpec = ParticlesSpec()
    excitation: ExcitationSpec = ExcitationSpec()
    structure: StructureSpec = StructureSpec()
    simulation: SimulationSpec = SimulationSpec()
    optimization: OptimizationSpec = OptimizationSpec()
    map: MapSpec = MapSpec()
    dem: DEMSpec = DEMSpec()

    # -- builders of the domain objects ------------------------------------------------
    def damper(self):
        """The :class:`~pdamper.damper.ParticleDamper` this scenario describes."""
        from pdamper.contact.restitution import ConstantRestitution
        from pdamper.damper import ParticleDamper

        c, p = self.container, self.particles
        return ParticleDamper(length=c.length, width=c.width, depth=c.depth,
                              particle_radius=p.radius, count=p.count,
                              particle_material=_material(p.material, "particles.material"),
                              wall_material=_material(c.material, "container.material"),
                              container_mass=c.mass, friction=p.friction,
                              restitution_pp=ConstantRestitution(self.dem.restitution_pp),
                              restitution_pw=ConstantRestitution(self.dem.restitution_pw))

    def structure_model(self):
        """The :class:`~pdamper.structure.SingleDOFStructure`; M defaults to the paper's
        (see :mod:`pdamper.parameters.vertical_dampers_paper`)."""
        from pdamper.structure import SingleDOFStructure

        s = self.structure
        return SingleDOFStructure(mass=paper.PAPER_MASS if s.mass is None else s.mass,
                                  damping=s.damping, stiffness=s.stiffness)

    def model(self, name: str | None = None, damper=None):
        """The damper model of fidelity ``name`` (default ``[simulation] model``) for
        ``damper`` (default :meth:`damper`), with the options of its section."""
        from pdamper.models import get_damper_model

        field = "model" if name is not None else "simulation.model"
        cls = get_damper_model(self.simulation.model if name is None else name, field)
        section = getattr(self, cls.fidelity, None)
        options = section.options() if hasattr(section, "options") else {}
        return cls(self.damper() if damper is None else damper, **options)

    def map_grid(self):
        """The Level II grid ``(frequency [Hz], amplitude [m])`` of ``[map]``."""
        import numpy as np

        from pdamper.units import parse_range

        f0, f1, nf = parse_range(self.map.frequency, "Hz", "map.frequency")
        x0, x1, nx = parse_range(self.map.amplitude, "m", "map.amplitude")
        for name, lo in (("map.frequency", min(f0, f1)), ("map.amplitude", min(x0, x1))):
            if lo <= 0:
                raise InputError(name, f"grid values must be > 0, got {lo:g}")
        return np.linspace(f0, f1, nf), np.linspace(x0, x1, nx)


def _material(spec, field: str):
    from pdamper.materials import Material, get_material

    if isinstance(spec, MaterialSpec):
        return Material(spec.name, spec.youngs_modulus, spec.poisson_ratio, spec.density)
    return get_material(spec, field)


def _first_error(exc: ValidationError) -> InputError:
    err = exc.errors()[0]
    loc = ".".join(str(p) for p in err["loc"]
                   if str(p) not in ("str", "MaterialSpec") and not str(p).startswith("function-"))
    msg = err["msg"].removeprefix("Value error, ")
    if err["type"] == "extra_forbidden":
        msg = "unknown key (check the spelling; `pdamper example-scenario` lists the keys)"
    elif "input" in err and err["type"] != "missing" and repr(err["input"]) not in msg \
            and "got" not in msg:
        msg = f"{msg} (got {err['input']!r})"
    return InputError(loc or "scenario", msg)


def _validate(sc: Scenario) -> None:
    """Build what every section describes (cheaply: no DEM run, no numba), so that its
    errors surface at load time whichever command reads the scenario."""
    damper = sc.damper()
    sc.structure_model()
    sc.map_grid()
    sc.model("dem", damper)
    sc.model(None, damper)


def scenario_from_dict(data: dict) -> Scenario:
    """Validate a dict (parsed TOML) into a :class:`Scenario`."""
    try:
        sc = Scenario.model_validate(data)
    except ValidationError as exc:
        raise _first_error(exc) from None
    _validate(sc)
    return sc


def load_scenario(path: str | Path | None, overrides: dict | None = None) -> Scenario:
    """Load a scenario TOML file (or the defaults when ``path`` is None) and apply
    ``overrides`` given as ``{"section.key": value}`` (None values are skipped).

    Examples
    --------
    >>> s = load_scenario(None, {"particles.count": 64, "excitation.frequency": "5 Hz"})
    >>> s.particles.count, s.excitation.frequency
    (64, 5.0)
    """
    data: dict = {}
    if path is not None:
        p = Path(path)
        if not p.is_file():
            raise InputError("scenario", f"file not found: {p}")
        try:
            data = tomllib.loads(p.read_text(encoding="utf-8"))
        except tomllib.TOMLDecodeError as exc:
            raise InputError("scenario", f"malformed TOML in {p}: {exc}") from None
        except UnicodeDecodeError:
            raise InputError("scenario", f"{p} is not UTF-8 text") from None
    for key, value in (overrides or {}).items():
        if value is None:
            continue
        section, _, name = key.partition(".")
        node = data.setdefault(section, {})
        if not isinstance(node, dict):
            raise InputError(section, "must be a table")
        node[name] = value
    return scenario_from_dict(data)


def _example() -> str:
    s = Scenario()
    c, p, x, st = s.container, s.particles, s.excitation, s.structure
    q = format_quantity
    dem = s.dem
    _MODELS = " or ".join(f'"{m}"' for m in DAMPING_MODELS)  # noqa: N806
    return f"""\
# pdamper scenario: the reference paper's benchmark damper on its beam-like structure.
# Every quantity carries its unit ("120 mm", "10 Hz", "7900 kg/m^3"); bare numbers are SI.
# Every section and key is optional; what is left out takes the value shown here.
title = "{s.title}"

[container]                 # cuboid particle container, inner dimensions
length = "{q(c.length, 'mm')}"           # along the excitation (vertical), L in h = L (1 - n_p/n_max)
width = "{q(c.width, 'mm')}"
depth = "{q(c.depth, 'mm')}"
material = "{c.material}"            # built-in: "PVC", "S235"; or an inline table:
# material = {{ name = "PMMA", youngs_modulus = "3.2 GPa", poisson_ratio = 0.35, density = "1190 kg/m^3" }}
mass = "{q(c.mass, 'kg')}"               # m_con, subtracted in Eq. (4) when a driving force includes it

[particles]
count = {p.count}                  # n_p; at most n_max (16 per layer x 12 layers = 192 here)
radius = "{q(p.radius, 'mm')}"
material = "{p.material}"
friction = {p.friction}              # sliding friction coefficient mu of every contact (DEM)

[excitation]                # Level II: x_c = X sin(2 pi f t)
frequency = "{q(x.frequency, 'Hz')}"
amplitude = "{q(x.amplitude, 'mm')}"         # stroke X

[structure]                 # Level III: M x'' + D x' + K x = F (Eq. 23)
# mass = "{q(paper.PAPER_MASS, 'kg')}"       # default K / (2 pi {paper.PAPER_EIGENFREQUENCY} Hz)^2: \
the printed {paper.PAPER_PRINTED_MASS} kg is inconsistent
stiffness = "{q(st.stiffness, 'N/m')}"
damping = "{q(st.damping, 'kg/s')}"
initial_displacement = "{q(st.initial_displacement, 'mm')}"

[simulation]
model = "{s.simulation.model}"          # damper fidelity: "analytic" (model 3) or "dem" (model 1)
duration = "{q(s.simulation.duration, 's')}"
sample_rate = "{q(s.simulation.sample_rate, 'Hz')}"     # of the stored trajectory

[optimization]
at = "{q(s.optimization.at, 's')}"                # objective: amplitude at this time after release
# step = 16                 # particle-count increment; default one layer

[map]                       # Level II grid, "start:stop:count"
frequency = "{s.map.frequency}"
amplitude = "{s.map.amplitude}"

[dem]                       # options of the DEM model ("pdamper dem", "--model dem")
integrator = "{dem.integrator}"         # "gear" (variable step, the paper's) or "verlet"
cycles = {dem.cycles}                  # excitation cycles of a Level II run
skip_cycles = {dem.skip_cycles}             # cycles left out of the complex power (Eqs. 1-4)
restitution_pp = {dem.restitution_pp}        # constant sphere-sphere COR
restitution_pw = {dem.restitution_pw}       # constant sphere-wall COR
damping_model = "{dem.damping_model}"     # damping law of the normal force: {_MODELS}
# min_impact_velocity = "0.01 m/s"  # onset-speed floor of the exact/gonthier damping
packing = "{dem.packing}"         # "lattice" (the paper's 4 x 4 layers) or "random"
seed = {dem.seed}                    # seed of the random packing (recorded always)
safety = {dem.safety}               # time step / Hertz contact time
sample_rate = "{q(dem.sample_rate, 'Hz')}"     # of the force and container series
# snapshot_rate = "200 Hz"  # particle snapshots per second (default: first and last)
"""


#: A commented scenario file with every key and its default (``pdamper example-scenario``).
EXAMPLE_SCENARIO = _example()


@functools.cache
def example_scenario() -> Scenario:
    """The example scenario, parsed (it must equal the defaults)."""
    return scenario_from_dict(tomllib.loads(EXAMPLE_SCENARIO))
