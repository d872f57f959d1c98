"""Design studies over several damper variables (extends paper Sect. 4.2.2).

The paper optimises one variable, the particle count, by brute force for the smallest
amplitude after 0.8 s. A design study varies any of the damper's design variables
(:data:`VARIABLES`: particle count, sphere radius, container length, width and depth,
particle material) and ranks the designs by one objective (:data:`OBJECTIVES`):

- ``amplitude-at``: amplitude envelope at T (the paper's objective; minimised) [m];
- ``settling-time``: first time the envelope of the negative peaks falls below a
  threshold (default a quarter of the release deflection; minimised; a design that never
  gets there within the simulated time is reported at that time with ``settled: false``) [s];
- ``mean-damping``: mean damping ratio (Eqs. 24-25) of the cycles that end by T
  (maximised) [-];
- ``peak``, ``rms``: largest |displacement| and RMS displacement of the output point under
  a load history (:mod:`pdamper.coupling.loads`; a force or base acceleration from rest,
  over the record and its free tail; minimised) [m];
- ``peak-frf``: largest steady amplitude of the output point over a frequency band under
  a harmonic load (the forced response of :mod:`pdamper.coupling.frf`, stepped sines up
  and down; minimised) [m];
- ``rms-frf``: RMS over the band's frequencies of that amplitude (minimised) [m].

Search
------
``method="grid"`` evaluates every combination (brute force, the paper's method);
``"optimize"`` runs :func:`scipy.optimize.differential_evolution` over the variables'
ranges (integer and categorical variables through ``integrality``; a continuous variable
given as ``start:stop:count`` spans [start, stop]); ``"auto"`` (default) takes the grid
when it has at most ``max_grid`` points and every variable is discrete, the optimiser
otherwise. Either way *every* evaluated design is returned (the landscape), and the
evaluations of a grid or of one optimiser generation run together through
:func:`pdamper.design.parallel.evaluate_parallel` (in-process or on dask.distributed).

A design whose spheres do not fit the container (more than n_max, or a diameter larger
than the container) is *infeasible*: it stays in the landscape with its reason and no
objective; an evaluation that fails is kept as ``failed`` with its error.

Physical limits (:mod:`pdamper.resources`: spheres of at least 0.1 mm, the release's
impacts quasi-static and, for the DEM, within Hertz's law) are judged where every run is
made (the damper model, the free vibration), so every candidate obeys them. A variable
whose *given range* reaches outside them is refused before anything runs, with one line
naming the variable (``optimization.vary.radius``: ``radius=1nm:3mm:4`` is a typo, not a
landscape to report); a combination of values each within the limits that is outside them
together (found by the optimiser, say) is an infeasible candidate with the reason.
The number of values of a variable is judged before they are built (:func:`values_cost`;
the scenario's whole study is judged by :func:`pdamper.runs.resources.check_resources`).

Added mass
----------
Added mass is a cost of every real damper, and landscapes are often flat near the optimum
(the paper's particle count: 64 to 112 spheres within 8 %). The result therefore also
carries the Pareto front of added mass against the objective (:func:`pareto_front`: both
minimised, a maximised objective taken with its sign turned) and the lightest design whose
objective is within a relative ``tolerance`` of the best (:func:`lightest_within`;
default :data:`DEFAULT_TOLERANCE`, 5 %). A design's mass is its bed's, m_bed (the key
``mass``), plus its container's (``container_mass``, the scenario's ``container.mass``):
``total_mass``, the mass the front and the lightest design are ranked by and the mass
limit bounds. Infeasible and failed designs have no objective and are never on the front.

Limits
------
``max_mass`` (bed plus container [kg]) and response limits (:class:`Limit`,
``"peak-acceleration<=10g"``, ``"peak<=3mm"``: :data:`LIMIT_QUANTITIES`, the quantities
the objective's runs compute at the observation point) mark the designs that violate one
as infeasible, with the reason (evaluated and listed; each candidate carries every limit's
value and margin, :func:`judge`). The best, the lightest within the tolerance, the front
and the lightest design within the limits (:attr:`DesignStudyResult.lightest_feasible`)
are chosen among the designs within them; when none is, the study names none best and
says by how much the closest misses (:attr:`DesignStudyResult.closest`). The optimiser
sees a violation as a penalty growing with the shortfall.

Variable specifications (CLI ``--vary``, scenario ``[optimization] vary``)
-------------------------------------------------------------------------
``particles=16:176:16``
    Particle count, ``start:stop:STEP`` (counts go in layers, like the paper's increment of
    16; the stop is included and must be reached by whole steps), or a list ``16,32,64``.
``radius=3mm:6mm:4``
    A continuous variable, ``start:stop:COUNT`` (as ``pdamper map``), a list
    ``3mm,4mm``, one value, or an interval ``3mm:6mm`` (optimiser only).
``particle-material=S235,PVC``
    Names of materials (:func:`pdamper.materials.get_material`).
``bed-mass=0.1kg:0.4kg:4``, ``fill=0.2:0.9:4``
    The bed's mass, or the fraction of the lattice's count n_max: the particle count is
    derived for each radius and material (:data:`DERIVED_VARIABLES`); at most one of
    ``particles``, ``bed-mass`` and ``fill``.
"""

from __future__ import annotations

import dataclasses
import logging
import math
import re
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING, Any, Protocol, TypeVar, cast

import numpy as np

from pdamper.coupling.simulation import Simulation
from pdamper.damper import ParticleDamper, quantity
from pdamper.design.parallel import Outcome, evaluate_parallel
from pdamper.errors import InputError, check_range
from pdamper.resources import (  # noqa: F401 - the study's defaults
    DEFAULT_MAX_EVALUATIONS,
    DEFAULT_MAX_GRID,
    DEFAULT_TOLERANCE,
)
from pdamper.settings import check_setting
from pdamper.units import DISPLAY_OF

if TYPE_CHECKING:
    from numpy.typing import ArrayLike

    from pdamper.coupling import FreeVibrationResult
    from pdamper.coupling.frf import FRFResult, HarmonicLoad
    from pdamper.coupling.loads import LoadHistory, LoadResponse
    from pdamper.resources import Cost
    from pdamper.structure import SingleDOFStructure
    from pdamper.structure.modal import ModalStructure

logger = logging.getLogger(__name__)

#: Largest grid a study accepts (a typo guard, not a design question).
MAX_GRID = 100_000
#: Objective value given to the optimiser for infeasible or failed designs.
_PENALTY = 1e6
#: Sample rate of the objective runs [Hz]: peaks are exact in the pseudo-force coupling;
#: the stored trajectory is not used.
_SAMPLE_RATE = 200.0
#: Sample rate of the load-history objective runs [Hz]: the peak is read from the samples
#: (relative error about (pi f / rate)^2 / 2 at a response frequency f: 4e-5 at 5.6 Hz).
LOAD_SAMPLE_RATE = 2000.0
METHODS = ("auto", "grid", "optimize")


# ----------------------------------------------------------------------------- variables
@dataclass(frozen=True)
class _VariableKind:
    kind: str  # "integer", "continuous", "categorical"
    unit: str
    attribute: str  # ParticleDamper field
    description: str
    #: the quantity's one name, its scenario key (``"particles.count"``)
    field: str = ""
    #: the declaration the values are checked against (:mod:`pdamper.settings`)
    declaration: dict = dataclasses.field(default_factory=dict, compare=False, repr=False)
    #: a variable that sets the particle count for each radius and material
    #: (:data:`DERIVED_VARIABLES`), applied after the others
    derived: bool = False

    @property
    def display(self) -> tuple[str, float]:
        """The unit values are shown in and its factor from SI (mm, g, %)."""
        if self.derived and not self.unit:  # a fraction
            return _DISPLAY["%"]
        return _DISPLAY.get(self.unit, (self.unit, 1.0))


#: A variable's kind from the kind of its quantity's declaration.
_KINDS = {"whole": "integer", "number": "continuous", "material": "categorical"}


def _variable(key: str) -> _VariableKind:
    """The design variable of the damper's quantity ``key``: kind, unit, field and doc from
    its declaration (:func:`pdamper.damper.quantity`)."""
    q = quantity(key)
    return _VariableKind(_KINDS[q["kind"]], q["unit"], q["attribute"], q["doc"], key, q)


#: Display unit and factor from SI of a variable's unit.
_DISPLAY = {**DISPLAY_OF, "%": ("%", 100.0)}


def _derived(name: str, doc: str, **declaration: Any) -> _VariableKind:
    """A variable that derives the particle count (:data:`DERIVED_VARIABLES`), declared as
    every setting (:func:`pdamper.settings.declared`)."""
    from pdamper.settings import declared

    decl = declared(doc, kind="number", **declaration)
    return _VariableKind("continuous", decl["declaration"]["unit"], "count", doc,
                         f"optimization.vary.{name}", decl["declaration"], derived=True)


#: Design variables that set the particle count n_p for each radius and material: the bed's
#: mass (``bed-mass``: n_p = round(m_bed / m_sphere), m_sphere = rho 4/3 pi r^3) or the
#: fraction of the lattice's count n_max (``fill``: n_p = round(fill n_max)), so that one
#: range means the same bed across radii and materials (8-80 spheres are 7 g of 3 mm steel
#: but 809 g of 5 mm tungsten). At most one of them with ``particles``.
DERIVED_VARIABLES: dict[str, _VariableKind] = {
    "bed_mass": _derived("bed_mass", "Mass of the bed m_bed; the count is the nearest whole "
                         "number of spheres of each radius and material.", unit="kg",
                         low=0.0),
    "fill": _derived("fill", "Fraction of the lattice's count n_max (full layers up to the "
                     "lid) of each radius and container; the count is the nearest whole "
                     "number.", low=0.0, high=1.0),
}


#: Design variables: name -> kind, unit, the :class:`ParticleDamper` field it sets and the
#: quantity's scenario key (``field``), derived from the damper's declarations. The names
#: are the keys of a study's designs in its results; ``--vary`` also takes the scenario key
#: (``particles.count=16:176:16``) and the field's name.
VARIABLES: dict[str, _VariableKind] = {
    "particles": _variable("particles.count"),
    "radius": _variable("particles.radius"),
    "container_length": _variable("container.length"),
    "container_width": _variable("container.width"),
    "container_depth": _variable("container.depth"),
    "particle_material": _variable("particles.material"),
}
#: Every design variable: the damper's quantities (:data:`VARIABLES`) and those that derive
#: the particle count (:data:`DERIVED_VARIABLES`).
DESIGN_VARIABLES: dict[str, _VariableKind] = {**VARIABLES, **DERIVED_VARIABLES}
#: Every name ``--vary`` takes for a variable: its name, its quantity's scenario key and
#: :class:`ParticleDamper` field, and the short names in use before these.
VARIABLE_NAMES: dict[str, str] = {
    **{alias: name for name, v in DESIGN_VARIABLES.items() if not v.derived
       for alias in (v.field.replace(".", "_"), v.attribute)},
    "particle_count": "particles", "length": "container_length", "material": "particle_material",
    **{name: name for name in DESIGN_VARIABLES},
}


@dataclass(frozen=True)
class DesignVariable:
    """One varied design variable.

    Attributes
    ----------
    name
        Key of :data:`DESIGN_VARIABLES` (``"particles"``, ``"radius"``, ...).
    values
        The values of a grid (SI floats, whole counts, or material names); None for a
        continuous interval.
    bounds
        (low, high) of a continuous variable in SI units, else None.
    spec
        The specification as given, for the record.
    """

    name: str
    values: tuple | None
    bounds: tuple[float, float] | None = None
    spec: str = ""

    def __post_init__(self) -> None:
        # a study over no value evaluates nothing and would end with no best design
        if self.values is None and self.bounds is None or (
                self.values is not None and len(self.values) == 0):
            raise InputError("optimization.vary", f"{self.spec or self.name!r}: no values; "
                             "give at least one value or an interval")

    @property
    def kind(self) -> str:
        return DESIGN_VARIABLES[self.name].kind

    @property
    def size(self) -> float:
        """Number of grid values (inf for an interval)."""
        return math.inf if self.values is None else len(self.values)


def _name(raw: str) -> str:
    name = raw.strip().lower().replace("-", "_").replace(".", "_")
    if name not in VARIABLE_NAMES:
        raise InputError("optimization.vary", f"unknown design variable {raw.strip()!r}; "
                         f"known: {', '.join(n.replace('_', '-') for n in DESIGN_VARIABLES)} "
                         f"(or their scenario keys: "
                         f"{', '.join(v.field for v in VARIABLES.values())})")
    return VARIABLE_NAMES[name]


#: Usual number of values of a design variable (the paper's study: 12 layers).
USUAL_VALUES = 12


def variable_field(name: str) -> str:
    """The field that names variable ``name`` in errors: ``optimization.vary.radius``."""
    return f"optimization.vary.{name}"


@dataclass(frozen=True)
class _Spec:
    """A parsed specification, not yet built: ``form`` is ``"list"`` (``items``),
    ``"range"`` (whole ``start, stop, step``), ``"grid"`` (``start, stop, count``) or
    ``"interval"`` (``start, stop``)."""

    name: str
    form: str
    items: tuple = ()
    start: float = 0.0
    stop: float = 0.0
    step: int = 1
    count: int = 0

    @property
    def size(self) -> float:
        """Number of values (inf for an interval), known without building them."""
        if self.form == "list":
            return len(self.items)
        if self.form == "range":
            return (int(self.stop) - int(self.start)) // self.step + 1
        return self.count if self.form == "grid" else math.inf


def _parse(spec: str) -> _Spec:
    """Read ``"name=..."`` completely (every check of the text) without building a range."""
    from pdamper.units import parse_quantity

    field_ = "optimization.vary"
    if not isinstance(spec, str) or "=" not in spec:
        raise InputError(field_, f"expected 'name=values' such as 'particles=16:176:16', "
                         f"got {spec!r}")
    raw_name, _, text = spec.partition("=")
    name = _name(raw_name)
    kind = DESIGN_VARIABLES[name]
    text = text.strip()
    if not text:
        raise InputError(field_, f"{spec!r}: no values after '='")
    where = variable_field(name)
    if kind.kind == "categorical":
        from pdamper.materials import get_material

        names = tuple(p.strip() for p in text.split(","))
        if not all(names):
            raise InputError(field_, f"{spec!r}: an empty material name in the list; give "
                             "names separated by commas (e.g. 'particle-material=S235,PVC')")
        for n in names:
            get_material(n, where)
        return _Spec(name, "list", names)
    if kind.kind == "integer":
        if ":" in text:
            parts = text.split(":")
            try:
                a, b, step = (int(p) for p in parts) if len(parts) == 3 else (0, -1, 0)
            except ValueError:
                a, b, step = 0, -1, 0  # not three whole numbers: refused just below
            if step < 1 or b < a:
                raise InputError(where, f"expected 'start:stop:step' of whole numbers with "
                                 f"stop >= start and step >= 1, got {text!r}")
            if (b - a) % step:
                raise InputError(where, f"{text!r}: stop - start = {b - a} is not a multiple of "
                                 f"the step {step} (particle counts use start:stop:STEP, e.g. "
                                 "16:176:16)")
            check_setting(where, a, kind.declaration)  # the stop is above the start
            return _Spec(name, "range", start=a, stop=b, step=step)
        try:
            values = tuple(int(p) for p in text.split(","))
        except ValueError:
            raise InputError(where, f"expected whole numbers, got {text!r}") from None
        for v in values:
            check_setting(where, v, kind.declaration)
        return _Spec(name, "list", values)
    # continuous
    parts = text.split(":")
    if len(parts) == 1:
        out = _Spec(name, "list", tuple(parse_quantity(p, kind.unit, where)
                                        for p in text.split(",")))
    elif len(parts) == 2:
        lo, hi = (parse_quantity(p, kind.unit, where) for p in parts)
        if not lo < hi:
            raise InputError(where, f"interval {text!r} must have start < stop")
        out = _Spec(name, "interval", start=lo, stop=hi)
    elif len(parts) == 3:
        lo, hi = (parse_quantity(p, kind.unit, where) for p in parts[:2])
        try:
            count = int(parts[2])
        except ValueError:
            raise InputError(where, f"count {parts[2]!r} of {text!r} must be a whole "
                             "number") from None
        if count < 1 or not lo <= hi or (count == 1 and lo != hi):
            raise InputError(where, f"expected 'start:stop:count' with start <= stop and "
                             f"count >= 1, got {text!r}")
        out = _Spec(name, "grid", start=lo, stop=hi, count=count)
    else:
        raise InputError(where, f"expected 'start:stop:count', 'start:stop' or a list, "
                         f"got {text!r}")
    # the ends decide for a range: the values between them are between them
    for v in out.items or (out.start, out.stop):
        check_setting(where, v, kind.declaration)
    return out


def variable_size(spec: str) -> tuple[str, float]:
    """``(name, number of values)`` of a specification (inf for an interval), every check of
    the text made, nothing built: what a count implies is judged from it
    (:func:`values_cost`) before :func:`parse_variable` builds the values.

    >>> variable_size("particles=0:1000000000:1")
    ('particles', 1000000001)
    """
    p = _parse(spec)
    return p.name, p.size


def values_cost(name: str, size: float) -> Cost:
    """The memory the values of variable ``name`` take (a :class:`pdamper.resources.Cost`),
    from their number."""
    from pdamper import resources

    field_ = variable_field(name)
    return resources.count_cost(0.0 if math.isinf(size) else size, f"the values of {field_}",
                                "values", bytes_each=resources.BYTES_PER_VALUE, field=field_,
                                usual=USUAL_VALUES)


def parse_variable(spec: str, force: bool = True) -> DesignVariable:
    """A :class:`DesignVariable` from ``"name=..."`` (module docstring for the forms).

    The number of values is judged by :mod:`pdamper.resources` before they are built
    (``force``: only the hard limits, what this machine cannot hold; the command line
    passes its ``--force``).

    Examples
    --------
    >>> parse_variable("particles=16:176:16").values[:3]
    (16, 32, 48)
    >>> [round(v * 1e3, 3) for v in parse_variable("radius=3mm:6mm:4").values]
    [3.0, 4.0, 5.0, 6.0]
    >>> parse_variable("radius=3mm:6mm").bounds
    (0.003, 0.006)
    """
    from pdamper import resources

    p = _parse(spec)
    resources.require(values_cost(p.name, p.size), force)
    if p.form == "list":
        return DesignVariable(p.name, p.items, spec=spec)
    if p.form == "range":
        return DesignVariable(p.name, tuple(range(int(p.start), int(p.stop) + 1, p.step)),
                              spec=spec)
    if p.form == "interval":
        return DesignVariable(p.name, None, (p.start, p.stop), spec=spec)
    values = tuple(float(v) for v in np.linspace(p.start, p.stop, p.count))
    return DesignVariable(p.name, values, (p.start, p.stop), spec=spec)


def apply_design(damper: ParticleDamper, design: dict[str, Any]) -> ParticleDamper:
    """``damper`` with the design's variables set; raises InputError if it cannot be built
    (e.g. more spheres than fit)."""
    from pdamper.materials import get_material

    counts = [n for n in design if n == "particles" or DESIGN_VARIABLES[n].derived]
    if len(counts) > 1:
        raise InputError("optimization.vary", f"{' and '.join(counts)} both set the particle "
                         "count: vary at most one of particles, bed-mass and fill")
    changes = {}
    for name, value in design.items():
        kind = DESIGN_VARIABLES[name]
        if kind.derived:
            continue
        if kind.kind == "categorical":
            value = get_material(value, variable_field(name))
        changes[kind.attribute] = value
    out = replace(damper, **changes) if changes else damper
    for name in counts:  # the count of the radius and material just set
        if name == "bed_mass":
            out = out.with_count(int(round(design[name] / out.particle_mass)))
        elif name == "fill":
            out = out.with_count(int(round(design[name] * out.max_count)))
    return out


def design_values(damper: ParticleDamper) -> dict[str, Any]:
    """Every design variable's value in ``damper`` (SI units, material names; the bed's
    mass and its fraction of the lattice's count for the derived variables)."""
    out: dict[str, Any] = {}
    for name, kind in DESIGN_VARIABLES.items():
        if name == "bed_mass":
            out[name] = damper.bed_mass
        elif name == "fill":
            out[name] = damper.count / damper.max_count if damper.max_count else 0.0
        else:
            v = getattr(damper, kind.attribute)
            out[name] = v.name if kind.kind == "categorical" else v
    return out


# ----------------------------------------------------------------------------- objectives
@dataclass(frozen=True)
class Objective:
    """An objective on the free vibration of a design.

    Attributes
    ----------
    name
        ``"amplitude-at"``, ``"settling-time"`` or ``"mean-damping"``.
    sense
        ``"min"`` or ``"max"``.
    unit
        Unit of the value (SI).
    at
        T [s]: time of the amplitude, or end of the cycles averaged.
    threshold
        Settling threshold [m] (settling-time).
    duration
        Simulated time of each design [s] (settling-time: the longest settling time that
        can be found).
    """

    name: str
    sense: str
    unit: str
    at: float
    threshold: float | None = None
    duration: float | None = None
    #: the :class:`~pdamper.coupling.loads.LoadHistory` of ``peak`` and ``rms``, its free
    #: tail [s] and the response's sample rate [Hz]
    load: Any = field(default=None, repr=False, compare=False)
    tail: float = 0.0
    sample_rate: float = LOAD_SAMPLE_RATE
    #: the forced-response objectives: the frequencies [Hz] of the band and the
    #: :class:`~pdamper.coupling.frf.HarmonicLoad`
    band: tuple[float, ...] | None = None
    frf_load: Any = None

    @property
    def label(self) -> str:
        """The objective in words with its display unit, e.g. ``"settling time [s]"``
        (:data:`OBJECTIVE_LABELS`)."""
        return (f"{OBJECTIVE_LABELS[self.name].format(at=self.at)} "
                f"[{DISPLAY_UNITS[self.unit][0]}]")

    @property
    def display_scale(self) -> float:
        """Factor from the SI value to the unit of :attr:`label` (1e3 for metres)."""
        return DISPLAY_UNITS[self.unit][1]

    def evaluate(self, res: FreeVibrationResult | LoadResponse | FRFResult
                 ) -> tuple[float, dict]:
        """Objective value of a :class:`~pdamper.coupling.FreeVibrationResult` (of a
        :class:`~pdamper.coupling.loads.LoadResponse` for ``peak``, ``rms``; of a
        :class:`~pdamper.coupling.frf.FRFResult` for ``peak-frf``, ``rms-frf``) and
        extras."""
        # the objective's name says which result it reads (DesignEvaluator runs that one)
        if self.name in FRF_OBJECTIVES:
            frf = cast("FRFResult", res)
            value = frf.peak() if self.name == "peak-frf" else frf.rms()
            steady = all(bool(np.all(c.steady)) for c in frf.sweeps.values())
            return value, {"steady": steady, **frf_accelerations(frf)}
        if self.name in LOAD_OBJECTIVES:
            forced = cast("LoadResponse", res)
            extras = {"peak_acceleration": forced.peak_acceleration,
                      "rms_acceleration": forced.rms_acceleration,
                      "dissipated_energy": forced.dissipated_energy}
            return (forced.peak if self.name == "peak" else forced.rms), extras
        res = cast("FreeVibrationResult", res)
        if self.name == "amplitude-at":
            return res.amplitude_at(self.at), {}
        if self.name == "mean-damping":
            amp, zeta = res.damping_ratio
            ends = np.asarray(res.peak_times[1:])
            sel = ends <= self.at * (1 + 1e-12)
            if not np.any(sel):
                return float("nan"), {"cycles": 0}
            return float(np.mean(zeta[sel])), {"cycles": int(np.count_nonzero(sel))}
        assert self.threshold is not None  # make_objective gives settling-time its threshold
        t = settling_time(res.peak_times, res.peak_amplitudes, self.threshold)
        if t is None:
            return float(res.time[-1]), {"settled": False}
        return t, {"settled": True}


def frf_accelerations(frf: FRFResult) -> dict[str, float]:
    """The largest steady acceleration amplitude (2 pi f)^2 X of the output point [m/s^2]
    over the frequencies of each sweep (``peak_acceleration_up``, ``..._down``) and of both
    (``peak_acceleration``); a sweep's unsteady steps are read as they are where none of
    its steps is steady. The output amplitude is absolute (a base-driven structure's too),
    so this is the acceleration an accelerometer there reads."""
    w2 = (2.0 * np.pi * np.asarray(frf.frequency, float)) ** 2
    out: dict[str, float] = {}
    for name, c in frf.sweeps.items():
        a = np.asarray(c.amplitude, float)
        steady = np.where(np.asarray(c.steady, bool), a, np.nan)
        use = a if np.all(np.isnan(steady)) else steady
        out[f"peak_acceleration_{name}"] = float(np.nanmax(w2 * use))
    if out:
        out["peak_acceleration"] = max(out.values())
    return out


def settling_time(peak_times: ArrayLike, peak_amplitudes: ArrayLike,
                  threshold: float) -> float | None:
    """First time [s] the exponential envelope of the negative peaks reaches ``threshold``
    [m] (interpolated as :meth:`FreeVibrationResult.amplitude_at`); None if it never does.

    >>> settling_time([0.0, 1.0, 2.0], [0.04, 0.02, 0.01], 0.02)
    1.0
    >>> round(settling_time([0.0, 1.0], [0.04, 0.01], 0.02), 3)
    0.5
    """
    tp = np.asarray(peak_times, float)
    ap = np.asarray(peak_amplitudes, float)
    if ap[0] <= threshold:
        return float(tp[0])
    k = np.flatnonzero(ap <= threshold)
    if k.size == 0:
        return None
    i = int(k[0])
    a0, a1 = ap[i - 1], ap[i]
    if a1 <= 0:
        return float(tp[i])
    q = math.log(threshold / a0) / math.log(a1 / a0)
    return float(tp[i - 1] + q * (tp[i] - tp[i - 1]))


OBJECTIVES = {"amplitude-at": ("min", "m"), "settling-time": ("min", "s"),
              "mean-damping": ("max", "1")}
#: Objectives on the response to a load history (module docstring).
LOAD_OBJECTIVES = {"peak": ("min", "m"), "rms": ("min", "m")}
OBJECTIVES.update(LOAD_OBJECTIVES)
#: Objectives on the forced response (pdamper.coupling.frf) over a frequency band.
FRF_OBJECTIVES = {"peak-frf": ("min", "m"), "rms-frf": ("min", "m")}
OBJECTIVES.update(FRF_OBJECTIVES)
#: The usual band of the forced-response objectives (a count the cost checks compare
#: with); without ``band`` the band spans every mode of the structure, each resonance
#: resolved for its damping (:func:`pdamper.coupling.frf.default_frequencies`); default
#: load 2 N.
FRF_BAND = (0.5, 1.5, 41)
FRF_LOAD = "2 N"
#: What each objective is, in words, for axes and tables (the value in the unit of
#: :attr:`Objective.display_unit`); every key of :data:`OBJECTIVES` has one.
OBJECTIVE_LABELS = {"amplitude-at": "amplitude at t = {at:g} s",
                    "settling-time": "settling time",
                    "mean-damping": "mean damping ratio",
                    "peak": "peak |displacement| under the load history",
                    "rms": "RMS displacement under the load history",
                    "peak-frf": "largest steady amplitude over the band",
                    "rms-frf": "RMS of the steady amplitude over the band"}
#: Unit in which objectives of each SI unit are shown, and its factor from SI.
DISPLAY_UNITS = {**DISPLAY_OF, "s": ("s", 1.0), "1": ("-", 1.0)}


def make_objective(name: str, at: float, initial_displacement: float,
                   structure: SingleDOFStructure | ModalStructure,
                   threshold: float | None = None, duration: float | None = None,
                   load: LoadHistory | None = None, tail: float = 0.0,
                   band: ArrayLike | None = None,
                   frf_load: HarmonicLoad | str | None = None) -> Objective:
    """The :class:`Objective` ``name`` with its defaults (module docstring).

    ``peak-frf`` and ``rms-frf`` take ``band`` (frequencies [Hz]; default every mode of
    the structure, :func:`pdamper.coupling.frf.default_frequencies`) and ``frf_load`` (a
    :class:`~pdamper.coupling.frf.HarmonicLoad` or its text, e.g. ``"2N"``, ``"0.3g"``;
    default :data:`FRF_LOAD`).

    ``peak`` and ``rms`` need ``load`` (a :class:`~pdamper.coupling.loads.LoadHistory`) and
    run over the record plus ``tail`` [s]; the free-decay objectives ignore a load.

    ``duration`` (settling-time) defaults to ``max(2 s, 2 at)``; the other objectives run to
    two periods of ``structure``'s natural frequency past T (so that two peaks bracket T,
    as in :func:`pdamper.design.optimize_particle_count`).
    """
    if name not in OBJECTIVES:
        raise InputError("optimization.objective", f"must be one of {', '.join(OBJECTIVES)}, "
                         f"got {name!r}")
    check_range("optimization.at", at, low=0.0, low_inclusive=False, unit="s")
    sense, unit = OBJECTIVES[name]
    if name in FRF_OBJECTIVES:
        from pdamper.coupling.frf import HarmonicLoad, check_damped

        check_damped(structure)  # before any design: its forced response must be bounded

        if band is None:  # every mode, each resonance resolved for its damping
            from pdamper.coupling.frf import default_frequencies

            band = default_frequencies(structure)
        f = np.atleast_1d(np.asarray(band, float))
        if f.ndim != 1 or f.size == 0 or not np.all(np.isfinite(f)) or np.any(f <= 0):
            raise InputError("optimization.band", "must be one or more finite frequencies "
                             "> 0 Hz")
        if not isinstance(frf_load, HarmonicLoad):
            frf_load = HarmonicLoad.parse(FRF_LOAD if frf_load is None else frf_load,
                                          field="optimization.frf_load")
        return Objective(name, sense, unit, at, band=tuple(float(v) for v in np.unique(f)),
                         frf_load=frf_load)
    if name in LOAD_OBJECTIVES:
        if load is None:
            raise InputError("optimization.objective", f"{name!r} is an objective on the "
                             "response to a load history: give one (--load or "
                             "--base-acceleration; [load] force or base_acceleration)")
        check_range("load.tail", tail, low=0.0, unit="s")
        return Objective(name, sense, unit, at, None, load.duration + tail, load, tail)
    if name == "settling-time":
        thr = 0.25 * abs(initial_displacement) if threshold is None else threshold
        check_range("optimization.threshold", thr, low=0.0, high=abs(initial_displacement),
                    low_inclusive=False, high_inclusive=False, unit="m")
        dur = max(2.0, 2.0 * at) if duration is None else duration
        return Objective(name, sense, unit, at, thr, dur)
    return Objective(name, sense, unit, at, None, at + 2.0 / structure.natural_frequency)


# ----------------------------------------------------------------------------- limits
#: Quantities a limit may bound: name -> (SI unit, what it is, where it is read: the
#: objectives whose runs compute it and, for each, the candidate's objective
#: (``"objective"``) or the extra of that name). ``mass`` is every design's: the bed plus
#: the container.
LIMIT_QUANTITIES: dict[str, tuple[str, str, dict[str, str]]] = {
    "mass": ("kg", "mass of bed and container", {}),
    "peak": ("m", "peak |displacement| at the observation point",
             {"peak": "objective", "peak-frf": "objective"}),
    "rms": ("m", "RMS displacement at the observation point",
            {"rms": "objective", "rms-frf": "objective"}),
    "peak-acceleration": ("m/s^2", "peak |acceleration| at the observation point",
                          {"peak": "peak_acceleration", "rms": "peak_acceleration",
                           "peak-frf": "peak_acceleration", "rms-frf": "peak_acceleration"}),
    "rms-acceleration": ("m/s^2", "RMS acceleration at the observation point",
                         {"peak": "rms_acceleration", "rms": "rms_acceleration"}),
    "amplitude-at": ("m", "amplitude of the free decay at T", {"amplitude-at": "objective"}),
    "settling-time": ("s", "settling time of the free decay",
                      {"settling-time": "objective"}),
    "mean-damping": ("1", "mean damping ratio of the free decay",
                     {"mean-damping": "objective"}),
    "peak-frf": ("m", "largest steady amplitude over the band",
                 {"peak-frf": "objective"}),
    "rms-frf": ("m", "RMS of the steady amplitude over the band",
                {"rms-frf": "objective"}),
}
#: g of a limit's or a shown acceleration [m/s^2]: the standard gravity (pint's g0), as in
#: a harmonic load's "0.5g" (:meth:`pdamper.coupling.frf.HarmonicLoad.parse`).
G0 = 9.80665
_LIMIT = re.compile(r"^\s*([A-Za-z][\w-]*)\s*(<=|>=|<|>)\s*(.+?)\s*$")


@dataclass(frozen=True)
class Limit:
    """A limit on a design: ``quantity`` (:data:`LIMIT_QUANTITIES`) ``op`` (``"<="`` or
    ``">="``) ``value`` (SI).

    The margin of a design is ``value - q`` for ``<=`` and ``q - value`` for ``>=``
    (positive: met, in the quantity's unit), and relative to ``|value|``.
    """

    quantity: str
    op: str
    value: float
    text: str = ""

    @property
    def unit(self) -> str:
        return LIMIT_QUANTITIES[self.quantity][0]

    def margin(self, q: float) -> float:
        """The margin of a design whose quantity is ``q`` (SI; >= 0: met)."""
        return self.value - q if self.op == "<=" else q - self.value

    def describe(self) -> str:
        """``"peak-acceleration <= 10 g"`` in display units."""
        return f"{self.quantity} {self.op} {show_quantity(self.value, self.unit)}"

    def as_dict(self) -> dict:
        return {"quantity": self.quantity, "op": self.op, "value": self.value,
                "unit": self.unit, "text": self.text or self.describe()}


def show_quantity(value: float, unit: str) -> str:
    """A value in the display unit of its SI ``unit``: mm, g (mass), g (acceleration, the
    standard gravity), s, % (a ratio)."""
    if unit == "m":
        return f"{value * 1e3:.4g} mm"
    if unit == "kg":
        return f"{value * 1e3:.4g} g"
    if unit == "m/s^2":
        return f"{value / G0:.4g} g"
    if unit == "1":
        return f"{value * 100:.4g} %"
    return f"{value:.4g} {unit}"


def parse_limit(text: str, field_: str = "optimization.require") -> Limit:
    """A response limit ``"QUANTITY<=VALUE"`` (or ``>=``), the value with its unit:
    ``"peak-acceleration<=10g"`` (g: the standard gravity), ``"peak<=3mm"``,
    ``"mean-damping>=2%"``.

    >>> parse_limit("peak<=3mm").value
    0.003
    >>> round(parse_limit("peak-acceleration <= 10 g").value, 4)
    98.0665
    """
    from pdamper.units import parse_quantity

    m = _LIMIT.match(text) if isinstance(text, str) else None
    if m is None:
        raise InputError(field_, f"expected 'QUANTITY<=VALUE' or 'QUANTITY>=VALUE' such as "
                         f"'peak-acceleration<=10g', got {text!r}")
    name, op, raw = m[1].lower().replace("_", "-"), m[2], m[3]
    if name not in LIMIT_QUANTITIES:
        raise InputError(field_, f"{text!r}: unknown quantity {m[1]!r}; known: "
                         f"{', '.join(LIMIT_QUANTITIES)}")
    op = {"<": "<=", ">": ">="}.get(op, op)
    unit = LIMIT_QUANTITIES[name][0]
    if unit == "m/s^2":  # "10g": g is the standard gravity (pint reads a bare g as gram)
        raw = re.sub(r"(?<=[\d.\s])g$", " g0", raw)
    if unit == "1":  # a ratio: a number or a percentage
        try:
            value = (float(raw[:-1]) / 100.0 if raw.endswith("%") else float(raw))
        except ValueError:
            raise InputError(field_, f"{text!r}: the value must be a number or a "
                             "percentage such as '2%'") from None
    else:
        try:
            value = parse_quantity(raw, unit, field_)
        except InputError as exc:
            raise InputError(field_, f"{text!r}: {exc.message}") from None
    if not math.isfinite(value) or value < 0 or (value == 0 and op == "<="):
        raise InputError(field_, f"{text!r}: the limit must be finite and > 0")
    return Limit(name, op, value, text.strip())


def check_limits(limits: Sequence[Limit], objective: Objective) -> None:
    """Refuse a limit on a quantity the objective's runs do not compute, naming those that
    do (before any design runs)."""
    for lim in limits:
        where = LIMIT_QUANTITIES[lim.quantity][2]
        if lim.quantity != "mass" and objective.name not in where:
            raise InputError("optimization.require", f"{lim.text or lim.describe()!r}: "
                             f"{lim.quantity} is computed by the objective(s) "
                             f"{', '.join(where)}, not by {objective.name!r} (the limits "
                             "bound what the objective's runs compute)")


def limit_quantity(lim: Limit, c: DesignCandidate, objective: Objective) -> float | None:
    """The value of ``lim``'s quantity for candidate ``c`` (SI; None: not computed)."""
    if lim.quantity == "mass":
        return c.total_mass
    source = LIMIT_QUANTITIES[lim.quantity][2].get(objective.name)
    value = c.objective if source == "objective" else c.extra.get(source or "")
    return None if value is None else float(value)


def judge(c: DesignCandidate, limits: Sequence[Limit], objective: Objective
          ) -> DesignCandidate:
    """``c`` with the margin of every limit and its violations (a design that violates
    one is infeasible with the reason; one not evaluated is judged by its mass only)."""
    if not limits or c.mass is None:
        return c
    rows, violations = [], []
    for lim in limits:
        q = limit_quantity(lim, c, objective)
        if q is None:
            if c.status == "ok":  # evaluated, yet the quantity is missing: not met
                violations.append(f"{lim.quantity} was not computed for this design")
            continue
        margin = lim.margin(q)
        rows.append({"quantity": lim.quantity, "op": lim.op, "limit": lim.value,
                     "value": q, "margin": margin,
                     "relative_margin": margin / abs(lim.value), "met": margin >= 0,
                     "unit": lim.unit})
        if margin < 0:
            violations.append(f"{lim.quantity} {show_quantity(q, lim.unit)} "
                              f"{'above' if lim.op == '<=' else 'below'} the limit "
                              f"{show_quantity(lim.value, lim.unit)} (by "
                              f"{show_quantity(-margin, lim.unit)}, "
                              f"{-margin / abs(lim.value) * 100:.3g} %)")
    return replace(c, limits=tuple(rows), violations=tuple(violations))


# ----------------------------------------------------------------------------- results
@dataclass(frozen=True)
class DesignCandidate:
    """One evaluated design.

    Attributes
    ----------
    design
        Every design variable's value (SI units, material names).
    particles, mass
        n_p and the bed mass [kg] (the paper study's keys).
    objective
        The objective's value (SI), None if infeasible or failed.
    status
        ``"ok"``, ``"infeasible"`` (does not fit the container) or ``"failed"``.
    reason
        Why infeasible or failed.
    extra
        Objective extras (``settled``, ``cycles``; the response quantities the limits
        read, ``peak_acceleration``, ...).
    container_mass
        The container's mass [kg] (``container.mass``): with the bed's, the design's
        :attr:`total_mass`, the mass its limit bounds.
    limits
        Each limit's row (:func:`judge`): ``quantity``, ``op``, ``limit``, ``value``,
        ``margin`` (SI, >= 0: met), ``relative_margin``, ``met``.
    violations
        The limits it violates, in words: a design with any is infeasible (evaluated, not
        chosen).
    """

    design: dict
    particles: int
    mass: float | None
    objective: float | None
    status: str = "ok"
    reason: str = ""
    extra: dict = field(default_factory=dict)
    container_mass: float = 0.0
    limits: tuple[dict, ...] = ()
    violations: tuple[str, ...] = ()

    @property
    def feasible(self) -> bool:
        """Buildable and within every limit."""
        return self.status != "infeasible" and not self.violations

    @property
    def total_mass(self) -> float | None:
        """Bed plus container [kg] (None: not built)."""
        return None if self.mass is None else self.mass + self.container_mass

    @property
    def chosen_from(self) -> bool:
        """Evaluated and within every limit: a candidate for best and lightest."""
        return self.status == "ok" and not self.violations

    def as_dict(self) -> dict:
        reason = self.reason or "; ".join(self.violations)
        out = {"particles": self.particles, "mass": self.mass, "objective": self.objective,
               **self.design, "container_mass": self.container_mass,
               "total_mass": self.total_mass, "feasible": self.feasible,
               "status": self.status, "reason": reason, **self.extra}
        if self.limits:
            out["limits"] = list(self.limits)
        why = (f"the design is {self.status}: {self.reason}" if self.status != "ok"
               else "not computed for this design")
        na = {k: why for k, v in out.items() if v is None}
        return {**out, "not_applicable": na} if na else out


@dataclass(frozen=True)
class DesignStudyResult:
    """The landscape of a design study and its best design.

    ``best`` is None when no design could be evaluated, or when designs failed and the
    evaluated ones are no comparison (one survivor, or only the bare structure: a design is
    never best because the others failed); :attr:`no_best` says why in a sentence. Where
    designs failed and a best is named, it is the best of the evaluated designs, and
    :attr:`failures` lists the others with their reasons.
    """

    best: DesignCandidate | None
    candidates: tuple[DesignCandidate, ...]
    variables: tuple[DesignVariable, ...]
    objective: Objective
    method: str
    seed: int | None = None
    tolerance: float = DEFAULT_TOLERANCE
    #: the limits every chosen design meets (:class:`Limit`; the mass limit first)
    limits: tuple[Limit, ...] = ()

    @property
    def feasible(self) -> tuple[DesignCandidate, ...]:
        """The evaluated designs within every limit (those best and lightest are chosen
        from)."""
        return tuple(c for c in self.candidates if c.chosen_from)

    @property
    def lightest_feasible(self) -> DesignCandidate | None:
        """The lightest design within every limit (of equal mass, the better objective):
        the first of the front; None when no evaluated design meets the limits."""
        front = self.front
        return front[0] if front else None

    @property
    def closest(self) -> DesignCandidate | None:
        """Where limits leave no evaluated design: the one that misses them least (the
        smallest largest relative shortfall; then the better objective); None otherwise."""
        if not self.limits or self.feasible:
            return None
        ok = [c for c in self.candidates if c.status == "ok" and c.objective is not None]
        if not ok:
            return None
        sign = 1.0 if self.objective.sense == "min" else -1.0

        def miss(c: DesignCandidate) -> tuple[float, float]:
            worst = max((-r["relative_margin"] for r in c.limits), default=math.inf)
            assert c.objective is not None
            return worst, sign * c.objective

        return min(ok, key=miss)

    @property
    def at(self) -> float:
        return self.objective.at

    @property
    def front(self) -> tuple[DesignCandidate, ...]:
        """Pareto front of added mass against the objective, lightest first
        (:func:`pareto_front`)."""
        return pareto_front(self.candidates, self.objective.sense)

    @property
    def lightest_within(self) -> DesignCandidate | None:
        """The lightest design within ``tolerance`` of the best (:func:`lightest_within`)."""
        return lightest_within(self.candidates, self.best, self.tolerance,
                               self.objective.sense)

    @property
    def failures(self) -> tuple[DesignCandidate, ...]:
        """The designs whose evaluation failed, each with its reason."""
        return tuple(c for c in self.candidates if c.status == "failed")

    @property
    def no_best(self) -> str | None:
        """Why the study names no best design, in a sentence (None: it names one)."""
        if self.best is not None:
            return None
        n, names = len(self.candidates), [v.name for v in self.variables]
        failed = self.failures
        infeasible = [c for c in self.candidates if c.status == "infeasible"]
        if failed:
            which = "; ".join(describe_design(c, names) for c in failed[:3])
            more = f"; {len(failed) - 3} more" if len(failed) > 3 else ""
            ok = [c for c in self.candidates if c.status == "ok"]
            left = ("none" if not ok else "only " + "; ".join(describe_design(c, names)
                                                             for c in ok))
            return (f"{len(failed)} of {n} designs failed ({which}{more}: each with its "
                    f"reason in the failures) and {left} could be evaluated: no design is "
                    "named best because the others failed; remove the cause of the failures")
        closest = self.closest
        if closest is not None:
            limits = "; ".join(lim.describe() for lim in self.limits)
            return (f"no evaluated design meets the limits ({limits}): of "
                    f"{sum(c.status == 'ok' for c in self.candidates)} evaluated, the closest "
                    f"({describe_design(closest, names)}) misses by "
                    f"{'; '.join(closest.violations)}")
        if infeasible and len(infeasible) == n:
            reasons = list(dict.fromkeys(c.reason for c in infeasible))
            more = (f" and {len(reasons) - 1} more reason(s)" if len(reasons) > 1 else "")
            return (f"no design is feasible: all {n} designs are outside what can be built "
                    f"or run ({describe_design(infeasible[0], names)}: {reasons[0]}{more}); change "
                    "the ranges of the design variables")
        return "no design was evaluated"

    def not_applicable(self) -> dict[str, str]:
        """``key -> reason`` of the result keys that are null (``best``,
        ``lightest_within``, ``closest``)."""
        why = self.no_best
        out = {}
        if self.limits and self.closest is None:
            out["closest"] = ("some evaluated design meets every limit, or none was "
                              "evaluated: no design is named as missing them least")
        if self.limits and self.lightest_feasible is None:
            out["lightest_feasible"] = "no evaluated design meets every limit"
        if why is None:
            return out
        return {**out, "best": why, "lightest_within": f"there is no best design: {why}"}

    def unset_reasons(self) -> dict[str, str]:
        """``key -> reason`` of the settings of :meth:`as_dict` that are null for this
        objective and method (``threshold``, ``seed``): with :meth:`not_applicable`, every
        null of its top level (``pdamper optimize --json``)."""
        why: dict[str, str] = {}
        if self.objective.threshold is None:
            why["threshold"] = (f"the objective {self.objective.name!r} has no threshold "
                                "(only settling-time has one)")
        if self.seed is None:
            why["seed"] = (f"the method {self.method!r} draws no random numbers (only "
                           "optimize, the differential evolution, is seeded)")
        return why

    def as_dict(self) -> dict:
        return {
            "best": None if self.best is None else self.best.as_dict(),
            "candidates": [c.as_dict() for c in self.candidates],
            "front": [c.as_dict() for c in self.front],
            "lightest_within": None if (light := self.lightest_within) is None
            else {**light.as_dict(), "tolerance": self.tolerance},
            "tolerance": self.tolerance,
            "at": self.objective.at,
            "objective_name": self.objective.name,
            "sense": self.objective.sense,
            "threshold": self.objective.threshold,
            **({"band": list(self.objective.band or ()),
                "frf_load": self.objective.frf_load.as_dict()}
               if self.objective.frf_load is not None else {}),
            "method": self.method,
            "seed": self.seed,
            "evaluations": len(self.candidates),
            "infeasible": sum(c.status == "infeasible" for c in self.candidates),
            "failed": sum(c.status == "failed" for c in self.candidates),
            "failures": [{**{v.name: c.design[v.name] for v in self.variables},
                          "reason": c.reason} for c in self.failures],
            **({"not_applicable": na} if (na := self.not_applicable()) else {}),
            "variables": [_variable_dict(v) for v in self.variables],
            "limits": [lim.as_dict() for lim in self.limits],
            **({"within_limits": len(self.feasible),
                "lightest_feasible": None if (first := self.lightest_feasible) is None
                else first.as_dict(),
                "closest": None if (near := self.closest) is None else near.as_dict()}
               if self.limits else {}),
        }


def _variable_dict(v: DesignVariable) -> dict:
    """A design variable as JSON: its ``values`` (a list or grid) or its ``bounds`` (an
    interval), the other null with its reason in ``not_applicable``."""
    out: dict = {"name": v.name, "field": DESIGN_VARIABLES[v.name].field, "spec": v.spec,
                 "kind": v.kind, "values": None if v.values is None else list(v.values),
                 "bounds": None if v.bounds is None else list(v.bounds)}
    na = {}
    if v.values is None:
        na["values"] = "an interval: the search takes values within its bounds"
    if v.bounds is None:
        na["bounds"] = "the values are listed (or a grid): no interval to search"
    return {**out, "not_applicable": na} if na else out


def describe_design(c: DesignCandidate, names: Sequence[str]) -> str:
    """Design ``c`` by the variables ``names``, in words: ``"particles 32, radius 3 mm"``."""
    return ", ".join(f"{name.replace('_', ' ')} {show_value(name, c.design[name])}"
                     for name in names)


def show_value(name: str, value: Any) -> str:
    """The value of variable ``name`` in its display unit: ``"3 mm"``, ``"120 g"``,
    ``"40 %"``, a count or a material as it is."""
    kind = DESIGN_VARIABLES[name]
    if kind.kind != "continuous" or not isinstance(value, int | float):
        return str(value)
    unit, scale = kind.display
    return f"{value * scale:.4g} {unit}".rstrip()


# ----------------------------------------------------------------------------- added mass
def parse_tolerance(value: Any) -> float:
    """A relative tolerance: ``"5%"`` or a fraction (``0.05``); 0 <= tolerance < 100 %.

    >>> parse_tolerance("5%"), parse_tolerance(0.1), parse_tolerance("0.02")
    (0.05, 0.1, 0.02)
    """
    text = value.strip() if isinstance(value, str) else value
    try:
        if isinstance(text, bool):
            raise ValueError
        if isinstance(text, str) and text.endswith("%"):
            tol = float(text[:-1].strip()) / 100.0
        else:
            tol = float(text)
    except (TypeError, ValueError):
        raise InputError("optimization.tolerance", f"must be a relative tolerance in "
                         f"[0 %, 100 %) such as '5%' or 0.05, got {value!r}") from None
    if not (math.isfinite(tol) and 0.0 <= tol < 1.0):
        raise InputError("optimization.tolerance", f"must be in [0 %, 100 %) (a relative "
                         f"tolerance on the objective, e.g. '5%'), got {value!r}")
    return tol


class _Scored(Protocol):
    """What the mass rules read of a candidate: a :class:`DesignCandidate` or the paper
    study's :class:`~pdamper.design.optimize.Candidate`."""

    @property
    def mass(self) -> float | None: ...

    @property
    def objective(self) -> float | None: ...


_C = TypeVar("_C", bound=_Scored)


def _ranked(candidates: Sequence[_C], sense: str) -> list[tuple[float, float, _C]]:
    """``(mass, signed objective, candidate)`` of the evaluated designs within their limits:
    both minimised (the mass is bed plus container where a candidate has both; a candidate
    without ``status``, the paper study's, counts as evaluated)."""
    sign = 1.0 if sense == "min" else -1.0
    return [(getattr(c, "total_mass", c.mass), sign * c.objective, c) for c in candidates
            if getattr(c, "status", "ok") == "ok" and c.mass is not None
            and c.objective is not None and not getattr(c, "violations", ())]


def pareto_front(candidates: Sequence[DesignCandidate],
                 sense: str = "min") -> tuple[DesignCandidate, ...]:
    """The designs no other design beats in both added mass and objective, lightest first.

    A design is dominated when another is at most as heavy and at least as good, and
    strictly lighter or strictly better; designs equal in both are all kept (in landscape
    order). ``sense`` is the objective's (``"min"`` or ``"max"``, :data:`OBJECTIVES`);
    infeasible and failed designs are never on the front.
    """
    ranked = _ranked(candidates, sense)
    order = sorted(range(len(ranked)), key=lambda k: (ranked[k][0], ranked[k][1], k))
    front: list[DesignCandidate] = []
    best_so_far = math.inf  # best signed objective of every strictly lighter design
    i = 0
    while i < len(order):
        j = i
        mass = ranked[order[i]][0]
        while j < len(order) and ranked[order[j]][0] == mass:
            j += 1
        group = [ranked[k] for k in order[i:j]]  # equal mass, best objective first
        top = group[0][1]
        if top < best_so_far:
            front.extend(c for _, o, c in group if o == top)
            best_so_far = top
        i = j
    return tuple(front)


def lightest_within(candidates: Sequence[_C], best: _C | None,
                    tolerance: float = DEFAULT_TOLERANCE,
                    sense: str = "min") -> _C | None:
    """The lightest design whose objective is within ``tolerance`` (relative, of |best|)
    of ``best``'s: at most ``best * (1 + tol)`` for a minimised objective, at least
    ``best * (1 - tol)`` for a maximised one (for a positive best). Of equally light ones,
    the better objective, then the first in the landscape. None without a best.
    It is on the Pareto front (:func:`pareto_front`)."""
    tolerance = parse_tolerance(tolerance)
    if best is None or best.objective is None:
        return None
    sign = 1.0 if sense == "min" else -1.0
    limit = sign * best.objective + tolerance * abs(best.objective)
    within = [(m, o, k, c) for k, (m, o, c) in enumerate(_ranked(candidates, sense))
              if o <= limit]
    if not within:
        return best
    return min(within, key=lambda t: t[:3])[3]


# ----------------------------------------------------------------------------- evaluation
@dataclass
class DesignEvaluator:
    """Objective of one design: build the damper, its model, run the structure.

    Picklable (for dask) when ``model`` is (cloudpickle takes closures).
    """

    structure: Any
    damper: ParticleDamper
    initial_displacement: float
    objective: Objective
    model: Callable[[ParticleDamper], Any]

    def __call__(self, design: dict) -> tuple[float, dict]:
        o = self.objective
        if o.frf_load is not None:  # a forced response, both sweep directions
            from pdamper.coupling.frf import assumption_record, frequency_response
            from pdamper.coupling.validity import design_marks

            sim = self.simulation(design)  # the same physics limits as every design
            frf = frequency_response(sim.model, self.structure, o.frf_load, o.band,
                                     sweep="both", with_harmonic_balance=False)
            value, extra = o.evaluate(frf)
            return value, {**extra, **design_marks(assumption_record(frf)),
                           **_harmonic(sim, frf)}
        if o.load is not None:  # the response to the load history
            from pdamper.coupling.loads import run_load

            sim = self.simulation(design)  # the same physics limits as every design
            run = run_load(sim.model, self.structure, o.load, o.sample_rate, o.tail)
            value, extra = o.evaluate(run)
            return value, {**extra, **_harmonic(sim, run)}
        assert o.duration is not None  # make_objective gives a free vibration its duration
        from pdamper.coupling.validity import decay_assumptions, design_marks

        sim = self.simulation(design)
        res = sim.run(o.duration, sample_rate=_SAMPLE_RATE)
        value, extra = o.evaluate(res)
        until = None if o.name == "settling-time" else o.at  # the updates it rests on
        return value, {**extra, **design_marks(decay_assumptions(sim.model, res, until)),
                       **_harmonic(sim, res)}

    def simulation(self, design: dict) -> Simulation:
        """The free vibration of ``design``, made but not run: making it judges the design
        by the physics limits every run obeys (the model's and the release's,
        :mod:`pdamper.resources`); raises InputError outside them."""
        return Simulation(self.structure, self.model(apply_design(self.damper, design)),
                          self.initial_displacement)

    def check(self, design: dict) -> None:
        """Raise InputError if ``design`` is outside the physical limits of a run."""
        self.simulation(design)


def _harmonic(sim: Simulation, result: Any) -> dict:
    """A design's near-harmonic marks (:func:`pdamper.coupling.harmonicity.design_marks`);
    {} without particles (no damper answer to rest on)."""
    from pdamper.coupling.harmonicity import design_marks

    if sim.model.damper.count == 0:
        return {}
    return design_marks(result)


def _feasibility(damper: ParticleDamper, design: dict,
                 check: Callable[[dict], None] | None = None
                 ) -> tuple[ParticleDamper | None, str]:
    try:
        full = apply_design(damper, design)
        if check is not None:
            check(design)
        return full, ""
    except InputError as exc:
        return None, str(exc)


def _show(v: DesignVariable, value) -> str:
    return show_value(v.name, value)


def check_ranges(damper: ParticleDamper, variables: Sequence[DesignVariable],
                 check: Callable[[dict], None]) -> None:
    """Refuse a variable whose given range reaches outside the physical limits of a run,
    before any design is evaluated: each variable at each end of its range (every material
    of a list), the others at ``damper``'s values, judged by ``check`` (e.g.
    :meth:`DesignEvaluator.check`). The limits grow monotonically with each variable (the
    sphere radius, the container height in the impact speed), so the ends decide. A value
    that does not fit the container is left to its candidates (infeasible, listed)."""
    for v in variables:
        ends: tuple
        if v.values is None:  # an interval (DesignVariable refuses neither values nor bounds)
            assert v.bounds is not None
            ends = v.bounds
        elif v.kind == "categorical":
            ends = v.values
        else:
            ends = (min(v.values), max(v.values))
        for value in dict.fromkeys(ends):
            design = {v.name: value}
            try:
                apply_design(damper, design)
            except InputError:
                continue
            try:
                check(design)
            except InputError as exc:
                raise InputError(variable_field(v.name), f"{v.spec!r} reaches {_show(v, value)}, "
                                 f"outside the physical limits: {exc.field}: "
                                 f"{exc.message}") from None


def _canonical(design: dict) -> tuple:
    return tuple(sorted((k, round(v, 12) if isinstance(v, float) else v)
                        for k, v in design.items()))


class _Landscape:
    """Evaluates batches of designs (feasibility first), caching repeated designs."""

    def __init__(self, damper, evaluate, workers, scheduler, progress, limits=(),
                 objective=None):
        self.damper, self.evaluate = damper, evaluate
        self.limits, self.objective = tuple(limits), objective
        self.check = getattr(evaluate, "check", None)
        self.workers, self.scheduler, self.progress = workers, scheduler, progress
        self.candidates: list[DesignCandidate] = []
        self._seen: dict[tuple, DesignCandidate] = {}

    def batch(self, designs: Sequence[dict]) -> list[DesignCandidate]:
        """Evaluate ``designs`` (feasible ones together, in parallel); the landscape keeps
        them in the order given, each distinct design once."""
        out: list[DesignCandidate | None] = [None] * len(designs)
        fresh: list[tuple[int, tuple]] = []  # (index, key) of designs first seen in this batch
        todo = []
        for k, design in enumerate(designs):
            key = _canonical(design)
            if key in self._seen or any(key == f for _, f in fresh):
                continue
            fresh.append((k, key))
            full, reason = _feasibility(self.damper, design, self.check)
            values = _reported_values(self.damper if full is None else full, design)
            if full is None:
                out[k] = DesignCandidate(values, values["particles"], None, None, "infeasible",
                                         reason, container_mass=self.damper.container_mass)
            else:
                todo.append((k, design, values, full))
        outcomes: list[Outcome] = evaluate_parallel(
            self.evaluate, [t[1] for t in todo], workers=self.workers,
            scheduler=self.scheduler, progress=self.progress) if todo else []
        for (k, _design, values, full), oc in zip(todo, outcomes, strict=True):
            mass, box = full.bed_mass, full.container_mass
            if oc.ok and oc.value is not None and math.isfinite(oc.value[0]):
                made = DesignCandidate(values, values["particles"], mass, float(oc.value[0]),
                                       extra=oc.value[1], container_mass=box)
            else:
                made = DesignCandidate(values, values["particles"], mass, None, "failed",
                                       oc.error or "objective is not a finite number",
                                       container_mass=box)
            out[k] = judge(made, self.limits, self.objective)
        for k, key in fresh:
            cand = out[k]
            assert cand is not None  # every design first seen here got its candidate above
            self._seen[key] = cand
            self.candidates.append(cand)
        return [self._seen[_canonical(d)] for d in designs]


def _reported_values(damper: ParticleDamper, design: dict) -> dict[str, Any]:
    """Every design variable's value: ``damper``'s (the design built, or the base damper
    for an infeasible design, which cannot be built), overridden by ``design``."""
    from pdamper.materials import get_material

    out = design_values(damper)
    for name, value in design.items():
        out[name] = get_material(value).name if DESIGN_VARIABLES[name].kind == "categorical" else value
    return out


def run_design_study(
    evaluate: Callable[[dict], tuple[float, dict]],
    damper: ParticleDamper,
    variables: Sequence[DesignVariable],
    objective: Objective,
    *,
    method: str = "auto",
    max_grid: int = DEFAULT_MAX_GRID,
    max_evaluations: int = DEFAULT_MAX_EVALUATIONS,
    seed: int = 0,
    workers: int | None = None,
    scheduler: str | None = None,
    progress: Callable[[int, int], None] | None = None,
    tolerance: float | str = DEFAULT_TOLERANCE,
    limits: Sequence[Limit | str] = (),
    max_mass: float | None = None,
) -> DesignStudyResult:
    """Evaluate designs of ``damper`` over ``variables`` and rank them by ``objective``.

    Parameters
    ----------
    evaluate
        ``evaluate(design) -> (value, extras)`` for a feasible design (a dict of variable
        values), e.g. a :class:`DesignEvaluator`; a synthetic function for tests. Its
        ``check(design)`` method, where it has one, judges the physical limits: each
        variable's range up front (:func:`check_ranges`), each candidate before it runs.
    damper
        The base design; unvaried variables keep its values.
    variables
        The varied :class:`DesignVariable` objects (distinct names).
    objective
        The :class:`Objective` (its sense ranks the candidates).
    method, max_grid, max_evaluations, seed
        Search (module docstring); the optimiser is seeded.
    workers, scheduler
        Parallel evaluation (:func:`pdamper.design.parallel.evaluate_parallel`).
    tolerance
        Relative tolerance of the lightest design nearly as good as the best
        (:func:`lightest_within`; ``"5%"`` or 0.05).
    limits, max_mass
        Response limits (:class:`Limit` or their text, ``"peak-acceleration<=10g"``,
        :func:`parse_limit`) and the largest mass of bed plus container [kg]: a design
        that violates one is infeasible with the reason (evaluated, listed with every
        limit's margin); best, lightest and the front are chosen among the others.
    """
    tolerance = parse_tolerance(tolerance)
    limits = make_limits(limits, max_mass, objective)
    variables = tuple(variables)
    if not variables:
        raise InputError("optimization.vary", "needs at least one design variable")
    names = [v.name for v in variables]
    if len(set(names)) != len(names):
        raise InputError("optimization.vary", f"each variable at most once, got {names}")
    if method not in METHODS:
        raise InputError("optimization.method", f"must be one of {', '.join(METHODS)}, "
                         f"got {method!r}")
    grid_size = math.prod(v.size for v in variables)
    check = getattr(evaluate, "check", None)
    if check is not None:  # a given range outside the physical limits: refused up front
        check_ranges(damper, variables, check)
    if method == "auto":
        method = "grid" if grid_size <= max_grid else "optimize"
    land = _Landscape(damper, evaluate, workers, scheduler, progress, limits, objective)
    if method == "grid":
        open_ = [v.spec for v in variables if v.values is None]
        if open_:
            raise InputError("optimization.vary", f"{open_[0]!r} is an interval: give "
                             "start:stop:count for a grid, or use the optimiser "
                             "(method 'optimize')")
        if grid_size > MAX_GRID:
            raise InputError("optimization.vary", f"the grid has {grid_size:.0f} designs, more "
                             f"than {MAX_GRID}; use fewer values or the optimiser")
        import itertools

        designs = [dict(zip(names, combo, strict=True))
                   for combo in itertools.product(*(v.values for v in variables
                                                    if v.values is not None))]
        land.batch(designs)
    else:
        _differential_evolution(land, variables, objective, max_evaluations, seed)
    sign = 1.0 if objective.sense == "min" else -1.0
    ok = [c for c in land.candidates if c.chosen_from]
    best = (min(ok, key=lambda c: _score(c, sign))
            if ok and _comparable(land.candidates) else None)
    return DesignStudyResult(best, tuple(land.candidates), variables, objective, method,
                             seed if method == "optimize" else None, tolerance, limits)


def make_limits(limits: Sequence[Limit | str] = (), max_mass: float | None = None,
                objective: Objective | None = None) -> tuple[Limit, ...]:
    """The study's limits: ``max_mass`` [kg] as ``mass <= max_mass`` first, then
    ``limits`` (parsed, :func:`parse_limit`), each checked against what ``objective``'s
    runs compute (:func:`check_limits`)."""
    out: list[Limit] = []
    if max_mass is not None:
        check_range("optimization.max_mass", max_mass, low=0.0, low_inclusive=False,
                    unit="kg")
        out.append(Limit("mass", "<=", float(max_mass), f"mass<={max_mass * 1e3:g}g"))
    out += [lim if isinstance(lim, Limit) else parse_limit(lim) for lim in limits]
    if objective is not None:
        check_limits(out, objective)
    return tuple(out)


def _comparable(candidates: Sequence[DesignCandidate]) -> bool:
    """Whether the evaluated designs can name a best: some were evaluated and, where
    others failed, at least two with at least one damper among them (a design is never
    best because the others failed: the bare structure, or the one survivor, alone is no
    comparison)."""
    ok = [c for c in candidates if c.status == "ok"]
    if not any(c.status == "failed" for c in candidates):
        return bool(ok)
    return len(ok) >= 2 and any(c.particles > 0 for c in ok)


def _score(c: DesignCandidate, sign: float) -> float:
    """The value minimised: ``sign`` times an evaluated candidate's objective, the penalty
    for an infeasible or failed one (for one outside its limits, growing with its largest
    relative shortfall, so that the optimiser moves towards the limits)."""
    if c.status != "ok" or c.objective is None:
        return _PENALTY
    if c.violations:
        return _PENALTY * (1.0 + max(-r["relative_margin"] for r in c.limits))
    return sign * c.objective


def _differential_evolution(land: _Landscape, variables, objective, max_evaluations, seed):
    """scipy's differential evolution, one generation per parallel batch."""
    from scipy.optimize import differential_evolution

    check_range("optimization.max_evaluations", max_evaluations, low=4)
    fixed = {v.name: v.values[0] for v in variables if v.values is not None and len(v.values) == 1}
    free = [v for v in variables if v.name not in fixed]
    if not free:
        land.batch([fixed])
        return
    bounds, integrality = [], []
    for v in free:
        if v.kind == "continuous":
            bounds.append(v.bounds if v.bounds is not None else (min(v.values), max(v.values)))
            integrality.append(False)
        else:  # an index into the values (a count grid or the materials)
            bounds.append((0, len(v.values) - 1))
            integrality.append(True)

    def decode(x) -> dict:
        out = dict(fixed)
        for v, xi in zip(free, x, strict=True):
            if v.kind == "continuous":
                out[v.name] = float(xi)
            else:
                out[v.name] = v.values[int(np.clip(round(xi), 0, len(v.values) - 1))]
        return out

    sign = 1.0 if objective.sense == "min" else -1.0

    def batch(xs):  # vectorised: xs has shape (n_variables, n_designs)
        cands = land.batch([decode(x) for x in np.atleast_2d(xs).T])
        return np.array([_score(c, sign) for c in cands])

    popsize = max(5, min(15, max_evaluations // (4 * len(free))))
    per_generation = popsize * len(free)
    maxiter = max(1, max_evaluations // per_generation - 1)
    differential_evolution(batch, bounds, integrality=integrality, vectorized=True,
                           updating="deferred", popsize=popsize, maxiter=maxiter, seed=seed,
                           polish=False, tol=1e-6)


def optimize_design(
    structure: SingleDOFStructure | ModalStructure,
    damper: ParticleDamper,
    initial_displacement: float,
    variables: Sequence[DesignVariable | str],
    objective: str = "amplitude-at",
    at: float = 0.8,
    model: Callable[[ParticleDamper], Any] | None = None,
    threshold: float | None = None,
    duration: float | None = None,
    load: LoadHistory | None = None,
    tail: float = 0.0,
    band: ArrayLike | None = None,
    frf_load: HarmonicLoad | str | None = None,
    **options: Any,
) -> DesignStudyResult:
    """A design study of ``damper`` on ``structure`` (module docstring).

    Parameters
    ----------
    structure
        :class:`~pdamper.structure.SingleDOFStructure` or
        :class:`~pdamper.structure.ModalStructure`.
    damper
        The base design.
    initial_displacement
        x0 [m] (paper: -58 mm).
    variables
        :class:`DesignVariable` objects or specifications (``"particles=16:176:16"``).
    objective, at, threshold, duration, load, tail, band, frf_load
        See :func:`make_objective` (``load``: the history of ``peak`` and ``rms``).
    model
        Damper model factory taking a :class:`ParticleDamper` (default: the analytical model).
    options
        ``method``, ``max_grid``, ``max_evaluations``, ``seed``, ``workers``, ``scheduler``,
        ``progress``, ``tolerance``, ``limits``, ``max_mass`` of :func:`run_design_study`.

    Examples
    --------
    >>> from pdamper.parameters import PAPER_DAMPER, PAPER_STRUCTURE
    >>> r = optimize_design(PAPER_STRUCTURE, PAPER_DAMPER, -0.058, ["particles=0:64:32"])
    >>> [c.particles for c in r.candidates], r.best.particles
    ([0, 32, 64], 64)
    """
    if model is None:
        from pdamper.models.analytical import AnalyticalDamper

        model = AnalyticalDamper
    parsed = [parse_variable(v) if isinstance(v, str) else v for v in variables]
    obj = make_objective(objective, at, initial_displacement, structure, threshold, duration,
                         load, tail, band, frf_load)
    evaluate = DesignEvaluator(structure, damper, initial_displacement, obj, model)
    return run_design_study(evaluate, damper, parsed, obj, **options)
