"""Realisations of DEM answers: the same inputs from N independent random packings, run
in parallel on the sweep engine (:func:`pdamper.sweep.run_sweep`).

A DEM result depends on the realisation (the random initial packing); the spread over
packings says how sure one run's answer is. Realisation ``k`` (``k = 0 .. N-1``) starts
from the random packing of seed ``dem.seed + k``, so the first is the single run of that
seed, and every realisation can be run again on its own with that seed.

* Level II runs (``pdamper dem``): :func:`run_realisations`.
* Maps (``pdamper map --model dem``): :func:`run_map_realisations`, the realisations
  combined by :func:`combine_realisations` (a ``realisation`` dimension and the spread of
  every cell), :func:`realisation_map` to take one out.
* Level III (``pdamper simulate``): :func:`run_level3_realisations` gives a
  :class:`Level3Band`: model 1 from N packings, or model 2 from the fields of a map's
  realisations (the map's band carried through the free vibration).
* Design studies (``pdamper optimize``): :func:`design_evaluator`, the objective's mean
  over N packings and its spread per design.

Example::

    from pdamper.io.scenario import load_scenario
    from pdamper.runs.realisations import run_realisations

    sc = load_scenario(None, {"dem.packing": "random", "particles.count": 16})
    res = run_realisations(sc, 5, serial=True)
    res.statistics("loss_factor")   # {"mean", "std", "min", "max", "values"}
"""

from __future__ import annotations

import contextlib
import functools
import json
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, cast

import numpy as np

from pdamper import resources
from pdamper.errors import InputError
from pdamper.runs.resources import check_resources, excitation_cost

if TYPE_CHECKING:
    from pathlib import Path

    from numpy.typing import ArrayLike
    from xarray import Dataset

    from pdamper.damper import ParticleDamper
    from pdamper.design.study import Objective
    from pdamper.io.scenario import Scenario
    from pdamper.models.base import DamperModel, DamperResponse
    from pdamper.models.dem import DEMDamper
    from pdamper.models.fields import EffectiveFieldDamper
    from pdamper.runs.maps import MapRun

#: The quantities whose spread over the realisations is reported.
SPREAD_KEYS = ("loss_factor", "effective_mass_ratio")

#: Usual number of realisations (a count far above it is judged by its cost first).
USUAL_REALISATIONS = 5


def count_settling(model: DEMDamper, response: DamperResponse) -> None:
    """Count the settling of the bed a one-point ``response`` started from in its run's
    steps and times (``settle_steps``, ``settle_seconds``; ``settle_reused`` false).

    The model settles through its per-process memo first, so its result reads as started
    from a kept bed; yet that settling was done for this run (one command, one
    realisation: a seed or contact law of its own settles a bed of its own), and its cost
    is part of what the run cost. A bed that an earlier run of the process settled and
    counted stays reused (:meth:`DEMDamper.claim_settling`)."""
    import dataclasses

    res = response.details.item()
    if not res.settle_reused:
        return
    bed = model.claim_settling(float(np.asarray(response.frequency)),
                               float(np.asarray(response.amplitude)))
    if bed is not None:
        response.details[()] = dataclasses.replace(
            res, settle_steps=int(bed.steps), settle_seconds=float(bed.seconds),
            settle_reused=False)


def run_summary(model: DEMDamper, response: DamperResponse) -> dict:
    """The scalar summary of one Level II DEM response (``pdamper dem --json``'s run keys):
    loss factor, effective mass ratio, dissipated energy per cycle [J], energy ledger [J],
    stationarity, motion mode and the run's diagnostics (SI units): the keys of
    :meth:`DEMResult.summary <pdamper.dem.DEMResult.summary>` (``steps`` and
    ``wall_seconds`` are the whole run, settling included, as in a map's diagnostics;
    ``excitation_steps``, ``excitation_wall_seconds`` the excitation's; ``settle_steps``,
    ``settle_seconds`` the settling's; ``total_steps``, ``total_wall_seconds`` the same
    sums as ``steps``, ``wall_seconds``), and ``settling``: ``steps``, ``wall_seconds``
    [s], ``simulated_time`` [s] (bed time), ``reused`` and ``stop`` of the settling the run
    started from."""
    r = response
    count_settling(model, r)
    res = r.details.item()
    st = r.diagnostics["stationarity"].item()
    motion = r.diagnostics["motion"].item()
    skip, span = st.first_cycle - 1, st.last_cycle - st.first_cycle + 1
    out = {
        **res.summary(),  # the run's own keys (steps, wall times, ...), one meaning each
        # the settling of the bed the run started from, in one place (the same values as
        # settle_steps, settle_seconds, settle_reused, settle_simulated_time, settle_stop)
        "settling": {"steps": int(res.settle_steps), "wall_seconds": float(res.settle_seconds),
                     "simulated_time": float(res.settle_simulated_time),
                     "reused": bool(res.settle_reused), "stop": res.settle_stop},
        "loss_factor": float(r.loss_factor),
        "effective_mass_ratio": float(r.effective_mass_ratio),
        "dissipated_energy_per_cycle": float(r.dissipated_energy_per_cycle),
        "ledger_per_cycle": res.ledger_per_cycle(skip, span),
        "stationary": bool(st.stationary),
        "steady_reason": st.reason,
        "cycles": st.cycles,
        "averaged_cycles": [st.first_cycle, st.last_cycle],
        "quiet_window": bool(st.quiet),
        "loss_factor_stderr": st.stderr,
        "motion_mode": motion.mode.label,
        "subharmonic_order": motion.subharmonic_order,
        "mode_reason": motion.reason,
        # which protocol ran: the start and how it was integrated (DEMDamper.protocol)
        "protocol": model.protocol("random" if int(r.diagnostics["random_packing"].item())
                                   else "lattice"),
    }
    stderr = out["loss_factor_stderr"]
    if stderr is None or not math.isfinite(stderr):  # one cycle averaged: s / sqrt(L) is 0/0
        out["loss_factor_stderr"] = None
        out["not_applicable"] = {"loss_factor_stderr": "fewer than two cycles averaged: no "
                                                       "scatter to estimate"}
    if model.error_estimate:
        d = r.diagnostics
        out.update(loss_factor_error=float(d["loss_factor_error"].item()),
                   effective_mass_ratio_error=float(d["effective_mass_ratio_error"].item()),
                   accuracy_met=bool(d["accuracy_met"].item()),
                   accuracy_refinements=int(d["accuracy_refinements"].item()),
                   realisation_loss_factor_spread=float(
                       d["realisation_loss_factor_spread"].item()),
                   realisation_effective_mass_ratio_spread=float(
                       d["realisation_effective_mass_ratio_spread"].item()),
                   realisation_dependent=bool(d["realisation_dependent"].item()))
    return out


def with_seed(scenario: Scenario, seed: int) -> Scenario:
    """``scenario`` with the DEM seed ``seed`` (everything else unchanged)."""
    return scenario.model_copy(update={"dem": scenario.dem.model_copy(update={"seed": seed})})


def realisation_point(params: dict, *, scenario: Scenario) -> dict:
    """One realisation (runs on a sweep worker): the DEM of ``scenario`` at the
    excitation's f, X from the random packing of seed ``params["seed"]``; its
    :func:`run_summary`."""
    sc = with_seed(scenario, int(params["seed"]))
    damper = sc.damper()
    model = cast("DEMDamper", sc.model("dem", damper))
    r = model.response(sc.excitation.frequency, sc.excitation.amplitude)
    return {**run_summary(model, r), "packing": model.initial_packing()}


def check_realisations(count: Any, scenario: Scenario | None = None, *,
                       force: bool = False) -> int:
    """``count`` as a number of realisations: a whole number >= 1 whose implied cost (N
    times one DEM run, judged by :mod:`pdamper.resources`) is within the limits; N > 1
    only from a random packing (the lattice is one realisation).

    Raises
    ------
    InputError
        ``realisations``: not a whole number >= 1, too costly, or N > 1 on the lattice.
    """
    if isinstance(count, bool) or isinstance(count, float) and not count.is_integer():
        raise InputError("realisations", f"must be a whole number >= 1, got {count!r}")
    try:
        n = int(count)
    except (TypeError, ValueError):
        raise InputError("realisations", f"must be a whole number >= 1, "
                         f"got {count!r}") from None
    if n < 1:
        raise InputError("realisations", f"must be a whole number >= 1, got {n}")
    if n == 1 or scenario is None:
        return n
    # the count is judged before any run: N runs of one DEM run's cost each
    one = excitation_cost(scenario, "dem")
    assert one is not None  # the DEM states what a run costs
    resources.require(resources.Cost(
        "the realisations", one.seconds * n, one.memory,
        f"{n:.3g} DEM runs, each {one.detail}",
        (("realisations", n / USUAL_REALISATIONS),), runs=n, longest=one.seconds,
        remedy="ask for fewer realisations"), force)
    model = cast("DEMDamper", scenario.model("dem", scenario.damper()))
    if model.initial_packing() != "random":
        raise InputError("realisations", f"must be 1 with the lattice packing (the lattice is "
                         f"one realisation), got {n}; use dem.packing = \"random\"")
    return n


@dataclass
class RealisationsResult:
    """N realisations of one DEM run (realisation ``k`` from seed ``seeds[k]``)."""

    seeds: list[int]
    runs: list[dict]
    seconds: float = math.nan
    workers: int = 0
    errors: list[str] = field(default_factory=list)

    @property
    def count(self) -> int:
        return len(self.seeds)

    def statistics(self, name: str) -> dict:
        """``{"mean", "std", "min", "max", "values"}`` of ``name`` over the realisations;
        ``std`` is the sample standard deviation (divisor N - 1; NaN for one)."""
        v = np.array([r[name] for r in self.runs], float)
        return {"mean": float(v.mean()),
                "std": float(v.std(ddof=1)) if v.size > 1 else math.nan,
                "min": float(v.min()), "max": float(v.max()), "values": v.tolist()}

    def as_dict(self) -> dict:
        """The ``realisations`` record of ``pdamper dem --json``."""
        return {"count": self.count, "seeds": list(self.seeds),
                "std_ddof": 1, "seconds": self.seconds, "workers": self.workers,
                **{k: self.statistics(k) for k in SPREAD_KEYS}}


def run_realisations(scenario: Scenario, count: int, *, workers: int | None = None,
                     scheduler: str | None = None, serial: bool = False,
                     force: bool = False, progress: Callable | None = None
                     ) -> RealisationsResult:
    """Run ``count`` realisations of the scenario's DEM run (``[excitation]``, ``[dem]``)
    from seeds ``dem.seed, dem.seed + 1, ...`` on the sweep engine (a local dask cluster
    of every core, ``workers`` processes, an existing ``scheduler``, or ``serial`` in this
    process).

    Raises
    ------
    InputError
        A bad count (:func:`check_realisations`).
    RuntimeError
        A realisation failed (its error).
    """
    from pdamper.sweep import run_sweep

    n = check_realisations(count, scenario, force=force)
    seed0 = int(scenario.dem.seed)
    seeds = [seed0 + k for k in range(n)]
    res = run_sweep(functools.partial(realisation_point, scenario=scenario),
                    [{"seed": s} for s in seeds], retries=0, workers=workers,
                    scheduler=scheduler, serial=serial, progress=progress)
    bad = [(p.params["seed"], p.error) for p in res.points if not p.ok]
    if bad:
        raise RuntimeError(f"realisation of seed {bad[0][0]} failed: {bad[0][1]}")
    return RealisationsResult(seeds, [p.values for p in res.points], res.seconds,
                              res.workers)


# --------------------------------------------------------------------------- shared
def parse_count(text: Any) -> int:
    """A command line's ``--realisations`` value as a whole number >= 1."""
    try:
        value = float(text) if isinstance(text, str) and "." in text else int(text)
    except (TypeError, ValueError):
        raise InputError("realisations", f"must be a whole number >= 1, got {text!r}") from None
    return check_count(value)


def check_count(count: Any) -> int:
    """``count`` as a whole number >= 1 (``InputError`` for ``realisations`` otherwise)."""
    return check_realisations(count, None)


def seeds_of(scenario: Scenario, count: int) -> list[int]:
    """The seeds of ``count`` realisations: ``dem.seed, dem.seed + 1, ...``."""
    seed0 = int(scenario.dem.seed)
    return [seed0 + k for k in range(count)]


def spread(values: ArrayLike) -> dict:
    """``{"mean", "std", "min", "max", "values"}`` of ``values`` (``std``: divisor N - 1,
    NaN for one value)."""
    v = np.asarray(values, float)
    return {"mean": float(v.mean()),
            "std": float(v.std(ddof=1)) if v.size > 1 else math.nan,
            "min": float(v.min()), "max": float(v.max()), "values": v.tolist()}


def _scaled_check(scenario, run: str, model: str | None, n: int, force: bool) -> None:
    """The cost check of :func:`~pdamper.runs.resources.check_resources` of ``run`` with
    ``model`` for ``n`` runs of it: every time cost it implies, ``n`` times over (memory is
    per run: one at a time per worker); the driver ``realisations`` is named when the
    count is what inflates it."""
    check_resources(scenario, run, model, force, require=scaled_require(n))


def _need_random(model, n: int) -> None:
    """N > 1 only for a model whose runs start from a seeded random packing."""
    packing = getattr(model, "initial_packing", None)
    if packing is None:
        raise InputError("realisations", f"must be 1 for the {model.fidelity} model (it has "
                         f"no random packing: every realisation is the same), got {n}")
    if packing() != "random":
        raise InputError("realisations", f"must be 1 with the lattice packing (the lattice is "
                         f"one realisation), got {n}; use dem.packing = \"random\"")


@contextlib.contextmanager
def _one_client(sweep_options: dict):
    """One dask client for several sweeps (a local cluster started once), unless the
    options run in this process or name a client or scheduler of their own."""
    if sweep_options.get("serial") or sweep_options.get("client") is not None \
            or sweep_options.get("scheduler") is not None:
        yield sweep_options
        return
    from pdamper.sweep.cluster import open_client

    opts = {k: v for k, v in sweep_options.items() if k != "workers"}
    with open_client(sweep_options.get("workers")) as client:
        yield {**opts, "client": client}


# --------------------------------------------------------------------------- maps
#: The map variables whose spread over the realisations a map carries.
MAP_SPREAD = ("loss_factor", "effective_mass_ratio", "dissipated_energy_per_cycle")


def check_map_realisations(count: Any, scenario: Scenario, model_name: str, *,
                           force: bool = False) -> int:
    """``count`` realisations of the scenario's map under ``model_name``: a whole number
    >= 1; N > 1 only for a model with a random packing (the DEM with ``dem.packing`` or
    ``[map] dem_packing`` random), and N times the map's cost within the limits."""
    n = check_count(count)
    if n > 1:
        _need_random(scenario.map_model(model_name), n)
        _scaled_check(scenario, "map", model_name, n, force)
    return n


def combine_realisations(datasets: Sequence[Dataset], seeds: Sequence[int]) -> Dataset:
    """One map from the maps of N realisations (same grid; realisation ``k`` of seed
    ``seeds[k]``).

    The variables of :data:`MAP_SPREAD` are the means over the realisations (attribute
    ``statistic = "mean"``), with ``<name>_std`` (divisor N - 1), ``<name>_min``,
    ``<name>_max`` per cell and every realisation's values in ``<name>_realisations``
    (dimension ``realisation``, coordinate the seed). A cell is failed (``status`` 1, its
    values NaN) when any realisation failed there, stationary only when every realisation
    was; ``motion_mode`` is the first realisation's, with ``motion_mode_agreement`` the
    share of the realisations in that mode. The other variables are the first
    realisation's.
    """
    import xarray as xr

    first = datasets[0]
    stack = {name: xr.concat([d[name] for d in datasets], dim="realisation")
             for name in MAP_SPREAD if name in first}
    status = xr.concat([d["status"] for d in datasets], dim="realisation")
    failed = (status != 0).any("realisation")
    out = first.copy()
    n = len(datasets)
    for name, s in stack.items():
        s = s.where(~failed)
        units = first[name].attrs.get("units", "1")
        long = first[name].attrs.get("long_name", name)
        out[name] = s.mean("realisation").assign_attrs(
            {**first[name].attrs, "statistic": "mean", "realisations": n})
        std = s.std("realisation", ddof=1) if n > 1 else xr.full_like(s[0], math.nan)
        for suffix, v, what in (("std", std, "standard deviation (divisor N - 1)"),
                                ("min", s.min("realisation"), "minimum"),
                                ("max", s.max("realisation"), "maximum")):
            out[f"{name}_{suffix}"] = v.assign_attrs(
                {"long_name": f"{long}: {what} over the realisations", "units": units})
        out[f"{name}_realisations"] = s.assign_attrs(
            {"long_name": f"{long} of each realisation", "units": units})
    out["status"] = xr.where(failed, 1, 0).astype(first["status"].dtype).assign_attrs(
        first["status"].attrs)
    if "error" in first:
        errs = np.asarray(first["error"].values, dtype=object).copy()
        for d in datasets[1:]:
            e = np.asarray(d["error"].values, dtype=object)
            errs = np.where((errs == "") & (e != ""), e, errs)
        out["error"] = (first["error"].dims, errs.astype(str), first["error"].attrs)
    if "stationary" in first:
        st = xr.concat([d["stationary"] for d in datasets], dim="realisation")
        out["stationary"] = xr.where(failed, -1, (st == 1).all("realisation").astype(int)
                                     ).astype(first["stationary"].dtype).assign_attrs(
            first["stationary"].attrs)
    if "motion_mode" in first:
        modes = xr.concat([d["motion_mode"] for d in datasets], dim="realisation")
        out["motion_mode_agreement"] = (modes == first["motion_mode"]).mean(
            "realisation").assign_attrs({"long_name": "share of the realisations in the "
                                         "first realisation's motion mode", "units": "1"})
    out = out.assign_coords(realisation=("realisation", np.arange(n), {
        "long_name": "realisation index"}), seed=("realisation", np.asarray(seeds, int), {
            "long_name": "seed of the realisation's random packing"}))
    out.attrs.update(realisations=n, seeds=json.dumps([int(s) for s in seeds]),
                     statistic="mean", std_ddof=1, seed=int(seeds[0]))
    return out


def realisation_map(ds: Dataset, k: int) -> Dataset:
    """The map of realisation ``k`` alone (index along ``realisation``) from a map with
    realisations: the :data:`MAP_SPREAD` variables of that realisation in place of the
    means, the spread variables dropped."""
    if "realisation" not in ds.dims:
        raise InputError("realisation", "the map has no realisations")
    n = ds.sizes["realisation"]
    if not 0 <= k < n:
        raise InputError("realisation", f"must be in [0, {n - 1}], got {k}")
    out = ds.copy()
    for name in MAP_SPREAD:
        if f"{name}_realisations" in ds:
            out[name] = ds[f"{name}_realisations"].isel(realisation=k, drop=True
                                                        ).assign_attrs(ds[name].attrs)
    drop = [v for v in out.data_vars if "realisation" in out[v].dims or any(
        v == f"{m}_{s}" for m in MAP_SPREAD for s in ("std", "min", "max"))
        or v == "motion_mode_agreement"]
    out = out.drop_vars(drop).drop_vars(["realisation", "seed"], errors="ignore")
    seeds = json.loads(ds.attrs.get("seeds", "[]"))
    out.attrs = {k_: v for k_, v in ds.attrs.items()
                 if k_ not in ("realisations", "seeds", "statistic", "std_ddof", "map_key")}
    if seeds:
        out.attrs["seed"] = int(seeds[k])
    return out


def map_realisation_count(ds: Dataset) -> int:
    """Number of realisations a map carries (1 without a ``realisation`` dimension)."""
    return int(ds.sizes["realisation"]) if "realisation" in ds.dims else 1


def run_map_realisations(scenario: Scenario, model_name: str, count: int, *,
                         frequency: ArrayLike | None = None,
                         amplitude: ArrayLike | None = None,
                         particles: ArrayLike | None = None, out: Path | None = None,
                         keep_partial: bool = False, progress: Callable | None = None,
                         force: bool = False, **sweep_options: Any) -> MapRun:
    """The map of :func:`pdamper.runs.maps.run_map` from ``count`` realisations
    (seeds ``dem.seed + k``), combined by :func:`combine_realisations`.

    Each realisation is a map on the sweep engine; the realisations share one dask cluster
    and, with ``out``, one ``<out>.partial/`` store (a point's key holds the scenario, its
    seed included, so a stopped run started again computes only the missing points of
    every realisation). Returns a :class:`~pdamper.runs.maps.MapRun` whose counts are
    over every realisation's points.
    """
    import time

    from pdamper.files import atomic_write_netcdf
    from pdamper.runs.maps import (
        MapRun,
        map_axes,
        map_context,
        map_key,
        partial_store,
        run_map,
    )

    n = check_map_realisations(count, scenario, model_name, force=force)
    if n == 1:
        return run_map(scenario, model_name, frequency=frequency, amplitude=amplitude,
                       particles=particles, out=out, keep_partial=keep_partial,
                       progress=progress, **sweep_options)
    t0 = time.perf_counter()
    seeds = seeds_of(scenario, n)
    frequency, amplitude, particles = map_axes(scenario, frequency, amplitude, particles)
    f, x = np.asarray(frequency, float), np.asarray(amplitude, float)
    sets, computed, reused, workers = [], 0, 0, 1
    done = [0]

    def tick(_done, total, point):  # one count over every realisation's points
        done[0] += 1
        if progress is not None:
            progress(done[0], total * n, point)

    store = None if out is None else partial_store(out)
    with _one_client(sweep_options) as opts:
        for s in seeds:
            ds, sweep = _map_points(with_seed(scenario, s), model_name, f, x, particles,
                                    store, tick, opts)
            sets.append(ds)
            computed += sweep.computed
            reused += sweep.reused
            workers = max(workers, sweep.workers)
    ds = combine_realisations(sets, seeds)
    context = {**map_context(scenario.for_map(), model_name), "realisations": seeds}
    ds.attrs["map_key"] = map_key(context, f, x, particles)
    failed = int((ds["status"].values != 0).sum())
    path = None
    if out is not None:
        path = atomic_write_netcdf(out, ds)
        if not keep_partial and store is not None:  # (a store exactly when out is given)
            from pdamper.sweep import PointStore

            PointStore(store).remove()
    return MapRun(ds, time.perf_counter() - t0, computed, reused, failed, workers, path)


def _map_points(scenario, model_name, f, x, particles, store, progress, opts):
    """One realisation's map on the sweep engine (as :func:`pdamper.runs.maps.run_map`
    computes a DEM map), its points kept in ``store``; ``(dataset, sweep)``."""
    from pdamper import __version__
    from pdamper.analysis.fields import sweep_field
    from pdamper.runs.maps import _retry_if, map_context

    model = scenario.map_model(model_name)
    context = map_context(scenario.for_map(), model_name)
    attrs = {"pdamper_version": __version__, "pdamper_source": context["pdamper_source"],
             "inputs": json.dumps(scenario.model_dump(mode="json")),
             "seed": int(scenario.dem.seed), "model_fidelity": model_name,
             "packing": scenario.for_map().dem.packing}
    opts = {"retry_if": _retry_if, **opts}
    return sweep_field(model, f, x, particles, store=store, context=context, attrs=attrs,
                       progress=progress, **opts)


def map_spread_record(ds: Dataset) -> dict:
    """The ``realisations`` record of ``pdamper map --json`` for a map with realisations:
    ``count``, ``seeds``, ``std_ddof`` and, per :data:`MAP_SPREAD` variable, the cell
    arrays ``mean``, ``std``, ``min``, ``max`` (nested lists in the map's dimension order;
    NaN as None)."""
    rec = {"count": map_realisation_count(ds), "seeds": json.loads(ds.attrs["seeds"]),
           "std_ddof": 1, "dims": list(ds["loss_factor"].dims)}

    def cells(v):
        a = np.asarray(v.values, float)
        cell = a.astype(object)
        cell[~np.isfinite(a)] = None
        return cell.tolist()

    for name in MAP_SPREAD:
        if f"{name}_std" in ds:
            rec[name] = {"mean": cells(ds[name]),
                         **{s: cells(ds[f"{name}_{s}"]) for s in ("std", "min", "max")}}
    return rec


# --------------------------------------------------------------------------- Level III
#: Spacing of the times at which the band of the amplitude envelope is reported [s].
ENVELOPE_STEP = 0.01


@dataclass
class Level3Band:
    """N realisations of one Level III free vibration and their band.

    Attributes
    ----------
    model
        The damper model's fidelity.
    runs
        One :class:`~pdamper.coupling.FreeVibrationResult` per realisation.
    at
        The time of the reported amplitude [s].
    seeds
        The random packing's seed of each realisation (the DEM), or None.
    map_realisations
        The map realisation of each run (the effective fields of a map with
        realisations), or None.
    seconds, workers
        Wall time [s] and worker processes of the runs.
    run_seconds
        Wall time of each realisation's run [s].
    """

    model: str
    runs: list
    at: float
    seeds: list[int] | None = None
    map_realisations: list[int] | None = None
    seconds: float = math.nan
    workers: int = 1
    run_seconds: list[float] = field(default_factory=list)

    @property
    def count(self) -> int:
        return len(self.runs)

    def amplitude_at(self) -> dict:
        """:func:`spread` of the amplitude envelope at :attr:`at` [m]
        (:meth:`FreeVibrationResult.amplitude_at`)."""
        return spread([r.amplitude_at(self.at) for r in self.runs])

    def final_amplitude(self) -> dict:
        """:func:`spread` of the last negative peak's amplitude [m]."""
        return spread([r.final_amplitude for r in self.runs])

    def envelope(self) -> dict:
        """The band of the amplitude envelope: at ``time`` (every :data:`ENVELOPE_STEP`
        from the release to the end) the ``mean``, ``std``, ``min`` and ``max`` [m] of the
        realisations' envelopes (each interpolated between its negative peaks)."""
        end = min(float(r.time[-1]) for r in self.runs)
        t = np.arange(0.0, end + 1e-12, ENVELOPE_STEP)
        a = np.array([[r.amplitude_at(ti) for ti in t] for r in self.runs])
        return {"time": t.tolist(), **_columns(a)}

    def trajectory(self) -> dict:
        """Pointwise band of the sampled trajectories: ``time`` [s] and the ``mean``,
        ``std``, ``min``, ``max`` of the displacement [m] over the realisations (arrays)."""
        n = min(len(r.time) for r in self.runs)
        x = np.array([r.displacement[:n] for r in self.runs])
        return {"time": np.asarray(self.runs[0].time[:n]), **_columns(x, lists=False)}

    def damping_ratio(self) -> list[dict]:
        """The damping ratio (Eqs. 24-25) per amplitude over the realisations: at every
        realisation's cycle amplitudes within the range all of them cover (largest first), the
        ``mean``, ``std``, ``min`` and ``max`` of each realisation's zeta, interpolated
        linearly in its cycle amplitude."""
        curves = [r.damping_ratio for r in self.runs]
        curves = [(a, z) for a, z in curves if len(a) >= 2]
        if len(curves) < len(self.runs):
            return []
        lo = max(float(a.min()) for a, _ in curves)
        hi = min(float(a.max()) for a, _ in curves)
        grid = sorted({float(v) for a, _ in curves for v in a if lo <= v <= hi},
                      reverse=True)
        if not grid:
            return []
        z = np.array([np.interp(grid, a[np.argsort(a)], zz[np.argsort(a)])
                      for a, zz in curves])
        cols = _columns(z)
        return [{"amplitude": g, **{k: cols[k][i] for k in cols}} for i, g in enumerate(grid)]

    def add_to(self, ds: Dataset) -> Dataset:
        """``ds`` (the first realisation's :meth:`FreeVibrationResult.to_dataset`) with the
        band: ``displacement_mean`` / ``_std`` / ``_min`` / ``_max`` over ``time`` and the
        amplitude envelope's ``envelope_mean`` / ... over ``envelope_time`` [m]; attributes
        ``realisations``, ``seeds`` or ``map_realisations`` (JSON), ``at``."""
        tr, env = self.trajectory(), self.envelope()
        n = len(tr["time"])
        out = ds.isel(time=slice(0, n))
        for k in ("mean", "std", "min", "max"):
            out[f"displacement_{k}"] = ("time", tr[k], {
                "long_name": f"end-effector displacement, {k} over the realisations",
                "units": "m"})
            out[f"envelope_{k}"] = ("envelope_time", np.asarray(env[k]), {
                "long_name": f"amplitude envelope, {k} over the realisations", "units": "m"})
        out = out.assign_coords(envelope_time=("envelope_time", np.asarray(env["time"]),
                                               {"units": "s"}))
        out.attrs.update(realisations=self.count, at=self.at, std_ddof=1)
        if self.seeds is not None:
            out.attrs["seeds"] = json.dumps(self.seeds)
        if self.map_realisations is not None:
            out.attrs["map_realisations"] = json.dumps(self.map_realisations)
        return out

    def as_dict(self) -> dict:
        """The ``realisations`` record of ``pdamper simulate --json`` (SI units)."""
        out = {"count": self.count, "model": self.model, "std_ddof": 1,
               "statistic": "mean, std (divisor N - 1), min, max over the realisations",
               "band": "min-max of the realisations around their mean",
               "seconds": self.seconds, "workers": self.workers,
               "run_seconds": list(self.run_seconds), "at": self.at,
               "amplitude_at": self.amplitude_at(),
               "final_amplitude": self.final_amplitude(),
               "damping_ratio": self.damping_ratio(), "envelope": self.envelope()}
        if self.seeds is not None:
            out["seeds"] = list(self.seeds)
        if self.map_realisations is not None:
            out["map_realisations"] = list(self.map_realisations)
        return out


def _columns(a, lists: bool = True) -> dict:
    """mean / std (divisor N - 1) / min / max over the first axis of ``a``."""
    a = np.asarray(a, float)
    std = a.std(axis=0, ddof=1) if a.shape[0] > 1 else np.full(a.shape[1:], math.nan)
    cols = {"mean": a.mean(axis=0), "std": std, "min": a.min(axis=0), "max": a.max(axis=0)}
    return {k: v.tolist() for k, v in cols.items()} if lists else cols


def level3_point(params: dict, *, scenario: Scenario, model_name: str) -> dict:
    """One Level III realisation (runs on a sweep worker): the scenario's free vibration
    with the model ``model_name`` of the random packing of seed ``params["seed"]``."""
    import time

    from pdamper.coupling import Simulation

    sc = with_seed(scenario, int(params["seed"]))
    t0 = time.perf_counter()
    r = Simulation(sc.structure_model(), sc.model(model_name, sc.damper()),
                   sc.structure.initial_displacement).run(sc.simulation.duration,
                                                          sc.simulation.sample_rate)
    return {"time": r.time, "displacement": r.displacement, "peak_times": r.peak_times,
            "peak_amplitudes": r.peak_amplitudes, "model": r.model,
            "wall_seconds": time.perf_counter() - t0}


def _result(values: dict):
    from pdamper.coupling import FreeVibrationResult

    return FreeVibrationResult(np.asarray(values["time"], float),
                               np.asarray(values["displacement"], float),
                               np.asarray(values["peak_times"], float),
                               np.asarray(values["peak_amplitudes"], float),
                               model=values["model"])


def _check_at(at: float, duration: float) -> float:
    if not 0 <= at <= duration:
        raise InputError("optimization.at", f"the time of the realisations' amplitude must be "
                         f"within the simulated time [0 s, {duration:g} s], got {at:g} s; "
                         "set a longer --duration or an earlier [optimization] at")
    return float(at)


def level3_kind(model: DamperModel) -> str | None:
    """How a Level III model makes realisations: ``"seed"`` (it starts from a seeded
    random packing), ``"map"`` (an effective-field map with realisations), or None."""
    if getattr(model, "initial_packing", None) is not None:
        return "seed"
    if int(getattr(model, "map_attrs", {}).get("realisations", 1) or 1) > 1:
        return "map"
    return None


def check_level3_realisations(count: Any, scenario: Scenario, model_name: str | None = None, *,
                              force: bool = False) -> int:
    """``count`` realisations of the scenario's free vibration with ``model_name``: a whole
    number >= 1; N > 1 for a model with a random packing (the DEM, N times its cost within
    the limits, ``[optimization] at`` within the simulated time) or the effective fields of
    a map with at least N realisations."""
    n = check_realisation_models(count, scenario, model_name)
    if n == 1:
        return n
    if level3_kind(scenario.model(model_name, scenario.damper())) != "map":
        _scaled_check(scenario, "simulation", model_name, n, force)  # N DEM runs
    _check_at(scenario.optimization.at, scenario.simulation.duration)
    return n


def run_level3_realisations(scenario: Scenario, count: int, model_name: str | None = None, *,
                            workers: int | None = None, scheduler: str | None = None,
                            serial: bool = False, force: bool = False) -> Level3Band:
    """The scenario's free vibration (``[structure]``, ``[simulation]``) from ``count``
    realisations of the damper model ``model_name`` (default ``[simulation] model``),
    with the amplitude band at ``[optimization] at``.

    A model with a random packing (the DEM co-simulation, model 1) runs realisation ``k``
    from seed ``dem.seed + k``, the realisations in parallel on the sweep engine (a local
    dask cluster of ``workers`` processes, every core by default; ``scheduler``; or
    ``serial``). The effective fields of a map with realisations (model 2) run realisation
    ``k`` with the field of the map's realisation ``k`` (seconds each: in this process).

    Raises
    ------
    InputError
        A bad count (:func:`check_level3_realisations`).
    RuntimeError
        A realisation failed (its error).
    """
    import time

    from pdamper.sweep import run_sweep

    n = check_level3_realisations(count, scenario, model_name, force=force)
    at = _check_at(scenario.optimization.at, scenario.simulation.duration)
    damper = scenario.damper()
    proto = scenario.model(model_name, damper)
    if level3_kind(proto) == "map":
        from pdamper.coupling import Simulation

        t0 = time.perf_counter()
        runs, secs = [], []
        for k in range(n):
            t1 = time.perf_counter()
            opts = {**scenario.fields.options(), "file": None,
                    "field": realisation_map(cast("EffectiveFieldDamper", proto)._map, k)}
            m = type(proto)(damper, **opts)
            runs.append(Simulation(scenario.structure_model(), m,
                                   scenario.structure.initial_displacement).run(
                scenario.simulation.duration, scenario.simulation.sample_rate))
            secs.append(time.perf_counter() - t1)
        return Level3Band(proto.fidelity, runs, at, map_realisations=list(range(n)),
                          seconds=time.perf_counter() - t0, run_seconds=secs)
    seeds = seeds_of(scenario, n)
    res = run_sweep(functools.partial(level3_point, scenario=scenario,
                                      model_name=model_name or scenario.simulation.model),
                    [{"seed": s} for s in seeds], retries=0, workers=workers,
                    scheduler=scheduler, serial=serial)
    bad = [(p.params["seed"], p.error) for p in res.points if not p.ok]
    if bad:
        raise RuntimeError(f"realisation of seed {bad[0][0]} failed: {bad[0][1]}")
    return Level3Band(proto.fidelity, [_result(p.values) for p in res.points], at,
                      seeds=seeds, seconds=res.seconds, workers=res.workers,
                      run_seconds=[float(p.values["wall_seconds"]) for p in res.points])


def realisation_models(scenario: Scenario, count: int, model_name: str | None = None
                       ) -> tuple[list[DamperModel], dict]:
    """The models of ``count`` realisations of the scenario's damper with fidelity
    ``model_name`` (default ``[simulation] model``): the DEM from the random packings of
    seeds ``dem.seed + k``, the effective fields from realisation ``k`` of their map; with
    the record of which (``{"seeds": [...]}`` or ``{"map_realisations": [...]}``). The
    count is judged by :func:`check_realisation_models` first."""
    damper = scenario.damper()
    proto = scenario.model(model_name, damper)
    if level3_kind(proto) == "map":
        m = cast("EffectiveFieldDamper", proto)
        opts = {**scenario.fields.options(), "file": None}
        return ([type(proto)(damper, **{**opts, "field": realisation_map(m._map, k)})
                 for k in range(count)], {"map_realisations": list(range(count))})
    seeds = seeds_of(scenario, count)
    return ([with_seed(scenario, s).model(model_name, damper) for s in seeds],
            {"seeds": seeds})


def check_realisation_models(count: Any, scenario: Scenario,
                             model_name: str | None = None) -> int:
    """``count`` realisations of the damper model: a whole number >= 1; N > 1 for a model
    with a random packing (the DEM) or the effective fields of a map with at least N
    realisations (the cost of the runs is the caller's to judge, N times one run's)."""
    n = check_count(count)
    if n == 1:
        return n
    model = scenario.model(model_name, scenario.damper())
    if level3_kind(model) == "map":
        have = int(cast("EffectiveFieldDamper", model).map_attrs["realisations"])
        if n > have:
            raise InputError("realisations", f"must be at most the {have} realisations of the "
                             f"effective-field map, got {n}")
    else:
        _need_random(model, n)
    return n


def scaled_require(n: int, require=None):
    """A ``require(cost, force)`` that judges ``n`` runs of ``cost`` (time ``n`` times
    over, memory per run), naming ``realisations`` as the driver (:func:`_scaled_check`)."""
    def scaled(cost, force_=False):
        if cost.seconds > 0 and n > 1:
            cost = resources.Cost(
                f"{n} realisations of {cost.what}", cost.seconds * n, cost.memory,
                f"{n} realisations, each {cost.detail}",
                (*cost.drivers, ("realisations", n / USUAL_REALISATIONS)),
                runs=n * max(cost.runs or 1, 1),
                longest=cost.longest if cost.longest is not None else cost.seconds,
                remedy="ask for fewer realisations" if n > USUAL_REALISATIONS else cost.remedy)
        return (require or resources.require)(cost, force_)

    return scaled


# --------------------------------------------------------------------------- design studies
def seeded_model(scenario: Scenario, seed: int, damper: ParticleDamper) -> DamperModel:
    """The ``[simulation]`` model of ``damper`` with the random packing of seed ``seed``
    (a picklable model factory of a design study, with ``functools.partial``)."""
    return with_seed(scenario, seed).model(None, damper)


@dataclass
class RealisationsEvaluator:
    """A design study's objective over N realisations of each design: the mean of the
    objective of the design's free vibration from the random packings of ``seeds``, with
    their spread in the candidate's extras (``objective_std``, divisor N - 1;
    ``objective_min``, ``objective_max``, ``objective_values``). Picklable for dask."""

    evaluators: list
    seeds: list[int]

    def __call__(self, design: dict) -> tuple[float, dict]:
        runs = [e(design) for e in self.evaluators]
        st = spread([v for v, _ in runs])
        return st["mean"], {**runs[0][1], "objective_std": st["std"],
                            "objective_min": st["min"], "objective_max": st["max"],
                            "objective_values": st["values"]}

    def check(self, design: dict) -> None:
        """The physical limits of the design (:meth:`DesignEvaluator.check`)."""
        self.evaluators[0].check(design)


def check_design_realisations(count: Any, scenario: Scenario, *, force: bool = False) -> int:
    """``count`` realisations of every design of the scenario's study: a whole number >= 1;
    N > 1 only with a ``[simulation]`` model of a random packing (the DEM) or the effective
    fields of a map with at least N realisations, N times the study's cost within the
    limits."""
    n = check_realisation_models(count, scenario)
    if n > 1:
        _scaled_check(scenario, "optimization", None, n, force)
    return n


def map_realisation_model(scenario: Scenario, k: int, damper: ParticleDamper) -> DamperModel:
    """The effective-field model of ``damper`` from realisation ``k`` of the scenario's map
    (a picklable model factory of a design study, with ``functools.partial``)."""
    proto = cast("EffectiveFieldDamper", scenario.model(None, damper))
    return type(proto)(damper, **{**scenario.fields.options(), "file": None},
                       field=realisation_map(proto._map, k))


def design_evaluator(scenario: Scenario, count: int,
                     objective: Objective) -> RealisationsEvaluator:
    """The evaluator of a design study over ``count`` realisations of each design
    (seeds ``dem.seed + k``) of the scenario's structure and release, for ``objective``
    (:func:`pdamper.design.study.make_objective`)."""
    from pdamper.design.study import DesignEvaluator

    structure, damper = scenario.structure_model(), scenario.damper()
    x0 = scenario.structure.initial_displacement
    if level3_kind(scenario.model(None, damper)) == "map":  # the map's realisations 0 .. N-1
        return RealisationsEvaluator(
            [DesignEvaluator(structure, damper, x0, objective,
                             functools.partial(map_realisation_model, scenario, k))
             for k in range(count)], list(range(count)))
    seeds = seeds_of(scenario, count)
    return RealisationsEvaluator(
        [DesignEvaluator(structure, damper, x0, objective,
                         functools.partial(seeded_model, scenario, s)) for s in seeds], seeds)
