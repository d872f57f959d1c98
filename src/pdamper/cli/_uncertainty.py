"""Options and output of ``--uncertainty N`` (``pdamper analytic``, ``map``, ``simulate``
(the free decay and a load history), ``frf``, ``optimize``, ``report``, ``dem``): the
spread of the answers under the inputs given as ``"value +- sd"``, and for the DEM a fitted
COR curve given as ``FIELD=fit`` (:mod:`pdamper.io.uncertain`, propagated by
:mod:`pdamper.runs.uncertainty`)."""

from __future__ import annotations

import re
from typing import Annotated, Any

import typer


def _whole(text: object, what: str, low: int) -> int:
    """A whole number >= ``low`` from the option's text (``"4.0"`` is refused: a count or a
    seed is written as one); refused as the option's one-line usage error."""
    if isinstance(text, int) and not isinstance(text, bool):
        value = text
    else:
        raw = str(text).strip()
        if not re.fullmatch(r"[+-]?\d+", raw):
            raise typer.BadParameter(f"must be {what}, got {raw!r}")
        value = int(raw)
    if value < low:
        raise typer.BadParameter(f"must be {what}, got {value}")
    return value


def points(text: object) -> int:
    """``--uncertainty N`` as a whole number (a power of two is judged by
    :func:`pdamper.design.uncertainty.check_points`)."""
    return _whole(text, "a whole number (a power of two of base points, e.g. 32)", 1)


def seed(text: object) -> int:
    """``--uncertainty-seed`` as a whole number >= 0."""
    return _whole(text, "a whole number >= 0 (the seed of the Sobol' sequence)", 0)


UncertaintyOpt = Annotated[int | None, typer.Option(
    "--uncertainty", parser=points, help="Propagate the inputs given as 'value +- sd' (scenario or "
    "--uncertain) with N quasi-Monte Carlo base points (a power of two; N (inputs + 2) "
    "runs): mean, std, percentiles and Sobol' indices of the answers.")]
UncertainOpt = Annotated[list[str] | None, typer.Option(
    "--uncertain", help="An uncertain input FIELD=VALUE+-SD (sd: a standard deviation; "
    "normal, truncated to the field's range), e.g. 'particles.friction=0.1+-0.03' or "
    "'container.length=120mm+-0.1mm', or a mode's 'mode1.damping_ratio=1%+-0.3%', "
    "'mode2.frequency=31Hz+-0.5Hz'; repeatable. 'pdamper dem' also takes "
    "'restitution.particle_wall=fit': the fitted COR curve's parameter covariance.")]
UncertaintySeedOpt = Annotated[int, typer.Option(
    "--uncertainty-seed", parser=seed, help="Seed of the scrambled Sobol' sequence (recorded).")]


def fits(items: list[str] | None) -> list[str]:
    """The fields of the ``--uncertain FIELD=fit`` items (fitted COR curves), in order."""
    from pdamper.errors import InputError
    from pdamper.io.uncertain import FIT_VALUE

    out: list[str] = []
    for item in items or ():
        key, eq, value = item.partition("=")
        if eq and value.strip().lower() == FIT_VALUE:
            key = key.strip()
            if key in out:
                raise InputError(key, "given twice in --uncertain")
            out.append(key)
    return out


def overrides(items: list[str] | None, allow_fits: bool = False) -> dict:
    """``{"section.key": "value +- sd"}`` of the ``--uncertain`` items (checked);
    ``FIELD=fit`` items are left to :func:`fits` where ``allow_fits`` (the DEM), refused
    elsewhere."""
    from pdamper.errors import InputError
    from pdamper.io.uncertain import FIT_VALUE, is_uncertain, parse_uncertain

    out = {}
    for item in items or ():
        key, eq, value = item.partition("=")
        key = key.strip()
        if not eq or not key:
            raise InputError("uncertain", f"expected FIELD=VALUE+-SD such as "
                             f"'particles.friction=0.1+-0.03', got {item!r}")
        if value.strip().lower() == FIT_VALUE:
            if allow_fits:
                continue
            raise InputError(key, f"'{FIT_VALUE}' (a COR fit's uncertainty) only moves the "
                             "DEM, which this command does not sample; use pdamper dem "
                             "--uncertainty N")
        if not is_uncertain(value):
            raise InputError(key, f"expected 'value +- sd' (sd: a standard deviation), got "
                             f"{value.strip()!r}")
        parse_uncertain(value, key)  # the field and the syntax, before the scenario
        if key in out:
            raise InputError(key, "given twice in --uncertain")
        out[key] = value
    return out


def merged(options: dict, items: list[str] | None, allow_fits: bool = False) -> dict:
    """The command's scenario ``options`` (``section__key``) with the ``--uncertain``
    items added; a field given both ways is an error."""
    from pdamper.errors import InputError

    out = dict(options)
    for key, value in overrides(items, allow_fits).items():
        name = key.replace(".", "__")
        if out.get(name) is not None:
            raise InputError(key, "given both with --uncertain and with its own option")
        out[name] = value
    return out


def check(sc, level: str, n: int | None, force: bool, **cost: Any) -> None:
    """What ``--uncertainty N`` implies, judged before any run (``cost``: the options of
    :func:`pdamper.runs.uncertainty.check_cost` for ``"frf"`` and ``"load"``)."""
    if n is None:
        return
    from pdamper.design.uncertainty import check_points
    from pdamper.errors import InputError
    from pdamper.runs.uncertainty import check_cost

    check_points(n)
    if not sc.uncertain_inputs():
        raise InputError("uncertainty", "no input carries an uncertainty: give one as "
                         "'value +- sd' in the scenario (e.g. friction = \"0.1 +- 0.03\") or "
                         "with --uncertain FIELD=VALUE+-SD"
                         + (" (or a fitted COR curve: --uncertain restitution.particle_wall="
                            "fit)" if level == "dem" else ""))
    check_cost(sc, level, n, force, **cost)


def propagate(sc, level: str, n: int, seed: int, **options: Any):
    """:func:`pdamper.runs.uncertainty.propagate_scenario` with a progress display of its
    runs on standard error (:class:`pdamper.cli._progress.Bar`; none with ``--quiet`` or
    when standard error is not a terminal, and never on standard output)."""
    from pdamper.cli._progress import Bar
    from pdamper.runs.uncertainty import propagate_scenario

    with Bar("uncertainty runs") as progress:
        return propagate_scenario(sc, level, n, seed, progress=progress, **options)


def lines(result, scale: dict[str, tuple[float, str]]) -> list[str]:
    """Human-readable summary of an :class:`~pdamper.design.uncertainty.UncertaintyResult`."""
    from pdamper.design.uncertainty import FitAxis

    out = [f"uncertainty: {result.runs} runs ({result.points} Sobol' base points, seed "
           f"{result.seed}, {result.seconds:.2f} s); inputs "
           + ", ".join(f"{u.field} (fit's principal axis, z in [{u.low:.2g}, {u.high:.2g}])"
                       if isinstance(u, FitAxis) else f"{u.field} = {u.value:.4g} +- {u.sd:.3g}"
                       for u in result.inputs)]
    for field, why in result.not_used.items():  # a zero index that is the model's blindness
        users = ", ".join(why["used_by"]) or "none"
        out.append(f"  {field}: not used by the {why['fidelity']} fidelity (used by: "
                   f"{users}): {why['reason']}")
    blind = bool(result.not_used) and all(u.field in result.not_used for u in result.inputs)
    for name, a in result.answers.items():
        k, unit = scale.get(name, (1.0, "" if a.unit == "1" else a.unit))
        out.append(f"  {name:28s} mean {a.mean * k:.4g}{' ' + unit if unit else ''}, std {a.std * k:.3g}, "
                   f"5-95 % [{a.percentiles[5.0] * k:.4g}, {a.percentiles[95.0] * k:.4g}]; "
                   + (f"driver {a.driver}" if a.driver is not None else
                      "no spread: its inputs are not used by this fidelity" if blind
                      else "driver none (no spread)")
                   + ("" if a.driver is None else
                      f" (total index {a.total_order[a.driver]:.2f})"))
        for group, g in a.groups.items():
            out.append(f"    {group} (its axes' indices summed): first order "
                       f"{g['first_order_sum']:.2f}, total {g['total_order_sum']:.2f}")
    return out


def map_spread(sc, model: str, n: int, seed: int, ds, out):
    """The map's spread under the uncertain inputs: ``<answer>_mean``, ``_std``, ``_p5``
    ... ``_p95`` variables added to ``ds`` (and the NetCDF file ``out`` written with
    them, its only write: the nominal map alone never reaches it), and the result's JSON
    without the per-cell bands (they are in the file)."""
    from pdamper.runs.uncertainty import MAP_BANDS, propagate_scenario

    spread = propagate_scenario(sc, "map", n, seed, model=model)
    dims = ds["loss_factor"].dims
    new = {}
    for name in MAP_BANDS:
        for stat, values in spread.bands[name].items():
            if stat == "nominal":
                continue
            new[f"{name}_{stat}"] = (dims, values, {
                "long_name": f"{stat} of {name} under the uncertain inputs",
                "units": "1", "uncertainty_seed": seed, "uncertainty_points": n})
    ds = ds.assign(new)
    if out is not None:
        from pdamper.files import atomic_write_netcdf

        atomic_write_netcdf(out, ds)
    d = spread.as_dict()
    d["bands"] = {k: sorted(v) for k, v in d["bands"].items()}  # names only: in the file
    d["variables"] = sorted(new)
    return spread, d
