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

A structure's modal parameters are uncertain inputs too: ``mode1.damping_ratio =
"1 % +- 0.3 %"``, ``mode2.frequency = "31 Hz +- 0.5 Hz"`` (:data:`MODAL_PARAMETERS`), on
the command line (``--uncertain mode1.damping_ratio=1%+-0.3%``), in a scenario's
``[uncertain]`` table (``"mode1.damping_ratio" = "1 % +- 0.3 %"``) or its ``[mode1]``
table. They apply to whatever structure the scenario describes (a modes file, the beam, the
1-DOF of Eq. 23 as mode 1: its stiffness follows the frequency, its damping the ratio); the
nominal value replaces the structure's own (:func:`with_modes`). A modes file may carry
them itself: a frequency or damping-ratio cell written ``0.01 +- 0.003`` (in its column's
unit; :func:`cell_uncertainty`) is that mode's uncertain input, which a scenario or
``--uncertain`` value of the same field replaces (:func:`pdamper.io.modes.file_inputs`).
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

#: Modal parameters that may carry an uncertainty, ``mode<k>.<name>`` (k from 1, in the
#: order of frequency): SI unit and valid range.
MODAL_PARAMETERS: dict[str, tuple[str, float, float]] = {
    "damping_ratio": ("1", 0.0, 1.0),
    "frequency": ("Hz", 0.0, math.inf),
}
_MODAL = re.compile(r"mode([1-9]\d*)\.(\w+)")
#: The scenario table of uncertain inputs named by their field (``"mode1.frequency" =
#: "12 Hz +- 0.2 Hz"``), beside the values given in their own sections.
UNCERTAIN_TABLE = "uncertain"


def modal_field(field: str) -> tuple[int, str] | None:
    """``(mode index from 0, parameter)`` of a modal field ``mode<k>.<parameter>`` (None:
    not one; an unknown parameter is an error)."""
    m = _MODAL.fullmatch(field)
    if m is None:
        return None
    if m.group(2) not in MODAL_PARAMETERS:
        raise InputError(field, f"a mode's uncertain parameters are "
                         f"{', '.join(MODAL_PARAMETERS)}, got {m.group(2)!r}")
    return int(m.group(1)) - 1, m.group(2)


def _field_spec(field: str) -> tuple[str, float, float]:
    """SI unit and valid range of an uncertain field (damper, excitation, structure or a
    modal parameter)."""
    modal = modal_field(field)
    if modal is not None:
        return MODAL_PARAMETERS[modal[1]]
    if field not in UNCERTAIN_FIELDS:
        raise InputError(field, f"cannot carry an uncertainty ('value +- sd'); these can: "
                         f"{', '.join(UNCERTAIN_FIELDS)}, and a mode's "
                         f"{' or '.join(MODAL_PARAMETERS)} as mode<k>.<parameter>, e.g. "
                         "mode1.damping_ratio")
    return UNCERTAIN_FIELDS[field]


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

    unit, low, high = _field_spec(field)
    parts = _SPLIT.split(text.strip())
    if len(parts) != 2 or not all(parts):
        raise InputError(field, f"expected 'value +- sd' (sd: a standard deviation, e.g. "
                         f"'0.1 +- 0.03' or '120 mm +- 0.1 mm'), got {text!r}")
    si = "" if unit == "1" else unit  # a ratio: '1 %' or 0.01
    value = parse_quantity(parts[0], si, field)
    sd = parse_quantity(parts[1], si, field)
    if not sd > 0:
        raise InputError(field, f"the standard deviation must be > 0 (leave out '+- sd' for "
                         f"an exact value), got {parts[1]!r}")
    if field in QUANTITIES:  # a quantity of the damper: its declaration's check and message
        check_setting(field, value, quantity(field))
    elif field in UNCERTAIN_FIELDS and not low <= value <= high:
        raise InputError(field, f"the nominal value must be in the field's range "
                         f"[{low:g}, {high:g}], got {parts[0]!r}")
    elif field not in UNCERTAIN_FIELDS and not low < value < high:  # a mode's
        raise InputError(field, f"the nominal value must be in ({low:g}, {high:g}), got "
                         f"{parts[0]!r}")
    return UncertainInput(field, value, sd, low, high, unit)


def extract_uncertain(data: dict) -> dict:
    """Replace every ``"value +- sd"`` of the scenario ``data`` (parsed TOML, changed in
    place) by its nominal value; returns ``{field: UncertainInput}``. The modal
    parameters (``[mode1]`` tables) and the ``[uncertain]`` table are taken out of
    ``data``: they are no section of the scenario."""
    out = {}
    listed = data.pop(UNCERTAIN_TABLE, None)
    if listed is not None:
        if not isinstance(listed, dict):
            raise InputError(UNCERTAIN_TABLE, "must be a table of \"field\" = \"value +- "
                             "sd\", e.g. \"mode1.damping_ratio\" = \"1 % +- 0.3 %\"")
        for field, value in listed.items():
            if not is_uncertain(value):
                raise InputError(f"{UNCERTAIN_TABLE}.{field}", f"expected 'value +- sd', "
                                 f"got {value!r}")
            if modal_field(field) is None:  # a plain field: its nominal in its section
                section, _, key = field.partition(".")
                node = data.setdefault(section, {})
                if not isinstance(node, dict) or key in node:
                    raise InputError(field, "given both in [uncertain] and in its section")
                node[key] = value
                continue
            out[field] = parse_uncertain(value, field)
    for section in [k for k in data if _MODAL.fullmatch(f"{k}.x")]:
        node = data.pop(section)
        if not isinstance(node, dict):
            raise InputError(section, "must be a table of the mode's uncertain parameters")
        for key, value in node.items():
            field = f"{section}.{key}"
            if not is_uncertain(value):
                raise InputError(field, "a mode's parameter here is an uncertain input "
                                 "('value +- sd'); an exact value belongs in the modes "
                                 "file or the beam")
            if field in out:
                raise InputError(field, "given both in [uncertain] and in its section")
            out[field] = parse_uncertain(value, field)
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


def cell_uncertainty(text: str, field: str, factor: float):
    """The :class:`~pdamper.design.uncertainty.UncertainInput` of a modes file's cell
    ``"0.01 +- 0.003"`` for ``field`` (``mode<k>.<parameter>``): nominal value and
    standard deviation as plain numbers in the column's unit, ``factor`` its factor to SI
    (a ``[%]`` column: 0.01), then judged as :func:`parse_uncertain` judges the field."""
    parts = _SPLIT.split(text.strip())
    try:
        value, sd = (float(x) * factor for x in parts) if len(parts) == 2 else (None, None)
    except ValueError:
        value = sd = None
    if value is None or sd is None or not (math.isfinite(value) and math.isfinite(sd)):
        raise InputError(field, f"expected 'value +- sd' of two numbers in the column's "
                         f"unit, e.g. '0.01 +- 0.003', got {text.strip()!r}")
    unit = _field_spec(field)[0]
    si = "" if unit == "1" else f" {unit}"
    return parse_uncertain(f"{value!r}{si} +- {sd!r}{si}", field)


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
    modal = {}
    for field, v in values.items():
        if "[" in field:
            continue
        if modal_field(field) is not None:
            modal[field] = v
            continue
        section, _, key = field.partition(".")
        sections.setdefault(section, {})[key] = v
    out = scenario.model_copy(update={
        s: getattr(scenario, s).model_copy(update=u) for s, u in sections.items()})
    if modal:  # the sampled modal parameters, on top of the nominal ones
        out._modal = {**scenario._modal, **modal}
    return out


def modal_values(scenario) -> dict[str, float]:
    """The modal parameters of ``scenario``: the nominal values of its uncertain modal
    inputs, replaced by a sample's (:func:`with_values`)."""
    nominal = {u.field: u.value for u in scenario.uncertain_inputs()
               if modal_field(u.field) is not None}
    return {**nominal, **scenario._modal}


def with_modes(structure, values: dict[str, float]):
    """``structure`` with the modal parameters ``values`` (``{"mode1.damping_ratio":
    0.012, ...}``) set: a :class:`~pdamper.structure.modal.ModalStructure`'s frequencies
    and damping ratios; the 1-DOF of Eq. (23) is mode 1 (its mass kept: the stiffness
    follows the frequency, then the damping the ratio, which the frequency alone leaves
    unchanged)."""
    if not values:
        return structure
    import dataclasses

    import numpy as np

    from pdamper.structure import SingleDOFStructure

    parsed = {f: (modal_field(f), v) for f, v in values.items()}
    n = getattr(structure, "modes", 1)
    for f, (mode, _v) in parsed.items():
        assert mode is not None  # every key of values is a modal field
        if mode[0] >= n:
            raise InputError(f, f"the structure has {n} mode{'s' if n > 1 else ''}: "
                             f"mode1{'' if n == 1 else f' to mode{n}'}")
    if isinstance(structure, SingleDOFStructure):
        m, zeta, k = structure.mass, structure.damping_ratio, structure.stiffness
        for mode, v in parsed.values():
            if mode is not None and mode[1] == "frequency":
                k = m * (2.0 * math.pi * v) ** 2
        for mode, v in parsed.values():
            if mode is not None and mode[1] == "damping_ratio":
                zeta = v
        return dataclasses.replace(structure, stiffness=k,
                                   damping=2.0 * zeta * math.sqrt(k * m))
    freqs = np.array(structure.frequencies, float)
    ratios = np.array(structure.damping_ratios, float)
    for mode, v in parsed.values():
        assert mode is not None
        (freqs if mode[1] == "frequency" else ratios)[mode[0]] = v
    if np.any(np.diff(freqs) < 0):
        raise InputError(next(x for x in values if x.endswith("frequency")),
                         f"the modes' frequencies must stay in ascending order, got "
                         f"{', '.join(f'{v:.4g}' for v in freqs)} Hz (narrow the standard "
                         "deviation)")
    return dataclasses.replace(structure, frequencies=freqs, damping_ratios=ratios)


__all__ = ["FIT_VALUE", "MODAL_PARAMETERS", "UNCERTAIN_FIELDS", "UNCERTAIN_TABLE",
           "add_fit_inputs", "extract_uncertain", "fit_uncertainty", "is_uncertain",
           "modal_field", "modal_values", "parse_uncertain", "sampled_damper", "with_modes",
           "with_values"]
