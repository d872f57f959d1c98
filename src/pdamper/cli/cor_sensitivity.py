"""``pdamper cor-sensitivity``: rerun DEM Level II points and the Level III model-1 run under
several COR models (do the COR values matter? paper Sect. 2).

Example::

    pdamper cor-sensitivity --variants "0.6/0.85,paper,paper*0.5,paper*1.5" \\
        --points "10Hz/15mm,10Hz/32mm" --plot cor-sensitivity.png

A variant is ``PP/PW`` (sphere-sphere / sphere-wall) or one model for both: ``0.6``,
``paper``, ``thornton``, a CSV table, each optionally ``*scale`` (``e -> 1 - s (1 - e)``).
The damper, structure, release and DEM options (``[dem]``: integrator, ...) come from the
scenario; Level II runs 48 cycles and averages the last 32 unless the scenario or
``--cycles`` / ``--skip-cycles`` say otherwise (the DEM's default 8 cycles end inside the
initial transient at small strokes). ``--json``: ``variants``, ``level2`` (loss factor, effective mass ratio,
the loss factor over both halves of the averaged window and ``stationary`` per variant and
point), ``level3`` (amplitude at 0.75 s, damping ratios near 53 and 41 mm).
"""

from __future__ import annotations

from typing import Annotated

import typer

from pdamper.cli._common import JsonOpt, ScenarioOpt, check_plot, emit, key_help, load, metadata, plot_param


def _points(text: str):
    from pdamper.errors import InputError
    from pdamper.units import parse_quantity

    out = []
    for item in text.split(","):
        parts = item.split("/")
        if len(parts) != 2:
            raise InputError("points", f"expected FREQUENCY/AMPLITUDE pairs such as "
                             f"'10Hz/15mm,10Hz/32mm', got {item!r}")
        f = parse_quantity(parts[0].strip(), "Hz", "points")
        x = parse_quantity(parts[1].strip(), "m", "points")
        if f <= 0 or x <= 0:
            raise InputError("points", f"frequency and amplitude must be > 0, got {item!r}")
        out.append((f, x))
    return out


def cor_sensitivity(
    variants: Annotated[str | None, typer.Option(
        "--variants", help="Comma-separated COR variants, e.g. '0.6/0.85,paper,paper*1.5' "
                           "(default: constants, the paper's curves x 0.5, 1, 1.5, nearly "
                           "elastic constants, Thornton).")] = None,
    points: Annotated[str | None, typer.Option(
        "--points", help="Level II points 'f/X,...', e.g. '10Hz/15mm,10Hz/32mm'.")] = None,
    level3: Annotated[bool, typer.Option(
        "--level3/--no-level3", help="Also run DEM model 1 on the structure.")] = True,
    duration: Annotated[str | None, typer.Option(
        "--duration", help=key_help("simulation.duration",
                                    "Level III simulated time, e.g. '2s' (default: the scenario's)."))
    ] = None,
    cycles: Annotated[int | None, typer.Option(
        "--cycles", help=key_help("dem.cycles",
                                  "Level II cycles per point (default: the scenario's [dem] value if "
                         "it sets one, else 48)."))] = None,
    skip_cycles: Annotated[int | None, typer.Option(
        "--skip-cycles", help=key_help("dem.skip_cycles",
                                       "Cycles left out of the complex power (default: the "
                              "scenario's, else 16)."))] = None,
    plot: Annotated[str | None, plot_param("the loss factors and amplitudes per COR variant")] = None,
    scenario: ScenarioOpt = None,
    as_json: JsonOpt = False,
) -> None:
    """Rerun DEM Level II points and Level III DEM model 1 under several COR models."""
    from pdamper.reports.cor_sensitivity import sensitivity_figure
    from pdamper.runs.cor_sensitivity import DEFAULT_POINTS, DEFAULT_VARIANTS, run_cor_sensitivity

    sc = load(scenario, simulation__duration=duration, dem__cycles=cycles,
              dem__skip_cycles=skip_cycles)
    plot_path = check_plot(plot)
    names = DEFAULT_VARIANTS if variants is None else [v for v in variants.split(",") if v.strip()]
    pts = DEFAULT_POINTS if points is None else _points(points)
    study = run_cor_sensitivity(sc, names, pts, level3=level3)
    payload = {**study.as_dict(), **metadata(sc)}
    if plot_path is not None:
        from pdamper.cli._common import write_figure

        fig = sensitivity_figure(study)
        payload["plot"] = str(write_figure(fig, plot_path, dpi=110))
    emit(payload, as_json, study.markdown() + f"\n{study.wall_seconds:.1f} s"
         + (f"; figure written to {payload['plot']}" if plot_path is not None else ""))
