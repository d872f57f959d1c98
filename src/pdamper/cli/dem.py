"""``pdamper dem``: a DEM run of the benchmark damper under harmonic excitation (Level II).

Example::

    pdamper dem --frequency 10Hz --amplitude 32mm --particles 32 --cycles 8 --out run.nc

prints JSON with ``steps``, ``wall_seconds``, ``loss_factor``, ``effective_mass_ratio``
(complex power method, Eqs. 1-4, over the cycles after ``--skip-cycles``) and
``energy_balance_error``, plus the inputs, the pdamper version and the seed.
"""

from __future__ import annotations

from pathlib import Path

import typer

from pdamper.cli import app
from pdamper.cli._common import emit
from pdamper.errors import InputError, check_range
from pdamper.units import parse_quantity


@app.command("dem")
def dem(
    frequency: str = typer.Option("10 Hz", "--frequency", help="Excitation frequency f, e.g. '10Hz'."),
    amplitude: str = typer.Option("32 mm", "--amplitude", help="Excitation amplitude X, e.g. '32mm'."),
    particles: int = typer.Option(32, "--particles", help="Number of spheres (benchmark box: <= 192)."),
    cycles: int = typer.Option(8, "--cycles", help="Number of excitation cycles."),
    out: Path | None = typer.Option(None, "--out", help="NetCDF file for the time series."),
    integrator: str = typer.Option("gear", "--integrator", help="gear (variable step) or verlet."),
    skip_cycles: int = typer.Option(2, "--skip-cycles", help="Cycles left out of the complex power (default 2: cycles 3-8)."),
    friction: float = typer.Option(0.1, "--friction", help="Friction coefficient mu, all contacts."),
    restitution_pp: float = typer.Option(0.6, "--restitution-pp", help="Constant sphere-sphere COR."),
    restitution_pw: float = typer.Option(0.85, "--restitution-pw", help="Constant sphere-wall COR."),
    damping_model: str = typer.Option("exact", "--damping-model", help="exact (default) or gonthier (the paper's)."),
    seed: int = typer.Option(0, "--seed", help="Seed of the random packing (recorded always)."),
    packing: str = typer.Option("lattice", "--packing", help="lattice (the paper's 4x4 layers) or random."),
    sample_rate: str = typer.Option("2 kHz", "--sample-rate", help="Sampling rate of the time series."),
    safety: float = typer.Option(0.04, "--safety", help="Time step / Hertz contact duration."),
    vtk: Path | None = typer.Option(None, "--vtk", help="Directory for ParaView snapshots (.vtp + .pvd)."),
    snapshot_rate: str = typer.Option("200 Hz", "--snapshot-rate", help="Snapshots per second for --vtk."),
    as_json: bool = typer.Option(False, "--json", help="Print JSON (the default output is JSON too)."),
) -> None:
    """Run the DEM of the benchmark damper and apply the complex power method."""
    from pdamper import __version__
    from pdamper.contact.restitution import ConstantRestitution
    from pdamper.dem import (
        Container,
        ContactParameters,
        DEMSimulation,
        HarmonicMotion,
        ParticleSet,
    )
    from pdamper.dem.packing import max_particles

    f = check_range("frequency", parse_quantity(frequency, "Hz", "frequency"), low=0.0,
                    low_inclusive=False, unit="Hz")
    x = check_range("amplitude", parse_quantity(amplitude, "m", "amplitude"), low=0.0, unit="m")
    rate = check_range("sample-rate", parse_quantity(sample_rate, "Hz", "sample-rate"), low=0.0,
                       low_inclusive=False, unit="Hz")
    check_range("cycles", cycles, low=1)
    if not 0 <= skip_cycles < cycles:
        raise InputError("skip-cycles", f"must be in [0, {cycles - 1}], got {skip_cycles}")
    if integrator not in ("gear", "verlet"):
        raise InputError("integrator", f"must be 'gear' or 'verlet', got {integrator!r}")
    if packing not in ("lattice", "random"):
        raise InputError("packing", f"must be 'lattice' or 'random', got {packing!r}")
    container = Container()
    nmax = max_particles(container.box, 0.005)
    if not 1 <= particles <= nmax:
        raise InputError("particles", f"must be in [1, {nmax}] for the benchmark box, got {particles}")
    contact = ContactParameters(
        restitution_pp=ConstantRestitution(check_range("restitution-pp", restitution_pp, low=0.0,
                                                       high=1.0, low_inclusive=False)),
        restitution_pw=ConstantRestitution(check_range("restitution-pw", restitution_pw, low=0.0,
                                                       high=1.0, low_inclusive=False)),
        friction_pp=check_range("friction", friction, low=0.0),
        friction_pw=friction, damping_model=damping_model)
    ps = (ParticleSet.lattice(particles, container.box) if packing == "lattice"
          else ParticleSet.random(particles, container.box, seed=seed))
    sim = DEMSimulation(ps, container, contact, HarmonicMotion(x, f), integrator=integrator,
                        safety=check_range("safety", safety, low=0.0, high=1.0,
                                           low_inclusive=False), seed=seed)
    snap = None
    if vtk is not None:
        snap = check_range("snapshot-rate", parse_quantity(snapshot_rate, "Hz", "snapshot-rate"),
                           low=0.0, low_inclusive=False, unit="Hz")
    res = sim.run(cycles / f, sample_rate=rate, snapshot_rate=snap)
    cp = res.complex_power(skip_cycles)
    ledger = res.ledger_per_cycle(skip_cycles)
    inputs = {"frequency_hz": f, "amplitude_m": x, "particles": particles, "cycles": cycles,
              "integrator": integrator, "skip_cycles": skip_cycles, "friction": friction,
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
    }
    if out is not None:
        payload["out"] = str(res.write_netcdf(out))
    if vtk is not None:
        payload["vtk"] = str(res.write_vtk(vtk))
    emit(payload, as_json=True)
