"""Scalar contact physics of the DEM, compiled with numba (paper Sect. 3, "Discrete element method").

These functions take and return plain floats, allocate nothing and call nothing but
``math`` and other numba functions, so that the CPU kernels of :mod:`pdamper.dem.kernels`
inline them and a later GPU path (``numba.cuda.jit(device=True)``) can reuse them as
device functions.

Normal force (Hertz with Gonthier's nonlinear damping)
------------------------------------------------------
``F_n = K delta^(3/2) (1 + d delta_dot)``, clipped at zero (no tension), with the overlap
``delta`` [m] and its rate ``delta_dot`` [m/s] (positive while approaching), the Hertz
stiffness ``K = 4/3 E* sqrt(R*)`` [N/m^1.5] and the damping parameter ``d`` [s/m].
``d = x(e(v0)) / v0`` is fixed at the contact onset from the impact speed ``v0`` and the
coefficient of restitution ``e(v0)`` of the material pair; ``x`` is either the root of the
exact relation ``ln(1 - e x) - ln(1 + x) + (1 + e) x = 0`` (default, see
:mod:`pdamper.contact.damping`) or Gonthier's ``(1 - e^2)/e`` (the paper's choice).

Tsuji's law (``DAMPING_TSUJI``, LIGGGHTS' and EDEM's "Hertz with COR"):
``F_n = K delta^(3/2) + c delta^(1/4) delta_dot`` with ``c = x(e) sqrt(3/2 K m*)``,
``x = 2 sqrt(5/6) |ln e| / sqrt(ln^2 e + pi^2)``, not clipped (as LIGGGHTS' default).

Tangential force (regularised Coulomb friction)
-----------------------------------------------
``F_t = -mu |F_n| tanh(|v_t| / v_reg) t_hat`` with the slip velocity ``v_t`` at the contact
point and ``t_hat = v_t / |v_t|``. The regularisation velocity ``v_reg`` defaults to
:data:`pdamper.contact.law.DEFAULT_REGULARISATION_VELOCITY` = 0.01 m/s: below it friction acts as a viscous
damper of coefficient ``mu |F_n| / v_reg``, above ~2 v_reg it is Coulomb sliding to within
4 %.

Tangential force (spring with a Coulomb limit, ``friction_model = "spring"``)
--------------------------------------------------------------------------
LIGGGHTS' ``tangential history`` (Yade's Mindlin without its damping): each contact keeps an
elastic tangential displacement ``xi`` [m], zero at the onset; every step adds ``v_t h``
and projects ``xi`` onto the current tangent plane (the contact turns with the spheres).
The force is ``F_t = -k_t xi - gamma_t v_t`` (sticking) with Mindlin's stiffness
``k_t = 8 G* sqrt(R* delta)`` [N/m] (:func:`tangential_stiffness`, ``G*`` of
:func:`pdamper.contact.elastic.effective_shear_modulus`) and LIGGGHTS' damping
``gamma_t = 2 sqrt(5/6) |beta| sqrt(k_t m*)`` (:func:`tangential_damping`, ``beta`` of the
COR at the onset as Tsuji's normal law). Where ``k_t |xi|`` exceeds ``mu |F_n|`` the
contact slips: ``xi`` is scaled back to ``mu |F_n| / k_t`` and ``F_t = -k_t xi`` (no
damping), the Coulomb force. The spring stores ``k_t |xi|^2 / 2`` (counted as elastic
energy); slip dissipates ``mu |F_n|`` times the slip distance, the damper
``gamma_t |v_t|^2``. Unlike the tanh law a contact below the friction limit sticks (no
creep) and an oblique impact at small incidence recoils tangentially (Maw, Barber &
Fawcett 1976).

Energies
--------
Elastic energy of a contact ``2/5 K delta^(5/2)``; power dissipated by the normal damping
``(F_n - K delta^(3/2)) delta_dot`` (>= 0, also when clipped) and by friction
``|F_t| |v_t|`` (>= 0).
"""

from __future__ import annotations

import math

from numba import njit

from pdamper.contact.damping import (
    exact_damping_factor_scalar,
    gonthier_damping_factor_scalar,
    tsuji_damping_ratio_scalar,
)


@njit(cache=True)
def cor_at(v, v_nodes, e_nodes):
    """COR at impact speed ``|v|`` from tabulated nodes; numba-compiled, no allocation."""
    s = abs(v)
    n = v_nodes.shape[0]
    if n == 1 or s <= v_nodes[0]:
        return e_nodes[0]
    if s >= v_nodes[n - 1]:
        return e_nodes[n - 1]
    lo, hi = 0, n - 1
    while hi - lo > 1:
        mid = (lo + hi) // 2
        if v_nodes[mid] <= s:
            lo = mid
        else:
            hi = mid
    t = (s - v_nodes[lo]) / (v_nodes[hi] - v_nodes[lo])
    return e_nodes[lo] + t * (e_nodes[hi] - e_nodes[lo])


@njit(cache=True, inline="always")
def tangential_stiffness(g_star, r_star, delta):
    """Mindlin's tangential stiffness ``k_t = 8 G* sqrt(R* delta)`` [N/m] (no
    micro-slip; LIGGGHTS' Hertz model) for the effective shear modulus ``G*`` [Pa], the
    effective radius ``R*`` [m] and the overlap ``delta`` [m]."""
    return 8.0 * g_star * math.sqrt(r_star * delta)


@njit(cache=True, inline="always")
def tangential_damping(x, k_t, m_eff):
    """LIGGGHTS' tangential damping ``gamma_t = x sqrt(k_t m*)`` [N s/m] with
    ``x = 2 sqrt(5/6) |beta|`` (:func:`pdamper.contact.damping.tsuji_damping_ratio_scalar`
    of the COR), the stiffness ``k_t`` [N/m] and the effective mass ``m*`` [kg]."""
    return x * math.sqrt(k_t * m_eff)


#: Integer codes of the damping models for the kernels.
DAMPING_EXACT = 0
DAMPING_GONTHIER = 1
DAMPING_TSUJI = 2
#: Code of each damping model name of :data:`pdamper.contact.law.DAMPING_MODELS`.
DAMPING_CODES = {"exact": DAMPING_EXACT, "gonthier": DAMPING_GONTHIER, "tsuji": DAMPING_TSUJI}


@njit(cache=True)
def damping_factor_for(e, model):
    """Damping factor for the COR ``e`` [-]: x = d v0 (0 = exact, default; 1 = Gonthier)
    or Tsuji's ``2 sqrt(5/6) |beta|`` (2)."""
    if e >= 1.0:
        return 0.0
    if model == DAMPING_GONTHIER:
        return gonthier_damping_factor_scalar(e)
    if model == DAMPING_TSUJI:
        return tsuji_damping_ratio_scalar(e)
    return exact_damping_factor_scalar(e)


@njit(cache=True)
def _damping_parameter(x, v, model, k, m_eff):
    if model == DAMPING_TSUJI:
        return x * math.sqrt(1.5 * k * m_eff)
    return x / v


@njit(cache=True)
def onset_damping(v0, v_nodes, e_nodes, model, v_min, k=0.0, m_eff=0.0):
    """Damping parameter of a contact that starts with normal speed ``v0`` [m/s]: ``d``
    [s/m] of the velocity-based laws (exact, Gonthier), or Tsuji's ``c`` [kg/(s m^0.25)]
    for the stiffness ``k`` [N/m^1.5] and effective mass ``m_eff`` [kg] of the contact.

    The COR is read from the pair's curve ``(v_nodes, e_nodes)`` at ``max(|v0|, v_min)``.
    """
    v = abs(v0)
    if v < v_min:
        v = v_min
    e = cor_at(v, v_nodes, e_nodes)
    return _damping_parameter(damping_factor_for(e, model), v, model, k, m_eff)


@njit(cache=True)
def onset_damping_cached(v0, v_nodes, e_nodes, model, v_min, cache, p, k=0.0, m_eff=0.0):
    """:func:`onset_damping` with a one-entry memo per pair type ``p``: bit-identical.

    ``cache[p] = (e, x)`` holds the last COR of pair type ``p`` and its damping factor
    ``x = d v0``. The root of the exact COR relation costs ~1.5 us (a bisection); with a
    constant COR, or onsets below ``v_min`` (contacts that open and close at rest), every
    onset after the first reuses it. Initialise ``cache[:, 0]`` to a value that is no COR
    (e.g. -1).
    """
    v = abs(v0)
    if v < v_min:
        v = v_min
    e = cor_at(v, v_nodes, e_nodes)
    if e != cache[p, 0]:
        cache[p, 0] = e
        cache[p, 1] = damping_factor_for(e, model)
    return _damping_parameter(cache[p, 1], v, model, k, m_eff)


@njit(cache=True, inline="always")
def normal_force(delta, delta_dot, k, d, model=DAMPING_EXACT):
    """Hertz normal force with nonlinear damping.

    Parameters
    ----------
    delta : float
        Overlap [m], > 0.
    delta_dot : float
        Overlap rate [m/s], positive while approaching.
    k : float
        Hertz stiffness [N/m^1.5].
    d : float
        Damping parameter ([s/m]; Tsuji's ``c`` [kg/(s m^0.25)]).
    model : int
        ``DAMPING_TSUJI``: ``K delta^1.5 + c delta^0.25 delta_dot``, not clipped; else
        ``K delta^1.5 (1 + d delta_dot)``, clipped at zero.

    Returns
    -------
    (f_n, f_el) : (float, float)
        Total normal force (>= 0 unless Tsuji's) and its elastic part ``K delta^1.5`` [N].
    """
    f_el = k * delta * math.sqrt(delta)
    if model == DAMPING_TSUJI:
        return f_el + d * math.sqrt(math.sqrt(delta)) * delta_dot, f_el
    f_n = f_el * (1.0 + d * delta_dot)
    if f_n < 0.0:
        f_n = 0.0
    return f_n, f_el


#: tanh(x) / x below x = 0.625: 1 + y P(y) / Q(y), y = x^2 (Moshier's Cephes library,
#: tanh.c); above it (1 - exp(-2x)) / (1 + exp(-2x)); both within 2e-16 of tanh
#: (relative, tests/contact/test_forces.py). Why not ``math.tanh``: libm's tanh has a
#: latency of ~40 ns, in the dependent chain of every slipping contact of every step; this
#: form needs no square root and no tanh in the resting contacts (small slip) and one
#: ``exp`` otherwise: 18 % less CPU per Gear step in a resting bed (docs/dem.md).
_TANH_SPLIT = 0.625
_TANH_P = (-9.64399179425052238628e-1, -9.92877231001918586564e1, -1.61468768441708447952e3)
_TANH_Q = (1.12811678491632931402e2, 2.23548839060100448583e3, 4.84406305325125486048e3)
#: tanh(20) = 1 - 8e-18: exactly 1.0 in double precision
_TANH_ONE = 20.0


@njit(cache=True, inline="always", error_model="numpy")
def friction_per_slip(mu, f_n, vt2, v_reg):
    """|F_t| / |v_t| = mu |F_n| tanh(|v_t| / v_reg) / |v_t| [N s/m] from the squared slip
    speed ``vt2`` [m^2/s^2] (> 0): the viscous coefficient the friction force applies to
    the slip velocity (no square root while ``|v_t| < 0.625 v_reg``)."""
    p0, p1, p2 = _TANH_P
    q0, q1, q2 = _TANH_Q
    y = vt2 / (v_reg * v_reg)
    if y < _TANH_SPLIT * _TANH_SPLIT:
        r = y * ((p0 * y + p1) * y + p2) / (((y + q0) * y + q1) * y + q2)
        return mu * abs(f_n) / v_reg * (1.0 + r)
    vt = math.sqrt(vt2)
    x = vt / v_reg
    if x > _TANH_ONE:
        return mu * abs(f_n) / vt
    e = math.exp(-2.0 * x)
    return mu * abs(f_n) * (1.0 - e) / ((1.0 + e) * vt)


@njit(cache=True)
def friction_magnitude(mu, f_n, v_t, v_reg):
    """|F_t| = mu |F_n| tanh(|v_t| / v_reg) [N] for the slip speed ``v_t`` [m/s]
    (the law of :func:`friction_per_slip`)."""
    if v_t == 0.0:
        return 0.0
    return friction_per_slip(mu, f_n, v_t * v_t, v_reg) * abs(v_t)


@njit(cache=True)
def elastic_energy(delta, f_el):
    """Elastic Hertz energy 2/5 K delta^(5/2) = 2/5 f_el delta [J]."""
    return 0.4 * f_el * delta
