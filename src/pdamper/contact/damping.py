"""Damping parameter of the contact law from a coefficient of restitution (COR).

The normal force of the paper's contact law (Gonthier et al. on top of Hertz) is

    F = K delta^n (1 + d delta_dot),     n = 3/2 for Hertz,

with ``delta`` the overlap and ``delta_dot`` its rate (positive while approaching).

Exact relation (default)
------------------------
With ``m* dv/dt = -K delta^n (1 + d v)`` and ``v = delta_dot``, divide by ``v = d delta/dt``:

    m* v dv / (1 + d v) = -K delta^n d delta.

The variables separate. Integrating from impact (delta = 0, v = v0) to separation
(delta = 0, v = -e v0) makes the right-hand side vanish, so

    (v - v0)/d - ln((1 + d v)/(1 + d v0))/d^2 = 0   at  v = -e v0,

which with ``x = d v0`` becomes, independently of K, n and m*:

    ln(1 - e x) - ln(1 + x) + (1 + e) x = 0.              (*)

For 0 < e < 1, (*) has exactly one positive root with ``x < 1/e``; the force
``1 + d v >= 1 - e x > 0`` never turns tensile, so no clipping is needed and the root is
exact for the unclipped law as implemented in the DEM. ``e = 1`` gives ``x = 0``; ``e -> 0``
needs ``x -> inf``.

Gonthier's approximation (the paper's)
--------------------------------------
``x = (1 - e^2) / e`` (Gonthier et al. 2004, small-dissipation expansion). It is
accurate as e -> 1 but gives e = 0.77 when 0.80 is asked for.

Tsuji's law ("Hertz with COR" of LIGGGHTS and EDEM)
---------------------------------------------------
A different force law, ``F = K delta^(3/2) + c delta^(1/4) delta_dot`` with
``c = 2 sqrt(5/6) |beta| sqrt(S m*) / delta^(1/4) = 2 sqrt(5/6) |beta| sqrt(3/2 K m*)``
(``S = 2 E* sqrt(R* delta) = 3/2 K delta^(1/2)``) and ``beta = ln e / sqrt(ln^2 e + pi^2)``:
the damping ratio of a *linear* spring-dashpot with COR e. Scaling ``delta`` with
``(m* v0^2 / K)^(2/5)`` and time with ``delta / v0`` leaves ``c / sqrt(K m*)`` as the only
parameter, so the COR this law produces does not depend on the impact speed; integrated
(``tests/contact/test_damping_relation.py``, scipy) it equals ``e`` to 1e-10, although
``beta`` comes from the linear spring. That holds only if the force may turn attractive
at the end of the contact (the damping term ``~ delta^(1/4)`` outlasts the elastic one):
LIGGGHTS' default (``limitForce off``) and pdamper's ``"tsuji"`` law. Clipped at zero the
law restitutes more (0.632 for e = 0.6, 0.397 for 0.3).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from pdamper.errors import check_range


@njit(cache=True)
def _residual(x: float, e: float) -> float:
    return math.log1p(-e * x) - math.log1p(x) + (1.0 + e) * x


@njit(cache=True)
def exact_damping_factor_scalar(e: float) -> float:
    """Root x = d v0 of Eq. (*) for one COR ``e`` in (0, 1]; numba-compiled.

    Bisection in ``log(x)`` bracketed by ``(0, 1/e)``: robust for every e in (0, 1] and
    cheap enough to call at each contact onset.
    """
    if e >= 1.0:
        return 0.0
    hi = (1.0 / e) * (1.0 - 1e-15)
    # below the root the residual is positive (~ x^2 (1 - e^2)/2); go down until it is
    lo = min((1.0 - e * e) / e, hi) * 0.5
    while _residual(lo, e) <= 0.0 and lo > 1e-300:
        lo *= 0.5
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if _residual(mid, e) > 0.0:
            lo = mid
        else:
            hi = mid
        if hi - lo <= 1e-15 * hi:
            break
    return 0.5 * (lo + hi)


@njit(cache=True)
def gonthier_damping_factor_scalar(e: float) -> float:
    """Gonthier's x = d v0 = (1 - e^2) / e; numba-compiled."""
    return (1.0 - e * e) / e


@njit(cache=True)
def restitution_from_damping_factor_scalar(x: float) -> float:
    """Inverse of Eq. (*): the COR that ``x = d v0`` produces (bisection in e)."""
    if x <= 0.0:
        return 1.0
    lo, hi = 0.0, 1.0
    # residual(x, e) is positive for e above the true COR (x below its root), negative below
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if mid * x >= 1.0 or _residual(x, mid) < 0.0:
            hi = mid
        else:
            lo = mid
        if hi - lo < 1e-15:
            break
    return 0.5 * (lo + hi)


@njit(cache=True)
def tsuji_damping_ratio_scalar(e: float) -> float:
    """``2 sqrt(5/6) |beta|``, ``beta = ln e / sqrt(ln^2 e + pi^2)``: Tsuji's damping
    coefficient is this times ``sqrt(3/2 K m*)``; numba-compiled."""
    if e >= 1.0:
        return 0.0
    le = math.log(e)
    return 2.0 * math.sqrt(5.0 / 6.0) * (-le) / math.sqrt(le * le + math.pi * math.pi)


def damping_factor(e, model: str = "exact"):
    """Dimensionless damping ``x = d * v_impact`` that yields the COR ``e``.

    Parameters
    ----------
    e : float or array_like
        Coefficient of restitution [-], in (0, 1].
    model : {"exact", "gonthier", "tsuji"}
        The damping law.
        ``"exact"``: root of Eq. (*) of this module (default);
        ``"gonthier"``: Gonthier's approximation (1 - e^2)/e, the paper's choice;
        ``"tsuji"``: ``2 sqrt(5/6) |beta|`` of Tsuji's law (see the module docstring).

    Returns
    -------
    float or ndarray
        ``x`` [-]; the damping parameter is ``d = x / v_impact`` [s/m] (exact, gonthier)
        or ``c = x sqrt(3/2 K m*)`` [kg/(s m^0.25)] (tsuji).

    Examples
    --------
    >>> round(float(damping_factor(0.8)), 4), round(float(damping_factor(0.8, "gonthier")), 4)
    (0.3731, 0.45)
    """
    arr = np.asarray(e, dtype=float)
    for v in np.ravel(arr):
        check_range("restitution", v, low=0.0, high=1.0, low_inclusive=False)
    f = {"exact": exact_damping_factor_scalar, "gonthier": gonthier_damping_factor_scalar,
         "tsuji": tsuji_damping_ratio_scalar}.get(model)
    if f is None:
        from pdamper.errors import InputError

        raise InputError("damping_model", f"must be 'exact', 'gonthier' or 'tsuji', got {model!r}")
    out = np.vectorize(f, otypes=[float])(arr)
    return float(out) if np.ndim(out) == 0 else out


def restitution_from_damping_factor(x):
    """COR produced by the damping factor ``x = d v0`` under the exact relation."""
    out = np.vectorize(restitution_from_damping_factor_scalar, otypes=[float])(np.asarray(x, float))
    return float(out) if np.ndim(out) == 0 else out
