"""Uncertain inputs of a scenario: ``"value +- sd"`` read, and the scenario at a sample.

A scenario value (or a command-line ``--uncertain FIELD=VALUE+-SD``) written as
``"0.1 +- 0.03"``, ``"120 mm +- 0.1 mm"`` or ``"0.1 ± 0.03"`` is a nominal value and a
*standard deviation*, both with the field's unit; the input is then normal with that mean
and standard deviation, truncated to the field's valid range
(:class:`pdamper.design.uncertainty.UncertainInput`). Every command uses the nominal value;
``--uncertainty N`` (``pdamper analytic``, ``map``, ``simulate``, ``report``)
samples the inputs (:mod:`pdamper.runs.uncertainty`) and reports the spread of the answers
and which input drives it; :func:`with_values` and :func:`sampled_damper` give the scenario
and the damper at one sample.

The fields that may carry an uncertainty are those of :data:`UNCERTAIN_FIELDS`; the COR
fit of a ``[restitution]`` table carries its own (its parameters' covariance,
:mod:`pdamper.contact.fit`), which only the DEM feels: the analytical and field models do
not depend on friction or restitution, and their answers show these inputs' Sobol' index 0.
``pdamper dem --uncertainty N --uncertain restitution.particle_wall=fit`` samples it
(:func:`add_fit_inputs`: one input per principal axis of the covariance,
:class:`pdamper.design.uncertainty.ParameterFit`) through the DEM
(:func:`pdamper.runs.uncertainty.dem_answers`).
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


__all__ = ["FIT_VALUE", "UNCERTAIN_FIELDS", "add_fit_inputs", "extract_uncertain",
           "fit_uncertainty", "is_uncertain", "parse_uncertain", "sampled_damper",
           "with_values"]
