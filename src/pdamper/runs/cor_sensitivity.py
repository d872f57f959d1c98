"""How much do the coefficients of restitution matter? (paper Sect. 2, last paragraph)

The paper states that "the CORs' values are of minor importance for the efficiency of the
particle damper for vertical vibrations". :func:`run_cor_sensitivity` tests it: it reruns
DEM Level II points (loss factor, effective mass; complex power method, Eqs. 1-4) and the
Level III DEM model 1 run (free vibration from the release, Fig. 7/8) of one scenario under
several COR models (:class:`CORVariant`: constants, the paper's curves, scaled curves
``e -> 1 - s (1 - e)``, Thornton's model), and reports each with the stationarity of its
Level II window (the loss factor over the first and the second half of the averaged cycles).

Variants are written as on the command line (:func:`cor_variant`): ``"0.6/0.85"``
(sphere-sphere / sphere-wall), ``"paper"`` (both pairs), ``"paper*1.5"``, ``"thornton"``,
``"0.9/paper"``. The study's figure is :func:`pdamper.reports.cor_sensitivity.
sensitivity_figure`.
"""

from __future__ import annotations

import logging
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

from pdamper.contact.restitution import RestitutionCurve
from pdamper.errors import InputError

if TYPE_CHECKING:
    import xarray as xr

    from pdamper.coupling import FreeVibrationResult

logger = logging.getLogger(__name__)

#: The study's default COR variants: the benchmark constants, the paper's curves, the
#: curves with half and one and a half times their dissipation, nearly elastic constants,
#: and Thornton's elastic-plastic model from the materials.
DEFAULT_VARIANTS = ("0.6/0.85", "paper", "paper*0.5", "paper*1.5", "0.9/0.95", "thornton")
#: Default Level II points (f [Hz], X [m]): 10 Hz at 15 mm (where constant CORs rattle above
#: 4/pi) and at X_opt = 32 mm, 5 Hz at 32 mm (single collect-and-collide) and 15 Hz at
#: 15 mm.
DEFAULT_POINTS = ((10.0, 0.015), (10.0, 0.032), (5.0, 0.032), (15.0, 0.015))
#: Relative change of the loss factor between the two halves of the averaged window above
#: which a Level II result is labelled a transient.
STATIONARITY_TOLERANCE = 0.1
#: Level II cycles per point and cycles left out, unless the scenario's ``[dem]`` section sets
#: them: the DEM's default of 8 (2 left out, the paper's) still holds the initial transient at
#: small strokes (at 10 Hz / 15 mm the 32-sphere bed rattles for ~16 cycles before it settles
#: to the same loss factor with every COR model; docs/restitution.md).
STUDY_CYCLES = 48
STUDY_SKIP_CYCLES = 16


@dataclass(frozen=True)
class CORVariant:
    """A pair of COR models under one name."""

    name: str
    restitution_pp: RestitutionCurve
    restitution_pw: RestitutionCurve

    def describe(self) -> str:
        return f"{self.restitution_pp.describe()} / {self.restitution_pw.describe()}"


def _model_reading(text: str, existing: bool) -> bool:
    """Whether ``text`` reads as one COR model (a table only where its file exists, with
    ``existing``)."""
    from pathlib import Path

    from pdamper.io.restitution import parse_model_text

    text = text.strip()
    if not text:
        return False
    try:
        spec = parse_model_text(text)
    except InputError:
        return False
    return not existing or spec["model"] != "table" or Path(spec["file"]).is_file()


def split_variant(text: str, field: str = "variants") -> tuple[str, str]:
    """The sphere-sphere and sphere-wall model texts of a variant ``text``: ``MODEL`` (both
    pairs) or ``PP/PW``.

    A COR table's path holds ``/`` too, so the text is read as one model for both pairs or
    split at the one ``/`` that leaves a model on both sides. Readings whose tables all
    exist are taken first; one reading must remain (else the error lists them).

    >>> split_variant("0.6/0.85"), split_variant("paper*1.5")
    (('0.6', '0.85'), ('paper*1.5', 'paper*1.5'))
    >>> split_variant("thornton/0.9*0.5")
    ('thornton', '0.9*0.5')
    """
    text = str(text).strip()
    cuts = [k for k, c in enumerate(text) if c == "/"]
    readings = [(text, text)] + [(text[:k].strip(), text[k + 1:].strip()) for k in cuts]

    def listed(found):
        return "; ".join(f"{a} / {b}" if a != b else f"{a} for both" for a, b in found)

    found = [r for r in readings if all(_model_reading(part, True) for part in r)]
    if len(found) > 1:
        raise InputError(field, f"{text!r} reads as several variants ({listed(found)}); "
                         "rename the tables so that one reading remains")
    if not found:  # a table not found: the reading that names it, if only one does
        found = [r for r in readings if all(_model_reading(part, False) for part in r)]
        if len(found) > 1:
            raise InputError(field, f"{text!r}: no such COR table (read as {listed(found)})")
    if not found:
        raise InputError(field, f"expected MODEL or PP/PW such as 0.6/0.85, paper*1.5 or "
                         f"pp.csv/pw.csv, got {text!r}")
    return found[0]


def cor_variant(text: str, damper, field: str = "variants") -> CORVariant:
    """The :class:`CORVariant` ``text`` (``"0.6/0.85"``, ``"paper*1.5"``, ``"cor.csv"``,
    ``"tables/pp.csv/tables/pw.csv"``: :func:`split_variant`) for the materials and radius
    of ``damper`` (a :class:`~pdamper.damper.ParticleDamper`)."""
    from pdamper.io.restitution import build_curve, parse_model_text, validate_spec

    parts = split_variant(text, field)
    sphere, wall, r = damper.particle_material, damper.wall_material, damper.particle_radius
    curves = []
    for part, pair, partner in zip(parts, ("particle_particle", "particle_wall"), (sphere, wall),
                                   strict=True):
        spec = validate_spec(parse_model_text(part, field), field)
        try:
            curves.append(build_curve(spec, pair, sphere, partner, r))
        except InputError as exc:
            raise InputError(field, f"{text!r}: {exc}") from None
    return CORVariant(str(text).strip(), curves[0], curves[1])


@dataclass
class CORSensitivity:
    """Results of :func:`run_cor_sensitivity`.

    Attributes
    ----------
    level2
        ``xarray.Dataset`` over (variant, point): ``loss_factor``, ``effective_mass_ratio``,
        ``dissipated_energy_per_cycle``, the loss factor over the first and the second half
        of the averaged cycles, ``stationary`` and ``energy_balance_error``.
    level3
        ``xarray.Dataset`` over (variant): amplitude at 0.75 s and damping ratios near 53
        and 41 mm of DEM model 1 (None without Level III).
    runs
        The Level III :class:`~pdamper.coupling.FreeVibrationResult` of each variant.
    analytical_run
        The same Level III run with the analytical model (model 3), for reference.
    variants
        The variants, in order.
    """

    level2: xr.Dataset
    level3: xr.Dataset | None = None
    runs: dict[str, FreeVibrationResult] = field(default_factory=dict)
    analytical_run: FreeVibrationResult | None = None
    variants: list = field(default_factory=list)
    wall_seconds: float = 0.0
    inputs: dict = field(default_factory=dict)

    def as_dict(self) -> dict:
        """JSON-ready summary."""
        level2: list[dict] = []
        out: dict[str, Any] = {"variants": [{"name": v.name, "cor": v.describe()}
                                            for v in self.variants],
                               "level2": level2, "wall_seconds": self.wall_seconds}
        ds = self.level2
        for v in ds["variant"].values:
            for p in range(ds.sizes["point"]):
                sel = ds.sel(variant=v).isel(point=p)
                level2.append({"variant": str(v), **{
                    k: (bool(sel[k]) if k == "stationary" else float(sel[k]))
                    for k in ("frequency", "amplitude", "loss_factor", "effective_mass_ratio",
                              "loss_factor_first_half", "loss_factor_second_half",
                              "stationary", "energy_balance_error")}})
        if self.level3 is not None:
            out["level3"] = [{"variant": str(v), **{k: float(self.level3[k].sel(variant=v))
                                                    for k in self.level3.data_vars}}
                             for v in self.level3["variant"].values]
        out["units"] = {"frequency": "Hz", "amplitude": "m", "amplitude_0p75s": "m",
                        "wall_seconds": "s"}
        return out

    def markdown(self) -> str:
        """The Level II and Level III tables in Markdown."""
        ds = self.level2
        pts = [(float(f), float(x)) for f, x in zip(ds["frequency"].values,
                                                    ds["amplitude"].values, strict=True)]
        head = " | ".join(f"{f:g} Hz / {x * 1e3:g} mm" for f, x in pts)
        lines = ["Level II, effective loss factor eta (cycles "
                 f"{ds.attrs['skip_cycles'] + 1}-{ds.attrs['cycles']}; * = the two halves of the "
                 f"window differ by more than {STATIONARITY_TOLERANCE:.0%}: transient)", "",
                 f"| COR model | {head} |", "|---|" + "---|" * len(pts)]
        for v in ds["variant"].values:
            sel = ds.sel(variant=v)
            cells = [f"{e:.3f}{'' if s else '*'}" for e, s in
                     zip(sel["loss_factor"].values, sel["stationary"].values, strict=True)]
            lines.append(f"| {v} | " + " | ".join(cells) + " |")
        lines.append("| analytical block model (no COR) | "
                     + " | ".join(f"{e:.3f}" for e in ds["loss_factor_analytical"].values) + " |")
        if self.level3 is not None:
            d3 = self.level3
            lines += ["", "Level III, DEM model 1, 32 spheres from -58 mm", "",
                      "| COR model | amplitude at 0.75 s [mm] | zeta near 53 mm | "
                      "zeta near 41 mm |", "|---|---|---|---|"]
            for v in d3["variant"].values:
                s = d3.sel(variant=v)
                lines.append(f"| {v} | {float(s['amplitude_0p75s']) * 1e3:.1f} | "
                             f"{float(s['zeta_53mm']):.4f} | {float(s['zeta_41mm']):.4f} |")
            if self.analytical_run is not None:
                run = self.analytical_run
                lines.append(f"| analytical model (model 3, no COR) | "
                             f"{d3.attrs['analytical_amplitude_0p75s'] * 1e3:.1f} | "
                             f"{_zeta_near(run, 0.053):.4f} | {_zeta_near(run, 0.041):.4f} |")
            lines.append("| experiment (paper) | 19 | ~0.035 | ~0.05 |")
        return "\n".join(lines) + "\n"


def _zeta_near(run, amplitude: float) -> float:
    amp, zeta = run.damping_ratio
    if len(amp) == 0:
        return float("nan")
    return float(zeta[int(np.argmin(np.abs(amp - amplitude)))])


def study_scenario(scenario, cycles: int | None = None, skip_cycles: int | None = None):
    """``scenario`` with the study's Level II window: ``cycles`` / ``skip_cycles`` if given,
    else the scenario's ``[dem]`` values where it sets them, else :data:`STUDY_CYCLES` /
    :data:`STUDY_SKIP_CYCLES`."""
    given = scenario.dem.model_fields_set
    n_cyc = cycles if cycles is not None else (
        scenario.dem.cycles if "cycles" in given else STUDY_CYCLES)
    n_skip = skip_cycles if skip_cycles is not None else (
        scenario.dem.skip_cycles if "skip_cycles" in given else STUDY_SKIP_CYCLES)
    return scenario.model_copy(update={"dem": scenario.dem.model_copy(
        update={"cycles": n_cyc, "skip_cycles": n_skip})})


def run_cor_sensitivity(scenario=None, variants: Sequence[str | CORVariant] = DEFAULT_VARIANTS,
                        points: Sequence[tuple[float, float]] = DEFAULT_POINTS,
                        level3: bool = True, duration: float | None = None,
                        cycles: int | None = None, skip_cycles: int | None = None,
                        progress: Callable[[str], None] | None = None) -> CORSensitivity:
    """Rerun DEM Level II points and the Level III model-1 run under each COR variant.

    Parameters
    ----------
    scenario
        :class:`~pdamper.io.scenario.Scenario` (default: the paper's case); its damper,
        structure, release and ``[dem]`` options are used, its own COR models are replaced
        by each variant's.
    variants
        Variant texts (:func:`cor_variant`) or :class:`CORVariant` objects.
    points
        Level II excitation points ``(f [Hz], X [m])``.
    level3
        Also run DEM model 1 on the structure (``duration``, default the scenario's).
    cycles, skip_cycles
        Level II cycles per point and cycles left out of the complex power (default: the
        scenario's ``[dem]`` values where it sets them, else :data:`STUDY_CYCLES` and
        :data:`STUDY_SKIP_CYCLES`).
    """
    import xarray as xr

    from pdamper.io.scenario import Scenario

    sc = study_scenario(Scenario() if scenario is None else scenario, cycles, skip_cycles)
    say = progress or (lambda _m: None)
    base = sc.damper()
    vs = [v if isinstance(v, CORVariant) else cor_variant(v, base) for v in variants]
    if not vs:
        raise InputError("variants", "give at least one COR variant")
    names = [v.name for v in vs]
    if len(set(names)) != len(names):
        raise InputError("variants", f"names must differ, got {names}")
    pts = [(float(f), float(x)) for f, x in points]
    if not pts:
        raise InputError("points", "give at least one (frequency, amplitude) point")
    from pdamper import resources

    for f, x in pts:  # the DEM's physics limits, for every point before the first run
        resources.check_motion(base, f, x, fields=("points", "points"), contact_law=True)
    t0 = time.perf_counter()
    shape = (len(vs), len(pts))
    out = {k: np.full(shape, np.nan) for k in (
        "loss_factor", "effective_mass_ratio", "dissipated_energy_per_cycle",
        "loss_factor_first_half", "loss_factor_second_half", "energy_balance_error")}
    model: Any = None
    for i, v in enumerate(vs):
        damper = base.with_restitution(v.restitution_pp, v.restitution_pw)
        model = sc.model("dem", damper)
        half = (model.cycles - model.skip_cycles) // 2
        if half < 1:
            raise InputError("dem.cycles", "the stationarity check needs at least 2 averaged "
                             f"cycles, got {model.cycles - model.skip_cycles}")
        for j, (f, x) in enumerate(pts):
            say(f"Level II, {v.name}: {f:g} Hz / {x * 1e3:g} mm")
            res = model.run(f, x)
            cp = res.complex_power(model.skip_cycles)
            out["loss_factor"][i, j] = cp.loss_factor
            out["effective_mass_ratio"][i, j] = cp.effective_mass_ratio
            out["dissipated_energy_per_cycle"][i, j] = cp.dissipated_energy_per_cycle
            out["loss_factor_first_half"][i, j] = res.complex_power(model.skip_cycles,
                                                                    half).loss_factor
            out["loss_factor_second_half"][i, j] = res.complex_power(
                model.cycles - half, half).loss_factor
            out["energy_balance_error"][i, j] = res.energy_balance_error()
    from pdamper.models import AnalyticalDamper

    analytical = AnalyticalDamper(base).response(np.array([p[0] for p in pts]),
                                                 np.array([p[1] for p in pts]))
    a, b = out["loss_factor_first_half"], out["loss_factor_second_half"]
    stationary = np.abs(b - a) <= STATIONARITY_TOLERANCE * np.maximum(np.abs(out["loss_factor"]),
                                                                     1e-12)
    units = {"loss_factor": "1", "effective_mass_ratio": "1", "dissipated_energy_per_cycle": "J",
             "loss_factor_first_half": "1", "loss_factor_second_half": "1",
             "energy_balance_error": "1"}
    level2 = xr.Dataset(
        {k: (("variant", "point"), val, {"units": units[k]}) for k, val in out.items()}
        | {"stationary": (("variant", "point"), stationary),
           "loss_factor_analytical": ("point", analytical.loss_factor.ravel(), {
               "units": "1", "description": "analytical block model (Eqs. 5-22), no COR"})},
        coords={"variant": names, "cor": ("variant", [v.describe() for v in vs]),
                "frequency": ("point", [p[0] for p in pts], {"units": "Hz"}),
                "amplitude": ("point", [p[1] for p in pts], {"units": "m"})},
        attrs={"cycles": model.cycles, "skip_cycles": model.skip_cycles,
               "integrator": model.integrator, "particle_count": base.count})
    cs = CORSensitivity(level2=level2, variants=vs, inputs=sc.model_dump(mode="json"))
    if level3:
        _run_level3(cs, sc, base, duration, say)
    cs.wall_seconds = time.perf_counter() - t0
    return cs


def _run_level3(cs: CORSensitivity, sc, base, duration: float | None,
                say: Callable[[str], None]) -> None:
    """The Level III part of :func:`run_cor_sensitivity`: DEM model 1 under each variant of
    ``cs`` and the analytical model for reference, into ``cs.runs``, ``cs.analytical_run``
    and ``cs.level3``."""
    import xarray as xr

    from pdamper.coupling import Simulation
    from pdamper.models import AnalyticalDamper
    from pdamper.parameters import vertical_dampers_paper as paper

    vs = cs.variants
    structure = sc.structure_model()
    x0 = sc.structure.initial_displacement
    t_end = sc.simulation.duration if duration is None else float(duration)
    t_cmp = paper.PAPER_COMPARISON_TIME
    d3 = {k: np.full(len(vs), np.nan) for k in ("amplitude_0p75s", "zeta_53mm", "zeta_41mm")}
    reference = Simulation(structure, AnalyticalDamper(base), x0).run(t_end)
    cs.analytical_run = reference
    for i, v in enumerate(vs):
        say(f"Level III, DEM model 1, {v.name}")
        damper = base.with_restitution(v.restitution_pp, v.restitution_pw)
        run = Simulation(structure, sc.model("dem", damper), x0).run(t_end)
        cs.runs[v.name] = run
        if run.time[-1] >= t_cmp * (1 - 1e-9):
            d3["amplitude_0p75s"][i] = run.amplitude_at(t_cmp)
        d3["zeta_53mm"][i] = _zeta_near(run, 0.053)
        d3["zeta_41mm"][i] = _zeta_near(run, 0.041)
    cs.level3 = xr.Dataset(
        {"amplitude_0p75s": ("variant", d3["amplitude_0p75s"], {"units": "m"}),
         "zeta_53mm": ("variant", d3["zeta_53mm"], {"units": "1"}),
         "zeta_41mm": ("variant", d3["zeta_41mm"], {"units": "1"})},
        coords={"variant": [v.name for v in vs]},
        attrs={"duration": t_end, "initial_displacement": x0,
               "analytical_amplitude_0p75s": float(reference.amplitude_at(t_cmp))
               if reference.time[-1] >= t_cmp * (1 - 1e-9) else float("nan")})


__all__ = ["CORSensitivity", "CORVariant", "DEFAULT_POINTS", "DEFAULT_VARIANTS",
           "STATIONARITY_TOLERANCE", "STUDY_CYCLES", "STUDY_SKIP_CYCLES", "cor_variant",
           "run_cor_sensitivity", "split_variant", "study_scenario"]
