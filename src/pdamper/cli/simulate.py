"""``pdamper simulate``: free vibration of the structure carrying the damper."""

from __future__ import annotations

from typing import Annotated

import typer

from pdamper.cli._common import (
    ForceOpt,
    JsonOpt,
    ModelOpt,
    ScenarioOpt,
    check_output,
    emit,
    load,
    metadata,
    write_atomic,
)


def simulate(
    model: ModelOpt = None,
    particles: Annotated[int | None, typer.Option(help="Number of spheres.")] = None,
    duration: Annotated[str | None, typer.Option(help="Simulated time, e.g. '2s'.")] = None,
    initial_displacement: Annotated[str | None, typer.Option(
        "--initial-displacement", help="Release deflection x0, e.g. '-58mm'.")] = None,
    out: Annotated[str | None, typer.Option(help="NetCDF file for the trajectory.")] = None,
    force: ForceOpt = False,
    scenario: ScenarioOpt = None,
    as_json: JsonOpt = False,
) -> None:
    """Release the structure from x0 and track the decay (paper Sect. 4.2.1, Figs. 7-8)."""
    from pdamper.coupling import Simulation

    sc = load(scenario, runs=("simulation",), force=force, simulation__model=model,
              particles__count=particles, simulation__duration=duration,
              structure__initial_displacement=initial_displacement)
    target = check_output(out)
    damper_model = sc.model()
    structure = sc.structure_model()
    res = Simulation(structure, damper_model, sc.structure.initial_displacement).run(
        sc.simulation.duration, sc.simulation.sample_rate)
    amp, zeta = res.damping_ratio
    meta = metadata(sc)
    if target is not None:
        ds = res.to_dataset()
        ds.attrs.update(pdamper_version=meta["version"])
        write_atomic(target, lambda p: ds.to_netcdf(p, engine="h5netcdf"))
    payload = {
        "peaks": [{"time": float(t), "amplitude": float(a)}
                  for t, a in zip(res.peak_times, res.peak_amplitudes, strict=True)],
        "damping_ratio": [{"amplitude": float(a), "zeta": float(z)}
                          for a, z in zip(amp, zeta, strict=True)],
        "final_amplitude": res.final_amplitude,
        "effective_frequency": [float(v) for v in res.effective_frequency],
        "cycles": [{"time": c.time, "amplitude": c.amplitude, "frequency": c.frequency,
                    "mode": c.mode.label, "effective_mass": c.effective_mass,
                    "damping": c.damping, "loss_factor": c.loss_factor} for c in res.cycles],
        "units": {"time": "s", "amplitude": "m", "frequency": "Hz", "effective_mass": "kg",
                  "damping": "kg/s"},
        **meta,
    }
    lines = [f"{damper_model!r} on M={structure.mass:.4g} kg, K={structure.stiffness:g} N/m; "
             f"x0 = {sc.structure.initial_displacement * 1e3:g} mm",
             "   t [s]   X [mm]   zeta     mode"]
    modes = [c.mode.title for c in res.cycles] or ["(not classified)"] * len(res.peak_times)
    for t, a, z, m in zip(res.peak_times, res.peak_amplitudes, list(zeta) + [float("nan")],
                          modes, strict=False):
        lines.append(f"  {t:6.3f}  {a * 1e3:7.2f}  {z:7.4f}  {m}")
    lines.append(f"final amplitude {res.final_amplitude * 1e3:.2f} mm")
    emit(payload, as_json, "\n".join(lines))
