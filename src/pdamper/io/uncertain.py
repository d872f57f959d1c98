"""Uncertain inputs of a scenario: ``"value +- sd"``, and their propagation to the answers.

A scenario value (or a command-line ``--uncertain FIELD=VALUE+-SD``) written as
``"0.1 +- 0.03"``, ``"120 mm +- 0.1 mm"`` or ``"0.1 ± 0.03"`` is a nominal value and a
*standard deviation*, both with the field's unit; the input is then normal with that mean
and standard deviation, truncated to the field's valid range
(:class:`pdamper.design.uncertainty.UncertainInput`). Every command uses the nominal value;
``--uncertainty N`` (``pdamper analytic``, ``map``, ``simulate``, ``report``)
samples the inputs (:func:`pdamper.design.uncertainty.propagate`) and reports the spread of
the answers and which input drives it.

The fields that may carry an uncertainty are those of :data:`UNCERTAIN_FIELDS`; the COR
fit of a ``[restitution]`` table carries its own (its parameters' covariance,
:mod:`pdamper.contact.fit`), which only the DEM feels: the analytical and field models do
not depend on friction or restitution, and their answers show these inputs' Sobol' index 0.
``pdamper dem --uncertainty N --uncertain restitution.particle_wall=fit`` samples it
(:func:`add_fit_inputs`: one input per principal axis of the covariance,
:class:`pdamper.design.uncertainty.ParameterFit`) through the DEM (:func:`dem_answers`).
"""

from __future__ import annotations

import math
import re
from typing import Any

from pdamper.damper import QUANTITIES, quantity, uncertain_fields
from pdamper.errors import InputError

#: Fields that may be given as ``"value +- sd"``: SI unit and valid range (truncation). The
#: damper's are derived from its declarations (:func:`pdamper.damper.uncertain_fields`).
UNCERTAIN_FIELDS: dict[str, tuple[str, float, float]] = {
    **uncertain_fields(),
    "excitation.frequency": ("Hz", 0.0, math.inf),
    "excitation.amplitude": ("m", 0.0, math.inf),
    "structure.mass": ("kg", 0.0, math.inf),
    "structure.stiffness": ("N/m", 0.0, math.inf),
    "structure.damping": ("kg/s", 0.0, math.inf),
}
_SPLIT = re.compile(r"\s*(?:\+-|\+/-|±)\s*")
#: Sample rate of the Level III runs of a propagation [Hz]: the peaks are exact in the
#: pseudo-force coupling (as in the design study); the trajectory is not stored.
_SAMPLE_RATE = 200.0
LEVEL2_UNITS = {"loss_factor": "1", "effective_mass_ratio": "1", "effective_mass": "kg",
                "dissipated_energy_per_cycle": "J"}
LEVEL3_UNITS = {"amplitude_at": "m", "final_amplitude": "m", "mean_damping_ratio": "1",
                "envelope": "m"}
#: Times of the Level III envelope band (from release to the end of the run).
ENVELOPE_POINTS = 101


def is_uncertain(value: Any) -> bool:
    """Whether ``value`` is text with ``+-``/``±``."""
    return isinstance(value, str) and _SPLIT.search(value) is not None


def parse_uncertain(text: str, field: str):
    """The :class:`~pdamper.design.uncertainty.UncertainInput` of ``"value +- sd"`` for
    ``field`` (a key of :data:`UNCERTAIN_FIELDS`).

    >>> u = parse_uncertain("120 mm +- 0.1 mm", "container.length")
    >>> round(u.value, 6), round(u.sd, 6)
    (0.12, 0.0001)
    """
    from pdamper.design.uncertainty import UncertainInput
    from pdamper.settings import check_setting
    from pdamper.units import parse_quantity

    if field not in UNCERTAIN_FIELDS:
        raise InputError(field, f"cannot carry an uncertainty ('value +- sd'); these can: "
                         f"{', '.join(UNCERTAIN_FIELDS)}")
    unit, low, high = UNCERTAIN_FIELDS[field]
    parts = _SPLIT.split(text.strip())
    if len(parts) != 2 or not all(parts):
        raise InputError(field, f"expected 'value +- sd' (sd: a standard deviation, e.g. "
                         f"'0.1 +- 0.03' or '120 mm +- 0.1 mm'), got {text!r}")
    value = parse_quantity(parts[0], unit, field)
    sd = parse_quantity(parts[1], unit, field)
    if not sd > 0:
        raise InputError(field, f"the standard deviation must be > 0 (leave out '+- sd' for "
                         f"an exact value), got {parts[1]!r}")
    if field in QUANTITIES:  # a quantity of the damper: its declaration's check and message
        check_setting(field, value, quantity(field))
    elif not low <= value <= high:
        raise InputError(field, f"the nominal value must be in the field's range "
                         f"[{low:g}, {high:g}], got {parts[0]!r}")
    return UncertainInput(field, value, sd, low, high, unit)


def extract_uncertain(data: dict) -> dict:
    """Replace every ``"value +- sd"`` of the scenario ``data`` (parsed TOML, changed in
    place) by its nominal value; returns ``{field: UncertainInput}``."""
    out = {}
    for section, table in data.items():
        if not isinstance(table, dict):
            continue
        for key, value in list(table.items()):
            if is_uncertain(value):
                field = f"{section}.{key}"
                u = parse_uncertain(value, field)
                table[key] = u.value
                out[field] = u
    return out


#: The ``--uncertain`` value that makes a fitted COR curve an uncertain input
#: (``--uncertain restitution.particle_wall=fit``).
FIT_VALUE = "fit"


def fit_uncertainty(scenario, pair: str):
    """The :class:`~pdamper.design.uncertainty.ParameterFit` of the COR curve that the
    scenario fits for ``pair`` (``"particle_particle"`` or ``"particle_wall"``): the fit's
    parameters with their covariance (:func:`pdamper.contact.fit.fit_restitution`), the
    curves built with the entry's ``scale``."""
    import numpy as np

    from pdamper.contact.fit import fit_restitution
    from pdamper.design.uncertainty import ParameterFit
    from pdamper.io.restitution import PAIRS, TableCOR, read_cor_table

    field = f"restitution.{pair}"
    if pair not in PAIRS:
        raise InputError("uncertain", f"'{FIT_VALUE}' is for a fitted COR curve: "
                         f"{' or '.join('restitution.' + p for p in PAIRS)}, got {field!r}")
    spec = getattr(scenario.restitution, pair)
    if not isinstance(spec, TableCOR) or spec.fit is None:
        raise InputError(field, "carries no fitted curve whose uncertainty could be sampled: "
                         "give it as { model = \"table\", file = \"cor.csv\", fit = "
                         "\"exponential\" } (or \"thornton\", \"linear\")")
    table = read_cor_table(spec.file, f"{field}.file")
    try:
        fit = fit_restitution(table.velocity, table.restitution, table.std, spec.fit,
                              name=f"{spec.fit} fit of {table.source} "
                                   f"({len(table.velocity)} points), sampled")
    except InputError as exc:
        raise InputError(field, exc.message) from None

    import functools

    return ParameterFit(field, tuple(fit.parameters), tuple(fit.curve.UNITS),
                        np.asarray(fit.values, float), np.asarray(fit.covariance, float),
                        functools.partial(_fitted_curve, fit=fit, scale=spec.scale))


def _fitted_curve(params, *, fit, scale: float):
    """The curve of ``fit``'s family at ``params``, scaled (picklable: for the workers)."""
    return fit.curve_at(params).scaled(scale)


def add_fit_inputs(scenario, fields) -> tuple:
    """Make the fitted COR curves ``fields`` (``"restitution.<pair>"``) uncertain inputs of
    ``scenario`` (changed in place): one per principal axis of each fit's parameters,
    ``restitution.<pair>[pc1]``, ... (:class:`~pdamper.design.uncertainty.ParameterFit`).
    Returns the inputs added."""
    added = []
    for f in fields:
        section, _, pair = f.partition(".")
        if section != "restitution":
            raise InputError(f, f"only a fitted COR curve (restitution.particle_wall, "
                             f"restitution.particle_particle) takes '{FIT_VALUE}'; give "
                             "other fields as 'value +- sd'")
        added.extend(fit_uncertainty(scenario, pair).inputs())
    scenario._uncertain = {**scenario._uncertain, **{u.field: u for u in added}}
    return tuple(added)


def sampled_damper(scenario, values: dict[str, float]):
    """The damper of ``scenario`` at the sample ``values``: plain fields set
    (:func:`with_values`), the fitted COR curves of the principal-axis inputs
    (:class:`~pdamper.design.uncertainty.FitAxis`) replaced by the sampled curves."""
    import dataclasses

    from pdamper.design.uncertainty import fit_groups

    damper = with_values(scenario, values).damper()
    for group, axes in fit_groups(scenario.uncertain_inputs()).items():
        z = [values.get(u.field, 0.0) for u in axes]
        fit = axes[0].fit
        if fit is None:  # an axis made by hand, without its fit: nothing to sample from
            raise InputError(group, "principal-axis input without its fit")
        try:
            curve = fit.sample(z)
        except InputError as exc:
            raise InputError(group, f"sampled parameters give no valid COR: "
                             f"{exc.message}") from None
        pair = group.removeprefix("restitution.")
        key = "restitution_pp" if pair == "particle_particle" else "restitution_pw"
        damper = dataclasses.replace(damper, **{key: curve})
    return damper


def with_values(scenario, values: dict[str, float]):
    """``scenario`` with the fields of ``values`` (``{"section.key": SI value}``) set (not
    validated again: the models and runs judge the values); the principal axes of a fitted
    curve (``restitution.<pair>[pcK]``) are left to :func:`sampled_damper`."""
    sections: dict[str, dict] = {}
    for field, v in values.items():
        if "[" in field:
            continue
        section, _, key = field.partition(".")
        sections.setdefault(section, {})[key] = v
    return scenario.model_copy(update={
        s: getattr(scenario, s).model_copy(update=u) for s, u in sections.items()})


def _model_class(scenario, name: str | None):
    from pdamper.models import get_damper_model

    field = "model" if name is not None else "simulation.model"
    cls = get_damper_model(scenario.simulation.model if name is None else name, field)
    if cls.expensive:
        raise InputError("uncertainty", f"the {cls.fidelity} model is not sampled (N (inputs "
                         "+ 2) runs of seconds to hours each); use --model analytic or fields")
    return cls


def level2_answers(scenario, model: str | None = None):
    """``evaluate(values) -> answers`` at ``[excitation]``: loss factor, effective mass
    (ratio and kg), dissipated energy per cycle (:data:`LEVEL2_UNITS`)."""
    _model_class(scenario, model or "analytic")

    def evaluate(values: dict[str, float]) -> dict[str, float]:
        sc = with_values(scenario, values)
        d = sc.damper()
        r = sc.model(model or "analytic", d).response(sc.excitation.frequency,
                                                     sc.excitation.amplitude)
        return {"loss_factor": float(r.loss_factor),
                "effective_mass_ratio": float(r.effective_mass_ratio),
                "effective_mass": float(r.effective_mass),
                "dissipated_energy_per_cycle": float(r.dissipated_energy_per_cycle)}

    return evaluate


def level3_answers(scenario, model: str | None = None):
    """``evaluate(values) -> answers`` of the free decay of ``[simulation]``: amplitude
    envelope at ``[optimization] at``, final amplitude, mean damping ratio of the cycles
    that end by then (Eqs. 24-25; :data:`LEVEL3_UNITS`), and the envelope at
    :data:`ENVELOPE_POINTS` times from 0 to the duration (``envelope``: its band)."""
    from pdamper.coupling import Simulation
    from pdamper.design.study import make_objective

    _model_class(scenario, model)
    at, duration = scenario.optimization.at, scenario.simulation.duration
    if at > duration:
        raise InputError("optimization.at", f"the time of the amplitude ({at:g} s) must be "
                         f"within the simulated {duration:g} s (simulation.duration)")

    import numpy as np

    times = np.linspace(0.0, duration, ENVELOPE_POINTS)

    def evaluate(values: dict[str, float]) -> dict:
        sc = with_values(scenario, values)
        structure = sc.structure_model()
        x0 = sc.structure.initial_displacement
        res = Simulation(structure, sc.model(model, sc.damper()), x0).run(duration,
                                                                           _SAMPLE_RATE)
        zeta, _ = make_objective("mean-damping", at, x0, structure).evaluate(res)
        return {"amplitude_at": float(res.amplitude_at(at)),
                "final_amplitude": float(res.final_amplitude), "mean_damping_ratio": zeta,
                "envelope": np.array([res.amplitude_at(t) for t in times])}

    return evaluate


def map_answers(scenario, model: str = "analytic"):
    """``evaluate(values) -> answers`` of the Level II map of ``[map]``: the largest and
    the mean loss factor over the grid (scalars), and the loss factor and effective mass
    ratio of every cell (arrays: their bands, :data:`MAP_BANDS`)."""
    _model_class(scenario, model)
    f, x = scenario.map_grid()
    counts = scenario.map_particles()

    def evaluate(values: dict[str, float]) -> dict:
        import numpy as np

        from pdamper.analysis.fields import effective_field

        sc = with_values(scenario, values)
        ds = effective_field(sc.map_model(model, sc.damper()), f, x, particles=counts)
        eta = np.asarray(ds["loss_factor"].values, float)
        return {"max_loss_factor": float(np.nanmax(eta)),
                "mean_loss_factor": float(np.nanmean(eta)), "loss_factor": eta,
                "effective_mass_ratio": np.asarray(ds["effective_mass_ratio"].values, float)}

    return evaluate


def dem_answers(scenario):
    """``evaluate(values) -> answers`` of one DEM run at ``[excitation]`` (Level II): loss
    factor, effective mass ratio and kg, dissipated energy per cycle
    (:data:`LEVEL2_UNITS`). Every sample runs from the scenario's seed (the same packing):
    the spread is the inputs', not the packing's (``--realisations`` gives that)."""

    def evaluate(values: dict[str, float]) -> dict[str, float]:
        sc = with_values(scenario, values)
        r = sc.model("dem", sampled_damper(scenario, values)).response(
            sc.excitation.frequency, sc.excitation.amplitude)
        return {"loss_factor": float(r.loss_factor),
                "effective_mass_ratio": float(r.effective_mass_ratio),
                "effective_mass": float(r.effective_mass),
                "dissipated_energy_per_cycle": float(r.dissipated_energy_per_cycle)}

    return evaluate


def dem_point(params: dict, *, scenario) -> dict:
    """One sample of :func:`dem_answers` on a sweep worker (``params``: the sample)."""
    return dem_answers(scenario)(params)


def dem_batch(scenario, *, workers: int | None = None, serial: bool = False, progress=None):
    """``batch(points) -> answers`` of :func:`dem_answers` on the sweep engine
    (:func:`pdamper.sweep.run_sweep`: a local cluster of ``workers`` processes, default
    every core, or ``serial`` in this process): the DEM runs of a propagation in
    parallel (:func:`pdamper.design.uncertainty.propagate`'s ``batch``)."""
    import functools

    def batch(points: list[dict]) -> list[dict]:
        from pdamper.sweep import run_sweep

        res = run_sweep(functools.partial(dem_point, scenario=scenario), points, retries=0,
                        workers=workers, serial=serial,
                        progress=None if progress is None else
                        (lambda done, total, _p: progress(done, total)))
        bad = [p for p in res.points if not p.ok]
        if bad:
            shown = ", ".join(f"{k} = {v:.6g}" for k, v in bad[0].params.items())
            raise InputError("uncertainty", f"the DEM run of the sample {shown} failed: "
                             f"{bad[0].error}")
        return [p.values for p in res.points]

    return batch


#: The map's answers whose bands become variables of its NetCDF file.
MAP_BANDS = ("loss_factor", "effective_mass_ratio")
MAP_UNITS = {"max_loss_factor": "1", "mean_loss_factor": "1", "loss_factor": "1",
             "effective_mass_ratio": "1"}


def check_cost(scenario, level: str, n: int, force: bool = False) -> None:
    """Refuse a propagation whose ``n (d + 2) + 1`` runs exceed the limits of
    :mod:`pdamper.resources`."""
    from pdamper import resources

    d = len(scenario.uncertain_inputs())
    runs = n * (d + 2) + 1
    if level == "map":
        (_, _, nf), (_, _, nx) = scenario.map_ranges()
        counts = scenario.map_particles()
        one = resources.analytic_map_cost(float(nf) * nx * (1 if counts is None
                                                            else counts.size))
    elif level == "dem":  # N (d + 2) + 1 DEM runs at the excitation, one after another
        one = scenario.excitation_cost("dem")
    elif level == "level3":
        one = resources.pseudo_force_cost(scenario.simulation.duration, _SAMPLE_RATE,
                                          scenario.structure_model().natural_frequency)
    else:
        one = resources.analytic_map_cost(1.0)
    resources.require(resources.Cost(
        "the uncertainty propagation", one.seconds * runs, one.memory,
        f"{runs} runs, each {one.detail}", (("uncertainty", n / 64),), runs=runs,
        longest=one.seconds), force)


def propagate_scenario(scenario, level: str, n: int, seed: int = 0, model: str | None = None,
                       progress=None, batch=None):
    """Propagate the scenario's uncertain inputs to its ``"level2"``, ``"map"`` or
    ``"level3"`` answers with ``n`` base points (:func:`pdamper.design.uncertainty.propagate`). A
    sample the models refuse is an error naming its field and the sample."""
    from pdamper.design.uncertainty import check_points, propagate

    check_points(n)
    inputs = scenario.uncertain_inputs()
    if level == "level2":
        evaluate, units = level2_answers(scenario, model), LEVEL2_UNITS
    elif level == "map":
        evaluate, units = map_answers(scenario, model or "analytic"), MAP_UNITS
    elif level == "dem":
        evaluate, units = dem_answers(scenario), LEVEL2_UNITS
    else:
        evaluate, units = level3_answers(scenario, model), LEVEL3_UNITS

    def checked(values):
        try:
            return evaluate(values)
        except InputError as exc:
            shown = ", ".join(f"{k} = {v:.6g}" for k, v in values.items())
            hint = " (narrow the standard deviations)" if exc.field in values else ""
            raise InputError(exc.field, f"at the uncertainty sample {shown}: "
                             f"{exc.message}{hint}") from None

    result = propagate(checked, inputs, n, seed, units=units, progress=progress, batch=batch)
    if "envelope" in result.bands:  # its times: release to the end of the run [s]
        import numpy as np

        result.bands["envelope"]["time"] = np.linspace(0.0, scenario.simulation.duration,
                                                       ENVELOPE_POINTS)
    return result


__all__ = ["FIT_VALUE", "MAP_BANDS", "UNCERTAIN_FIELDS", "add_fit_inputs", "check_cost",
           "dem_answers", "dem_batch", "dem_point", "extract_uncertain", "fit_uncertainty", "is_uncertain",
           "level2_answers", "level3_answers", "map_answers", "parse_uncertain",
           "propagate_scenario", "sampled_damper", "with_values"]
