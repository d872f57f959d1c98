"""Initial particle positions for DEM runs of a particle damper.

The container is a rectangular box given by its inner dimensions ``(Lx, Ly, Lz)`` [m] in
the container frame: ``x`` in ``[0, Lx]``, ``y`` in ``[0, Ly]``, ``z`` in ``[0, Lz]``, with
``z`` vertical (up, against gravity).

Two ways of filling it are provided:

* :func:`lattice_layers` -- a regular square lattice, layer by layer from the floor. For the
  benchmark damper of the reference paper (40 x 40 x 120 mm, spheres of radius 5 mm) four
  diameters fill the width exactly, so one layer holds 4 x 4 = 16 spheres, twelve layers fit
  and ``n_max = 192``; 32 spheres are two full layers standing in 16 "locked columns".
* :func:`random_packing` -- random non-overlapping positions, reproducible from an explicit
  integer seed, for every count the lattice holds. It first tries random sequential
  addition with a cell grid (:func:`sequential_packing`). Sequential addition cannot fill
  more than about 0.38 of space (its jamming limit; less in a narrow box, where the walls
  waste room), so above :data:`RANDOM_FILL_LIMIT`, or when one sphere finds no room in
  ``max_attempts`` tries, a dense random bed is grown instead (:func:`dense_packing`:
  random centres whose contact distance grows step by step while overlaps are relaxed
  away, a collective rearrangement). A count the growth cannot reach -- about 95 % of the
  lattice's count in a box that the lattice fills exactly -- is refused with the number
  that fits.

:func:`~pdamper.damper.max_particles` (with :func:`~pdamper.damper.spheres_per_layer` and
:func:`~pdamper.damper.max_layers`, re-exported here) is the capacity ``n_max`` used by the
clearance formula ``h = L (1 - n_p / n_max)``; its one home is :mod:`pdamper.damper`.
:func:`scaled_box` gives containers for scaling benchmarks with many particles.
"""

from __future__ import annotations

import math
import operator
from collections.abc import Sequence
from typing import Any

import numba
import numpy as np

from pdamper.damper import FIT_TOLERANCE as _FIT_TOLERANCE
from pdamper.damper import lattice_fit as _fits
from pdamper.damper import max_layers, max_particles, spheres_per_layer
from pdamper.errors import InputError, check_range

__all__ = [
    "RANDOM_FILL_LIMIT",
    "dense_packing",
    "lattice_layers",
    "max_layers",
    "max_particles",
    "random_packing",
    "scaled_box",
    "sequential_packing",
    "spheres_per_layer",
]

#: Largest solid volume fraction of the box that random sequential addition attempts [-]
#: (:func:`sequential_packing`; :func:`random_packing` grows a dense bed above it).
#: Random sequential addition of equal spheres jams at about 0.384 in unbounded space.
RANDOM_FILL_LIMIT = 0.35

#: Largest solid volume fraction that :func:`dense_packing` attempts [-]: random close
#: packing of equal spheres in unbounded space (about 0.64); walls only lower it.
DENSE_FILL_LIMIT = 0.64

_BOX_FIELD = "container.box"
_RADIUS_FIELD = "particles.radius"
_COUNT_FIELD = "particles.count"


# --------------------------------------------------------------------------- validation


def _as_box(box: Sequence[float]) -> tuple[float, float, float]:
    """Validate a box ``(Lx, Ly, Lz)`` [m]: three finite positive numbers."""
    try:
        values = [float(v) for v in box]
    except (TypeError, ValueError):
        raise InputError(
            _BOX_FIELD, f"must be three inner dimensions (Lx, Ly, Lz) in m, got {box!r}"
        ) from None
    if len(values) != 3:
        raise InputError(
            _BOX_FIELD,
            f"must be three inner dimensions (Lx, Ly, Lz) in m, got {len(values)} values",
        )
    for name, v in zip("xyz", values, strict=True):
        if not math.isfinite(v) or v <= 0.0:
            raise InputError(
                _BOX_FIELD, f"L{name} must be a finite number in (0, inf) m, got {v}"
            )
    return values[0], values[1], values[2]


def _as_radius(radius: Any) -> float:
    """One radius as the user gave it (a scalar) as a float [m] > 0, or an InputError."""
    return check_range(_RADIUS_FIELD, radius, low=0.0, low_inclusive=False, unit="m")


def _as_count(n: Any) -> int:
    """``n`` (as the user gave it) as a whole count >= 0, or an InputError."""
    if isinstance(n, bool):
        raise InputError(_COUNT_FIELD, f"must be a whole number >= 0, got {n!r}")
    try:
        count = operator.index(n)
    except TypeError:
        if isinstance(n, float) and math.isfinite(n) and n.is_integer():
            count = int(n)
        else:
            raise InputError(_COUNT_FIELD, f"must be a whole number >= 0, got {n!r}") from None
    if count < 0:
        raise InputError(_COUNT_FIELD, f"must be a whole number >= 0, got {count}")
    return count


def _as_radii(radius: float | Sequence[float] | np.ndarray, n: int) -> np.ndarray:
    """Validate a scalar radius or one radius per particle; return an (n,) array [m]."""
    arr = None
    if not np.isscalar(radius):
        try:
            arr = np.asarray(radius, dtype=float)
        except (TypeError, ValueError):
            raise InputError(
                _RADIUS_FIELD, f"must be one number or one radius per particle, got {radius!r}"
            ) from None
    if arr is None or arr.ndim == 0:
        r = _as_radius(radius if arr is None else float(arr))
        return np.full(n, r)
    if arr.shape != (n,):
        raise InputError(
            _RADIUS_FIELD,
            f"must be one number or one radius per particle, shape ({n},), got shape "
            f"{arr.shape}",
        )
    bad = ~np.isfinite(arr) | (arr <= 0.0)
    if np.any(bad):
        i = int(np.flatnonzero(bad)[0])
        raise InputError(
            _RADIUS_FIELD, f"must be finite numbers in (0, inf) m, got {arr[i]} at index {i}"
        )
    return arr



def _describe(box: tuple[float, float, float], radius: float, gap: float = 0.0) -> str:
    text = (
        f"a {box[0] * 1e3:g}x{box[1] * 1e3:g}x{box[2] * 1e3:g} mm box and "
        f"r = {radius * 1e3:g} mm"
    )
    if gap > 0.0:
        text += f" with a gap of {gap * 1e3:g} mm"
    return text


def _check_fits(box: tuple[float, float, float], diameter: float) -> None:
    for name, length in zip("xyz", box, strict=True):
        if length * (1.0 + _FIT_TOLERANCE) < diameter:
            raise InputError(
                _BOX_FIELD,
                f"L{name} must be at least one particle diameter ({diameter * 1e3:g} mm), "
                f"got {length * 1e3:g} mm",
            )


# ------------------------------------------------------------------------------ lattice


def lattice_layers(
    n: int, radius: float, box: Sequence[float], gap: float = 0.0
) -> np.ndarray:
    """Sphere centres on a square lattice, filled layer by layer from the floor.

    The bottom layer rests on the floor (centres at ``z = radius``); each layer is centred
    in x and y. Sites are filled in a fixed order: layer by layer upwards, inside a layer
    row by row in y with x running fastest, so the last, partially filled layer fills its
    low-y rows first. With ``gap = 0`` neighbouring spheres touch exactly (for the
    benchmark box the spheres then stand in 16 locked columns, as in the paper).

    Parameters
    ----------
    n
        Number of spheres [-], ``0 <= n <= max_particles(box, radius, gap)``.
    radius
        Sphere radius [m].
    box
        Inner container dimensions ``(Lx, Ly, Lz)`` [m]; every side at least one diameter.
    gap
        Clearance between neighbouring spheres, horizontally and between layers [m].

    Returns
    -------
    numpy.ndarray
        Centres, shape ``(n, 3)`` [m], in the container frame.

    Raises
    ------
    InputError
        For a negative or non-whole ``n``, a non-positive or non-finite radius or gap, a
        box side that is not positive or smaller than a diameter, or ``n`` above the
        lattice capacity (field ``particles.count``, message with the allowed range).
    """
    count = _as_count(n)
    r = _as_radius(radius)
    lbox = _as_box(box)
    g = check_range("particles.gap", gap, low=0.0, unit="m")
    _check_fits(lbox, 2.0 * r)
    nx, ny, nz = (_fits(length, r, g) for length in lbox)
    capacity = nx * ny * nz
    if count > capacity:
        raise InputError(
            _COUNT_FIELD,
            f"must be in [0, {capacity}] for {_describe(lbox, r, g)}, got {count}",
        )
    pitch = 2.0 * r + g
    offsets = []
    for length, k in ((lbox[0], nx), (lbox[1], ny)):
        span = k * 2.0 * r + (k - 1) * g
        # max(): with the fit tolerance the span may exceed the side by ~1e-9 relative.
        offsets.append(max(0.0, 0.5 * (length - span)) + r)
    i = np.arange(count)
    per_layer = nx * ny
    layer, site = np.divmod(i, per_layer)
    iy, ix = np.divmod(site, nx)
    out = np.empty((count, 3))
    out[:, 0] = offsets[0] + pitch * ix
    out[:, 1] = offsets[1] + pitch * iy
    out[:, 2] = r + pitch * layer
    return out


# ------------------------------------------------------------------------------- random


@numba.njit(cache=True)
def _rsa_kernel(  # pragma: no cover - compiled
    pos, radii, order, k, attempts, cand, box, ncell, csize, head, nxt, factor, max_attempts
):
    """Random sequential addition over the candidates ``cand`` (uniform in [0, 1)^3).

    Places ``order[k], order[k+1], ...`` until the candidates run out, every particle is
    placed, or one particle has used ``max_attempts`` candidates. Returns the new ``k``,
    the attempts spent on particle ``order[k]`` and a failure flag.
    """
    n = order.shape[0]
    ncx, ncy, ncz = ncell[0], ncell[1], ncell[2]
    for j in range(cand.shape[0]):
        if k >= n:
            break
        i = order[k]
        ri = radii[i]
        p0 = ri + cand[j, 0] * (box[0] - 2.0 * ri)
        p1 = ri + cand[j, 1] * (box[1] - 2.0 * ri)
        p2 = ri + cand[j, 2] * (box[2] - 2.0 * ri)
        cx = min(int(p0 / csize[0]), ncx - 1)
        cy = min(int(p1 / csize[1]), ncy - 1)
        cz = min(int(p2 / csize[2]), ncz - 1)
        ok = True
        for ax in range(max(cx - 1, 0), min(cx + 2, ncx)):
            for ay in range(max(cy - 1, 0), min(cy + 2, ncy)):
                for az in range(max(cz - 1, 0), min(cz + 2, ncz)):
                    m = head[(ax * ncy + ay) * ncz + az]
                    while m >= 0:
                        d0 = pos[m, 0] - p0
                        d1 = pos[m, 1] - p1
                        d2 = pos[m, 2] - p2
                        reach = (ri + radii[m]) * factor
                        if d0 * d0 + d1 * d1 + d2 * d2 < reach * reach:
                            ok = False
                            break
                        m = nxt[m]
                    if not ok:
                        break
                if not ok:
                    break
            if not ok:
                break
        if ok:
            pos[i, 0] = p0
            pos[i, 1] = p1
            pos[i, 2] = p2
            c = (cx * ncy + cy) * ncz + cz
            nxt[i] = head[c]
            head[c] = i
            k += 1
            attempts = 0
        else:
            attempts += 1
            if attempts >= max_attempts:
                return k, attempts, True
    return k, attempts, False


def _seed_and_attempts(seed, max_attempts) -> tuple[int, int]:
    """The checked seed (a whole number >= 0) and attempt limit (>= 1) of a packing."""
    if isinstance(seed, bool):
        raise InputError("particles.seed", f"must be a whole number >= 0, got {seed!r}")
    try:
        seed_int = operator.index(seed)
    except TypeError:
        raise InputError("particles.seed", f"must be a whole number >= 0, got {seed!r}") from None
    if seed_int < 0:
        raise InputError("particles.seed", f"must be a whole number >= 0, got {seed_int}")
    try:
        attempts_max = operator.index(max_attempts)
    except TypeError:
        attempts_max = -1
    if attempts_max < 1:
        raise InputError(
            "particles.max_attempts", f"must be a whole number >= 1, got {max_attempts!r}"
        )
    return seed_int, attempts_max


def _check_fill(count: int, radii: np.ndarray, lbox) -> tuple[float, str, str]:
    """The volume fraction the spheres would fill [-] (refused above
    :data:`RANDOM_FILL_LIMIT`), and the radius and box as the messages name them."""
    r_max = float(radii.max())
    volume = lbox[0] * lbox[1] * lbox[2]
    fill = float(np.sum(4.0 / 3.0 * math.pi * radii**3)) / volume
    r_text = f"r = {r_max * 1e3:g} mm" if np.all(radii == r_max) else f"r <= {r_max * 1e3:g} mm"
    box_text = f"{lbox[0] * 1e3:g}x{lbox[1] * 1e3:g}x{lbox[2] * 1e3:g} mm box"
    if fill > RANDOM_FILL_LIMIT:
        raise InputError(
            _COUNT_FIELD,
            f"{count} spheres ({r_text}) would fill {fill:.2f} of the {box_text}; random "
            f"placement is limited to {RANDOM_FILL_LIMIT:g} of the volume; use fewer "
            "spheres, a larger box or lattice_layers",
        )
    return fill, r_text, box_text


def _cell_grid(lbox, reach: float, count: int) -> tuple[np.ndarray, np.ndarray]:
    """Cells (number per axis, size [m]) at least one contact distance ``reach`` [m] wide,
    but not vastly more cells than particles (a huge, nearly empty box would otherwise
    cost memory)."""
    cell = reach
    cap = max(64, 8 * count)
    while True:
        ncell = np.array([max(1, int(length / cell)) for length in lbox], dtype=np.int64)
        if int(np.prod(ncell)) <= cap:
            break
        cell *= 1.25
    return ncell, np.array(lbox) / ncell


def _sequential(count, radii, lbox, seed_int, attempts_max, m) -> tuple[np.ndarray, int]:
    """Random sequential addition: the centres and how many of them were placed (all
    ``count`` unless one sphere found no room in ``attempts_max`` candidates)."""
    r_max = float(radii.max())
    ncell, csize = _cell_grid(lbox, 2.0 * r_max * (1.0 + m), count)
    head = np.full(int(np.prod(ncell)), -1, dtype=np.int64)
    nxt = np.full(count, -1, dtype=np.int64)
    pos = np.zeros((count, 3))
    order = np.argsort(-radii, kind="stable").astype(np.int64)
    box_arr = np.array(lbox)
    rng = np.random.default_rng(seed_int)
    chunk = 8192
    k, attempts = 0, 0
    while k < count:
        cand = rng.random((chunk, 3))
        k, attempts, failed = _rsa_kernel(
            pos, radii, order, k, attempts, cand, box_arr, ncell, csize, head, nxt,
            1.0 + m, attempts_max,
        )
        if failed:
            break
    return pos, k


def sequential_packing(
    n: int,
    radius: float | Sequence[float] | np.ndarray,
    box: Sequence[float],
    seed: int,
    max_attempts: int = 20_000,
    *,
    margin: float = 1e-6,
) -> np.ndarray:
    """Random non-overlapping sphere centres by random sequential addition alone.

    Particles are placed one after the other (largest first when the radii differ) at
    uniformly random positions that keep every centre at least its radius from each wall;
    a candidate closer than ``(r_i + r_j) (1 + margin)`` to a placed sphere is rejected.
    A cell grid keeps each test local, so 10 000 spheres take well under a second. This is
    :func:`random_packing` without its dense fallback: where it succeeds, both give the same
    positions.

    Parameters
    ----------
    n
        Number of spheres [-].
    radius
        One radius for all spheres, or one per sphere, shape ``(n,)`` [m].
    box
        Inner container dimensions ``(Lx, Ly, Lz)`` [m]; every side at least the largest
        diameter.
    seed
        Seed of :func:`numpy.random.default_rng` [-], a whole number >= 0; the same seed
        gives the same positions.
    max_attempts
        Rejected candidates allowed for one sphere before giving up [-].
    margin
        Relative clearance between spheres [-], ``0 <= margin < 1``.

    Returns
    -------
    numpy.ndarray
        Centres, shape ``(n, 3)`` [m], in the container frame; row ``i`` belongs to
        ``radius[i]``.

    Raises
    ------
    InputError
        For invalid arguments; and (field ``particles.count``) when the spheres would fill
        more than :data:`RANDOM_FILL_LIMIT` of the box volume, or when one of them could not
        be placed within ``max_attempts`` candidates.
    """
    count = _as_count(n)
    radii = _as_radii(radius, count)
    lbox = _as_box(box)
    seed_int, attempts_max = _seed_and_attempts(seed, max_attempts)
    m = check_range("particles.margin", margin, low=0.0, high=1.0, high_inclusive=False)
    if count == 0:
        return np.empty((0, 3))
    _check_fits(lbox, 2.0 * float(radii.max()))
    fill, r_text, box_text = _check_fill(count, radii, lbox)
    pos, k = _sequential(count, radii, lbox, seed_int, attempts_max, m)
    if k < count:
        raise InputError(
            _COUNT_FIELD,
            f"could place only {k} of {count} random non-overlapping spheres "
            f"({r_text}) in the {box_text} within {attempts_max} attempts for one "
            f"sphere (they would fill {fill:.2f} of the volume); use fewer spheres, a "
            "larger box or lattice_layers",
        )
    return pos


def random_packing(
    n: int,
    radius: float | Sequence[float] | np.ndarray,
    box: Sequence[float],
    seed: int,
    max_attempts: int = 20_000,
    *,
    margin: float = 1e-6,
) -> np.ndarray:
    """Random non-overlapping sphere centres inside the box, for every count it holds.

    Random sequential addition first (:func:`sequential_packing`, the same positions where
    it succeeds); when the spheres would fill more than :data:`RANDOM_FILL_LIMIT` of the
    box, or one of them finds no room within ``max_attempts`` candidates, a dense random
    bed grown from the same seed (:func:`dense_packing`). Every centre keeps at least its
    radius from each wall and ``(r_i + r_j) (1 + margin)`` from every other centre.

    Parameters
    ----------
    n
        Number of spheres [-]; equal spheres at most the lattice's count
        (:func:`max_particles`).
    radius
        One radius for all spheres, or one per sphere, shape ``(n,)`` [m].
    box
        Inner container dimensions ``(Lx, Ly, Lz)`` [m]; every side at least the largest
        diameter.
    seed
        Seed of :func:`numpy.random.default_rng` [-], a whole number >= 0; the same seed
        gives the same positions.
    max_attempts
        Rejected candidates allowed for one sphere in sequential addition before the dense
        bed is grown instead [-].
    margin
        Relative clearance between spheres [-], ``0 <= margin < 1``.

    Returns
    -------
    numpy.ndarray
        Centres, shape ``(n, 3)`` [m], in the container frame; row ``i`` belongs to
        ``radius[i]``.

    Raises
    ------
    InputError
        For invalid arguments; and (field ``particles.count``) for more equal spheres than
        the lattice holds, or a bed too dense to grow at random (the message gives about
        how many fit).
    """
    count = _as_count(n)
    radii = _as_radii(radius, count)
    lbox = _as_box(box)
    seed_int, attempts_max = _seed_and_attempts(seed, max_attempts)
    m = check_range("particles.margin", margin, low=0.0, high=1.0, high_inclusive=False)
    if count == 0:
        return np.empty((0, 3))
    _check_fits(lbox, 2.0 * float(radii.max()))
    if _fill(radii, lbox) <= RANDOM_FILL_LIMIT:
        pos, k = _sequential(count, radii, lbox, seed_int, attempts_max, m)
        if k == count:
            return pos
    return _dense(count, radii, lbox, seed_int, m)


def dense_packing(
    n: int,
    radius: float | Sequence[float] | np.ndarray,
    box: Sequence[float],
    seed: int,
    *,
    margin: float = 1e-6,
) -> np.ndarray:
    """A dense random bed: random centres relaxed apart while their contact distance grows.

    The centres start uniformly at random inside the walls with the spheres shrunk to a
    solid fraction of 0.2. The contact distance ``s (r_i + r_j)`` then grows in relative
    steps of at most 1 % towards ``(1 + margin)`` times the touching distance; after each
    step the overlaps are relaxed away by collective rearrangement (every overlapping pair
    pushed apart by half its overlap each, all pairs at once, centres clamped inside the
    walls) until the largest overlap is below 1e-7 of the contact distance. A step whose
    relaxation does not converge in 1000 sweeps is taken back, the bed shaken (normal
    displacements of 2 % of the radius) and retried with half the step; the growth gives
    up when the step falls below 1e-5. A growth that gave up is tried again from new
    random centres, three growths at most. Random
    close packing (a solid fraction near 0.64) grows this way in open space; in a box the
    walls lower what fits. Every random number comes from ``seed``, so the bed is
    reproducible.

    Parameters
    ----------
    n
        Number of spheres [-]; equal spheres at most the lattice's count
        (:func:`max_particles`), and at most :data:`DENSE_FILL_LIMIT` of the volume.
    radius
        One radius for all spheres, or one per sphere, shape ``(n,)`` [m].
    box
        Inner container dimensions ``(Lx, Ly, Lz)`` [m]; every side at least the largest
        diameter.
    seed
        Seed [-], a whole number >= 0; the same seed gives the same positions.
    margin
        Relative clearance between spheres [-], ``0 <= margin < 1``.

    Returns
    -------
    numpy.ndarray
        Centres, shape ``(n, 3)`` [m], in the container frame.

    Raises
    ------
    InputError
        For invalid arguments; and (field ``particles.count``) for more equal spheres than
        the lattice holds, or a bed the growth cannot reach (the message gives about how
        many fit).
    """
    count = _as_count(n)
    radii = _as_radii(radius, count)
    lbox = _as_box(box)
    seed_int, _ = _seed_and_attempts(seed, 1)
    m = check_range("particles.margin", margin, low=0.0, high=1.0, high_inclusive=False)
    if count == 0:
        return np.empty((0, 3))
    _check_fits(lbox, 2.0 * float(radii.max()))
    return _dense(count, radii, lbox, seed_int, m)


def _fill(radii: np.ndarray, lbox) -> float:
    """Solid volume fraction of the spheres in the box [-]."""
    return float(np.sum(4.0 / 3.0 * math.pi * radii**3)) / (lbox[0] * lbox[1] * lbox[2])


@numba.njit(cache=True)
def _relax_kernel(  # pragma: no cover - compiled
    pos, radii, box, scale, ncell, csize, head, nxt, disp, sweeps, tol
):
    """Collective rearrangement at contact distance ``scale (r_i + r_j)``.

    Each sweep pushes every overlapping pair apart by half its overlap each (Jacobi: all
    pairs from the same positions) and clamps the centres inside the walls, until the
    largest overlap over contact distance is below ``tol`` or ``sweeps`` sweeps are done.
    Returns the sweeps done and that largest overlap ratio (of the last positions tested).
    """
    n = pos.shape[0]
    ncx, ncy, ncz = ncell[0], ncell[1], ncell[2]
    worst = 0.0
    for sweep in range(sweeps):
        head[:] = -1
        for i in range(n):
            cx = min(max(int(pos[i, 0] / csize[0]), 0), ncx - 1)
            cy = min(max(int(pos[i, 1] / csize[1]), 0), ncy - 1)
            cz = min(max(int(pos[i, 2] / csize[2]), 0), ncz - 1)
            c = (cx * ncy + cy) * ncz + cz
            nxt[i] = head[c]
            head[c] = i
            disp[i, 0] = 0.0
            disp[i, 1] = 0.0
            disp[i, 2] = 0.0
        worst = 0.0
        for i in range(n):
            cx = min(max(int(pos[i, 0] / csize[0]), 0), ncx - 1)
            cy = min(max(int(pos[i, 1] / csize[1]), 0), ncy - 1)
            cz = min(max(int(pos[i, 2] / csize[2]), 0), ncz - 1)
            for ax in range(max(cx - 1, 0), min(cx + 2, ncx)):
                for ay in range(max(cy - 1, 0), min(cy + 2, ncy)):
                    for az in range(max(cz - 1, 0), min(cz + 2, ncz)):
                        j = head[(ax * ncy + ay) * ncz + az]
                        while j >= 0:
                            if j > i:
                                d0 = pos[i, 0] - pos[j, 0]
                                d1 = pos[i, 1] - pos[j, 1]
                                d2 = pos[i, 2] - pos[j, 2]
                                s = (radii[i] + radii[j]) * scale
                                dd = d0 * d0 + d1 * d1 + d2 * d2
                                if dd < s * s:
                                    d = math.sqrt(dd)
                                    worst = max(worst, (s - d) / s)
                                    if d > 0.0:
                                        f = 0.5 * (s - d) / d
                                    else:  # coincident centres: part them vertically
                                        d2, f = 1.0, 0.5 * s
                                    disp[i, 0] += f * d0
                                    disp[i, 1] += f * d1
                                    disp[i, 2] += f * d2
                                    disp[j, 0] -= f * d0
                                    disp[j, 1] -= f * d1
                                    disp[j, 2] -= f * d2
                            j = nxt[j]
        if worst < tol:
            return sweep + 1, worst
        for i in range(n):
            for a in range(3):
                pos[i, a] = min(max(pos[i, a] + disp[i, a], radii[i]), box[a] - radii[i])
    return sweeps, worst


#: Relative overlap below which a relaxation has converged [-]; the growth aims at a
#: contact distance larger by _DENSE_EXTRA than asked, so converged beds keep the margin.
_DENSE_TOL = 1e-7
_DENSE_EXTRA = 1e-5
#: Smallest relative growth step tried before the growth gives up [-].
_DENSE_MIN_STEP = 1e-5
#: Growths from new random centres before a count is refused [-]: one growth in a few
#: jams early (60 of 64 sites stopped at 0.94 of the volume) where another start packs.
_DENSE_TRIES = 3
#: Refusals of dense beds in this process, by their inputs: a map with ``packing = "auto"``
#: asks for the same bed at every point and falls back to the lattice each time.
_REFUSED: dict[tuple, str] = {}
#: The count a refusal offers is the reached volume share of the asked count, times this:
#: a growth near its limit gives up on some seeds and not others, so the offer keeps room.
_DENSE_FITS_SAFETY = 0.95


def _dense(count: int, radii: np.ndarray, lbox, seed_int: int, m: float) -> np.ndarray:
    """:func:`dense_packing` on validated inputs (a refusal names the count and box)."""
    fill = _fill(radii, lbox)
    r_max = float(radii.max())
    equal = bool(np.all(radii == r_max))
    cap = max_particles(lbox, r_max) if equal else None
    if cap is not None and count > cap:
        raise InputError(
            _COUNT_FIELD,
            f"must be in [0, {cap}] for {_describe(lbox, r_max)} (what the container "
            f"holds), got {count}",
        )
    r_text = f"r = {r_max * 1e3:g} mm" if equal else f"r <= {r_max * 1e3:g} mm"
    box_text = f"{lbox[0] * 1e3:g}x{lbox[1] * 1e3:g}x{lbox[2] * 1e3:g} mm container"
    if fill > DENSE_FILL_LIMIT:
        raise InputError(
            _COUNT_FIELD,
            f"{count} spheres ({r_text}) would fill {fill:.2f} of the {box_text}; random "
            f"beds fill at most {DENSE_FILL_LIMIT:g}: use fewer spheres or a larger "
            "container (container.box)",
        )
    key = (count, radii.tobytes(), tuple(lbox), seed_int, m)
    refusal = _REFUSED.get(key)
    if refusal is not None:  # the same growths would give up again, at the same cost
        raise InputError(_COUNT_FIELD, refusal)
    reached = 0.0
    for attempt in range(_DENSE_TRIES):
        # streams of their own, so the bed does not reuse sequential addition's numbers
        rng = np.random.default_rng([seed_int, 1 + attempt])
        bed, share = _grow(radii, lbox, rng, fill, m)
        if bed is not None:
            return bed
        reached = max(reached, share)
    fits = int(count * reached * _DENSE_FITS_SAFETY)
    lattice = f", the lattice {cap}" if cap is not None else ""
    refusal = (
        f"{count} spheres ({r_text}) would fill {fill:.2f} of the {box_text}: too dense "
        f"for a random bed, which holds about {fits} of them here{lattice}; use at most "
        f"{fits} spheres (particles.count, --particles) or a larger container "
        "(container.box)"
    )
    _REFUSED[key] = refusal
    while len(_REFUSED) > 32:
        _REFUSED.pop(next(iter(_REFUSED)))
    raise InputError(_COUNT_FIELD, refusal)


def _grow(
    radii: np.ndarray, lbox, rng, fill: float, m: float
) -> tuple[np.ndarray | None, float]:
    """One growth of a dense bed from random centres drawn from ``rng``: the bed (``None``
    if the growth gave up) and the share of the asked sphere volume it reached [-]."""
    count = radii.shape[0]
    target = (1.0 + m) * (1.0 + _DENSE_EXTRA)
    box_arr = np.array(lbox)
    lo = radii[:, None]
    hi = box_arr[None, :] - radii[:, None]
    pos = lo + rng.random((count, 3)) * (hi - lo)
    ncell, csize = _cell_grid(lbox, 2.0 * float(radii.max()) * target, count)
    head = np.empty(int(np.prod(ncell)), dtype=np.int64)
    nxt = np.empty(count, dtype=np.int64)
    disp = np.empty((count, 3))
    # the start: shrunk to a solid fraction of 0.2, where the relaxation always converges
    scale = min(target, (0.2 / fill) ** (1.0 / 3.0))
    worst = 1.0
    while worst >= _DENSE_TOL:
        _, worst = _relax_kernel(pos, radii, box_arr, scale, ncell, csize, head, nxt, disp,
                                 1000, _DENSE_TOL)
    good, good_scale, step = pos.copy(), scale, 0.01
    while good_scale < target:
        scale = min(target, good_scale * (1.0 + step))
        _, worst = _relax_kernel(pos, radii, box_arr, scale, ncell, csize, head, nxt, disp,
                                 1000, _DENSE_TOL)
        if worst < _DENSE_TOL:
            good[:], good_scale = pos, scale
            step = min(0.01, 1.5 * step)
            continue
        step *= 0.5
        if step < _DENSE_MIN_STEP:
            return None, (good_scale / target) ** 3
        # back to the last relaxed bed, shaken, so the retry can find another way
        pos[:] = good + rng.normal(0.0, 0.02, (count, 3)) * radii[:, None]
        np.clip(pos, lo, hi, out=pos)
    return good, 1.0


# ---------------------------------------------------------------------- scaled container


def scaled_box(
    n: int,
    radius: float,
    fill_fraction: float = 1.0 / 6.0,
    *,
    min_per_side: int = 4,
    max_bed_layers: int = 12,
) -> tuple[float, float, float]:
    """A container for ``n`` spheres with the benchmark's proportions, for scaling runs.

    The benchmark damper at 32 spheres has a bed of 2 lattice layers in a box 12 layers
    high, i.e. the bed fills ``1/6`` of the height. This box keeps that ratio:

    * the cross-section is square, ``k`` diameters wide, with ``k`` the smallest whole
      number ``>= min_per_side`` such that ``k^2 * max_bed_layers >= n`` -- the benchmark
      width (4 diameters) up to 192 spheres, wider above, so the bed is never deeper than
      the benchmark's 12 layers;
    * the bed has ``ceil(n / k^2)`` layers (at least one) and the height is the smallest
      whole number of diameters with bed height / box height ``<= fill_fraction``.

    For 32 spheres of radius 5 mm this gives the benchmark box (0.04, 0.04, 0.12) m; for
    10 000 spheres it gives 290 x 290 x 720 mm (29 per side, a 12-layer bed).

    Parameters
    ----------
    n
        Number of spheres [-].
    radius
        Sphere radius [m].
    fill_fraction
        Bed height over box height [-], in ``(0, 1]``.
    min_per_side
        Smallest number of diameters across the box [-].
    max_bed_layers
        Deepest bed, in lattice layers, before the box is widened [-].

    Returns
    -------
    tuple of float
        Inner dimensions ``(Lx, Ly, Lz)`` [m]; ``max_particles(box, radius) >= n``.
    """
    count = _as_count(n)
    r = _as_radius(radius)
    f = check_range("container.fill_fraction", fill_fraction, low=0.0, high=1.0,
                    low_inclusive=False)
    for field, value in (("container.min_per_side", min_per_side),
                         ("container.max_bed_layers", max_bed_layers)):
        if isinstance(value, bool) or not isinstance(value, int | np.integer) or value < 1:
            raise InputError(field, f"must be a whole number >= 1, got {value!r}")
    need = -(-count // max_bed_layers)  # spheres per layer needed
    k = math.isqrt(need)
    if k * k < need:
        k += 1
    k = max(k, int(min_per_side))
    layers = max(1, -(-count // (k * k)))
    height_layers = math.ceil(layers / f * (1.0 - _FIT_TOLERANCE))
    d = 2.0 * r
    return (k * d, k * d, height_layers * d)
