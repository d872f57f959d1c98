"""Effective-field maps of a scenario (``pdamper map``, and the case study's DEM map).

:func:`run_map` evaluates the scenario's damper model on its ``[map]`` grid (or a given
one): vectorised models (the analytical formulas) in one call, the others (the DEM) point
by point on the resumable sweep engine of :mod:`pdamper.sweep`, with every finished point
stored in ``<out>.partial/`` as it completes. The final NetCDF is written atomically and
records the inputs, the pdamper version, the seed and a key of everything the values depend
on (``map_key``), by which :func:`load_cached_map` recognises an up-to-date file.
"""

from __future__ import annotations

import hashlib
import json
import logging
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

logger = logging.getLogger(__name__)

#: Scenario sections a Level II map does not depend on (the grid travels with each point).
_NOT_LEVEL_II = ("title", "map", "excitation", "structure", "simulation", "optimization")


@dataclass
class MapRun:
    """A computed (or cached) map.

    Attributes
    ----------
    dataset
        The field (:mod:`pdamper.analysis.fields`).
    seconds
        Wall time of this call [s].
    computed, reused, failed
        Points computed now, taken from the partial store or the cached file, and failed.
    workers
        Worker processes of the sweep (1: in-process or vectorised).
    path
        The NetCDF written (None without ``out``).
    cached
        The whole map came from an up-to-date file.
    """

    dataset: object
    seconds: float
    computed: int
    reused: int
    failed: int
    workers: int
    path: Path | None = None
    cached: bool = False


def map_context(scenario, model_name: str) -> dict:
    """What every point of a map depends on besides its own (f, X, n): the Level II inputs
    of the scenario, the model, the pdamper version and the digest of its source (the
    version changes only at releases)."""
    from pdamper._version import __version__, source_digest

    inputs = scenario.model_dump(mode="json")
    level2 = {k: v for k, v in inputs.items() if k not in _NOT_LEVEL_II}
    return {"model": model_name, "inputs": level2, "pdamper_version": __version__,
            "pdamper_source": source_digest()}


def map_key(context: dict, frequency, amplitude, particles=None) -> str:
    """Key of a whole map: its context and grid."""
    text = json.dumps({"context": context, "frequency": np.asarray(frequency).tolist(),
                       "amplitude": np.asarray(amplitude).tolist(),
                       "particles": None if particles is None else
                       np.asarray(particles).tolist()}, sort_keys=True)
    return hashlib.sha256(text.encode()).hexdigest()[:16]


def load_cached_map(path: Path, key: str):
    """The dataset in ``path`` if it exists and was computed with ``key``, else None."""
    import xarray as xr

    path = Path(path)
    if not path.is_file():
        return None
    try:
        with xr.open_dataset(path, engine="h5netcdf") as ds:
            if ds.attrs.get("map_key") != key:
                return None
            return ds.load()
    except (OSError, ValueError) as exc:
        logger.warning("ignoring unreadable map %s: %s", path, exc)
        return None


def partial_store(out: Path) -> Path:
    """Directory of the per-point results of the map written to ``out``."""
    out = Path(out)
    return out.with_name(out.name + ".partial")


def map_axes(scenario: Any, frequency: Any = None, amplitude: Any = None,
             particles: Any = None) -> tuple[Any, Any, Any]:
    """The map's frequency, amplitude and particle-count axes: those given, the scenario's
    ``[map]`` grid for those left None."""
    if frequency is None or amplitude is None:
        f_sc, x_sc = scenario.map_grid()
        frequency = f_sc if frequency is None else frequency
        amplitude = x_sc if amplitude is None else amplitude
    if particles is None:
        particles = scenario.map_particles()
    return frequency, amplitude, particles


def run_map(scenario, model_name: str, *, frequency=None, amplitude=None, particles=None,
            out: Path | None = None, cache: bool = False, keep_partial: bool = False,
            progress: Callable | None = None, **sweep_options) -> MapRun:
    """The effective field of ``scenario``'s damper under model ``model_name``.

    Parameters
    ----------
    scenario
        A :class:`~pdamper.io.scenario.Scenario`.
    model_name
        Damper fidelity (``"analytic"``, ``"dem"``).
    frequency, amplitude, particles
        The grid (default: ``[map]`` of the scenario; ``particles`` None and no
        ``[map] particles``: the one count of ``[particles]``).
    out
        NetCDF file to write (atomically); its ``<out>.partial/`` directory holds the
        finished points until the map is complete (then it is removed unless
        ``keep_partial``).
    cache
        Return the map in ``out`` without computing if it was made with the same inputs.
    progress
        ``progress(done, total, point_result)`` of the sweep.
    sweep_options
        ``workers``, ``scheduler``, ``client``, ``serial``, ``retries``, ``retry_failed``
        (:func:`pdamper.sweep.run_sweep`); they force the sweep engine for a vectorised
        model too.
    """
    from pdamper import __version__
    from pdamper.analysis.fields import effective_field, sweep_field
    from pdamper.files import atomic_write_netcdf

    t0 = time.perf_counter()
    model = scenario.map_model(model_name)
    effective = scenario.for_map()
    frequency, amplitude, particles = map_axes(scenario, frequency, amplitude, particles)
    f = np.asarray(frequency, float)
    x = np.asarray(amplitude, float)
    context = map_context(effective, model_name)
    key = map_key(context, f, x, particles)
    attrs = {"pdamper_version": __version__, "pdamper_source": context["pdamper_source"],
             "inputs": json.dumps(scenario.model_dump(
        mode="json")), "seed": int(scenario.dem.seed), "map_key": key,
        "model_fidelity": model_name, "packing": effective.dem.packing}
    if out is not None and cache:
        ds = load_cached_map(out, key)
        if ds is not None:
            n = int(ds["status"].size) if "status" in ds else 0
            failed = int((ds["status"].values != 0).sum()) if "status" in ds else 0
            return MapRun(ds, time.perf_counter() - t0, 0, n, failed, 0, Path(out), True)
    vectorised = getattr(model, "vectorised", False) and not any(
        sweep_options.get(k) for k in ("workers", "scheduler", "client"))
    if vectorised:
        ds = effective_field(model, f, x, attrs=attrs, particles=particles)
        computed, reused, failed, workers = int(ds["status"].size), 0, 0, 1
    else:
        store = partial_store(out) if out is not None else None
        # a deterministic failure (bad input, unstable run) fails again: no retry
        sweep_options.setdefault("retry_if", _retry_if)
        ds, sweep = sweep_field(model, f, x, particles, store=store, context=context,
                                attrs=attrs, progress=progress, **sweep_options)
        computed, reused, failed, workers = (sweep.computed, sweep.reused, sweep.failed,
                                             sweep.workers)
    path = None
    if out is not None:
        path = atomic_write_netcdf(out, ds)
        if not vectorised and not keep_partial:
            from pdamper.sweep import PointStore

            PointStore(partial_store(out)).remove()
    return MapRun(ds, time.perf_counter() - t0, computed, reused, failed, workers, path)


def _retry_if(exc: BaseException) -> bool:
    """Retry what may pass on a second attempt (a lost worker, memory), not pdamper's own
    deterministic errors (``InputError``, ``SimulationError``)."""
    from pdamper.errors import PdamperError

    return not isinstance(exc, PdamperError)
