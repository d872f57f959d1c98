"""The reference paper's case study, end to end, with each reported number next to ours.

:func:`run_case_study` computes (Level I) the Fig. 2 material table and COR curves with
single DEM impacts, (Level II) the Fig. 4 trajectories and the Fig. 5a/5c maps with the
analytical model, the Fig. 5b/5d map with the DEM (on the scenario's ``[map]
dem_frequency x dem_amplitude`` grid, on dask.distributed, cached under the output
directory) with its agreement with the analytical map and Fig. 3 snapshots, and (Level III)
the Fig. 7/8 free vibration and the Sect. 4.2.2 / Fig. 9 optimisation, all from one
:class:`~pdamper.io.scenario.Scenario` (the paper's case by default);
:func:`pdamper.reports.paper_case_study.write_case_study` writes it out (figures, maps,
the comparison table and ``report.html``). The paper's numbers and the tolerance of each comparison come
from :mod:`pdamper.parameters.vertical_dampers_paper`.

Figs. 7 and 8 show the three damper models of Sect. 4.1: the analytical formulas (model
3), the effective fields (model 2) and the DEM (model 1). Model 2 reads, in this order of
preference, the scenario's ``[fields] file``, the case study's DEM map (``CaseStudy.dem_map``,
when the study has one), or the analytical Fig. 5 map; the figure and the models table say
which. A map of the case study's own is used with ``extrapolation = "clamp"`` and that is
recorded with it.
"""

from __future__ import annotations

import logging
import math
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any, TypeVar, cast

import numpy as np

from pdamper.analysis.analytical import BedTrajectory, bed_response, bed_trajectory
from pdamper.analysis.fields import effective_field, field_agreement
from pdamper.analysis.modes import PAPER_MODES, MotionMode
from pdamper.contact.restitution import ConstantRestitution, RestitutionCurve
from pdamper.coupling import FreeVibrationResult, Simulation
from pdamper.design.optimize import OptimizationResult, optimize_particle_count
from pdamper.design.study import lightest_within
from pdamper.errors import InputError, SimulationError
from pdamper.models import AnalyticalDamper, EffectiveFieldDamper
from pdamper.parameters import vertical_dampers_paper as paper

if TYPE_CHECKING:
    from xarray import Dataset

    from pdamper.damper import ParticleDamper
    from pdamper.dem.impacts import ImpactCheck
    from pdamper.dem.result import DEMResult
    from pdamper.io.scenario import Scenario
    from pdamper.models.base import DamperModel
    from pdamper.models.dem import DEMDamper
    from pdamper.runs.maps import MapRun
    from pdamper.runs.realisations import Level3Band
    from pdamper.structure import SingleDOFStructure
    from pdamper.structure.modal import ModalStructure

_T = TypeVar("_T")

logger = logging.getLogger(__name__)

#: Frequency at which "A >> g" is evaluated for Eq. (21) [Hz].
_HIGH_FREQUENCY = 200.0
#: The DEM map's file in the output directory (also its cache).
DEM_MAP_FILE = "fig5_dem_map.nc"
#: Random packings of DEM model 1's band in Figs. 7/8 (``pdamper paper --realisations``).
PAPER_REALISATIONS = 5
#: Fig. 3: the modes it shows, at Fig. 4 points (label, f [Hz], X [m]); the double CaC
#: at the benchmark point X_opt (10 Hz, 32 mm).
FIG3_POINTS = (("a) solid-like", 4.0, 0.015), ("b) single CaC", 6.0, 0.015),
               ("c) double CaC", 10.0, 0.032))
#: Lowest frequency of the paper's "DEM maximum 1.25 near X_opt" (f < 5 Hz falls off) [Hz].
_XOPT_MIN_FREQUENCY = 8.0


@dataclass
class Row:
    """One reported number: the paper's, ours, and where it comes from."""

    quantity: str
    paper: str
    ours: str
    source: str
    agrees: bool | None = None
    note: str = ""

    def __post_init__(self) -> None:
        if self.agrees is not None:
            self.agrees = bool(self.agrees)


def _row(key: str, ours: str, value: Any, **fmt: Any) -> Row:
    """The table row of the paper's number ``key`` with our ``value`` (shown as ``ours``);
    ``value`` None: not computable here (no verdict)."""
    r = paper.REPORTED[key]
    agrees = None if value is None else r.agrees(value)
    return Row(r.quantity.format(**fmt), r.paper, ours, r.source, agrees, r.note)


@dataclass
class CaseStudy:
    """Everything the case study computed."""

    rows: list[Row] = field(default_factory=list)
    field_map: Dataset | None = None
    trajectories: list[tuple[str, BedTrajectory]] = field(default_factory=list)
    run_32: FreeVibrationResult | None = None
    run_empty: FreeVibrationResult | None = None
    run_best: FreeVibrationResult | None = None
    run_dem: FreeVibrationResult | None = None
    dem_map: Dataset | None = None  # the DEM on its grid
    analytic_on_dem_grid: Dataset | None = None
    dem_map_run: MapRun | None = None
    agreement: dict = field(default_factory=dict)
    snapshots: list[tuple[str, DEMResult]] = field(default_factory=list)
    run_dem_curves: FreeVibrationResult | None = None
    cor_checks: list[ImpactCheck] = field(default_factory=list)
    damper: ParticleDamper | None = None
    run_fields: FreeVibrationResult | None = None
    fields_source: str = ""
    #: why model 2 fell back to the analytical map (the DEM map's error), or ""
    fields_failure: str = ""
    optimization: OptimizationResult | None = None
    best_count: int = 0
    inputs: dict = field(default_factory=dict)
    #: Wall time of each step and of each Level III model's run [s].
    timings: dict = field(default_factory=dict)
    #: DEM model 1 from random packings (:class:`pdamper.runs.realisations.Level3Band`)
    dem_band: Level3Band | None = None

    def models(self) -> list[dict]:
        """The Level III runs of Figs. 7/8 (and the no-particle envelope) for the tables."""
        t_cmp = paper.PAPER_COMPARISON_TIME
        out = []
        for label, run, source, key in (
                ("analytical formulas (model 3)", self.run_32, "Eqs. 5-22", "model 3"),
                ("effective fields (model 2)", self.run_fields,
                 self.fields_source + (f": {self.fields_failure}" if self.fields_failure
                                       else ""), "model 2"),
                ("DEM (model 1)", self.run_dem, "DEM co-simulation", "model 1"),
                ("DEM (model 1), paper's COR curves",
                 None if self.run_dem_curves is self.run_dem else self.run_dem_curves,
                 "DEM co-simulation, Fig. 2 curves", "model 1, paper's COR curves"),
                ("no particles", self.run_empty, "structure only", "no particles")):
            if run is None:
                continue
            long_enough = run.time[-1] >= t_cmp * (1.0 - 1e-9)
            out.append({"label": label, "model": run.model, "source": source,
                        "amplitude_0p75": run.amplitude_at(t_cmp) if long_enough else None,
                        "final_amplitude": run.final_amplitude,
                        "seconds": self.timings.get(key)})
        b = self.dem_band
        if b is not None:  # the means, the band in the source column and its own keys
            a, fin = b.amplitude_at(), b.final_amplitude()
            at = b.at >= t_cmp * (1.0 - 1e-9)
            band = (f"; at 0.75 s std {a['std'] * 1e3:.2f} mm, min {a['min'] * 1e3:.2f}, "
                    f"max {a['max'] * 1e3:.2f} mm" if at else "")
            seeds = _need(b.seeds, "seeds of the random packings")
            out.append({"label": f"DEM (model 1), mean of {b.count} random packings",
                        "model": b.model,
                        "source": f"DEM co-simulation, seeds {seeds[0]}-{seeds[-1]}"
                                  + band,
                        "amplitude_0p75": a["mean"] if at else None,
                        "amplitude_0p75_band": {k: a[k] for k in ("std", "min", "max")}
                        if at else None,
                        "final_amplitude": fin["mean"],
                        "seconds": self.timings.get(f"model 1, {b.count} random packings")})
        return out


def _need(value: _T | None, what: str) -> _T:
    """``value``, which :func:`run_case_study` always sets (a CaseStudy made otherwise may
    lack it)."""
    if value is None:
        raise ValueError(f"the case study has no {what}; make it with run_case_study")
    return value


def _fields_model(sc: Scenario, cs: CaseStudy,
                  damper: ParticleDamper) -> tuple[DamperModel, str]:
    """Model 2 for Figs. 7/8 and a description of its map (module docstring)."""
    if sc.fields.file is not None:
        return sc.model("fields", damper), f"map {sc.fields.file}"
    dem_map = getattr(cs, "dem_map", None)
    opts = {**sc.fields.options(), "file": None, "extrapolation": "clamp"}
    what = "analytical Fig. 5 map"
    if dem_map is not None:
        try:
            return (EffectiveFieldDamper(damper, field=dem_map, **opts),
                    "DEM map, clamped at its edges")
        except InputError as exc:  # e.g. a DEM grid too small to interpolate
            logger.warning("model 2 cannot use the DEM map (%s); using the analytical map",
                           exc.message)
            what = "analytical Fig. 5 map (the DEM map cannot serve it)"
    return EffectiveFieldDamper(damper, field=cs.field_map, **opts), \
        f"{what}, clamped at its edges"


def _timed(cs: CaseStudy, key: str, fn: Callable[[], _T]) -> _T:
    """``fn()``, its wall time [s] recorded in ``cs.timings[key]``."""
    t0 = time.perf_counter()
    out = fn()
    cs.timings[key] = time.perf_counter() - t0
    return out


def _zeta_at(res: FreeVibrationResult, amplitude: float) -> tuple[float, float]:
    """(zeta, mean amplitude) of the cycle whose mean amplitude is nearest ``amplitude``."""
    amp, zeta = res.damping_ratio
    i = int(np.argmin(np.abs(amp - amplitude)))
    return float(zeta[i]), float(amp[i])


def _amplitude_row(key: str, res: FreeVibrationResult, t: float, extra: str = "",
                   **fmt: Any) -> Row:
    """Amplitude envelope at ``t`` [s], or no verdict if the run ends before ``t``."""
    if res.time[-1] < t * (1.0 - 1e-9):
        return _row(key, f"n/a (the run ends at {res.time[-1]:g} s)", None, **fmt)
    a = res.amplitude_at(t)
    return _row(key, f"{a * 1e3:.1f} mm{extra}", a, **fmt)


def run_case_study(scenario: Scenario | None = None,
                   progress: Callable[[str], None] | None = None,
                   dem: bool = True, out: Path | None = None,
                   map_progress: Callable | None = None, realisations: int = 1,
                   **sweep_options: Any) -> CaseStudy:
    """Compute the paper's case study for ``scenario`` (default: the paper's case).

    The scenario sets the damper, the structure, the release, the duration of Figs. 7/8,
    the Fig. 5 grids, the optimisation (time, step) and the DEM options; every row compares
    with the paper's number. ``dem`` adds the DEM: the Fig. 5b/5d map (its points on the
    sweep engine, ``sweep_options`` such as ``workers``; cached as ``out/fig5_dem_map.nc``
    when ``out`` is given, so that a rerun does not recompute it; ``map_progress`` gets
    its points), the Fig. 3 snapshots, the Fig. 2 check (the paper's COR curves in single
    DEM impacts) and DEM model 1, run with the scenario's COR and with the paper's Fig. 2
    curves; ``realisations`` N > 1 adds DEM model 1 from N random packings (seeds
    ``dem.seed + k``, on the sweep engine: in this process unless ``sweep_options`` name
    ``workers`` or a ``scheduler``), drawn as a band in Figs. 7/8.
    """
    from pdamper.io.scenario import Scenario

    sc = Scenario() if scenario is None else scenario
    say: Callable[[str], None] = progress or (lambda _msg: None)
    damper, structure = sc.damper(), _single_dof(sc.structure_model())
    x0, duration = sc.structure.initial_displacement, sc.simulation.duration
    cs = CaseStudy(inputs=sc.model_dump(mode="json"), damper=damper)
    _level2_rows(cs, sc, damper, say)
    if dem:
        _dem_map(cs, sc, damper, say, out, map_progress, sweep_options)
    _level3_runs(cs, sc, damper, structure, x0, duration, say)
    _level3_rows(cs, damper, structure)
    if dem:
        _dem_rows(cs, sc, damper, structure, x0, duration, say)
        if realisations > 1:
            _dem_band(cs, sc, realisations, say, sweep_options)
    _optimisation_rows(cs, sc, damper, structure, x0, duration, say)
    return cs


def _single_dof(structure: SingleDOFStructure | ModalStructure) -> SingleDOFStructure:
    """The 1-DOF structure of Eq. (23) the case study is on; a ``[structure] modes`` or
    ``beam`` structure of one mode gives its equivalent, one of several is refused."""
    from pdamper.structure.modal import ModalStructure

    if not isinstance(structure, ModalStructure):
        return structure
    if structure.modes != 1 or not structure.coincident:
        raise InputError("structure", f"the paper's case study is on a 1-DOF structure "
                         f"(Eq. 23); this one has {structure.modes} mode(s) (use "
                         "`pdamper simulate` or `optimize` for N modes)")
    return structure.equivalent_single_dof()


def _level2_rows(cs: CaseStudy, sc: Scenario, damper: ParticleDamper,
                 say: Callable[[str], None]) -> None:
    """Fig. 4's bed trajectories and the analytical Fig. 5a/5c map with its rows."""
    rows = cs.rows
    h = damper.clearance
    say("Fig. 4: bed trajectories")
    for x_fig4, f_fig4, _mode, case in paper.FIG4_EXAMPLES:
        tr = bed_trajectory(f_fig4, x_fig4, h)
        cs.trajectories.append((case, tr))
        rows.append(_row(f"fig4_{case}", tr.mode.title, tr.mode))

    f, xs = sc.map_grid()
    grid = f"{len(f)} x {len(xs)}"
    say(f"Fig. 5a/5c: analytical map {grid}")
    ds = _timed(cs, "Fig. 5 analytical map", lambda: effective_field(AnalyticalDamper(damper), f,
                                                                    xs))
    cs.field_map = ds
    eta, modes = ds["loss_factor"].values, ds["motion_mode"].values
    x_opt = damper.optimal_stroke
    rows.append(_row("x_opt", f"{x_opt * 1e3:.1f} mm", x_opt))
    hi = bed_response(_HIGH_FREQUENCY, x_opt, h, damper.bed_mass)
    gam = x_opt * (2 * math.pi * _HIGH_FREQUENCY) ** 2 / hi.gravity
    rows.append(_row("eta_max", f"{float(hi.loss_factor):.3f} (f = {_HIGH_FREQUENCY:g} Hz, "
                     f"A = {gam:.0f} g)", float(hi.loss_factor)))
    for key, mode_set in (
        ("double_cac_harmonic_eta", (MotionMode.DOUBLE_CAC_HARMONIC,)),
        ("single_cac_harmonic_eta", (MotionMode.SINGLE_CAC_HARMONIC,)),
        ("subharmonic_eta", (MotionMode.SINGLE_CAC_SUBHARMONIC,
                             MotionMode.DOUBLE_CAC_SUBHARMONIC)),
    ):
        sel = np.isin(modes, [int(m) for m in mode_set])
        if not sel.any():
            rows.append(_row(key, "mode not on this grid", None))
            continue
        lo, hi_ = float(eta[sel].min()), float(eta[sel].max())
        rows.append(_row(key, f"{lo:.2f} - {hi_:.2f}", (lo, hi_)))
    i, j = np.unravel_index(np.argmax(eta), eta.shape)
    rows.append(_row("eta_max_grid", f"{eta[i, j]:.3f} at X = {xs[j] * 1e3:.1f} mm, "
                     f"f = {f[i]:.1f} Hz", float(eta[i, j]), grid=grid))


def _level3_runs(cs: CaseStudy, sc: Scenario, damper: ParticleDamper,
                 structure: SingleDOFStructure, x0: float, duration: float,
                 say: Callable[[str], None]) -> None:
    """Figs. 7/8: the free vibration with models 3 and 2, and without particles."""
    say("Fig. 7/8: free vibration, no particles and the scenario's damper")
    cs.run_32 = _timed(cs, "model 3", lambda: Simulation(structure, AnalyticalDamper(damper),
                                                          x0).run(duration))
    say("Fig. 7/8: effective fields (model 2)")
    m2, cs.fields_source = _fields_model(sc, cs, damper)
    try:
        cs.run_fields = _timed(cs, "model 2", lambda: Simulation(structure, m2, x0).run(
            duration))
    except InputError as exc:  # e.g. a DEM map with a hole on the trajectory: say so
        if sc.fields.file is not None or getattr(cs, "dem_map", None) is None:
            raise
        logger.warning("model 2 on the %s failed (%s); using the analytical map",
                       cs.fields_source, exc)
        # the reason goes to the table and the JSON, not into Fig. 7's legend (a legend
        # line of a whole error message collapses the axes)
        cs.fields_source = "analytical Fig. 5 map (the DEM map failed)"
        cs.fields_failure = exc.message
        m2 = EffectiveFieldDamper(damper, field=cs.field_map, extrapolation="clamp")
        cs.run_fields = _timed(cs, "model 2", lambda: Simulation(structure, m2, x0).run(
            duration))
    # the undamped envelope is cheap: always long enough for the paper's 2 s comparison
    cs.run_empty = _timed(cs, "no particles", lambda: Simulation(
        structure, AnalyticalDamper(damper.with_count(0)), x0).run(
        max(duration, paper.PAPER_DURATION)))


def _level3_rows(cs: CaseStudy, damper: ParticleDamper, structure: SingleDOFStructure) -> None:
    """The structure's rows (Eq. 23, the beam, no particles) and those of model 3."""
    from pdamper.structure.beam import modal_reduction

    rows = cs.rows
    run_32, run_empty = _need(cs.run_32, "model 3 run"), _need(cs.run_empty, "empty run")
    rows.append(_row("eigenfrequency", f"{structure.natural_frequency:.2f} Hz",
                     structure.natural_frequency))
    fe = modal_reduction(*paper.paper_beam())
    rows.append(_row("beam_eigenfrequency", f"{fe.natural_frequency:.2f} Hz (M = {fe.mass:.3f} "
                     f"kg, K = {fe.stiffness:.0f} N/m)", fe.natural_frequency))
    z0 = float(np.mean(run_empty.damping_ratio[1]))
    rows.append(_row("undamped_zeta", f"{z0:.4f}", z0))
    rows.append(_amplitude_row("undamped_amplitude_2s", run_empty, paper.PAPER_DURATION))
    x_min = structure.min_amplitude(damper.bed_mass)
    rows.append(_row("x_min", f"{x_min * 1e3:.2f} mm", x_min))
    for key, target in (("zeta_53mm", 0.053), ("zeta_41mm", 0.041)):
        z, a = _zeta_at(run_32, target)
        rows.append(_row(key, f"{z:.4f} at {a * 1e3:.1f} mm", z))
    first_single = next((c for c in run_32.cycles
                         if c.mode is not MotionMode.DOUBLE_CAC_HARMONIC), None)
    if first_single is not None:
        rows.append(_row("cac_switch", f"at {first_single.amplitude * 1e3:.1f} mm",
                         first_single.amplitude))
    rows.append(_amplitude_row("amplitude_32_0p75s", run_32, paper.PAPER_COMPARISON_TIME))


def _optimisation_rows(cs: CaseStudy, sc: Scenario, damper: ParticleDamper,
                       structure: SingleDOFStructure, x0: float, duration: float,
                       say: Callable[[str], None]) -> None:
    """Sect. 4.2.2 / Fig. 9: the particle count's optimisation and the paper's optimum."""
    at = sc.optimization.at
    rows = cs.rows
    say("Sect. 4.2.2: optimisation of the particle count")
    opt = _timed(cs, "optimisation", lambda: optimize_particle_count(
        structure, damper, x0, at, step=sc.optimization.step))
    cs.optimization = opt
    n_paper = paper.PAPER_OPTIMAL_COUNT
    ref = next((c for c in opt.candidates if c.particles == n_paper), None)
    if ref is None and n_paper <= damper.max_count:  # the paper's count is off this step
        ref = optimize_particle_count(structure, damper, x0, at, counts=[n_paper]).best
    within = ("" if ref is None else
              f"; {n_paper} within {(ref.objective / opt.best.objective - 1) * 100:.0f} %")
    tol = sc.optimization.tolerance  # the mass-aware rule of `pdamper optimize`
    light = _need(lightest_within(opt.candidates, opt.best, tol), "lightest design")
    within += f"; lightest within {tol * 100:g} %: {light.particles} ({light.mass * 1e3:.0f} g)"
    rows.append(_row("optimal_count", f"{opt.best.particles} ({opt.best.mass * 1e3:.0f} g)"
                     + within, opt.best.particles, at=f"{at:g}"))
    best = damper.with_count(min(n_paper, damper.max_count))
    cs.best_count = best.count
    cs.run_best = Simulation(structure, AnalyticalDamper(best), x0).run(duration)
    rows.append(_amplitude_row("amplitude_64_0p75s", cs.run_best, paper.PAPER_COMPARISON_TIME))
    rows.append(_row("bed_mass_64", f"{best.bed_mass * 1e3:.0f} g", best.bed_mass))


def _dem_map(cs: CaseStudy, sc: Scenario, damper: ParticleDamper,
             say: Callable[[str], None], out: Path | None, map_progress: Callable | None,
             sweep_options: dict[str, Any]) -> None:
    """Fig. 5b/5d from the DEM, its agreement rows, and the Fig. 3 snapshots."""
    from pdamper.dem import warmup
    from pdamper.runs.maps import run_map

    # the kernels once here, before the map's workers start: each worker then loads them
    # from numba's cache instead of compiling them again (a fresh installation: ~30 s of
    # CPU per process); Fig. 3 and model 1 below run them in this process anyway
    say(f"compiling the DEM kernels ({sc.dem.integrator}; first run only, then cached)")
    cs.timings["DEM kernels"] = warmup((sc.dem.integrator,))
    fd, xd = sc.dem_map_grid()
    grid = f"{len(fd)} x {len(xd)}"
    say(f"Fig. 5b/5d: DEM map {grid} (cached in the output directory)")
    cache = None if out is None else Path(out) / DEM_MAP_FILE
    run = run_map(sc, "dem", frequency=fd, amplitude=xd, out=cache, cache=True,
                  progress=map_progress, **sweep_options)
    cs.dem_map_run = run
    cs.dem_map = ds = cast("Dataset", run.dataset)  # a map run holds its field's Dataset
    cs.analytic_on_dem_grid = ana = effective_field(AnalyticalDamper(damper), fd, xd)
    cs.agreement = agr = field_agreement(ds, ana)
    rows = cs.rows
    rows.append(_row("dem_map_steady", f"{agr['steady']} of {agr['cells'] + agr['failed']} "
                     f"steady, {agr['failed']} failed", None, grid=grid))
    rows.append(_row("dem_mode_agreement", f"{100 * agr['mode_agreement']:.0f} % of "
                     f"{agr['cells']} cells", None))
    for mode in PAPER_MODES:
        by = agr["by_mode"].get(mode.label)
        key = f"dem_delta_eta_{mode.label}"
        if by is None:
            rows.append(_row(key, "mode not on this grid", None))
        else:
            rows.append(_row(key, f"{by['median_abs_delta_eta']:.3f} ({by['cells']} cells, "
                             f"{100 * by['mode_agreement']:.0f} % same mode)",
                             by["median_abs_delta_eta"]))
    j = int(np.argmin(np.abs(xd - damper.optimal_stroke)))
    hi = fd >= _XOPT_MIN_FREQUENCY
    ok = hi & (ds["status"].values[:, j] == 0)
    if ok.any():
        vals = ds["loss_factor"].values[ok, j]
        rows.append(_row("dem_eta_xopt", f"{vals.max():.3f} (X = {xd[j] * 1e3:.1f} mm; "
                         f"{vals.min():.2f}-{vals.max():.2f} over {ok.sum()} frequencies)",
                         float(vals.max())))
    else:
        rows.append(_row("dem_eta_xopt", "no DEM result at f >= 8 Hz near X_opt", None))
    say("Fig. 3: DEM snapshots over one cycle")
    # as the DEM map: a steady cycle, the map's packing (the "dem" fidelity's DEMDamper)
    model = cast("DEMDamper", sc.map_model("dem", damper))
    for label, f, x in FIG3_POINTS:
        snap = model.clone(snapshot_rate=24.0 * f)  # a copy, 24 snapshots per cycle
        try:
            cs.snapshots.append((label, snap.run(f, x)))
        except SimulationError as exc:
            logger.warning("Fig. 3 %s: %s", label, exc)


def _cor_curves(damper: ParticleDamper) -> tuple[RestitutionCurve, RestitutionCurve]:
    """The sphere-sphere and sphere-wall COR curves of the case study's damper (the
    scenario's damper has both)."""
    return (_need(damper.restitution_pp, "sphere-sphere COR"),
            _need(damper.restitution_pw, "sphere-wall COR"))


def _cor_text(damper: ParticleDamper) -> str:
    """The COR models of a damper, for row labels."""
    pp, pw = _cor_curves(damper)
    if (pp, pw) == (paper.PAPER_COR_PP, paper.PAPER_COR_PW):
        return "the paper's COR curves"
    if isinstance(pp, ConstantRestitution) and isinstance(pw, ConstantRestitution):
        return f"constant COR {pp.e:g} / {pw.e:g}"
    return f"COR {pp.describe()} / {pw.describe()}"


def _dem_rows(cs: CaseStudy, sc: Scenario, damper: ParticleDamper,
              structure: SingleDOFStructure, x0: float, duration: float,
              say: Callable[[str], None]) -> None:
    """Fig. 2 check and DEM model 1 with the scenario's COR and with the paper's curves."""
    from pdamper.dem.impacts import check_restitution
    from pdamper.materials import PVC, S235

    say("Fig. 2: the paper's COR curves in single DEM impacts")
    v = np.linspace(0.01, 2.0, 20)
    r = paper.PAPER_PARTICLE_RADIUS
    cs.cor_checks = [check_restitution(v, paper.PAPER_COR_PP, S235, S235, r),
                     check_restitution(v, paper.PAPER_COR_PW, S235, PVC, r)]
    worst = max(c.max_deviation for c in cs.cor_checks)
    cs.rows.append(_row("dem_cor_calibration", f"{worst:.1e} (steel-steel and steel-PVC, "
                        f"{len(v)} speeds each)", worst))

    t_cmp = paper.PAPER_COMPARISON_TIME
    a75 = _need(cs.run_32, "model 3 run").amplitude_at(t_cmp)
    curves = damper.with_restitution(paper.PAPER_COR_PP, paper.PAPER_COR_PW)
    cor = _cor_text(damper)
    say(f"Fig. 7/8: DEM model 1, {cor}")
    cs.run_dem = _timed(cs, "model 1", lambda: Simulation(
        structure, sc.model("dem", damper), x0).run(duration))
    if curves == damper:  # the scenario already runs the paper's curves
        cs.run_dem_curves = cs.run_dem
    else:
        say("Fig. 7/8: DEM model 1, the paper's COR curves (Fig. 2)")
        cs.run_dem_curves = _timed(cs, "model 1, paper's COR curves", lambda: Simulation(
            structure, sc.model("dem", curves), x0).run(duration))
    cs.rows.append(_amplitude_row("dem_amplitude_32_0p75s", cs.run_dem, t_cmp,
                                  f" (analytical {a75 * 1e3:.1f} mm)", cor=cor))
    cs.rows.append(_amplitude_row("dem_curves_amplitude_32_0p75s", cs.run_dem_curves, t_cmp,
                                  f" (analytical {a75 * 1e3:.1f} mm)"))
    for prefix, run in (("dem", cs.run_dem), ("dem_curves", cs.run_dem_curves)):
        for key, target in ((f"{prefix}_zeta_53mm", 0.053), (f"{prefix}_zeta_41mm", 0.041)):
            z, a = _zeta_at(run, target)
            cs.rows.append(_row(key, f"{z:.4f} at {a * 1e3:.1f} mm", z, cor=cor))


def band_scenario(sc: Scenario) -> Scenario:
    """The scenario of DEM model 1's realisations: ``sc`` from a random packing (the
    lattice is one realisation), the band's amplitude at the paper's comparison time
    (the end of a shorter run)."""
    at = min(paper.PAPER_COMPARISON_TIME, sc.simulation.duration)
    return sc.model_copy(update={
        "dem": sc.dem.model_copy(update={"packing": "random"}),
        "optimization": sc.optimization.model_copy(update={"at": at})})


def _dem_band(cs: CaseStudy, sc: Scenario, n: int, say: Callable[[str], None],
              sweep_options: dict[str, Any]) -> None:
    """DEM model 1 from ``n`` random packings on the sweep engine (:func:`band_scenario`)."""
    from pdamper.runs.realisations import run_level3_realisations

    say(f"Fig. 7/8: DEM model 1 from {n} random packings")
    opts = {k: v for k, v in sweep_options.items() if k in ("workers", "scheduler", "serial")}
    if not opts.get("workers") and not opts.get("scheduler"):
        # a few runs of seconds each: in this process, whose kernels are loaded, they cost
        # less than a new cluster's start and its workers' kernel loads
        opts["serial"] = True
    cs.dem_band = _timed(cs, f"model 1, {n} random packings",
                         lambda: run_level3_realisations(band_scenario(sc), n, "dem", **opts))
