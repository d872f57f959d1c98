"""The effective-field damper model (the paper's model 2, Sects. 3.1.2 and 4.1).

The damper is described by pre-computed effective fields: the loss factor eta (Fig. 5b) and
the effective particle mass (Fig. 5d) over a (frequency x stroke) grid, as written by
``pdamper map`` (DEM or analytical, :func:`pdamper.analysis.fields.effective_field`).
:meth:`EffectiveFieldDamper.response` interpolates them; the Level III pseudo-force coupling
(Sect. 4.1) turns them into ``F = -(m_eff x'' + d x')`` at each minimum of the end-effector.

What is interpolated
--------------------
The loss factor eta (Eq. 3), not the dissipated energy E~ (Eq. 2), by default. The coupling
needs ``d = E~ / (pi W X^2)`` and with Eq. (3) (``E~ = pi eta m_bed W^2 X^2``) this is
exactly ``d = eta m_bed W``: an interpolation error of eta is the same relative error of d.
E~ grows like X^2 W^2 across the grid, so linear interpolation of E~ adds the curvature of
that factor to the error (docs/level3.md: on the paper's 14 x 24 analytical map, along the
32-sphere trajectory, the median |delta eta| at the updates is 0.09 interpolating eta and
0.14 interpolating E~, and the final amplitude is model 3's 10.48 mm against 9.12 mm).
eta is also independent of the bed mass, which lets a map be reused for another particle
material of the same geometry (Sect. 3.2) and lets maps of different particle counts be
interpolated. ``interpolate="dissipated_energy"`` is available for comparison.
The effective mass ratio m_eff / m_bed (Eq. 4) is interpolated the same way (bilinear); the
motion mode, a category, is taken from the nearest valid grid point.

Particle-count axis
-------------------
A map may carry a third axis ``particles``. A count on the axis is selected; a count between
two counts n_a < n < n_b is interpolated linearly in n *at equal stroke-to-clearance ratio*
X / h(n) (each neighbour is read at ``X h(n_a) / h(n)``, resp. ``h(n_b)``), because the
collect-and-collide motion modes scale with the clearance (X_opt = h / pi, Eq. 19); plain
interpolation at equal X would smear the double-CaC band edge, which moves with h.
A count outside the axis follows the extrapolation policy.

Failed and non-stationary cells
-------------------------------
A cell is *valid* if its values are finite, its ``status`` (if the map has one) says it
was computed (0, ``"ok"``, or the CF flag meaning ``ok``/``done``/``success``), and, with
``nonstationary="mask"`` (default), its ``stationary`` flag (if present) is true: a transient
is never used as a steady value. Invalid cells are holes: a query uses the valid corners
of its grid cell with their bilinear weights renormalised, and fails with an error naming
the cell if none of the four is valid. ``nonstationary="use"`` uses transient cells too (and
counts them in the lookup's diagnostics).

Outside the map
---------------
``extrapolation="error"`` (default): a point outside the map's (f, X) range (or count range)
is an :class:`~pdamper.errors.InputError` naming the point, the map's range and the options.
``"clamp"``: the value at the nearest point of the map's boundary (for strokes below the
map this is the solid-like value of the smallest stroke; crude above the map).
``"analytic"``: the analytical model (model 3, Eqs. 5-22) answers outside the map.
Every response records per point where its value came from (:class:`FieldLookup`).

Matching the map to the damper
------------------------------
The map's attributes (``clearance``, ``particle_count``, and the container and particle
geometry in ``inputs``) must match the simulated damper: the fields are a property of that
geometry. A mismatch is an error (``strict=True``, default) or a logged warning
(``strict=False``). The particle material and density may differ: eta and the mass ratio
are normalised by the bed mass (Sect. 3.2: the dissipation is linear in the bed mass), and
the response uses the simulated damper's own m_bed.
"""

from __future__ import annotations

import json
import logging
import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from pdamper.damper import ParticleDamper
from pdamper.errors import InputError, check_range
from pdamper.models.analytical import AnalyticalDamper
from pdamper.models.base import DamperModel, DamperResponse

logger = logging.getLogger(__name__)

#: Policies for points outside the map.
EXTRAPOLATIONS = ("error", "clamp", "analytic")
#: Interpolated dissipation quantity.
INTERPOLATED = ("loss_factor", "dissipated_energy")
#: Policies for cells whose ``stationary`` flag is false.
NONSTATIONARY = ("mask", "use")

#: Where a looked-up value came from (``FieldLookup.source``).
SOURCE_MAP, SOURCE_CLAMPED, SOURCE_ANALYTIC = 0, 1, 2

#: Names of a map's particle-count dimension (``pdamper map`` writes ``particles``).
_COUNT_DIMS = ("particles", "particle_count")
#: Status flag meanings that mark a computed cell.
_OK_MEANINGS = ("ok", "done", "success", "computed", "valid")
#: Relative tolerance of geometry comparisons between map and damper.
_GEOMETRY_RTOL = 1e-6
#: Mode code of unclassified points (DEM maps before motion-mode classification).
_UNCLASSIFIED = -1


@dataclass(frozen=True)
class FieldLookup:
    """Diagnostics of one :meth:`EffectiveFieldDamper.response` (its ``details``).

    Attributes
    ----------
    source
        Per point: 0 interpolated in the map, 1 clamped to the map's boundary, 2 answered by
        the analytical model (extrapolation policy).
    holes
        Per point: number of invalid corners (failed or masked non-stationary cells) that
        the masked interpolation left out [-].
    transient
        Per point: number of non-stationary corners used (``nonstationary="use"``) [-].
    file
        The map file (None for an in-memory map).
    count_axis
        The map's particle counts used (one, or the two neighbours), empty without an axis.
    """

    source: np.ndarray
    holes: np.ndarray
    transient: np.ndarray
    file: str | None
    count_axis: tuple[int, ...] = ()


class _Grid:
    """One (f, X) field: values, validity and masked bilinear lookup."""

    def __init__(self, f, x, eta, ratio, mode, valid, transient):
        self.f, self.x = f, x
        self.eta, self.ratio, self.mode = eta, ratio, mode
        self.valid, self.transient = valid, transient

    def inside(self, f, x):
        tol_f = 1e-12 * max(abs(self.f[-1]), 1.0)
        tol_x = 1e-12 * max(abs(self.x[-1]), 1.0)
        return ((f >= self.f[0] - tol_f) & (f <= self.f[-1] + tol_f)
                & (x >= self.x[0] - tol_x) & (x <= self.x[-1] + tol_x))

    def lookup(self, f, x):
        """Masked bilinear interpolation at points inside the grid (clipped onto it).

        Returns eta, ratio, mode, holes, transient, ok (whether a valid corner existed)."""
        f = np.clip(f, self.f[0], self.f[-1])
        x = np.clip(x, self.x[0], self.x[-1])
        i = np.clip(np.searchsorted(self.f, f, side="right") - 1, 0, len(self.f) - 2)
        j = np.clip(np.searchsorted(self.x, x, side="right") - 1, 0, len(self.x) - 2)
        u = (f - self.f[i]) / (self.f[i + 1] - self.f[i])
        v = (x - self.x[j]) / (self.x[j + 1] - self.x[j])
        corners = ((i, j, (1 - u) * (1 - v)), (i + 1, j, u * (1 - v)),
                   (i, j + 1, (1 - u) * v), (i + 1, j + 1, u * v))
        w_sum = np.zeros(f.shape)
        n_valid = np.zeros(f.shape)
        eta = np.zeros(f.shape)
        ratio = np.zeros(f.shape)
        eta_mean = np.zeros(f.shape)
        ratio_mean = np.zeros(f.shape)
        holes = np.zeros(f.shape, int)
        transient = np.zeros(f.shape, int)
        best_w = np.full(f.shape, -1.0)
        mode = np.full(f.shape, _UNCLASSIFIED, int)
        for ci, cj, w in corners:
            ok = self.valid[ci, cj]
            e = np.where(ok, self.eta[ci, cj], 0.0)
            r = np.where(ok, self.ratio[ci, cj], 0.0)
            eta += w * e
            ratio += w * r
            eta_mean += e
            ratio_mean += r
            w_sum += np.where(ok, w, 0.0)
            n_valid += ok
            holes += (~ok) & (w > 0)
            transient += ok & self.transient[ci, cj] & (w > 0)
            better = ok & (w > best_w)
            mode = np.where(better, self.mode[ci, cj], mode)
            best_w = np.where(better, w, best_w)
        has = n_valid > 0
        # a query sitting on an invalid node has all its weight there: fall back to the
        # plain mean of the valid corners of the cell
        on_hole = has & (w_sum < 1e-12)
        with np.errstate(invalid="ignore", divide="ignore"):
            eta = np.where(on_hole, eta_mean / np.maximum(n_valid, 1), eta / w_sum)
            ratio = np.where(on_hole, ratio_mean / np.maximum(n_valid, 1), ratio / w_sum)
        return eta, ratio, mode, holes, transient, has


def _whole_count(value) -> int | None:
    try:
        if int(value) == value:
            return int(value)
    except (TypeError, ValueError, OverflowError):
        pass
    return None


class EffectiveFieldDamper(DamperModel):
    """Particle damper described by effective fields over (f x X) (the paper's model 2).

    Parameters
    ----------
    damper
        The simulated physical damper; it must match the map's geometry (see ``strict``).
    file
        NetCDF map written by ``pdamper map`` (or
        :func:`~pdamper.analysis.fields.effective_field` and ``to_netcdf``).
    field
        The map as an :class:`xarray.Dataset` instead of a file.
    extrapolation
        ``"error"`` (default), ``"clamp"`` or ``"analytic"``: what answers outside the map
        (module docstring).
    interpolate
        ``"loss_factor"`` (default) or ``"dissipated_energy"``: the interpolated dissipation.
    nonstationary
        ``"mask"`` (default): cells flagged non-stationary are holes; ``"use"``: use them.
    strict
        Whether a map made for another geometry is an error (default) or a warning.
    gravity
        g [m/s^2] of the simulated damper, or None (not checked). A map records the g it
        was made at (attribute ``gravity``); a map made at another g is refused whatever
        ``strict`` says: the fields of a bed under gravity do not hold without it.

    Examples
    --------
    >>> import numpy as np
    >>> from pdamper.analysis.fields import effective_field
    >>> from pdamper.parameters import PAPER_DAMPER
    >>> ds = effective_field(AnalyticalDamper(PAPER_DAMPER), np.linspace(4, 8, 9),
    ...                      np.linspace(0.005, 0.06, 12))
    >>> m2 = EffectiveFieldDamper(PAPER_DAMPER, field=ds)
    >>> r2, r3 = m2.response(6.0, 0.05), AnalyticalDamper(PAPER_DAMPER).response(6.0, 0.05)
    >>> round(float(r2.loss_factor), 3) == round(float(r3.loss_factor), 3)  # on a grid node
    True
    """

    fidelity = "fields"
    coupling = "pseudo_force"
    takes_gravity = True
    #: the map's fields were computed at the friction and COR of its own runs
    unused_inputs = {
        f: "the effective fields are read from the map, computed at the friction and COR "
           "of its own runs (a map per value: pdamper map --model dem)"
        for f in ("particles.friction", "dem.restitution_pp", "dem.restitution_pw",
                  "restitution.particle_particle", "restitution.particle_wall")}
    #: per particle count of the map (None: no count axis): the count, its grid, its bed mass
    _grids: list[tuple[int | None, _Grid, float]]
    #: the grids read for the damper's count with their weights (empty: model 3 throughout)
    _pair: tuple[tuple[tuple[int | None, _Grid, float], float], ...]

    def __init__(self, damper: ParticleDamper, file: str | Path | None = None, *,
                 field: Any = None, extrapolation: str = "error",
                 interpolate: str = "loss_factor", nonstationary: str = "mask",
                 strict: bool = True, gravity: float | None = None):
        super().__init__(damper)
        for name, value, allowed in (("fields.extrapolation", extrapolation, EXTRAPOLATIONS),
                                     ("fields.interpolate", interpolate, INTERPOLATED),
                                     ("fields.nonstationary", nonstationary, NONSTATIONARY)):
            if value not in allowed:
                raise InputError(name, f"must be one of {', '.join(allowed)}, got {value!r}")
        if not isinstance(strict, bool):
            raise InputError("fields.strict", f"must be true or false, got {strict!r}")
        self.extrapolation = extrapolation
        self.interpolate = interpolate
        self.nonstationary = nonstationary
        self.strict = strict
        self.gravity = None if gravity is None else check_range("excitation.gravity", gravity,
                                                                low=0.0, unit="m/s^2")
        if (file is None) == (field is None):
            raise InputError("fields.file", "the fields model needs one effective-field map: "
                             "a NetCDF file from `pdamper map` (--fields FILE or [fields] file)")
        self.file = None if file is None else str(file)
        self.field = field
        ds = _open(file) if field is None else field
        self._label = self.file or "the given map"
        self.map_attrs = dict(ds.attrs)
        self._map = ds
        self._analytic = (AnalyticalDamper(damper, **({} if self.gravity is None else
                                                      {"gravity": self.gravity}))
                          if extrapolation == "analytic" else None)
        self.reset_outside()
        self._setup(ds)

    # ------------------------------------------------------------------ set-up
    def _setup(self, ds) -> None:
        for coord in ("frequency", "amplitude"):
            if coord not in ds.dims:
                raise InputError("fields.file", f"{self._label} has no {coord!r} axis; "
                                 "expected a map from `pdamper map`")
        for coord, unit in (("frequency", "Hz"), ("amplitude", "m")):
            got = ds[coord].attrs.get("units", unit)
            if got != unit:
                raise InputError("fields.file", f"{self._label}: {coord} must be in {unit}, "
                                 f"got {got!r}")
        dissipation = "loss_factor" if self.interpolate == "loss_factor" else \
            "dissipated_energy_per_cycle"
        for var in (dissipation, "effective_mass_ratio"):
            if var not in ds:
                raise InputError("fields.file", f"{self._label} has no variable {var!r}")
        count_dim = next((d for d in _COUNT_DIMS if d in ds.dims), None)
        self.count_dim = count_dim
        ds = ds.transpose(*([count_dim] if count_dim else []), "frequency", "amplitude", ...)
        f = np.asarray(ds["frequency"].values, float)
        x = np.asarray(ds["amplitude"].values, float)
        for name, axis in (("frequency", f), ("amplitude", x)):
            if axis.size < 2:
                raise InputError("fields.file", f"{self._label}: the {name} axis needs at least "
                                 f"2 values to interpolate, got {axis.size}")
            if not np.all(np.isfinite(axis)) or not np.all(np.diff(axis) > 0):
                raise InputError("fields.file", f"{self._label}: the {name} axis must be "
                                 "finite and strictly increasing")
        self.frequency_range = (float(f[0]), float(f[-1]))
        self.amplitude_range = (float(x[0]), float(x[-1]))
        valid, transient = _validity(ds, self._label)
        if self.nonstationary == "use":
            valid = valid | (transient & _computed(ds))
        self.masked_cells = int(np.count_nonzero(~valid))
        if self.masked_cells:
            logger.warning("%s: %d of %d cells are failed or non-stationary and left out of "
                           "the interpolation", self._label, self.masked_cells, valid.size)
        mode = (np.asarray(ds["motion_mode"].values, int) if "motion_mode" in ds
                else np.full(valid.shape, _UNCLASSIFIED))
        ratio = np.asarray(ds["effective_mass_ratio"].values, float)
        raw = np.asarray(ds[dissipation].values, float)
        counts: list[int | None]
        if count_dim is None:
            counts = [None]
            bed_masses = [float(ds.attrs.get("bed_mass", self.damper.bed_mass))]
            raw, ratio, mode, valid, transient = (a[None] for a in (raw, ratio, mode, valid,
                                                                     transient))
        else:
            found = [_whole_count(n) for n in ds[count_dim].values]
            whole = [n for n in found if n is not None]
            if len(whole) < len(found) or any(n < 1 for n in whole) or any(np.diff(whole) <= 0):
                raise InputError("fields.file", f"{self._label}: the {count_dim} axis must hold "
                                 "increasing whole counts >= 1")
            one = self.damper.particle_mass
            bed_masses = [n * one for n in whole]
            counts = list(whole)
        valid = valid & np.isfinite(raw) & np.isfinite(ratio)
        self._grids = []
        for k, n in enumerate(counts):  # raw: eta, or E~ with interpolate="dissipated_energy"
            self._grids.append((n, _Grid(f, x, raw[k], ratio[k], mode[k], valid[k],
                                         transient[k]), bed_masses[k]))
        self.counts = tuple(n for n in counts if n is not None)
        self._check_damper(ds)
        self._select_count()

    def _check_damper(self, ds) -> None:
        """The map's geometry against the simulated damper (module docstring)."""
        d = self.damper
        problems = []
        attrs = ds.attrs
        if self.count_dim is None:
            n = attrs.get("particle_count")
            if n is not None and int(n) != d.count:
                problems.append(f"the map is for {int(n)} particles, the damper has {d.count} "
                                "(make a map with --particles N or a particle-count axis)")
            h = attrs.get("clearance")
            if h is not None and not math.isclose(float(h), d.clearance, rel_tol=_GEOMETRY_RTOL,
                                                  abs_tol=1e-12):
                problems.append(f"clearance {float(h) * 1e3:g} mm in the map, "
                                f"{d.clearance * 1e3:g} mm in the damper")
        inputs = attrs.get("inputs")
        if isinstance(inputs, str):
            try:
                inputs = json.loads(inputs)
            except ValueError:
                inputs = None
        if isinstance(inputs, dict):
            geometry = (("container", "length", d.length), ("container", "width", d.width),
                        ("container", "depth", d.depth), ("particles", "radius",
                                                          d.particle_radius))
            for section, key, ours in geometry:
                theirs = (inputs.get(section) or {}).get(key)
                if isinstance(theirs, int | float) and not math.isclose(
                        float(theirs), ours, rel_tol=_GEOMETRY_RTOL):
                    problems.append(f"{section}.{key} {float(theirs) * 1e3:g} mm in the map, "
                                    f"{ours * 1e3:g} mm in the damper")
            mat = (inputs.get("particles") or {}).get("material")
            name = mat.get("name") if isinstance(mat, dict) else mat
            if isinstance(name, str) and name.lower() != d.particle_material.name.lower():
                logger.info("%s was made for %s spheres, the damper has %s: eta and the mass "
                            "ratio are per bed mass (Sect. 3.2), so the map is used as is",
                            self._label, name, d.particle_material.name)
        self._check_gravity(attrs, inputs)
        if problems:
            msg = f"{self._label} does not match the damper: " + "; ".join(problems)
            if self.strict:
                raise InputError("fields.file", msg + " (set [fields] strict = false to use it "
                                 "anyway)")
            logger.warning("%s", msg)

    def _check_gravity(self, attrs, inputs) -> None:
        """Refuse a map made at another g than :attr:`gravity` (the ``gravity`` attribute;
        for maps without it, ``excitation.gravity`` of its recorded ``inputs``)."""
        if self.gravity is None:
            return
        theirs = attrs.get("gravity")
        if theirs is None and isinstance(inputs, dict):
            theirs = (inputs.get("excitation") or {}).get("gravity")
        try:
            made_at = float(theirs)
        except (TypeError, ValueError):
            return  # a map that does not say: nothing to compare
        if not math.isclose(made_at, self.gravity, rel_tol=_GEOMETRY_RTOL, abs_tol=1e-12):
            raise InputError("excitation.gravity", f"must be the g {self._label} was made at, "
                             f"{made_at:g} m/s^2, got {self.gravity:g} m/s^2 (make a map "
                             f"with [excitation] gravity = \"{self.gravity:g} m/s^2\")")

    def _select_count(self) -> None:
        n = self.damper.count
        if self.count_dim is None:
            self._pair = ((self._grids[0], 1.0),)
            return
        counts = self.counts
        if n in counts:
            self._pair = ((self._grids[counts.index(n)], 1.0),)
            return
        if counts[0] < n < counts[-1]:
            k = int(np.searchsorted(counts, n)) - 1
            w = (n - counts[k]) / (counts[k + 1] - counts[k])
            self._pair = ((self._grids[k], 1.0 - w), (self._grids[k + 1], w))
            return
        if self.extrapolation == "error":
            raise InputError("fields.file", f"{self._label} covers {counts[0]}-{counts[-1]} "
                             f"particles, the damper has {n} (the fields model does not "
                             "extrapolate in the count; [fields] extrapolation = 'clamp' takes "
                             "the nearest count, 'analytic' uses model 3)")
        if self.extrapolation == "analytic":
            self._pair = ()
            return
        k = 0 if n < counts[0] else len(counts) - 1
        logger.warning("%s: %d particles outside the map's %d-%d; clamped to %d", self._label, n,
                       counts[0], counts[-1], counts[k])
        self._pair = ((self._grids[k], 1.0),)

    def with_damper(self, damper: ParticleDamper) -> EffectiveFieldDamper:
        """The same map and options for another damper (e.g. another particle count on a
        map with a count axis); the map is checked against it again."""
        new = EffectiveFieldDamper.__new__(EffectiveFieldDamper)
        DamperModel.__init__(new, damper)
        for k, v in vars(self).items():
            if k not in ("damper", "_pair", "_analytic"):
                setattr(new, k, v)
        new._analytic = AnalyticalDamper(damper) if self.extrapolation == "analytic" else None
        new.reset_outside()
        new._check_damper(self._map)
        new._select_count()
        return new

    # ------------------------------------------------------------------ Level II
    def response(self, frequency, amplitude) -> DamperResponse:
        """Interpolated eta, m_eff / m_bed and mode at every (f [Hz], X [m]) point; the
        ``details`` are a :class:`FieldLookup`."""
        f, x = np.broadcast_arrays(np.asarray(frequency, float), np.asarray(amplitude, float))
        if not (np.all(np.isfinite(f)) and np.all(f > 0) and np.all(np.isfinite(x))
                and np.all(x > 0)):
            raise InputError("fields", "frequency and amplitude must be finite and > 0")
        shape = f.shape
        f, x = f.ravel(), x.ravel()
        d = self.damper
        h = d.clearance
        w = 2.0 * math.pi * f
        eta = np.zeros(f.shape)
        ratio = np.zeros(f.shape)
        mode = np.full(f.shape, _UNCLASSIFIED, int)
        source = np.full(f.shape, SOURCE_MAP, int)
        holes = np.zeros(f.shape, int)
        transient = np.zeros(f.shape, int)
        analytic = np.zeros(f.shape, bool) if self._pair else np.ones(f.shape, bool)
        best = -1.0
        for (n, grid, m_bed), weight in self._pair:
            # read a neighbouring count at the same X / h (module docstring)
            xq = x if n is None or len(self._pair) == 1 else x * _clearance(d, n) / h
            inside = grid.inside(f, xq)
            self._count_outside(f, xq, inside, weight)
            if not np.all(inside):
                bad = int(np.flatnonzero(~inside)[0])
                if self.extrapolation == "error":
                    raise InputError("fields.file", self._outside_message(f[bad], xq[bad]))
                if self.extrapolation == "analytic":
                    analytic |= ~inside
                else:
                    source = np.where(inside, source, SOURCE_CLAMPED)
            e, r, mo, hl, tr, has = grid.lookup(f, xq)
            if not np.all(has | analytic):
                bad = int(np.flatnonzero(~(has | analytic))[0])
                raise InputError("fields.file", self._hole_message(grid, f[bad], xq[bad]))
            if self.interpolate == "dissipated_energy":
                # E~ of the map's bed at its (f, X) -> eta, then as for the loss factor
                with np.errstate(invalid="ignore", divide="ignore"):
                    e = e / (math.pi * m_bed * (2.0 * math.pi * f) ** 2 * xq**2)
            eta += weight * e
            ratio += weight * r
            holes += hl
            transient += tr
            if weight > best:
                mode, best = mo, weight
        if np.any(analytic):
            # points outside the map are analytic only with extrapolation = 'analytic'
            assert self._analytic is not None
            ra = self._analytic.response(f[analytic], x[analytic])
            eta[analytic] = ra.loss_factor
            ratio[analytic] = ra.effective_mass_ratio
            mode[analytic] = ra.mode
            source[analytic] = SOURCE_ANALYTIC
        e_tilde = math.pi * eta * d.bed_mass * w**2 * x**2  # Eq. (3) with V = X W
        details = FieldLookup(source.reshape(shape), holes.reshape(shape),
                              transient.reshape(shape), self.file,
                              tuple(n for (n, _g, _m), _w in self._pair if n is not None))
        return DamperResponse(frequency=f.reshape(shape), amplitude=x.reshape(shape),
                              mode=mode.reshape(shape), loss_factor=eta.reshape(shape),
                              dissipated_energy_per_cycle=e_tilde.reshape(shape),
                              effective_mass_ratio=ratio.reshape(shape), bed_mass=d.bed_mass,
                              details=details)

    # ------------------------------------------------------------------ outside the map
    def reset_outside(self) -> None:
        """Forget the lookups counted so far (:meth:`outside_record`); a run that reports
        them calls it first."""
        self._outside = {"lookups": 0, "outside": 0, "furthest": 1.0}

    def _count_outside(self, f: np.ndarray, x: np.ndarray, inside: np.ndarray,
                       weight: float) -> None:
        """Count the lookups and those outside the map's (f, X) range (the count read
        most: the weight of a neighbouring count's map is at least a half), and how far
        outside: the largest factor by which f or X is beyond the range."""
        if weight < 0.5:
            return
        rec = self._outside
        rec["lookups"] += int(f.size)
        out = ~inside
        if np.any(out):
            (f0, f1), (x0, x1) = self.frequency_range, self.amplitude_range
            fo, xo = f[out], x[out]
            beyond = np.maximum.reduce([fo / f1, f0 / fo, xo / x1, x0 / xo])
            rec["outside"] += int(out.sum())
            rec["furthest"] = max(rec["furthest"], float(beyond.max()))

    def outside_record(self) -> dict | None:
        """The lookups since :meth:`reset_outside` outside the map's (f, X) range, answered
        by the extrapolation policy (``"clamp"`` or ``"analytic"``; ``"error"`` refuses the
        first): ``{"lookups", "outside", "fraction", "furthest", "extrapolation",
        "frequency_range" [Hz], "amplitude_range" [m]}``, ``furthest`` the largest factor
        by which f or X was beyond the range [-]; None when every lookup was inside."""
        rec = self._outside
        if not rec["outside"]:
            return None
        (f0, f1), (x0, x1) = self.frequency_range, self.amplitude_range
        return {"lookups": rec["lookups"], "outside": rec["outside"],
                "fraction": rec["outside"] / max(rec["lookups"], 1),
                "furthest": rec["furthest"], "extrapolation": self.extrapolation,
                "frequency_range": [float(f0), float(f1)],
                "amplitude_range": [float(x0), float(x1)]}

    @staticmethod
    def outside_warning(record: dict) -> str:
        """One line of text for an :meth:`outside_record`."""
        return (f"warning: the fields map was used outside its range (f {record['frequency_range'][0]:g}-"
                f"{record['frequency_range'][1]:g} Hz, X {record['amplitude_range'][0] * 1e3:g}-"
                f"{record['amplitude_range'][1] * 1e3:g} mm) for {100 * record['fraction']:.3g} % "
                f"of the damper's lookups over the record, up to {record['furthest']:.3g}x "
                f"beyond it; extrapolation = '{record['extrapolation']}' answered there")

    def _outside_message(self, f: float, x: float) -> str:
        (f0, f1), (x0, x1) = self.frequency_range, self.amplitude_range
        return (f"f = {f:.4g} Hz, X = {x * 1e3:.4g} mm is outside {self._label} "
                f"(f {f0:g}-{f1:g} Hz, X {x0 * 1e3:g}-{x1 * 1e3:g} mm); enlarge the map or set "
                "[fields] extrapolation = 'clamp' or 'analytic'")

    def _hole_message(self, grid: _Grid, f: float, x: float) -> str:
        i = int(np.clip(np.searchsorted(grid.f, f, side="right") - 1, 0, len(grid.f) - 2))
        j = int(np.clip(np.searchsorted(grid.x, x, side="right") - 1, 0, len(grid.x) - 2))
        return (f"f = {f:.4g} Hz, X = {x * 1e3:.4g} mm lies in a cell of {self._label} whose "
                f"four corners (f {grid.f[i]:g}-{grid.f[i + 1]:g} Hz, X {grid.x[j] * 1e3:g}-"
                f"{grid.x[j + 1] * 1e3:g} mm) all failed or are non-stationary; recompute them "
                "or set [fields] nonstationary = 'use'")

    def __repr__(self) -> str:
        return (f"EffectiveFieldDamper(count={self.damper.count}, file={self.file!r}, "
                f"extrapolation={self.extrapolation!r})")


def _clearance(damper: ParticleDamper, count: int) -> float:
    """h = L (1 - n / n_max) of the damper's container with ``count`` spheres [m]."""
    return damper.length * (1.0 - count / damper.max_count)


def _open(file):
    import xarray as xr

    p = Path(file)
    if not p.is_file():
        raise InputError("fields.file", f"file not found: {p}")
    try:
        with xr.open_dataset(p, engine="h5netcdf") as ds:
            return ds.load()
    except (OSError, ValueError) as exc:
        raise InputError("fields.file", f"cannot read {p} as a NetCDF map ({exc})") from None


def _computed(ds) -> np.ndarray:
    """Cells whose ``status`` marks them computed (all cells without a status variable)."""
    shape = tuple(ds.sizes[d] for d in ds["effective_mass_ratio"].dims)
    if "status" not in ds:
        return np.ones(shape, bool)
    st = ds["status"].transpose(*ds["effective_mass_ratio"].dims)
    values = np.asarray(st.values)
    if values.dtype.kind in "USO":
        text = np.char.strip(np.char.lower(values.astype(str)))
        return np.isin(text, ("", *_OK_MEANINGS))
    meanings = str(st.attrs.get("flag_meanings", "")).split()
    flags = st.attrs.get("flag_values")
    if meanings and flags is not None and len(meanings) == len(np.atleast_1d(flags)):
        ok = [v for v, m in zip(np.atleast_1d(flags), meanings, strict=True)
              if m.lower() in _OK_MEANINGS]
        return np.isin(values, ok)
    return values == 0


def _validity(ds, label: str) -> tuple[np.ndarray, np.ndarray]:
    """(valid, transient): computed and stationary cells, and computed transient cells.

    ``stationary`` is read through its CF flags when it has them (``pdamper map`` writes
    ``-1 no_result, 0 transient, 1 steady``): only ``transient`` cells count as
    non-stationary; ``no_result`` (a model that does not assess stationarity, such as the
    analytical formulas, or a failed point, which ``status`` already excludes) does not.
    Without flags: booleans as they are; integers 1 steady, 0 transient, < 0 not assessed.
    """
    computed = _computed(ds)
    if "stationary" not in ds:
        return computed, np.zeros(computed.shape, bool)
    st = ds["stationary"].transpose(*ds["effective_mass_ratio"].dims)
    values = np.asarray(st.values)
    meanings = str(st.attrs.get("flag_meanings", "")).split()
    flags = st.attrs.get("flag_values")
    if meanings and flags is not None and len(meanings) == len(np.atleast_1d(flags)):
        transient_codes = [v for v, m in zip(np.atleast_1d(flags), meanings, strict=True)
                           if m.lower() in ("transient", "nonstationary", "non_stationary")]
        transient = np.isin(values, transient_codes)
    elif values.dtype.kind == "b":
        transient = ~values
    elif values.dtype.kind in "iuf":
        transient = np.asarray(values, float) == 0
    else:
        raise InputError("fields.file", f"{label}: 'stationary' must be boolean or integer "
                         "flags")
    return computed & ~transient, computed & transient
