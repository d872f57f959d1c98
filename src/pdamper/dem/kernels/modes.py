"""A structure of N mass-normalised modes carrying the container (the DEM co-simulation
on N modes).

The modal coordinates ``q_j`` (relative to the base) obey

    q_j'' + 2 zeta_j w_j q_j' + w_j^2 q_j = phi_c,j F_z + phi_L,j F(t) - Gamma_j a_b(t)

(``F_z`` the force of the particles on the container, ``phi_c`` the modes at the
container, ``phi_L`` at the load point, ``Gamma`` the participation factors of a base
translation), and the container moves with the modal sum at its point,
``z_c = phi_c . q + z_b``, ``v_c = phi_c . q' + v_b``, ``a_c = phi_c . q'' + a_b``
(absolute: what the particles feel). Without a load history ``F(t)`` is the drive's
harmonic load ``F cos(W t + phi)`` (``drive.amplitude``, ``omega``, ``z0``) and the base
is fixed.

The arrays live in the :class:`~pdamper.dem.kernels.state.Drive` bundle
(``drive.nmodes > 0``; 0 is the 1-DOF of :func:`pdamper.dem.kernels.motion.structure_acceleration`):
``m_state`` (3, N) holds ``(q, q', q'')`` between chunks and is velocity Verlet's state,
``m_nord`` (6, N) the Gear Nordsieck vectors ``(q, h q', h^2 q''/2, ...)`` of the modes
(``m_backup`` the copy a rejected step restores; velocity Verlet uses both as scratch),
``m_samples`` (samples, 3N) the coordinates, their rates and accelerations at the
samples.
"""

from __future__ import annotations

import math

from numba import njit

from pdamper.dem.kernels.motion import structure_load


@njit(cache=True, fastmath=False, error_model="numpy")
def modal_forcing(drive, t):
    """Base position [m], velocity [m/s], acceleration [m/s^2] and the external force [N]
    at time ``t`` [s]. The base acceleration table ``table_b`` is interpolated linearly as
    the others (uniform step ``table_dt`` from ``t = 0``, constant beyond its ends)."""
    if drive.loaded != 0:
        zb, vb, fe = structure_load(t, drive)
        tb = drive.table_b
        s = t / drive.table_dt
        i = int(math.floor(s))
        nt = tb.shape[0]
        if i < 0:
            ab = tb[0]
        elif i >= nt - 1:
            ab = tb[nt - 1]
        else:
            ab = tb[i] + (s - i) * (tb[i + 1] - tb[i])
        return zb, vb, ab, fe
    return 0.0, 0.0, 0.0, drive.amplitude * math.cos(drive.omega * t + drive.z0)


@njit(cache=True, fastmath=False, error_model="numpy")
def modal_acceleration(fz, src, rq, rv, scale, drive, t, ms):
    """The modal accelerations ``q_j''`` (into ``ms[2]``) with ``q_j = src[rq, j]``,
    ``q_j' = scale src[rv, j]`` (a Nordsieck vector: ``rv = 1``, ``scale = 1/h``) under
    the particles' force ``fz`` [N] at time ``t`` [s]; returns the container's absolute
    acceleration ``phi_c . q'' + a_b`` [m/s^2]."""
    _, _, ab, fe = modal_forcing(drive, t)
    phi = drive.m_phi
    load = drive.m_load
    gam = drive.m_gamma
    c = drive.m_c
    w2 = drive.m_w2
    ac = ab
    for j in range(drive.nmodes):
        a = (phi[j] * fz + load[j] * fe - gam[j] * ab - c[j] * (scale * src[rv, j])
             - w2[j] * src[rq, j])
        ms[2, j] = a
        ac += phi[j] * a
    return ac


@njit(cache=True, fastmath=False, error_model="numpy")
def modal_container(src, rq, rv, scale, drive, t):
    """Container position and velocity (absolute) ``(phi_c . q + z_b, phi_c . q' + v_b)``
    of the coordinates ``src[rq]``, velocities ``scale src[rv]``."""
    zb, vb, _, _ = modal_forcing(drive, t)
    phi = drive.m_phi
    z = 0.0
    v = 0.0
    for j in range(drive.nmodes):
        z += phi[j] * src[rq, j]
        v += phi[j] * src[rv, j]
    return z + zb, scale * v + vb


@njit(cache=True, fastmath=False, error_model="numpy")
def modal_gear_begin(fz, h, drive, t):
    """Gear's Nordsieck vectors of the modes for a first step ``h`` from ``m_state``
    (the derivatives above the acceleration zero); returns the container's acceleration."""
    ms = drive.m_state
    mn = drive.m_nord
    ac = modal_acceleration(fz, ms, 0, 1, 1.0, drive, t, ms)
    for j in range(drive.nmodes):
        mn[0, j] = ms[0, j]
        mn[1, j] = h * ms[1, j]
        mn[2, j] = 0.5 * h * h * ms[2, j]
        for k in range(3, 6):
            mn[k, j] = 0.0
    return ac


@njit(cache=True, fastmath=False, error_model="numpy")
def modal_gear_predict(q1, q2, q3, q4, q5, ih, drive, t):
    """Back up, rescale (ratio^k) and predict (Pascal triangle) the modes' Nordsieck
    vectors; returns the predicted container position and velocity at ``t``."""
    mn = drive.m_nord
    bk = drive.m_backup
    for j in range(drive.nmodes):
        c0 = mn[0, j]
        c1 = mn[1, j] * q1
        c2 = mn[2, j] * q2
        c3 = mn[3, j] * q3
        c4 = mn[4, j] * q4
        c5 = mn[5, j] * q5
        bk[0, j] = c0
        bk[1, j] = c1
        bk[2, j] = c2
        bk[3, j] = c3
        bk[4, j] = c4
        bk[5, j] = c5
        mn[0, j] = c0 + c1 + c2 + c3 + c4 + c5
        mn[1, j] = c1 + 2.0 * c2 + 3.0 * c3 + 4.0 * c4 + 5.0 * c5
        mn[2, j] = c2 + 3.0 * c3 + 6.0 * c4 + 10.0 * c5
        mn[3, j] = c3 + 4.0 * c4 + 10.0 * c5
        mn[4, j] = c4 + 5.0 * c5
        mn[5, j] = c5
    return modal_container(mn, 0, 1, ih, drive, t)


@njit(cache=True, fastmath=False, error_model="numpy")
def modal_gear_restore(drive):
    """The modes' Nordsieck vectors at the start of the step (rescaled): a step undone."""
    mn = drive.m_nord
    bk = drive.m_backup
    for j in range(drive.nmodes):
        for k in range(6):
            mn[k, j] = bk[k, j]


@njit(cache=True, fastmath=False, error_model="numpy")
def modal_gear_error(fz, hh, h, ih, vscale, g1, drive, t):
    """The accelerations at the prediction (into ``m_state[2]``) and the largest local
    error of the modes, measured as the particles' is: ``|w_j corr_j| / (h (v_scale +
    |w_j q_j'|))``, ``corr_j`` the corrector difference of mode j, ``g1`` the corrector's
    velocity coefficient and ``w_j`` the mode's weight ``m_weight`` [1/sqrt(kg)] (its
    largest shape at the container and the load point), so that the error is a
    displacement of the structure's points that the particles and the load see. Returns
    ``(a_c, err)``."""
    ms = drive.m_state
    mn = drive.m_nord
    wgt = drive.m_weight
    ac = modal_acceleration(fz, mn, 0, 1, ih, drive, t, ms)
    err = 0.0
    for j in range(drive.nmodes):
        corr = hh * ms[2, j] - mn[2, j]
        w = wgt[j]
        ec = abs(w * corr) / (h * (vscale + abs(w * (mn[1, j] + g1 * corr) * ih)))
        if ec > err:
            err = ec
    return ac, err


@njit(cache=True, fastmath=False, error_model="numpy")
def modal_gear_correct(hh, ih, drive, t, g0, g1, g3, g4, g5):
    """Correct the modes' Nordsieck vectors from the accelerations in ``m_state[2]`` (the
    position rows' Gear coefficients ``g*``); returns the container's position and
    velocity."""
    ms = drive.m_state
    mn = drive.m_nord
    for j in range(drive.nmodes):
        corr = hh * ms[2, j] - mn[2, j]
        mn[0, j] += g0 * corr
        mn[1, j] += g1 * corr
        mn[2, j] += corr
        mn[3, j] += g3 * corr
        mn[4, j] += g4 * corr
        mn[5, j] += g5 * corr
    return modal_container(mn, 0, 1, ih, drive, t)


@njit(cache=True, fastmath=False, error_model="numpy")
def modal_gear_store(h, drive):
    """``m_state``'s ``(q, q')`` from the Nordsieck vectors (the end of a chunk: another
    integrator or the next chunk resumes from them)."""
    ms = drive.m_state
    mn = drive.m_nord
    ih = 1.0 / h
    for j in range(drive.nmodes):
        ms[0, j] = mn[0, j]
        ms[1, j] = mn[1, j] * ih


@njit(cache=True, fastmath=False, error_model="numpy")
def modal_verlet_drift(dt, drive, t):
    """First half of a velocity-Verlet step of the modes: the half-step velocities (into
    ``m_backup[0]``), the velocity estimate at the step's end (``m_backup[1]``) and the
    new positions (``m_state[0]``, copied into ``m_backup[2]``); returns the container's
    position and estimated velocity at ``t``."""
    ms = drive.m_state
    bk = drive.m_backup
    hdt = 0.5 * dt
    for j in range(drive.nmodes):
        vh = ms[1, j] + hdt * ms[2, j]
        bk[0, j] = vh
        bk[1, j] = ms[1, j] + dt * ms[2, j]
        ms[0, j] += dt * vh
        bk[2, j] = ms[0, j]
    zb, vb, _, _ = modal_forcing(drive, t)
    phi = drive.m_phi
    z = 0.0
    v = 0.0
    for j in range(drive.nmodes):
        z += phi[j] * ms[0, j]
        v += phi[j] * bk[1, j]
    return z + zb, v + vb


@njit(cache=True, fastmath=False, error_model="numpy")
def modal_verlet_kick(fz, dt, drive, t):
    """Second half of a velocity-Verlet step: the accelerations under ``fz`` at the
    estimated velocities, the velocities' second half kick; returns the container's
    velocity and acceleration."""
    ms = drive.m_state
    bk = drive.m_backup
    # the accelerations at the new positions and the estimated velocities (as the
    # particles' forces are evaluated), into ms[2]
    ac = modal_acceleration(fz, bk, 2, 1, 1.0, drive, t, ms)
    hdt = 0.5 * dt
    for j in range(drive.nmodes):
        ms[1, j] = bk[0, j] + hdt * ms[2, j]
    _, vb, _, _ = modal_forcing(drive, t)
    phi = drive.m_phi
    v = 0.0
    for j in range(drive.nmodes):
        v += phi[j] * ms[1, j]
    return v + vb, ac


@njit(cache=True, fastmath=False, error_model="numpy")
def modal_record(k, src, scale, drive):
    """Sample row ``k`` of ``m_samples``: ``(q, q', q'')``, N columns each, with
    ``q = src[0]``, ``q' = scale src[1]`` (``m_state``: 1; a Nordsieck vector: 1/h) and
    ``q''`` from ``m_state[2]``."""
    ms = drive.m_state
    out = drive.m_samples
    n = drive.nmodes
    if k < out.shape[0]:
        for j in range(n):
            out[k, j] = src[0, j]
            out[k, n + j] = scale * src[1, j]
            out[k, 2 * n + j] = ms[2, j]
