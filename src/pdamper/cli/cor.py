"""``pdamper cor``: a COR curve and the COR of simulated single impacts (Level I).

Example::

    pdamper cor --pair S235:PVC --velocity 0.01m/s:2m/s:40 --model paper --plot cor.png

``--pair SPHERE:PARTNER`` names the sphere material and its partner: the same material twice
(``S235:S235``) is a sphere-sphere impact of two equal spheres, otherwise a sphere hits a
wall of the partner material. The target curve is ``--model`` (``0.6``, ``paper``,
``thornton``, ``cor.csv``, each optionally ``*scale``) or else the scenario's COR curve of that
pair type (``[restitution]``, or the ``[dem]`` constants). Each velocity is one DEM run of
the real engine without gravity. ``--json``: ``velocity``, ``cor_target``,
``cor_simulated``, ``max_deviation`` and what was simulated.
"""

from __future__ import annotations

from typing import Annotated

import typer

from pdamper.cli._common import (
    ForceOpt,
    JsonOpt,
    ScenarioOpt,
    check_plot,
    emit,
    key_help,
    load,
    metadata,
    plot_param,
)

#: Default velocity grid of ``--velocity``.
DEFAULT_VELOCITY = "0.01m/s:2m/s:40"
#: Its count: the usual number of single impacts.
DEFAULT_IMPACTS = 40


def cor(
    pair: Annotated[str | None, typer.Option(
        "--pair", help="SPHERE:PARTNER materials, e.g. S235:PVC (sphere-wall) or S235:S235 "
                       "(sphere-sphere); default: the scenario's sphere and wall.")] = None,
    velocity: Annotated[str, typer.Option(
        "--velocity", help="Impact speeds 'start:stop:count', e.g. '0.01m/s:2m/s:40'.")
    ] = DEFAULT_VELOCITY,
    model: Annotated[str | None, typer.Option(
        "--model", help="Target COR curve: 0.6, paper, thornton or a CSV table, optionally "
                        "*scale (default: the scenario's COR curve of this pair).")] = None,
    damping_model: Annotated[str | None, typer.Option(
        "--damping-model", help=key_help("dem.damping_model",
                                         "Damping law of the impacts (default: the scenario's)"))] = None,
    integrator: Annotated[str | None, typer.Option(
        "--integrator", help=key_help("dem.integrator",
                                      "Integrator of the impacts (default: gear)"))] = None,
    radius: Annotated[str | None, typer.Option(
        "--radius", help=key_help("particles.radius",
                                  "Sphere radius, e.g. '5mm' (default: the scenario's)."))] = None,
    plot: Annotated[str | None, plot_param("the target and simulated COR")] = None,
    force: ForceOpt = False,
    scenario: ScenarioOpt = None,
    as_json: JsonOpt = False,
) -> None:
    """Show a COR curve and the COR that the DEM contact law gives in single impacts
    (paper Sect. 2, Fig. 2-right)."""
    import numpy as np

    from pdamper import resources
    from pdamper.dem.impacts import check_restitution, impacts_cost
    from pdamper.errors import InputError
    from pdamper.io.restitution import build_curve, parse_model_text, validate_spec
    from pdamper.units import parse_range

    sc = load(scenario, particles__radius=radius, dem__damping_model=damping_model,
              dem__integrator=integrator)
    plot_path = check_plot(plot)
    v0, v1, n = parse_range(velocity, "m/s", "velocity")
    if min(v0, v1) <= 0:
        raise InputError("velocity", f"impact speeds must be > 0 m/s, got {min(v0, v1):g} m/s")
    resources.require(impacts_cost(n), force)  # judged from the count, before the list exists
    v = np.linspace(v0, v1, n)

    damper = sc.damper()
    sphere, partner = _pair(damper, pair)
    sphere_sphere = sphere.name == partner.name
    kind = "particle_particle" if sphere_sphere else "particle_wall"
    r = damper.particle_radius
    if model is not None:
        curve = build_curve(validate_spec(parse_model_text(model), "model"), kind, sphere,
                            partner, r)
    else:
        curve = sc.restitution_curves(sphere, partner, r)[0 if sphere_sphere else 1]

    check = check_restitution(v, curve, sphere, partner, r, sphere_sphere,
                              sc.dem.damping_model, sc.dem.integrator)
    payload = {**check.as_dict(), **metadata(sc, model=model)}
    if model is None:  # the echo of --model: the curve is the scenario's
        payload["not_applicable"] = {"model": "--model not given: the scenario's "
                                              "[restitution] curve, named in curve"}
    if plot_path is not None:
        from matplotlib.figure import Figure

        from pdamper.cli._common import write_figure
        from pdamper.plots import plot_cor_check

        fig = Figure(figsize=(7, 4.5), layout="constrained")
        plot_cor_check(check, ax=fig.subplots(), curve=curve)
        payload["plot"] = str(write_figure(fig, plot_path, dpi=120))
    emit(payload, as_json, _table(check, r, sphere_sphere, payload.get("plot")))


def _pair(damper, pair: str | None) -> tuple:
    """The (sphere, partner) materials of ``--pair``; the damper's own materials first."""
    from pdamper.errors import InputError
    from pdamper.materials import get_material

    if pair is None:
        return damper.particle_material, damper.wall_material
    own = {m.name.lower(): m for m in (damper.particle_material, damper.wall_material)}
    names = pair.split(":")
    if len(names) != 2 or not all(x.strip() for x in names):
        raise InputError("pair", f"expected SPHERE:PARTNER such as S235:PVC or S235:S235, "
                         f"got {pair!r}")
    return tuple(own.get(x.strip().lower()) or get_material(x.strip(), "pair") for x in names)


def _table(check, r: float, sphere_sphere: bool, plot: str | None) -> str:
    """The command's text: target and simulated COR per impact speed."""
    kind_text = "sphere-sphere" if sphere_sphere else "sphere-wall"
    lines = [f"{check.pair} ({kind_text}, r = {r * 1e3:g} mm): target {check.curve}",
             f"DEM single impacts: {check.damping_model} COR-damping relation, "
             f"{check.integrator} integrator",
             "  v [m/s]   target   simulated   deviation"]
    lines += [f"  {a:7.4f}  {b:7.4f}  {c:9.4f}  {c - b:+10.2e}"
              for a, b, c in zip(check.velocity, check.cor_target, check.cor_simulated,
                                 strict=True)]
    lines.append(f"max |deviation| {check.max_deviation:.2e}"
                 + (f"; figure written to {plot}" if plot is not None else ""))
    return "\n".join(lines)
