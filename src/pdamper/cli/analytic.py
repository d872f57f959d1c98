"""``pdamper analytic``: the analytical bed model at one (f, X) point."""

from __future__ import annotations

from typing import Annotated

import typer

from pdamper.cli import _uncertainty
from pdamper.cli._common import ForceOpt, JsonOpt, ScenarioOpt, emit, key_help, load, metadata

#: Scenario sections this command reads nothing of, with the reason (JSON ``unused_inputs``).
_UNUSED = {
    "load": "the analytical model answers one harmonic stroke (f, X) of the container; a load "
            "history drives a structure (pdamper simulate)",
    "structure": "the analytical model answers the damper alone at the stroke X; the "
                 "structure enters pdamper simulate, frf and optimize",
}


def analytic(
    frequency: Annotated[str | None, typer.Option(help=key_help(
        "excitation.frequency", "Excitation frequency, e.g. '10Hz'."))] = None,
    amplitude: Annotated[str | None, typer.Option(help=key_help("excitation.amplitude",
                                                                "Container stroke X, e.g. '32mm'."))] = None,
    particles: Annotated[int | None, typer.Option(help=key_help("particles.count",
                                                                "Number of spheres."))] = None,
    gravity: Annotated[str | None, typer.Option(
        "--gravity", help=key_help("excitation.gravity",
                                   "g, e.g. '9.81 m/s^2' (default); '0 m/s^2' for a structure in "
                          "orbit."))] = None,
    uncertainty: _uncertainty.UncertaintyOpt = None,
    uncertain: _uncertainty.UncertainOpt = None,
    uncertainty_seed: _uncertainty.UncertaintySeedOpt = 0,
    force: ForceOpt = False,
    scenario: ScenarioOpt = None,
    as_json: JsonOpt = False,
) -> None:
    """Motion mode, loss factor and effective mass of the bed (paper Eqs. 5-22)."""
    import math

    from pdamper.analysis.analytical import ETA_MAX
    from pdamper.analysis.modes import MotionMode
    from pdamper.units import format_quantity

    sc = load(scenario, runs=("excitation",), model="analytic", **_uncertainty.merged(dict(
        excitation__frequency=frequency, excitation__amplitude=amplitude,
        particles__count=particles, excitation__gravity=gravity), uncertain))
    _uncertainty.check(sc, "level2", uncertainty, force)
    damper = sc.damper()
    f, x = sc.excitation.frequency, sc.excitation.amplitude
    r = sc.model("analytic", damper).response(f, x)
    bed = r.details
    mode = MotionMode(int(r.mode))
    payload = {
        "mode": mode.label,
        "loss_factor": float(r.loss_factor),
        "dissipated_energy_per_cycle": float(r.dissipated_energy_per_cycle),
        "effective_mass_ratio": float(r.effective_mass_ratio),
        "clearance": damper.clearance,
        "optimal_stroke": damper.optimal_stroke,
        "subharmonic_order": int(bed.subharmonic_order),
        "bed_mass": damper.bed_mass,
        # without gravity the ratio is unbounded: null in JSON, with the reason
        "acceleration_ratio": (x * (2 * math.pi * f) ** 2 / bed.gravity if bed.gravity > 0
                               else None),
        **({} if bed.gravity > 0 else {"not_applicable": {
            "acceleration_ratio": "gravity is 0: the acceleration ratio X W^2 / g is "
                                  "unbounded (the bed is never held by its weight)"}}),
        "gravity": bed.gravity,
        "eta_max": ETA_MAX,
        "assumptions_hold": bool(r.diagnostics["assumptions_hold"]),  # docs/analytical.md
        "assumptions": str(r.diagnostics["assumptions"]),
        "units": {"gravity": "m/s^2", "dissipated_energy_per_cycle": "J", "clearance": "m",
                  "optimal_stroke": "m", "bed_mass": "kg", "loss_factor": "1", "effective_mass_ratio": "1"},
        **metadata(sc),
    }
    human = (
        f"f = {format_quantity(f, 'Hz')}, X = {format_quantity(x, 'mm')}, "
        f"{damper.count} particles ({format_quantity(damper.bed_mass, 'g')})\n"
        f"  motion mode                  {mode.title}\n"
        f"  effective loss factor        {float(r.loss_factor):.4g}  (max 4/pi = {ETA_MAX:.3f})\n"
        f"  dissipated energy per cycle  {format_quantity(float(r.dissipated_energy_per_cycle), 'mJ')}\n"
        f"  effective mass ratio         {float(r.effective_mass_ratio):.3g}\n"
        f"  clearance h                  {format_quantity(damper.clearance, 'mm')}\n"
        f"  optimal stroke X_opt = h/pi  {format_quantity(damper.optimal_stroke, 'mm')}"
    )
    if not payload["assumptions_hold"]:
        human += f"\n  outside the model's assumptions: {payload['assumptions']}"
    unused = {k: why for k, why in _UNUSED.items() if k in sc.model_fields_set}
    if unused:
        payload["unused_inputs"] = unused
        human += "".join(f"\nunused: [{k}]: {why}" for k, why in unused.items())
    if uncertainty is not None:
        from pdamper.runs.uncertainty import propagate_scenario

        spread = propagate_scenario(sc, "level2", uncertainty, uncertainty_seed)
        payload["uncertainty"] = spread.as_dict()
        human += "\n" + "\n".join(_uncertainty.lines(spread, {
            "effective_mass": (1e3, "g"), "dissipated_energy_per_cycle": (1e3, "mJ")}))
    emit(payload, as_json, human)
