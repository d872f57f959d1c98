"""``pdamper dem``: a DEM run of the benchmark damper under harmonic excitation (Level II).

Example::

    pdamper dem --frequency 10Hz --amplitude 32mm --particles 32 --cycles 8 --out run.nc

prints JSON with ``steps``, ``wall_seconds``, ``loss_factor``, ``effective_mass_ratio``
(complex power method, Eqs. 1-4, over the cycles after ``--skip-cycles``) and
``energy_balance_error``, plus the inputs, the pdamper version and the seed.
"""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from pdamper.cli import app
from pdamper.cli._common import emit, load
from pdamper.cli.analytic import ScenarioOpt
from pdamper.errors import InputError, check_range
from pdamper.units import parse_quantity


@app.command("dem")
def dem(
    frequency: Annotated[str | None, typer.Option("--frequency",
                         help="Excitation frequency f, e.g. '10Hz'.")] = None,
    amplitude: Annotated[str | None, typer.Option("--amplitude",
                         help="Excitation amplitude X, e.g. '32mm'.")] = None,
    particles: Annotated[int | None, typer.Option("--particles",
                         help="Number of spheres (benchmark box: <= 192).")] = None,
    cycles: Annotated[int, typer.Option("--cycles", help="Number of excitation cycles.")] = 8,
    out: Annotated[Path | None, typer.Option("--out",
                         help="NetCDF file for the time series.")] = None,
    integrator: Annotated[str, typer.Option("--integrator",
                         help="gear (variable step) or verlet.")] = "gear",
    skip_cycles: Annotated[int, typer.Option("--skip-cycles",
                         help="Cycles left out of the complex power (default 2: cycles 3-8).")] = 2,
    friction: Annotated[float | None, typer.Option("--friction",
                         help="Friction coefficient mu, all contacts (default 0.1).")] = None,
    restitution_pp: Annotated[float, typer.Option("--restitution-pp",
                         help="Constant sphere-sphere COR.")] = 0.6,
    restitution_pw: Annotated[float, typer.Option("--restitution-pw",
                         help="Constant sphere-wall COR.")] = 0.85,
    damping_model: Annotated[str, typer.Option("--damping-model",
                         help="exact (default) or gonthier (the paper's).")] = "exact",
    seed: Annotated[int, typer.Option("--seed",
                         help="Seed of the random packing (recorded always).")] = 0,
    packing: Annotated[str, typer.Option("--packing",
                         help="lattice (the paper's 4x4 layers) or random.")] = "lattice",
    sample_rate: Annotated[str, typer.Option("--sample-rate",
                         help="Sampling rate of the time series.")] = "2 kHz",
    safety: Annotated[float, typer.Option("--safety",
                         help="Time step / Hertz contact time (Verlet; Gear: x 6 at onsets).")] = 0.02,
    vtk: Annotated[Path | None, typer.Option("--vtk",
                         help="Directory for ParaView snapshots (.vtp + .pvd).")] = None,
    snapshot_rate: Annotated[str, typer.Option("--snapshot-rate",
                         help="Snapshots per second for --vtk.")] = "200 Hz",
    scenario: ScenarioOpt = None,
    as_json: Annotated[bool, typer.Option("--json",
                         help="Print JSON (the default output is JSON too).")] = False,
) -> None:
    """Run the DEM of a damper (default: the paper's benchmark) under harmonic excitation
    and apply the complex power method."""
    from pdamper import __version__
    from pdamper.contact.restitution import ConstantRestitution
    from pdamper.coupling.dem import DEMDamper
    from pdamper.dem import ContactParameters, HarmonicMotion

    sc = load(scenario, excitation__frequency=frequency, excitation__amplitude=amplitude,
              particles__count=particles, particles__friction=friction)
    damper = sc.damper()
    f, x = sc.excitation.frequency, sc.excitation.amplitude
    rate = check_range("sample-rate", parse_quantity(sample_rate, "Hz", "sample-rate"), low=0.0,
                       low_inclusive=False, unit="Hz")
    check_range("cycles", cycles, low=1)
    if not 0 <= skip_cycles < cycles:
        raise InputError("skip-cycles", f"must be in [0, {cycles - 1}], got {skip_cycles}")
    if integrator not in ("gear", "verlet"):
        raise InputError("integrator", f"must be 'gear' or 'verlet', got {integrator!r}")
    if damper.count < 1:
        raise InputError("particles.count", f"must be in [1, {damper.max_count}] for the DEM, "
                         f"got {damper.count}")
    contact = ContactParameters(
        restitution_pp=ConstantRestitution(check_range("restitution-pp", restitution_pp, low=0.0,
                                                       high=1.0, low_inclusive=False)),
        restitution_pw=ConstantRestitution(check_range("restitution-pw", restitution_pw, low=0.0,
                                                       high=1.0, low_inclusive=False)),
        friction_pp=damper.friction, friction_pw=damper.friction, damping_model=damping_model)
    model = DEMDamper(damper, contact, integrator=integrator, cycles=cycles,
                      skip_cycles=skip_cycles, packing=packing, seed=seed, sample_rate=rate,
                      safety=check_range("safety", safety, low=0.0, high=1.0,
                                         low_inclusive=False))
    sim = model.simulation(HarmonicMotion(x, f))
    snap = None
    if vtk is not None:
        snap = check_range("snapshot-rate", parse_quantity(snapshot_rate, "Hz", "snapshot-rate"),
                           low=0.0, low_inclusive=False, unit="Hz")
    res = sim.run(cycles / f, sample_rate=rate, snapshot_rate=snap)
    cp = res.complex_power(skip_cycles)
    ledger = res.ledger_per_cycle(skip_cycles)
    inputs = {"frequency_hz": f, "amplitude_m": x, "particles": damper.count, "cycles": cycles,
              "integrator": integrator, "skip_cycles": skip_cycles, "friction": damper.friction,
              "restitution_pp": restitution_pp, "restitution_pw": restitution_pw,
              "damping_model": damping_model, "packing": packing, "sample_rate_hz": rate,
              "safety": safety}
    res.attrs.update({f"input_{k}": v for k, v in inputs.items()})
    payload = {
        "steps": res.steps,
        "wall_seconds": res.wall_seconds,
        "loss_factor": cp.loss_factor,
        "effective_mass_ratio": cp.effective_mass_ratio,
        "energy_balance_error": res.energy_balance_error(),
        "dissipated_energy_per_cycle": cp.dissipated_energy_per_cycle,
        "ledger_per_cycle": ledger,
        "settle_steps": res.settle_steps,
        "time_step": res.time_step,
        "contact_time": res.contact_time,
        "max_overlap_ratio": res.max_overlap_ratio,
        "inputs": inputs,
        "seed": seed,
        "pdamper_version": __version__,
        "version": __version__,
        "scenario": sc.model_dump(mode="json"),
    }
    if out is not None:
        payload["out"] = str(res.write_netcdf(out))
    if vtk is not None:
        payload["vtk"] = str(res.write_vtk(vtk))
    emit(payload, as_json=True)
