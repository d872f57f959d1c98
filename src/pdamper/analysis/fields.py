"""Effective fields: Level II quantities over (frequency x amplitude) grids.

Every damper model answers :meth:`~pdamper.models.DamperModel.response` with a
:class:`~pdamper.models.DamperResponse`; :func:`effective_field` evaluates it on a grid and
labels it as an :class:`xarray.Dataset` with units, ready for NetCDF, plots and
interpolation. It only calls ``model.response``: any fidelity works, and this Level II
module imports no model.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from pdamper.analysis.modes import MODE_FLAG_ATTRS
from pdamper.errors import InputError

if TYPE_CHECKING:  # pragma: no cover
    import xarray as xr


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


def effective_field(model, frequency, amplitude, attrs: dict | None = None) -> xr.Dataset:
    """Evaluate ``model.response`` on the grid ``frequency x amplitude``.

    Parameters
    ----------
    model
        A :class:`~pdamper.models.DamperModel` (anything with ``response(f, X)``).
    frequency, amplitude : array_like
        1-D grids, f [Hz] and X [m].
    attrs
        Extra global attributes (inputs, version) to record.

    Returns
    -------
    xarray.Dataset
        Variables ``loss_factor``, ``effective_mass_ratio``, ``dissipated_energy_per_cycle``,
        ``motion_mode`` on coordinates ``frequency`` [Hz] and ``amplitude`` [m].
    """
    import xarray as xr

    if not callable(getattr(model, "response", None)):
        raise InputError("model", "must be a damper model with response(f, X) (a "
                         "pdamper.models.DamperModel, e.g. AnalyticalDamper(damper)), got "
                         f"{type(model).__name__}")
    f = _grid("frequency", frequency, "Hz")
    x = _grid("amplitude", amplitude, "m")
    r = model.response(f[:, None], x[None, :])
    dims = ("frequency", "amplitude")
    ds = xr.Dataset(
        {
            "loss_factor": (dims, np.asarray(r.loss_factor, float),
                            {"long_name": "effective loss factor (Eq. 3)", "units": "1"}),
            "effective_mass_ratio": (dims, np.asarray(r.effective_mass_ratio, float),
                                     {"long_name": "effective particle mass / bed mass",
                                      "units": "1"}),
            "dissipated_energy_per_cycle": (
                dims, np.asarray(r.dissipated_energy_per_cycle, float),
                {"long_name": "dissipated energy per cycle E~ (Eq. 2)", "units": "J"}),
            "motion_mode": (dims, np.asarray(r.mode, np.int8),
                            {"long_name": "motion mode", **MODE_FLAG_ATTRS}),
        },
        coords={
            "frequency": ("frequency", f, {"long_name": "excitation frequency", "units": "Hz"}),
            "amplitude": ("amplitude", x, {"long_name": "container stroke amplitude X",
                                           "units": "m"}),
        },
        attrs={"bed_mass": float(r.bed_mass), "bed_mass_units": "kg",
               "model": getattr(model, "fidelity", type(model).__name__), **(attrs or {})},
    )
    damper = getattr(model, "damper", None)
    if damper is not None:
        ds.attrs.update(clearance=damper.clearance, clearance_units="m",
                        particle_count=damper.count)
    return ds
