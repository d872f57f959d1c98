"""The design behind ``pdamper explore``'s page, without the page: its inputs (scenario keys
with their declared units and ranges), the scenario they make, the TOML that reproduces it,
and what the views show (:func:`compute`), so that every number the page draws is the one
the command line prints for the same scenario.

The page (:mod:`pdamper.explore.app`) only turns widgets into :class:`Inputs` and
:class:`Views` into figures; everything here runs and is tested without a browser.
"""

from __future__ import annotations

import dataclasses
import functools
import math
import time
import tomllib
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

if TYPE_CHECKING:
    from pdamper.coupling.frf import FRFResult
    from pdamper.io.scenario import Scenario


@dataclass(frozen=True)
class Control:
    """One input of the page: a scenario key, how the page shows it and its span.

    ``unit`` is the unit the widget shows (``scale`` SI units per widget unit); ``low`` and
    ``high`` bound the slider inside the declared range (``allowed`` of the key's
    declaration, which the page shows beside it and which the scenario judges).
    """

    key: str
    label: str
    unit: str
    scale: float
    low: float
    high: float
    step: float
    integer: bool = False

    def declaration(self) -> Any:
        """The scenario's declaration of the key (unit, default, allowed range, doc)."""
        from pdamper.io.scenario_reference import declaration_of

        return declaration_of(self.key)

    def text(self, value: float) -> str | int | float:
        """The value as the scenario reads it (``"4 mm"``; a bare number without a unit)."""
        if self.integer:
            return int(value)
        return f"{value:g} {self.unit}" if self.unit not in ("", "1") else float(value)


#: The page's numeric inputs, in the order shown. Slider spans are what the page offers; the
#: declared ranges (``>= 0``, ``> 0``) are wider and the scenario judges every value.
CONTROLS: tuple[Control, ...] = (
    Control("particles.count", "particles", "1", 1.0, 0, 200, 1, integer=True),
    Control("particles.radius", "sphere radius", "mm", 1e-3, 0.5, 10.0, 0.1),
    Control("container.length", "container length (vertical)", "mm", 1e-3, 10.0, 300.0, 1.0),
    Control("container.width", "container width", "mm", 1e-3, 10.0, 200.0, 1.0),
    Control("container.depth", "container depth", "mm", 1e-3, 10.0, 200.0, 1.0),
    Control("container.mass", "container mass", "g", 1e-3, 0.0, 1000.0, 1.0),
    Control("particles.friction", "friction coefficient", "1", 1.0, 0.0, 1.0, 0.01),
    Control("structure.stiffness", "structure stiffness", "N/m", 1.0, 100.0, 1e5, 1.0),
    Control("structure.damping", "structure damping", "kg/s", 1.0, 0.0, 50.0, 0.01),
    Control("structure.initial_displacement", "free decay: release displacement", "mm", 1e-3,
            -200.0, -1.0, 0.5),
)
CONTROL = {c.key: c for c in CONTROLS}
#: Controls whose slider spans a decade either side of the scenario's value (a structure's
#: stiffness or damping has no span common to all users).
RELATIVE = ("structure.stiffness", "structure.damping")
#: Controls that only the time view uses (the free decay's release): a change of them leaves
#: the forced response and the map as they were (cached, not solved again).
TIME_ONLY = ("structure.initial_displacement",)
#: Controls shown for a structure from a modes file too (the release point of its decay).
WITH_MODES = ("structure.initial_displacement",)


def span(control: Control, value: float) -> tuple[float, float]:
    """The slider's (low, high) for a control whose scenario value is ``value``: the
    control's span, a decade either side for :data:`RELATIVE` ones, and always wide
    enough to hold ``value``."""
    low, high = control.low, control.high
    if control.key in RELATIVE and value > 0:
        low, high = value / 10.0, value * 10.0
    return min(low, value), max(high, value)

#: Loads the page offers: kind -> (unit shown, SI per unit, slider span). Each is the
#: command line's option of that name (``pdamper frf --force 2N``, ``--base 1mm``,
#: ``--unbalance 1.76kg*mm``).
LOADS: dict[str, tuple[str, float, float, float]] = {
    "force": ("N", 1.0, 0.1, 50.0),
    "base": ("mm", 1e-3, 0.1, 20.0),
    "unbalance": ("kg*mm", 1e-3, 0.1, 20.0),
}


@dataclass(frozen=True)
class Inputs:
    """What the page holds: the base scenario (a file or the paper's), the values the user
    set (scenario key -> value in the control's unit; ``None`` keeps the scenario's), the
    load and the frequency grid of the forced response."""

    scenario: Path | None = None
    values: tuple[tuple[str, Any], ...] = ()
    load_kind: str = "force"
    load_amplitude: float = 2.0          # in LOADS[load_kind]'s unit
    frequency: str = ""                  # 'start:stop:count'; "" = the command's default
                                         # (the scenario's [frf], else every mode resolved)
    sweep: str = "both"
    model: str | None = None             # fidelity; None = the scenario's [simulation] model
    fields: Path | None = None
    bed_mass: float | None = None        # [g]; set: the count is derived from it (below)

    def with_value(self, key: str, value: Any) -> Inputs:
        rest = tuple((k, v) for k, v in self.values if k != key)
        return dataclasses.replace(self, values=rest + ((key, value),))

    def overrides(self) -> dict[str, Any]:
        """Scenario overrides (dotted key -> the scenario's text) of the values set."""
        out: dict[str, Any] = {}
        for key, value in self.values:
            if value is None:
                continue
            c = CONTROL.get(key)
            out[key] = c.text(value) if c is not None else value
        if self.model is not None:
            out["simulation.model"] = self.model
        if self.fields is not None:
            out["fields.file"] = str(self.fields)
        return out

    def load_text(self) -> str:
        unit = LOADS[self.load_kind][0]
        return f"{self.load_amplitude:g}{unit}"

    def command(self, saved: Path) -> str:
        """The ``pdamper frf`` command line that answers this view from the saved scenario."""
        grid = f"--frequency {self.frequency} " if self.frequency else ""
        return (f"pdamper frf --scenario {saved} --{self.load_kind} {self.load_text()} "
                f"{grid}--sweep {self.sweep}")


def scenario_load(inputs: Inputs) -> Inputs:
    """``inputs`` with the load of the scenario's ``[frf]`` where it gives one the page
    offers (a force, an unbalance, a base displacement); else unchanged (2 N)."""
    frf = scenario_of(inputs).frf
    for kind, key in (("force", "force"), ("unbalance", "unbalance"),
                      ("base", "base_displacement")):
        value = getattr(frf, key, None)
        if value is not None:
            return dataclasses.replace(inputs, load_kind=kind,
                                       load_amplitude=float(value) / LOADS[kind][1])
    return inputs


def scenario_of(inputs: Inputs) -> Scenario:
    """The scenario the page shows: the base scenario with the page's values on top (judged
    as the command line judges them: an :class:`~pdamper.errors.InputError` naming the key);
    with a bed mass the count derived from it (:func:`with_derived_count`)."""
    from pdamper.io.scenario import load_scenario

    return load_scenario(inputs.scenario, with_derived_count(inputs).overrides())


def with_derived_count(inputs: Inputs) -> Inputs:
    """``inputs`` with the particle count of its bed mass, where one is set: the nearest
    whole number of spheres of the radius and material set, as ``pdamper optimize``'s
    ``bed-mass`` variable derives it (:func:`pdamper.design.study.apply_design`); a bed
    mass that needs more spheres than fit is refused naming ``bed_mass``."""
    if inputs.bed_mass is None:
        return inputs
    from pdamper.design.study import apply_design
    from pdamper.errors import InputError
    from pdamper.io.scenario import load_scenario

    if not (math.isfinite(inputs.bed_mass) and inputs.bed_mass >= 0):
        raise InputError("bed_mass", f"must be >= 0 g, got {inputs.bed_mass:g} g")
    rest = dataclasses.replace(inputs, bed_mass=None)
    damper = load_scenario(rest.scenario, rest.overrides()).damper()
    try:
        count = apply_design(damper.with_count(0), {"bed_mass": inputs.bed_mass * 1e-3}).count
    except InputError as exc:  # more spheres than fit: said of the bed mass
        most = damper.max_count * damper.particle_mass * 1e3
        raise InputError("bed_mass", f"must be at most {most:.0f} g "
                         f"({damper.max_count} spheres of this radius and material fit), "
                         f"got {inputs.bed_mass:g} g ({exc.message})") from None
    return rest.with_value("particles.count", count)


def scenario_toml(inputs: Inputs) -> str:
    """TOML text of a scenario file that reproduces the page: the base file's tables with the
    page's values written in, units included (``radius = "4 mm"``), and a ``[frf]`` comment
    with the command that reproduces the forced response.

    The result is read back and judged before it is returned, so a file that would not load
    is never written.
    """
    import tomli_w

    inputs = with_derived_count(inputs)
    base: dict[str, Any] = {}
    if inputs.scenario is not None:
        base = tomllib.loads(Path(inputs.scenario).read_text(encoding="utf-8"))
        base = _relative_paths(base, Path(inputs.scenario).parent)
    for key, value in inputs.overrides().items():
        *tables, name = key.split(".")
        node = base
        for t in tables:
            sub = node.get(t)
            if not isinstance(sub, dict):  # a table given by name ("PVC") becomes its name
                sub = {}
                node[t] = sub
            node = sub
        node[name] = value
    text = tomli_w.dumps(base)
    header = ("# written by `pdamper explore`; the forced response of the page:\n"
              f"#   {inputs.command(Path('<this file>'))}\n")
    return header + text


def _relative_paths(table: dict[str, Any], root: Path) -> dict[str, Any]:
    """The base scenario's file keys (a modes file, a load record, a fields map: any text
    that names a file beside the scenario) made absolute, so that the saved copy, elsewhere,
    still finds them."""
    out: dict[str, Any] = {}
    for key, value in table.items():
        if isinstance(value, dict):
            out[key] = _relative_paths(value, root)
        elif isinstance(value, str) and not Path(value).is_absolute() \
                and (root / value).is_file():
            out[key] = str((root / value).resolve())
        else:
            out[key] = value
    return out


def save_scenario(inputs: Inputs, path: Path) -> Path:
    """Write :func:`scenario_toml` to ``path`` atomically after judging it (the scenario it
    describes must load); returns ``path``."""
    from pdamper.files import atomic_write_text
    from pdamper.io.scenario import load_scenario

    text = scenario_toml(inputs)
    probe = path.with_name(path.name + ".check.toml")
    try:  # judged as the command line will read it, before the file exists
        probe.write_text(text, encoding="utf-8")
        load_scenario(probe)
    finally:
        probe.unlink(missing_ok=True)
    atomic_write_text(path, text)
    return path


@dataclass
class Quick:
    """What the page redraws at once for a design (all SI; the page converts): the bare
    structure's FRF, the damper's Level II map, its mass."""

    frequency: np.ndarray                 # [Hz]
    bare: np.ndarray                      # |x| of the structure without the damper [m]
    map_frequency: np.ndarray             # [Hz]
    map_stroke: np.ndarray                # container stroke amplitude [m]
    map_loss_factor: np.ndarray           # (stroke, frequency) [1]
    map_mode: np.ndarray                  # MotionMode code (stroke, frequency), -1 none
    bed_mass: float                       # [kg]
    container_mass: float                 # [kg]
    unused: dict[str, str] = field(default_factory=dict)
    seconds: float = 0.0
    #: whether the fidelity's assumptions hold at each map cell, and why not ("" where
    #: they do; the analytical model's ``assumptions`` diagnostics; all True for a
    #: fidelity without such checks)
    map_holds: np.ndarray | None = None
    map_reasons: np.ndarray | None = None


@dataclass
class Response:
    """The forced response of a design, as ``pdamper frf`` computes and prints it."""

    frf: FRFResult
    peak_lines: list[str]                 # `pdamper frf`'s peak lines, verbatim
    seconds: float = 0.0
    #: per frequency, whether the fidelity's assumptions hold where the upward sweep
    #: (else the one run) drives the damper, and why not ("" where they do)
    holds: np.ndarray | None = None
    reasons: np.ndarray | None = None
    #: a preview (:func:`preview`): the size of the full grid it samples; None: the answer
    of: int | None = None
    #: a preview's ``--frequency`` where it is ``pdamper frf``'s for a coarser grid
    grid: str | None = None


def _resolved(inputs: Inputs, sc: Scenario) -> tuple[Any, np.ndarray]:
    """The load and the frequencies [Hz] as ``pdamper frf`` resolves them for these
    options and this scenario (the same function)."""
    from pdamper.cli.frf import _frequencies, _resolved, parse_load

    text = inputs.load_text()
    given = parse_load(**{k: text if k == inputs.load_kind else None
                          for k in ("force", "base", "unbalance")}, default=None)
    freqs = _frequencies(inputs.frequency) if inputs.frequency else None
    load, grid, _, _ = _resolved(sc, given, freqs, inputs.sweep)
    return load, np.unique(np.asarray(grid, dtype=float))


def forced_inputs(inputs: Inputs) -> Inputs:
    """``inputs`` without the values only the time view uses (:data:`TIME_ONLY`): what the
    quick views and the forced response depend on, their cache key."""
    if not any(k in TIME_ONLY for k, _ in inputs.values):
        return inputs
    return dataclasses.replace(inputs, values=tuple((k, v) for k, v in inputs.values
                                                    if k not in TIME_ONLY))


@functools.lru_cache(maxsize=64)
def quick(inputs: Inputs) -> Quick:
    """The views that redraw at once (cached per design; a value only the time view uses
    is judged but reuses the design's views). Raises :class:`~pdamper.errors.InputError`
    for a value the scenario refuses."""
    from pdamper.cli.frf import _acting
    from pdamper.coupling.frf import _modal, linear_frf

    base = forced_inputs(inputs)
    if base != inputs:
        scenario_of(inputs)  # judged whole: a refused release is said as the CLI says it
        return quick(base)
    t0 = time.perf_counter()
    sc = scenario_of(inputs)
    load, freqs = _resolved(inputs, sc)
    damper = sc.damper()
    bare = np.abs(linear_frf(_modal(_acting(sc)), load, freqs))
    mf, ms, eta, mode, holds, why = _level2(sc, damper, inputs.model, freqs)
    return Quick(freqs, bare, mf, ms, eta, mode, float(damper.bed_mass),
                 float(sc.container.mass), unused_inputs(sc, inputs.model),
                 time.perf_counter() - t0, holds, why)


@functools.lru_cache(maxsize=64)
def response(inputs: Inputs) -> Response:
    """The forced response of the design: ``pdamper frf`` with the page's scenario, load,
    frequencies and sweep (its cost judged first, as the command judges it). Cached per
    design; a value only the time view uses reuses the design's response."""
    base = forced_inputs(inputs)
    if base != inputs:
        scenario_of(inputs)
        return response(base)
    return _forced(inputs)


#: Frequencies of the page's first answer to a new design, at most (:func:`preview`).
PREVIEW_POINTS = 21


def preview_grid(count: int, points: int = PREVIEW_POINTS) -> np.ndarray | None:
    """Every k-th of ``count`` frequencies with the last, at most ``points`` (k the
    smallest step that gives no more): the indices of a coarser grid; ``None`` for a grid
    of fewer than twice ``points`` (its own answer comes about as soon: no preview)."""
    if count < 2 * points:
        return None
    step = math.ceil((count - 1) / max(points - 1, 1))
    idx = np.arange(0, count, step)
    return idx if idx[-1] == count - 1 else np.append(idx, count - 1)


def preview_inputs(inputs: Inputs, freqs: np.ndarray | None = None,
                   points: int = PREVIEW_POINTS) -> Inputs | None:
    """The design on a coarser grid of the same band, for a grid of at least twice
    ``points`` frequencies (else ``None``): where the page's grid is ``start:stop:count``,
    every k-th of its frequencies where a step k (the smallest of :func:`preview_grid`'s
    up to twice it) divides it (``start:stop:1 + (count - 1) / k``), else
    ``start:stop:points``; the command's default grid (``freqs``, resolved around the
    modes and dense at them) by ``points`` evenly spaced over its band. The preview is
    then what ``pdamper frf --frequency`` prints for that grid."""
    parts = inputs.frequency.split(":")
    if len(parts) == 3 and parts[2].strip().isdigit():
        count = int(parts[2])
        if preview_grid(count, points) is None:
            return None
        start, stop = parts[0].strip(), parts[1].strip()
        low = math.ceil((count - 1) / max(points - 1, 1))
        for step in range(low, 2 * low + 1):
            if (count - 1) % step == 0:
                return dataclasses.replace(
                    inputs, frequency=f"{start}:{stop}:{(count - 1) // step + 1}")
        return dataclasses.replace(inputs, frequency=f"{start}:{stop}:{points}")
    if inputs.frequency or freqs is None or preview_grid(freqs.size, points) is None:
        return None
    return dataclasses.replace(
        inputs, frequency=f"{float(freqs[0]):.6g}Hz:{float(freqs[-1]):.6g}Hz:{points}")


@functools.lru_cache(maxsize=64)
def preview(inputs: Inputs) -> Response | None:
    """A first answer to the design at the resolution a curve needs, in a fraction of the
    full grid's time: :func:`response` on a coarser grid of the same band
    (:func:`preview_inputs`; its ``grid`` the ``--frequency`` of ``pdamper frf`` that
    prints the same); ``None`` where the grid is that small already. Its ``of`` is the
    full grid's size: the page shows it as a preview until :func:`response` arrives."""
    base = forced_inputs(inputs)
    if base != inputs:
        scenario_of(inputs)
        return preview(base)
    _, freqs = _resolved(inputs, scenario_of(inputs))
    coarse = preview_inputs(inputs, freqs)
    if coarse is None:
        return None
    return dataclasses.replace(response(coarse), of=freqs.size, grid=coarse.frequency)


def _forced(inputs: Inputs) -> Response:
    """:func:`response`, computed."""
    from pdamper.cli.frf import _acting, _table
    from pdamper.coupling.frf import frequency_response
    from pdamper.runs.resources import check_frf

    t0 = time.perf_counter()
    sc = scenario_of(inputs)
    load, freqs = _resolved(inputs, sc)
    check_frf(sc, inputs.model, freqs, load, max_cycles=None, sweep=inputs.sweep, force=False)
    damper = sc.damper()
    res = frequency_response(sc.model(None, damper), _acting(sc), load, freqs,
                             sweep=inputs.sweep)
    peaks = [line for line in _table(res)
             if any(line.startswith(f"{s}: peak") for s in res.sweeps)]
    path = res.sweeps.get("up") or next(iter(res.sweeps.values()), None)
    holds = why = None
    if path is not None:
        holds, why = assumptions(sc, damper, inputs.model, res.frequency, path.stroke)
    return Response(res, peaks, time.perf_counter() - t0, holds, why)


def assumptions(sc: Scenario, damper: Any, name: str | None, frequency: np.ndarray,
                stroke: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Whether the fidelity's assumptions hold at the points (f [Hz], X [m]) and why not:
    the model's ``assumptions_hold`` and ``assumptions`` diagnostics (the analytical
    model's, :func:`~pdamper.analysis.analytical.assumption_checks`); all hold for a
    fidelity without them, an empty bed, or a point the fidelity refuses (that point is
    not drawn)."""
    f = np.asarray(frequency, float)
    x = np.asarray(stroke, float)
    holds = np.ones(np.broadcast(f, x).shape, bool)
    why = np.full(holds.shape, "", dtype=object)
    ok = np.isfinite(f) & np.isfinite(x) & (x > 0)
    if damper.count == 0 or not np.any(ok):
        return holds, why
    try:
        r = sc.model(name, damper).response(np.broadcast_to(f, holds.shape)[ok],
                                            np.broadcast_to(x, holds.shape)[ok])
    except Exception:  # noqa: BLE001 - a refused point has no assumptions to judge
        return holds, why
    d = r.diagnostics or {}
    if "assumptions_hold" in d:
        holds[ok] = np.ravel(d["assumptions_hold"])
        why[ok] = np.ravel(d["assumptions"])
    return holds, why


def design_wide(*reasons: np.ndarray | None) -> list[str]:
    """The reasons shared by every point of the arrays of :func:`assumptions`' reasons (a
    bed of fewer spheres than a layer, a clearance the lattice does not give): they fail
    the whole design, not a point; [] where any point holds."""
    common: set[str] | None = None
    for arr in reasons:
        if arr is None:
            continue
        for r in np.ravel(arr):
            parts = set(_split(str(r)))
            common = parts if common is None else common & parts
            if not common:
                return []
    return sorted(common or ())


def _split(reason: str) -> list[str]:
    """The single reasons of a ``"; "``-joined reason text (each ends with the fidelity to
    use there, ``...; use dem``)."""
    out: list[str] = []
    parts = reason.split("; ")
    for p in parts:
        if p.startswith("use ") and out:
            out[-1] += "; " + p
        elif p:
            out.append(p)
    return out


def marked(reasons: np.ndarray | None, common: list[str]) -> np.ndarray:
    """Points whose assumptions fail for a reason of their own (beyond the design-wide
    ones): the points the page marks."""
    if reasons is None:
        return np.zeros(0, bool)
    flat = [set(_split(str(r))) - set(common) for r in np.ravel(reasons)]
    return np.array([bool(r) for r in flat], bool).reshape(np.shape(reasons))


def fields_offer(views: Quick, res: Response | None, fidelity: str) -> str:
    """The line the page shows where the fidelity's assumptions fail: those that fail the
    whole design, how many map cells and forced-response points fail on their own (the
    marked ones) and why, and the fidelity to use there (a fields map from the DEM,
    ``--fields map.nc``); "" where they hold everywhere."""
    path = None if res is None else res.reasons
    common = design_wide(views.map_reasons, path)
    cells = int(np.count_nonzero(marked(views.map_reasons, common)))
    points = int(np.count_nonzero(marked(path, common)))
    if not common and not cells and not points:
        return ""
    said = []
    if common:
        said.append(f"the {fidelity} fidelity's assumptions fail for this design everywhere: "
                    + "; ".join(r.split("; use")[0] for r in common))
    if cells or points:
        own = [r for arr in (path, views.map_reasons) if arr is not None
               for p in np.ravel(arr) for r in _split(str(p)) if r not in common]
        who = "also" if common else f"the {fidelity} fidelity's assumptions"
        first = own[0].split("; use")[0] if own else ""
        said.append(f"{who} fail at {cells} map cell(s) and {points} forced-response "
                    f"point(s) (marked x): {first}")
    return ("; ".join(said) + ". There a DEM map answers: `pdamper map --scenario "
            "<saved>.toml --model dem --out map.nc`, then `pdamper explore --scenario "
            "<saved>.toml --fields map.nc` (fidelity: fields)")


@dataclass
class TimeResponse:
    """The design in time, as ``pdamper simulate`` runs it for the scenario: the release
    from the structure's initial displacement (its free decay) or, where the scenario
    has a ``[load]``, the response to that history."""

    kind: str                             # "release" or "load"
    time: np.ndarray                      # [s]
    displacement: np.ndarray              # output point [m]
    lines: list[str]                      # `pdamper simulate`'s lines for the run
    run: Any                              # FreeVibrationResult or LoadResponse
    seconds: float = 0.0


@functools.lru_cache(maxsize=32)
def time_response(inputs: Inputs) -> TimeResponse:
    """What ``pdamper simulate --scenario <saved>`` computes for the page's design, by the
    same calls (the model of the page's fidelity): the release
    (:class:`~pdamper.coupling.Simulation` from ``structure.initial_displacement`` over
    ``simulation.duration``) or, with a ``[load]``, the load history
    (:func:`~pdamper.coupling.loads.run_load` with the ``[load]`` tail), its cost judged
    first as the command judges it; the lines are the command's (its decay table, or its
    peak and RMS line) without the wall time."""
    t0 = time.perf_counter()
    sc = scenario_of(inputs)
    damper = sc.damper()
    model = sc.model(inputs.model, damper)
    if sc.load.given:
        from pdamper.coupling.loads import acting_at, check_cost, check_model, run_load

        history = sc.load.history()
        assert history is not None  # a given [load] has its history
        structure = acting_at(sc.structure_model(), sc.load.at)
        check_model(model, structure)
        check_cost(model, structure, history, sc.simulation.sample_rate, sc.load.tail, False)
        lr = run_load(model, structure, history, sc.simulation.sample_rate, sc.load.tail)
        rel = " (relative to the base)" if history.kind != "force" else ""
        lines = [f"peak {lr.peak * 1e3:.3f} mm, RMS {lr.rms * 1e3:.3f} mm{rel}; acceleration "
                 f"peak {lr.peak_acceleration:.4g} m/s^2, RMS {lr.rms_acceleration:.4g} "
                 f"m/s^2; damper dissipated {lr.dissipated_energy:.4g} J"]
        return TimeResponse("load", np.asarray(lr.time), np.asarray(lr.displacement), lines,
                            lr, time.perf_counter() - t0)
    from pdamper.cli.simulate import _table
    from pdamper.coupling import Simulation
    from pdamper.runs.resources import check_resources

    structure = sc.structure_model()
    check_resources(sc, "simulation", inputs.model, force=False)
    r = Simulation(structure, model, sc.structure.initial_displacement).run(
        sc.simulation.duration, sc.simulation.sample_rate)
    return TimeResponse("release", np.asarray(r.time), np.asarray(r.displacement),
                        _table("", r)[1:], r, time.perf_counter() - t0)


#: Points of the Level II map: strokes from a twentieth of to this many times the damper's
#: optimal stroke (Eq. (5): where the loss factor peaks), log-spaced; frequencies over the
#: forced response's band.
MAP_STROKES = 20
MAP_FREQUENCIES = 30
MAP_TOP = 4.0


def level2_map(sc: Scenario, damper: Any, name: str | None, freqs: np.ndarray
               ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Loss factor and motion mode of the damper over (frequency x stroke): the Level II
    field the structure's operating path runs through. Cells outside the fidelity's range
    (a fields map's grid) stay blank (NaN, mode -1)."""
    mf, ms, eta, mode, _, _ = _level2(sc, damper, name, freqs)
    return mf, ms, eta, mode


def _level2(sc: Scenario, damper: Any, name: str | None, freqs: np.ndarray
            ) -> tuple[np.ndarray, ...]:
    """:func:`level2_map` and the :func:`assumptions` of its cells (from the same call of
    the model where it answers the whole map at once)."""
    top = max(float(damper.optimal_stroke), 1e-4) * MAP_TOP
    mf = np.linspace(float(freqs[0]), float(freqs[-1]), MAP_FREQUENCIES)
    ms = np.geomspace(top / 80.0, top, MAP_STROKES)
    model = sc.model(name, damper)
    F, X = np.meshgrid(mf, ms)
    eta = np.full(F.shape, np.nan)
    mode = np.full(F.shape, -1, dtype=int)
    holds = np.ones(F.shape, bool)
    why = np.full(F.shape, "", dtype=object)
    if damper.count == 0:
        return mf, ms, np.zeros(F.shape), mode, holds, why
    try:
        r = model.response(F.ravel(), X.ravel())
    except Exception:  # noqa: BLE001 - the map point by point: a refused cell stays blank
        pass
    else:
        d = r.diagnostics or {}
        if "assumptions_hold" in d:
            holds = np.asarray(d["assumptions_hold"], bool).reshape(F.shape)
            why = np.asarray(d["assumptions"], dtype=object).reshape(F.shape)
        return (mf, ms, np.asarray(r.loss_factor, dtype=float).reshape(F.shape),
                np.asarray(r.mode, dtype=int).reshape(F.shape), holds, why)
    for i, j in np.ndindex(F.shape):
        try:
            r = model.response(F[i, j], X[i, j])
        except Exception:  # noqa: BLE001
            continue
        eta[i, j] = float(np.ravel(r.loss_factor)[0])
        mode[i, j] = int(np.ravel(r.mode)[0])
    holds, why = assumptions(sc, damper, name, F, X)
    return mf, ms, eta, mode, holds, why


def unused_inputs(sc: Scenario, name: str | None) -> dict[str, str]:
    """Inputs the page shows that the design's fidelity does not use: key -> the reason and
    the fidelities that do (the models' declarations, :func:`pdamper.models.registry.not_used`)."""
    from pdamper.models.registry import not_used

    shown = [c.key for c in CONTROLS] + ["restitution.particle_particle",
                                         "restitution.particle_wall"]
    out = not_used(type(sc.model(name, sc.damper())), shown)
    return {k: f"{v['reason']}; used by: {', '.join(v['used_by']) or 'none'}"
            for k, v in out.items()}


def mass_text(views: Quick, limit: float | None) -> str:
    """The design's mass in grams, against ``limit`` [kg] where one is set."""
    total = views.bed_mass + views.container_mass
    text = (f"bed {views.bed_mass * 1e3:.1f} g + container {views.container_mass * 1e3:.1f} g "
            f"= {total * 1e3:.1f} g")
    if limit is not None and math.isfinite(limit):
        margin = limit - total
        text += (f"; limit {limit * 1e3:.0f} g: " +
                 (f"met by {margin * 1e3:.1f} g" if margin >= 0
                  else f"exceeded by {-margin * 1e3:.1f} g"))
    return text


def values_of(sc: Scenario) -> dict[str, float]:
    """The scenario's value of every control, in the control's unit (the widgets' start)."""
    out: dict[str, float] = {}
    for c in CONTROLS:
        section, _, name = c.key.partition(".")
        value = getattr(getattr(sc, section), name, None)
        if isinstance(value, (int, float)) and value is not None:
            out[c.key] = float(value) / c.scale
    return out


def materials() -> list[str]:
    """Material names the page offers (the library's)."""
    from pdamper.materials.library import known_names

    return list(known_names())
