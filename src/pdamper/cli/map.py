"""``pdamper map``: an effective field over a (frequency x amplitude) grid, to NetCDF."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from pdamper.cli._common import (
    ForceOpt,
    JsonOpt,
    ScenarioOpt,
    check_output,
    emit,
    load,
    metadata,
    write_atomic,
)


def map_(
    model: Annotated[str, typer.Option(help="Damper model (fidelity): analytic or dem.")] = "analytic",
    frequency: Annotated[str | None, typer.Option(
        help="Grid 'start:stop:count', e.g. '2Hz:20Hz:14'.")] = None,
    amplitude: Annotated[str | None, typer.Option(
        help="Grid 'start:stop:count', e.g. '1mm:200mm:24'.")] = None,
    particles: Annotated[int | None, typer.Option(help="Number of spheres.")] = None,
    out: Annotated[str | None, typer.Option(help="NetCDF file to write.")] = None,
    force: ForceOpt = False,
    scenario: ScenarioOpt = None,
    as_json: JsonOpt = False,
) -> None:
    """Loss factor, effective mass and motion mode over a grid (paper Fig. 5)."""
    import json
    import time

    import numpy as np

    from pdamper.analysis.fields import effective_field

    sc = load(scenario, runs=("map",), model=model, force=force, map__frequency=frequency,
              map__amplitude=amplitude, particles__count=particles)
    target = check_output(out)
    damper_model = sc.model(model)
    f, x = sc.map_grid()
    t0 = time.perf_counter()
    meta = metadata(sc, model=model)
    ds = effective_field(damper_model, f, x,
                         attrs={"pdamper_version": meta["version"],
                                "inputs": json.dumps(meta["inputs"])})
    seconds = time.perf_counter() - t0
    if target is not None:
        write_atomic(target, lambda p: ds.to_netcdf(p, engine="h5netcdf"))
    eta = ds["loss_factor"].values
    i, j = np.unravel_index(np.argmax(eta), eta.shape)
    payload = {
        "out": str(Path(out)) if out else None, "shape": [len(f), len(x)], "seconds": seconds,
        "max_loss_factor": float(eta[i, j]),
        "max_at": {"frequency": float(f[i]), "amplitude": float(x[j])}, **meta,
    }
    human = (f"{model} field {len(f)} x {len(x)} in {seconds * 1e3:.0f} ms; max loss factor "
             f"{eta[i, j]:.3f} at f = {f[i]:.3g} Hz, X = {x[j] * 1e3:.3g} mm"
             + (f"; written to {out}" if out else ""))
    emit(payload, as_json, human)
