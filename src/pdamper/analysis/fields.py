"""Effective fields: Level II quantities over (frequency x amplitude [x particle count]) grids.

Every damper model answers :meth:`~pdamper.models.DamperModel.response` with a
:class:`~pdamper.models.DamperResponse`; this module evaluates it on a grid and labels it as
an :class:`xarray.Dataset` with units, ready for NetCDF, plots and interpolation. It only
calls ``model.response`` (and ``model.with_damper`` for a particle-count axis): any fidelity
works, and this Level II module imports no model.

- :func:`effective_field`: one vectorised call of ``response`` over the grid (the
  analytical formulas: milliseconds).
- :func:`sweep_field`: one ``response`` per point on the resumable dask.distributed sweep
  engine of :mod:`pdamper.sweep` (the DEM: seconds per point, hundreds of points). Every
  finished point is stored as it completes; failed points are retried, then kept with
  their error in ``status`` / ``error``.

Both give the same variables: ``loss_factor``, ``effective_mass_ratio``,
``dissipated_energy_per_cycle``, ``motion_mode``, ``subharmonic_order``, ``stationary``,
``status`` (and from a sweep ``error``, ``attempts`` and the model's run diagnostics).
A model whose answers carry ``assumptions_hold`` / ``assumptions`` (the analytical one,
docs/analytical.md) adds them per point: a 0/1 flag and the reason with the fidelity to use.
"""

from __future__ import annotations

import functools
import hashlib
import math
import pickle
from collections.abc import Callable
from typing import TYPE_CHECKING

import numpy as np

from pdamper import resources
from pdamper.analysis.modes import MODE_FLAG_ATTRS
from pdamper.errors import InputError

if TYPE_CHECKING:  # pragma: no cover
    import xarray as xr

#: Long name and unit of every variable a field may hold.
VARIABLES: dict[str, tuple[str, str]] = {
    "loss_factor": ("effective loss factor (Eq. 3)", "1"),
    "effective_mass_ratio": ("effective particle mass / bed mass", "1"),
    "dissipated_energy_per_cycle": ("dissipated energy per cycle E~ (Eq. 2)", "J"),
    "subharmonic_order": ("subharmonic order n_s (Eqs. 12, 18; -1: none)", "1"),
    "wall_seconds": ("wall time of the run, settling included", "s"),
    "point_seconds": ("wall time of the point on its worker (all runs and the analysis)", "s"),
    "steps": ("time steps of the run (settling included: total_steps)", "1"),
    "total_steps": ("time steps of the run, settling included", "1"),
    "excitation_steps": ("time steps of the run's excitation phase", "1"),
    "settle_steps": ("time steps of the run's settling (0: a bed settled once reused)", "1"),
    "energy_balance_error": ("relative closure error of the energy ledger", "1"),
    "max_overlap_ratio": ("largest contact overlap / particle radius", "1"),
    "max_impact_velocity": ("fastest normal impact velocity of the run", "m s-1"),
    "stepped_fraction": ("mean share of the spheres a Gear step integrated (the others in "
                         "free flight)", "1"),
    "random_packing": ("the run started from a random packing (1) or the lattice (0)", "1"),
    "cycles": ("excitation cycles simulated", "1"),
    "first_cycle": ("first cycle of the averaged window (1-based)", "1"),
    "last_cycle": ("last cycle of the averaged window (1-based)", "1"),
    "loss_factor_stderr": ("standard error of the loss factor over the window", "1"),
    "loss_factor_spread": ("largest deviation of a window mean from the mean", "1"),
    "loss_factor_drift": ("least-squares change of the cycle loss factor across the window",
                          "1"),
    "symmetric_state": ("bed kept the mirror symmetry of an ideal lattice (1) or not (0)",
                        "1"),
    "quiet_window": ("the window was judged by the rule for quiet beds, shorter windows (1), "
                     "or the full one (0)", "1"),
    "period": ("repetition period of the bed motion (0: none)", "1"),
    "periodicity_residual": ("relative residual of the best repetition period", "1"),
    "lift": ("range of the bed's height in the container", "m"),
    "contact_fraction": ("share of the time the bed presses on a wall", "1"),
    "lid_contacts_per_cycle": ("lid impacts of the bed per cycle", "1"),
    "loss_factor_error": ("bound of the integration error of the loss factor (refined "
                          "companion run)", "1"),
    "effective_mass_ratio_error": ("bound of the integration error of the effective mass "
                                   "ratio (refined companion run)", "1"),
    "accuracy_met": ("error estimate within the accuracy target (1) or not (0)", "1"),
    "accuracy_refinements": ("times the run was redone refined for the accuracy target", "1"),
    "realisation_loss_factor_spread": ("change of the loss factor when the spheres start "
                                       "moved by 1e-9 m", "1"),
    "realisation_effective_mass_ratio_spread": ("change of the effective mass ratio when "
                                                "the spheres start moved by 1e-9 m", "1"),
    "realisation_dependent": ("the state depends on the transient or the realisation beyond "
                              "the accuracy target (1) or not (0)", "1"),
}

def _grid(field: str, values, unit: str) -> np.ndarray:
    """A 1-D grid of numbers, or an InputError saying what was expected."""
    expected = f"a 1-D sequence of numbers in {unit}"
    if isinstance(values, str | bytes):
        raise InputError(field, f"must be {expected}, got {values!r}")
    try:
        grid = np.array(values, dtype=float, ndmin=1)
    except (TypeError, ValueError):
        raise InputError(field, f"must be {expected}, got {values!r}") from None
    if grid.ndim != 1 or grid.size == 0:
        raise InputError(field, f"must be {expected} with at least one value, got shape "
                         f"{grid.shape}")
    return grid


def _require_grid(frequency, amplitude, particles) -> None:
    """Refuse a grid that no run can compute (more memory than the machine has, months of
    computing: the hard limits of :mod:`pdamper.resources`), judged from the axes' lengths
    before any array of the grid exists; the analytical model's cost per point, the least
    of every model's, stands for all."""
    sizes = [("frequency", _length(frequency)), ("amplitude", _length(amplitude)),
             ("particles", 1 if particles is None else _length(particles))]
    resources.require(resources.analytic_map_cost(math.prod(n for _, n in sizes), sizes),
                      force=True)


def _length(values) -> int:
    """Number of values of a 1-D grid as given (a list, an array, a range), without
    converting it (1 for a number; what is not a grid is refused by :func:`_grid`)."""
    if isinstance(values, str | bytes):
        return 1
    try:
        return len(values)
    except TypeError:
        return 1


#: Integer variables (stored as such; -1 where a point has no value).
_INTEGER = {"subharmonic_order", "steps", "total_steps", "excitation_steps", "settle_steps",
            "cycles", "first_cycle", "last_cycle",
            "symmetric_state", "quiet_window", "period", "accuracy_met",
            "accuracy_refinements", "realisation_dependent"}

STATIONARY_ATTRS = {"long_name": "averaged window is a steady state", "units": "1",
                    "flag_values": [-1, 0, 1], "flag_meanings": "no_result transient steady"}
ASSUMPTIONS_HOLD_ATTRS = {
    "long_name": "the analytical model's assumptions hold at the point (0: its answer is "
                 "outside them, see 'assumptions')", "units": "1", "flag_values": [0, 1],
    "flag_meanings": "outside_assumptions assumptions_hold"}
ASSUMPTIONS_ATTRS = {"long_name": "why the analytical model's assumptions fail, and the "
                                  "fidelity to use there (empty: they hold)"}
#: Per-point labels of the analytical model's validity (its response's ``diagnostics``).
ASSUMPTION_VARIABLES = ("assumptions_hold", "assumptions")
STATUS_ATTRS = {"long_name": "outcome of the point", "units": "1", "flag_values": [0, 1],
                "flag_meanings": "ok failed"}


def _coords(frequency, amplitude, particles):
    coords = {
        "frequency": ("frequency", frequency, {"long_name": "excitation frequency",
                                               "units": "Hz"}),
        "amplitude": ("amplitude", amplitude, {"long_name": "container stroke amplitude X",
                                               "units": "m"}),
    }
    dims: tuple[str, ...] = ("frequency", "amplitude")
    if particles is not None:
        coords["particles"] = ("particles", np.asarray(particles, int),
                               {"long_name": "number of particles", "units": "1"})
        dims = ("particles", *dims)
    return coords, dims


def _dataset(values: dict[str, np.ndarray], coords, dims, attrs: dict) -> xr.Dataset:
    import xarray as xr

    data = {}
    for name, arr in values.items():
        if name == "motion_mode":
            data[name] = (dims, np.asarray(arr, np.int8),
                          {"long_name": "motion mode", **MODE_FLAG_ATTRS})
        elif name == "stationary":
            data[name] = (dims, np.asarray(arr, np.int8), dict(STATIONARY_ATTRS))
        elif name == "status":
            data[name] = (dims, np.asarray(arr, np.int8), dict(STATUS_ATTRS))
        elif name == "error":
            data[name] = (dims, np.asarray(arr, dtype=str),
                          {"long_name": "error of a failed point (empty if ok)"})
        elif name == "assumptions_hold":
            data[name] = (dims, np.asarray(arr, bool).astype(np.int8),
                          dict(ASSUMPTIONS_HOLD_ATTRS))
        elif name == "assumptions":
            data[name] = (dims, np.asarray(arr, dtype=str), dict(ASSUMPTIONS_ATTRS))
        elif name == "attempts":
            data[name] = (dims, np.asarray(arr, np.int32),
                          {"long_name": "attempts of the point", "units": "1"})
        elif name in VARIABLES:
            long_name, units = VARIABLES[name]
            dtype = np.int64 if name in _INTEGER else float
            data[name] = (dims, np.asarray(arr, dtype), {"long_name": long_name, "units": units})
    return xr.Dataset(data, coords=coords, attrs=attrs)


def _model_attrs(model, bed_mass: float | None) -> dict:
    out = {"model": getattr(model, "fidelity", type(model).__name__)}
    if bed_mass is not None:
        out.update(bed_mass=float(bed_mass), bed_mass_units="kg")
    gravity = getattr(model, "gravity", None)
    if isinstance(gravity, int | float):  # the fields hold at this g only
        out.update(gravity=float(gravity), gravity_units="m/s^2")
    damper = getattr(model, "damper", None)
    if damper is not None:
        out.update(clearance=damper.clearance, clearance_units="m",
                   particle_count=damper.count)
    return out


def effective_field(model, frequency, amplitude, attrs: dict | None = None,
                    particles=None) -> xr.Dataset:
    """Evaluate ``model.response`` on the grid ``frequency x amplitude`` in one call.

    Parameters
    ----------
    model
        A :class:`~pdamper.models.DamperModel` (anything with ``response(f, X)``).
    frequency, amplitude : array_like
        1-D grids, f [Hz] and X [m].
    attrs
        Extra global attributes (inputs, version) to record.
    particles
        Optional 1-D grid of particle counts: a third, leading dimension (the model is
        re-made for each count with ``model.with_damper``).

    Returns
    -------
    xarray.Dataset
        Variables ``loss_factor``, ``effective_mass_ratio``, ``dissipated_energy_per_cycle``,
        ``motion_mode``, ``subharmonic_order``, ``stationary``, ``status`` on coordinates
        ``frequency`` [Hz] and ``amplitude`` [m] (and ``particles``).
    """
    if not callable(getattr(model, "response", None)):
        raise InputError("model", "must be a damper model with response(f, X) (a "
                         "pdamper.models.DamperModel, e.g. AnalyticalDamper(damper)), got "
                         f"{type(model).__name__}")
    _require_grid(frequency, amplitude, particles)
    f = _grid("frequency", frequency, "Hz")
    x = _grid("amplitude", amplitude, "m")
    models = [model] if particles is None else [
        model.with_damper(model.damper.with_count(int(n))) for n in np.ravel(particles)]
    rs = [m.response(f[:, None], x[None, :]) for m in models]

    def stack(get):
        arrs = [np.array(np.broadcast_to(np.asarray(get(r)), (f.size, x.size))) for r in rs]
        return arrs[0] if particles is None else np.stack(arrs)

    values = {
        "loss_factor": stack(lambda r: r.loss_factor),
        "effective_mass_ratio": stack(lambda r: r.effective_mass_ratio),
        "dissipated_energy_per_cycle": stack(lambda r: r.dissipated_energy_per_cycle),
        "motion_mode": stack(lambda r: r.mode),
        "subharmonic_order": stack(lambda r: -1 if r.subharmonic_order is None
                                   else r.subharmonic_order),
        "stationary": stack(lambda r: -1 if r.stationary is None else r.stationary),
        "status": stack(lambda r: 0),
    }
    for name in rs[0].diagnostics:
        if name in VARIABLES or name in ASSUMPTION_VARIABLES:
            values[name] = stack(lambda r, n=name: r.diagnostics[n])
    coords, dims = _coords(f, x, particles)
    ds = _dataset(values, coords, dims, {})
    ds.attrs.update(_model_attrs(model, rs[0].bed_mass if particles is None else None))
    if particles is not None:
        ds.attrs.pop("particle_count", None)
        ds["bed_mass"] = ("particles", np.array([r.bed_mass for r in rs]),
                          {"long_name": "mass of the particle bed", "units": "kg"})
    ds.attrs.update(attrs or {})
    return ds


# ------------------------------------------------------------------ on the sweep engine
def field_point(model, params: dict) -> dict:
    """Point function of :func:`sweep_field`: the response of ``model`` at one point.

    ``params``: ``frequency`` [Hz], ``amplitude`` [m] and optionally ``particles`` (the
    model is then re-made for that count). Returns plain numbers: the response, its
    stationarity and motion mode, and the numeric diagnostics of the run.
    """
    m = model
    if params.get("particles") is not None:
        m = model.with_damper(model.damper.with_count(int(params["particles"])))
    r = m.response(float(params["frequency"]), float(params["amplitude"]))
    out = {
        "loss_factor": float(r.loss_factor),
        "effective_mass_ratio": float(r.effective_mass_ratio),
        "dissipated_energy_per_cycle": float(r.dissipated_energy_per_cycle),
        "motion_mode": int(r.mode),
        "subharmonic_order": -1 if r.subharmonic_order is None else int(r.subharmonic_order),
        "stationary": -1 if r.stationary is None else int(bool(r.stationary)),
        "bed_mass": float(r.bed_mass),
    }
    for name, arr in r.diagnostics.items():
        v = np.asarray(arr).item() if np.ndim(arr) == 0 else None
        if isinstance(v, bool | int | float | np.number):
            out[name] = v.item() if isinstance(v, np.number) else v
        elif name == "assumptions" and v is not None:
            out[name] = v  # the reasons (a str, "" where the assumptions hold)
        elif name == "stationarity" and v is not None:
            out["steady_reason"] = v.reason
        elif name == "motion" and v is not None:
            out["mode_reason"] = v.reason
    return out


def model_fingerprint(model) -> str:
    """Hash of a model's pickled state: identifies its inputs in a sweep's context."""
    return hashlib.sha256(pickle.dumps(model, protocol=4)).hexdigest()[:16]


def sweep_field(model, frequency, amplitude, particles=None, *, store=None,
                context: dict | None = None, attrs: dict | None = None,
                progress: Callable | None = None, **sweep_options):
    """Evaluate ``model`` point by point on the sweep engine (:func:`pdamper.sweep.run_sweep`).

    Parameters
    ----------
    model
        A picklable :class:`~pdamper.models.DamperModel` (e.g. a
        :class:`~pdamper.models.DEMDamper`).
    frequency, amplitude : array_like
        1-D grids, f [Hz] and X [m].
    particles
        Optional 1-D grid of particle counts (a leading dimension).
    store
        Directory for the per-point results (resume); None: no store.
    context
        What the results depend on besides the point (default: the pdamper version and a
        fingerprint of the model); part of every point's key.
    attrs
        Extra global attributes.
    progress
        ``progress(done, total, point_result)``.
    sweep_options
        ``workers``, ``scheduler``, ``client``, ``serial``, ``retries``, ``retry_if``,
        ``retry_failed`` of :func:`~pdamper.sweep.run_sweep`.

    Returns
    -------
    (xarray.Dataset, pdamper.sweep.SweepResult)
        The field (variables as :func:`effective_field`, plus ``error``, ``attempts`` and
        the diagnostics the model reports; NaN / -1 where a point failed) and the sweep.
    """
    from pdamper._version import __version__, source_digest
    from pdamper.sweep import run_sweep

    if not callable(getattr(model, "response", None)):
        raise InputError("model", "must be a damper model with response(f, X) (a "
                         "pdamper.models.DamperModel, e.g. AnalyticalDamper(damper)), got "
                         f"{type(model).__name__}")

    _require_grid(frequency, amplitude, particles)
    f = _grid("frequency", frequency, "Hz")
    x = _grid("amplitude", amplitude, "m")
    counts = None if particles is None else np.asarray(particles, int).ravel()
    grid = [(None,)] if counts is None else [(int(n),) for n in counts]
    points = []
    for (n,) in grid:
        for fi in f:
            for xi in x:
                p = {"frequency": float(fi), "amplitude": float(xi)}
                if n is not None:
                    p["particles"] = n
                points.append(p)
    ctx = {"pdamper_version": __version__, "pdamper_source": source_digest(),
           "model": model_fingerprint(model)} if context is None else dict(context)
    sweep = run_sweep(functools.partial(field_point, model), points, store=store, context=ctx,
                      progress=progress, **sweep_options)
    shape = (f.size, x.size) if counts is None else (counts.size, f.size, x.size)
    ok = np.array([p.ok for p in sweep.points]).reshape(shape)
    values: dict[str, np.ndarray] = {}
    names = ["loss_factor", "effective_mass_ratio", "dissipated_energy_per_cycle",
             "motion_mode", "subharmonic_order", "stationary"]
    names += [k for k in VARIABLES if k not in names
              and any(k in p.values for p in sweep.points)]
    for name in names:
        fill = -1 if name in _INTEGER or name in ("motion_mode", "stationary") else math.nan
        values[name] = sweep.values(name, fill).reshape(shape)
    values["status"] = sweep.status_codes().reshape(shape)
    values["error"] = np.array(sweep.errors(), dtype=str).reshape(shape)
    values["attempts"] = np.array([p.attempts for p in sweep.points]).reshape(shape)
    values["point_seconds"] = np.array([p.seconds for p in sweep.points]).reshape(shape)
    coords, dims = _coords(f, x, counts)
    ds = _dataset(values, coords, dims, {})
    reasons = {k: np.array([p.values.get(k, "") for p in sweep.points], dtype=str)
               for k in ("steady_reason", "mode_reason")}
    if any("assumptions_hold" in p.values for p in sweep.points):  # the analytical model's
        hold = np.array([bool(p.values.get("assumptions_hold", True)) for p in sweep.points])
        why = np.array([str(p.values.get("assumptions", "")) for p in sweep.points], dtype=str)
        ds["assumptions_hold"] = (dims, hold.reshape(shape).astype(np.int8),
                                  dict(ASSUMPTIONS_HOLD_ATTRS))
        ds["assumptions"] = (dims, why.reshape(shape), dict(ASSUMPTIONS_ATTRS))
    for k, long_name in (("steady_reason", "why the window is not steady (empty: steady)"),
                         ("mode_reason", "how the motion mode was decided")):
        if any(reasons[k]):
            ds[k] = (dims, reasons[k].reshape(shape), {"long_name": long_name})
    ds.attrs.update(_model_attrs(model, model.bed_mass if counts is None else None))
    if counts is not None:
        ds.attrs.pop("particle_count", None)
        ds["bed_mass"] = ("particles", np.array(
            [model.damper.with_count(int(n)).bed_mass for n in counts]),
            {"long_name": "mass of the particle bed", "units": "kg"})
    ds.attrs.update(points=int(ok.size), points_failed=int((~ok).sum()),
                    points_reused=sweep.reused, points_computed=sweep.computed,
                    sweep_seconds=float(sweep.seconds), sweep_workers=int(sweep.workers),
                    sweep_retries=int(sweep.attrs["retries"]))
    ds.attrs.update(attrs or {})
    return ds, sweep


def field_agreement(ds, reference) -> dict:
    """How well the field ``ds`` (e.g. the DEM's) agrees with ``reference`` (e.g. the
    analytical one) on the points where ``ds`` has a result (``status == 0``).

    ``reference`` is interpolated onto the grid of ``ds`` where the grids differ (its
    modes by nearest neighbour).

    Returns
    -------
    dict
        ``cells`` (points with a result), ``failed``, ``steady`` (of the cells),
        ``mode_agreement`` (share of cells with the same motion mode),
        ``median_abs_delta_eta`` (all cells) and ``by_mode``: for every motion mode of the
        reference, ``{"cells", "mode_agreement", "median_abs_delta_eta"}``.
    """
    from pdamper.analysis.modes import MotionMode

    same = (np.array_equal(reference["frequency"].values, ds["frequency"].values)
            and np.array_equal(reference["amplitude"].values, ds["amplitude"].values))
    ref = reference if same else reference.interp(frequency=ds["frequency"],
                                                  amplitude=ds["amplitude"])
    ref_mode = (reference["motion_mode"] if same else reference["motion_mode"].sel(
        frequency=ds["frequency"], amplitude=ds["amplitude"], method="nearest")).values
    ok = (ds["status"].values == 0) if "status" in ds else np.ones(ds["loss_factor"].shape, bool)
    delta = np.abs(ds["loss_factor"].values - ref["loss_factor"].values)
    agree = ds["motion_mode"].values == ref_mode
    out = {"cells": int(ok.sum()), "failed": int((~ok).sum()),
           "steady": int(((ds["stationary"].values == 1) & ok).sum()) if "stationary" in ds
           else int(ok.sum()),
           "mode_agreement": float(agree[ok].mean()) if ok.any() else math.nan,
           "median_abs_delta_eta": float(np.median(delta[ok])) if ok.any() else math.nan,
           "by_mode": {}}
    by_mode: dict[str, dict] = out["by_mode"]  # type: ignore[assignment]
    for mode in MotionMode:
        sel = ok & (ref_mode == int(mode))
        if sel.any():
            by_mode[mode.label] = {"cells": int(sel.sum()),
                                          "mode_agreement": float(agree[sel].mean()),
                                          "median_abs_delta_eta": float(np.median(delta[sel]))}
    return out
