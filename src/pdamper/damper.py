"""The physical particle damper: a box container partly filled with equal spheres.

This is the design object of all three levels: Level II characterises it under harmonic
excitation, Level III mounts it on a structure and optimises its filling. It carries no
paper values: the paper's damper is :data:`pdamper.parameters.PAPER_DAMPER`.

The lattice capacity of a box (spheres per layer, layers, ``n_max``) has its one home here;
:mod:`pdamper.dem.packing` places spheres on that lattice.

Each quantity of the damper is declared once, as a field of :class:`ParticleDamper`
(:func:`pdamper.settings.declared` metadata: unit, range, docstring and its one name, the
scenario key ``section.key`` such as ``container.length``). The scenario's ``[container]``
and ``[particles]`` sections, the uncertain inputs (:func:`uncertain_fields`) and the design
variables of :mod:`pdamper.design.study` derive their units, ranges and docs from these
declarations (:func:`quantity`, :data:`QUANTITIES`).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field, fields, replace
from typing import Any

from pdamper.contact.restitution import RestitutionCurve
from pdamper.errors import InputError, check_range
from pdamper.materials import Material
from pdamper.settings import check_setting, declaration, declarations, declared, setting

#: Relative tolerance of the "how many diameters fit" counts, so that e.g. 0.04 / 0.01
#: counts 4 although the floating-point quotient may be 3.9999999999999996.
FIT_TOLERANCE = 1e-9


def lattice_fit(length: float, radius: float, gap: float = 0.0) -> int:
    """How many spheres of ``radius`` [m] fit side by side, ``gap`` [m] apart, in ``length`` [m].

    >>> lattice_fit(0.04, 0.005), lattice_fit(0.12, 0.005)
    (4, 12)
    """
    pitch = 2.0 * radius + gap
    return max(0, math.floor((length + gap) / pitch * (1.0 + FIT_TOLERANCE)))


def _box(box: Sequence[float]) -> tuple[float, float, float]:
    try:
        values = [float(v) for v in box]
    except (TypeError, ValueError):
        raise InputError("container.box",
                         f"must be three inner dimensions (Lx, Ly, Lz) in m, got {box!r}") from None
    if len(values) != 3:
        raise InputError("container.box", f"must be three inner dimensions (Lx, Ly, Lz) in m, "
                         f"got {len(values)} values")
    for name, v in zip("xyz", values, strict=True):
        check_range(f"container.box.L{name}", v, low=0.0, low_inclusive=False, unit="m")
    return values[0], values[1], values[2]


def spheres_per_layer(box: Sequence[float], radius: float, gap: float = 0.0) -> int:
    """Spheres in one square-lattice layer, ``floor(Lx/2r) * floor(Ly/2r)`` [-].

    Parameters
    ----------
    box
        Inner container dimensions ``(Lx, Ly, Lz)`` [m], ``Lz`` vertical.
    radius
        Sphere radius [m].
    gap
        Clearance between neighbouring spheres [m]; with ``gap > 0`` the count along x is
        ``floor((Lx + gap) / (2 r + gap))``.

    >>> spheres_per_layer((0.04, 0.04, 0.12), 0.005)
    16
    """
    lx, ly, _ = _box(box)
    r = check_range("particles.radius", radius, low=0.0, low_inclusive=False, unit="m")
    g = check_range("particles.gap", gap, low=0.0, unit="m")
    return lattice_fit(lx, r, g) * lattice_fit(ly, r, g)


def max_layers(box: Sequence[float], radius: float, gap: float = 0.0) -> int:
    """Lattice layers that fit in the height, ``floor(Lz/2r)`` [-].

    >>> max_layers((0.04, 0.04, 0.12), 0.005)
    12
    """
    _, _, lz = _box(box)
    r = check_range("particles.radius", radius, low=0.0, low_inclusive=False, unit="m")
    g = check_range("particles.gap", gap, low=0.0, unit="m")
    return lattice_fit(lz, r, g)


def max_particles(box: Sequence[float], radius: float, gap: float = 0.0) -> int:
    """Capacity ``n_max`` = spheres per layer x layers of the square lattice [-].

    >>> max_particles((0.04, 0.04, 0.12), 0.005)
    192
    """
    return spheres_per_layer(box, radius, gap) * max_layers(box, radius, gap)


def _cor_curve(pair: str, key: str) -> dict:
    """The declaration of the COR curve of one pair type (``pair``: "sphere-sphere" or
    "sphere-wall"), scenario key ``key``."""
    return declared(
        f"COR curve e(v) of {pair} impacts, Level I (needed by the DEM only; in a scenario "
        "a constant COR or [restitution]).", low=0.0, high=1.0, low_inclusive=False,
        kind="curve", key=key,
        none="not given (the analytical and field models do not use it)")


@dataclass(frozen=True)
class ParticleDamper:
    """A rectangular container with ``count`` equal spheres.

    Each field is a quantity declared once (:func:`pdamper.settings.declared`): its
    unit (SI), range, meaning and its one name, the scenario key (``container.length``,
    ``particles.radius``, ...); :meth:`declarations` lists them, :data:`QUANTITIES` maps the
    names to the fields. Positional order: ``length, width, depth, particle_radius, count,
    particle_material, wall_material``, then ``container_mass`` [kg], ``friction`` [-],
    ``restitution_pp`` and ``restitution_pw`` (COR curves e(v)).

    Examples
    --------
    The paper's benchmark damper with 32 spheres:

    >>> from pdamper.materials import PVC, S235
    >>> d = ParticleDamper(0.120, 0.040, 0.040, 0.005, 32, S235, PVC)
    >>> d.max_count, round(d.clearance, 4), round(d.bed_mass * 1000, 1)
    (192, 0.1, 132.4)
    """

    length: float = field(metadata=declared(
        "Inner height L of the container along the excitation (vertical); the clearance is "
        "h = L (1 - n_p / n_max).",
        unit="m", low=0.0, low_inclusive=False, kind="number", key="container.length"))
    width: float = field(metadata=declared(
        "Inner width of the container (horizontal).",
        unit="m", low=0.0, low_inclusive=False, kind="number", key="container.width"))
    depth: float = field(metadata=declared(
        "Inner depth of the container (horizontal).",
        unit="m", low=0.0, low_inclusive=False, kind="number", key="container.depth"))
    particle_radius: float = field(metadata=declared(
        "Sphere radius r.",
        unit="m", low=0.0, low_inclusive=False, kind="number", key="particles.radius"))
    count: int = field(metadata=declared(
        "Number of spheres n_p, at most n_max (spheres per lattice layer x layers: 192 in the "
        "benchmark container).",
        low=0, kind="whole", key="particles.count"))
    particle_material: Material = field(metadata=declared(
        "Material of the spheres (docs/materials.md; in a scenario a library name or an "
        "inline table).",
        kind="material", key="particles.material"))
    wall_material: Material = field(metadata=declared(
        "Material of the container's walls (docs/materials.md; in a scenario a library name "
        "or an inline table).",
        kind="material", key="container.material"))
    container_mass: float = field(default=0.0, metadata=declared(
        "m_con, the container alone (Eq. 4 of the complex power method).",
        unit="kg", low=0.0, kind="number", key="container.mass"))
    friction: float | None = field(default=None, metadata=declared(
        "Sliding friction coefficient mu of every contact (needed by the DEM only).",
        low=0.0, kind="number", key="particles.friction",
        none="not given (the analytical and field models do not use it)"))
    restitution_pp: RestitutionCurve | None = field(default=None, metadata=_cor_curve(
        "sphere-sphere", "dem.restitution_pp"))
    restitution_pw: RestitutionCurve | None = field(default=None, metadata=_cor_curve(
        "sphere-wall", "dem.restitution_pw"))

    def __post_init__(self) -> None:
        # every quantity against its declaration; the whole count, the types of the
        # materials and curves and what depends on two quantities below
        for name in ("length", "width", "depth", "particle_radius", "container_mass",
                     "friction"):
            decl = declaration(ParticleDamper, name)
            check_setting(decl["key"], getattr(self, name), decl)
        for name, material in (("particles.material", self.particle_material),
                               ("container.material", self.wall_material)):
            if not isinstance(material, Material):
                raise InputError(name, f"must be a Material, got {material!r}")
        for name in ("restitution_pp", "restitution_pw"):
            curve = getattr(self, name)
            if curve is not None and not isinstance(curve, RestitutionCurve):
                raise InputError(f"particles.{name}",
                                 f"must be a RestitutionCurve (e.g. ConstantRestitution(0.8)), "
                                 f"got {curve!r}")
        d = 2.0 * self.particle_radius
        if min(self.width, self.depth, self.length) < d * (1 - FIT_TOLERANCE):
            raise InputError("particles.radius",
                             f"sphere diameter {d * 1000:g} mm must fit the container "
                             f"({self.width * 1000:g} x {self.depth * 1000:g} x "
                             f"{self.length * 1000:g} mm)")
        try:
            whole = not isinstance(self.count, bool) and int(self.count) == self.count
        except (TypeError, ValueError, OverflowError):
            whole = False
        if not whole:
            raise InputError("particles.count", f"must be a whole number, got {self.count!r}")
        if not 0 <= self.count <= self.max_count:
            raise InputError("particles.count",
                             f"must be in [0, {self.max_count}] (n_max of this container), "
                             f"got {self.count}")
        object.__setattr__(self, "count", int(self.count))

    @classmethod
    def declarations(cls) -> dict[str, dict]:
        """Every quantity's declaration by field name: ``unit``, ``kind``, range, ``key``
        (the scenario key), ``doc`` and ``default`` (None: required)."""
        return declarations(cls)

    @property
    def box(self) -> tuple[float, float, float]:
        """Inner dimensions ``(Lx, Ly, Lz)`` = (width, depth, length) [m], ``Lz`` vertical."""
        return (self.width, self.depth, self.length)

    @property
    def per_layer(self) -> int:
        """Spheres per lattice layer (16 in the benchmark container)."""
        return spheres_per_layer(self.box, self.particle_radius)

    @property
    def max_count(self) -> int:
        """n_max: spheres in full lattice layers up to the lid (192 in the benchmark)."""
        return max_particles(self.box, self.particle_radius)

    @property
    def particle_mass(self) -> float:
        """Mass of one sphere [kg]."""
        return 4.0 / 3.0 * math.pi * self.particle_radius**3 * self.particle_material.density

    @property
    def bed_mass(self) -> float:
        """m_bed, mass of all spheres [kg]."""
        return self.count * self.particle_mass

    @property
    def clearance(self) -> float:
        """h = L (1 - n_p / n_max) [m] (paper Sect. 3.1.1)."""
        return self.length * (1.0 - self.count / self.max_count)

    @property
    def optimal_stroke(self) -> float:
        """X_opt = h / pi [m] (Eq. 19)."""
        return self.clearance / math.pi

    def with_count(self, count: int) -> ParticleDamper:
        """The same damper with another particle count."""
        return replace(self, count=count)

    def with_restitution(self, restitution_pp: RestitutionCurve | None = None,
                         restitution_pw: RestitutionCurve | None = None) -> ParticleDamper:
        """The same damper with other COR curves (None: keep that pair's curve)."""
        return replace(self,
                       restitution_pp=self.restitution_pp if restitution_pp is None else restitution_pp,
                       restitution_pw=self.restitution_pw if restitution_pw is None else restitution_pw)


#: The damper's quantities by their one name (the scenario key ``section.key``, as errors,
#: ``--uncertain`` and the scenario write them) -> the :class:`ParticleDamper` field.
QUANTITIES: dict[str, str] = {declaration(ParticleDamper, f.name)["key"]: f.name
                              for f in fields(ParticleDamper)}


def quantity(key: str) -> dict:
    """The declaration of the damper's quantity ``key`` (``"container.length"``), with
    ``doc``, ``default`` and ``attribute`` (its :class:`ParticleDamper` field).

    >>> q = quantity("container.length")
    >>> q["unit"], q["low"], q["attribute"]
    ('m', 0.0, 'length')
    """
    if key not in QUANTITIES:
        raise InputError(key, f"is no quantity of the damper; these are: "
                         f"{', '.join(QUANTITIES)}")
    name = QUANTITIES[key]
    return {**ParticleDamper.declarations()[name], "attribute": name}


def quantity_setting(key: str, default: Any, **changes: Any) -> Any:
    """A field of a scenario section declared by the damper's quantity ``key`` (its unit,
    kind, range, doc and key; ``default``: the section's, ``changes``: e.g. ``none=""``
    where the section always has a value): :func:`pdamper.settings.setting` of it."""
    q = quantity(key)
    args = {k: q[k] for k in ("unit", "low", "high", "low_inclusive", "high_inclusive", "kind",
                              "infinite", "none")}
    return setting(default, q["doc"], choices=tuple(q["choices"]), key=key,
                   **{**args, **changes})


def uncertain_fields() -> dict[str, tuple[str, float, float]]:
    """The damper's quantities that may carry an uncertainty (the numbers: not the
    materials, not the count): scenario key -> (SI unit, low, high) of their declarations,
    an open end as -inf or inf (the truncation of the uncertain input)."""
    out = {}
    for key in QUANTITIES:
        q = quantity(key)
        if q["kind"] in ("number", "curve"):
            out[key] = (q["unit"], -math.inf if q["low"] is None else float(q["low"]),
                        math.inf if q["high"] is None else float(q["high"]))
    return out
