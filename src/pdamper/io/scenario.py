"""Scenario files: declarative TOML inputs with units, validated by pydantic.

Every quantity is written with its unit (``"120 mm"``, ``"7900 kg/m^3"``) and converted to
an SI float on load; a bare number is taken as SI. :func:`load_scenario` turns every
problem (malformed TOML, unknown unit, out-of-range value, unknown key) into a one-line
:class:`~pdamper.errors.InputError` naming the field.
"""

from __future__ import annotations

import functools
import tomllib
from pathlib import Path
from typing import Annotated, Any

from pydantic import BaseModel, BeforeValidator, ConfigDict, Field, ValidationError

from pdamper.errors import InputError
from pdamper.units import parse_quantity


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


class _Section(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True)


class MaterialSpec(_Section):
    """A material given by its constants instead of a built-in name."""

    name: str
    youngs_modulus: Modulus
    poisson_ratio: Annotated[float, Field(gt=-1, lt=0.5)]
    density: Density


class ContainerSpec(_Section):
    length: PositiveLength = 0.120
    width: PositiveLength = 0.040
    depth: PositiveLength = 0.040
    material: str | MaterialSpec = "PVC"
    mass: Mass = 0.0


class ParticlesSpec(_Section):
    count: Annotated[int, Field(ge=0, strict=True)] = 32
    radius: PositiveLength = 0.005
    material: str | MaterialSpec = "S235"
    friction: Annotated[float, Field(ge=0)] = 0.1


class ExcitationSpec(_Section):
    frequency: Frequency = 10.0
    amplitude: PositiveLength = 0.032


class StructureSpec(_Section):
    mass: PositiveMass | None = None
    stiffness: Stiffness = 1848.0
    damping: Damping = 0.55
    initial_displacement: Annotated[float, _q("m"), Field(lt=0)] = -0.058


class SimulationSpec(_Section):
    damper: str = "analytic"
    duration: Duration = 2.0
    sample_rate: Frequency = 2000.0


class OptimizationSpec(_Section):
    at: Duration = 0.8
    step: Annotated[int, Field(ge=1)] | None = None


class MapSpec(_Section):
    frequency: str = "2Hz:20Hz:14"
    amplitude: str = "1mm:200mm:24"


class Scenario(_Section):
    """A complete scenario; every section is optional and defaults to the paper's case."""

    title: str = "paper benchmark damper"
    container: ContainerSpec = ContainerSpec()
    particles: ParticlesSpec = ParticlesSpec()
    excitation: ExcitationSpec = ExcitationSpec()
    structure: StructureSpec = StructureSpec()
    simulation: SimulationSpec = SimulationSpec()
    optimization: OptimizationSpec = OptimizationSpec()
    map: MapSpec = MapSpec()

    # -- builders of the domain objects ------------------------------------------------
    def damper(self):
        """The :class:`~pdamper.damper.ParticleDamper` this scenario describes."""
        from pdamper.damper import ParticleDamper

        c, p = self.container, self.particles
        return ParticleDamper(length=c.length, width=c.width, depth=c.depth,
                              particle_radius=p.radius, count=p.count,
                              particle_material=_material(p.material, "particles.material"),
                              wall_material=_material(c.material, "container.material"),
                              container_mass=c.mass, friction=p.friction)

    def structure_model(self):
        """The :class:`~pdamper.structure.SingleDOFStructure`; M defaults to the paper's
        (see :mod:`pdamper.parameters.vertical_dampers_paper`)."""
        from pdamper.parameters.vertical_dampers_paper import PAPER_MASS
        from pdamper.structure import SingleDOFStructure

        s = self.structure
        return SingleDOFStructure(mass=PAPER_MASS if s.mass is None else s.mass,
                                  damping=s.damping, stiffness=s.stiffness)


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


def scenario_from_dict(data: dict) -> Scenario:
    """Validate a dict (parsed TOML) into a :class:`Scenario`."""
    try:
        return Scenario.model_validate(data)
    except ValidationError as exc:
        raise _first_error(exc) from None


def load_scenario(path: str | Path | None, overrides: dict | None = None) -> Scenario:
    """Load a scenario TOML file (or the defaults when ``path`` is None) and apply
    ``overrides`` given as ``{"section.key": value}``.

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


EXAMPLE_SCENARIO = """\
# pdamper scenario: the reference paper's benchmark damper on its beam-like structure.
# Every quantity carries its unit ("120 mm", "10 Hz", "7900 kg/m^3"); bare numbers are SI.
# Every section and key is optional; what is left out takes the value shown here.
title = "paper benchmark damper"

[container]                 # cuboid particle container, inner dimensions
length = "120 mm"           # along the excitation (vertical), L in h = L (1 - n_p/n_max)
width = "40 mm"
depth = "40 mm"
material = "PVC"            # built-in: "PVC", "S235"; or an inline table:
# material = { name = "PMMA", youngs_modulus = "3.2 GPa", poisson_ratio = 0.35, density = "1190 kg/m^3" }
mass = "0 kg"               # m_con, subtracted in Eq. (4) when a driving force includes it

[particles]
count = 32                  # n_p; at most n_max (192 here: 16 per layer x 12 layers)
radius = "5 mm"
material = "S235"
friction = 0.1              # sliding friction coefficient mu of every contact

[excitation]                # Level II: x_c = X sin(2 pi f t)
frequency = "10 Hz"
amplitude = "32 mm"         # stroke X

[structure]                 # Level III: M x'' + D x' + K x = F (Eq. 23)
# mass = "1.514 kg"         # default K / (2 pi 5.56 Hz)^2: the printed 1.139 kg is inconsistent
stiffness = "1848 N/m"
damping = "0.55 kg/s"
initial_displacement = "-58 mm"

[simulation]
damper = "analytic"         # "analytic" (the effective-field and DEM models join later)
duration = "2 s"
sample_rate = "2000 Hz"     # of the stored trajectory; the pseudo-force solution is exact

[optimization]
at = "0.8 s"                # objective: amplitude at this time after release
# step = 16                 # particle-count increment; default one layer

[map]                       # Level II grid, "start:stop:count"
frequency = "2Hz:20Hz:14"
amplitude = "1mm:200mm:24"
"""


@functools.cache
def example_scenario() -> Scenario:
    """The example scenario, parsed (it must equal the defaults)."""
    return scenario_from_dict(tomllib.loads(EXAMPLE_SCENARIO))
