"""``pdamper optimize``: brute-force particle count (paper Sect. 4.2.2)."""

from __future__ import annotations

from typing import Annotated

import typer

from pdamper.cli._common import ForceOpt, JsonOpt, ModelOpt, ScenarioOpt, emit, load, metadata


def optimize(
    model: ModelOpt = None,
    at: Annotated[str | None, typer.Option(help="Objective time T, e.g. '0.8s'.")] = None,
    step: Annotated[int | None, typer.Option(help="Particle-count increment (default: one layer).")] = None,
    force: ForceOpt = False,
    scenario: ScenarioOpt = None,
    as_json: JsonOpt = False,
) -> None:
    """Particle count with the smallest amplitude at time T; every candidate is listed."""
    from pdamper.design import optimize_particle_count

    sc = load(scenario, runs=("optimization",), force=force, simulation__model=model,
              optimization__at=at, optimization__step=step)
    res = optimize_particle_count(sc.structure_model(), sc.damper(),
                                  sc.structure.initial_displacement, sc.optimization.at,
                                  model=lambda d: sc.model(None, d), step=sc.optimization.step)
    payload = {**res.as_dict(), "units": {"mass": "kg", "objective": "m", "at": "s"},
               **metadata(sc)}
    lines = [f"amplitude at t = {res.at:g} s ({sc.simulation.model} model)",
             "  particles  mass [g]  amplitude [mm]"]
    for c in res.candidates:
        mark = "  <- best" if c is res.best else ""
        lines.append(f"  {c.particles:9d}  {c.mass * 1e3:8.1f}  {c.objective * 1e3:14.2f}{mark}")
    emit(payload, as_json, "\n".join(lines))
