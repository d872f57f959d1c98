"""``pdamper map``: an effective field over a (frequency x amplitude) grid, to NetCDF."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from pdamper.cli import app
from pdamper.cli._common import emit, load, metadata, write_atomic
from pdamper.cli.analytic import JsonOpt, ScenarioOpt


@app.command("map")
def map_(
    model: Annotated[str, typer.Option(help="Damper model: analytic.")] = "analytic",
    frequency: Annotated[str | None, typer.Option(
        help="Grid 'start:stop:count', e.g. '2Hz:20Hz:14'.")] = None,
    amplitude: Annotated[str | None, typer.Option(
        help="Grid 'start:stop:count', e.g. '1mm:200mm:24'.")] = None,
    particles: Annotated[int | None, typer.Option(help="Number of spheres.")] = None,
    out: Annotated[Path | None, typer.Option(help="NetCDF file to write.")] = None,
    scenario: ScenarioOpt = None,
    as_json: JsonOpt = False,
) -> None:
    """Loss factor, effective mass and motion mode over a grid (paper Fig. 5)."""
    import time

    import numpy as np

    from pdamper.analysis.fields import effective_field
    from pdamper.coupling.registry import get_damper_model
    from pdamper.units import parse_range

    sc = load(scenario, map__frequency=frequency, map__amplitude=amplitude,
              particles__count=particles)
    cls = get_damper_model(model, "model")
    f0, f1, nf = parse_range(sc.map.frequency, "Hz", "frequency")
    x0, x1, nx = parse_range(sc.map.amplitude, "m", "amplitude")
    for name, lo in (("frequency", f0), ("amplitude", x0)):
        if lo <= 0:
            from pdamper.errors import InputError

            raise InputError(name, f"grid values must be > 0, got {lo:g}")
    f = np.linspace(f0, f1, nf)
    x = np.linspace(x0, x1, nx)
    t0 = time.perf_counter()
    meta = metadata(sc, model=model)
    import json

    ds = effective_field(cls(sc.damper()), f, x,
                         attrs={"pdamper_version": meta["version"],
                                "inputs": json.dumps(meta["inputs"])})
    seconds = time.perf_counter() - t0
    if out is not None:
        write_atomic(out, lambda p: ds.to_netcdf(p, engine="h5netcdf"))
    eta = ds["loss_factor"].values
    i, j = np.unravel_index(np.argmax(eta), eta.shape)
    payload = {
        "out": str(out) if out else None, "shape": [nf, nx], "seconds": seconds,
        "max_loss_factor": float(eta[i, j]),
        "max_at": {"frequency": float(f[i]), "amplitude": float(x[j])}, **meta,
    }
    human = (f"{model} field {nf} x {nx} in {seconds * 1e3:.0f} ms; max loss factor "
             f"{eta[i, j]:.3f} at f = {f[i]:.3g} Hz, X = {x[j] * 1e3:.3g} mm"
             + (f"; written to {out}" if out else ""))
    emit(payload, as_json, human)
