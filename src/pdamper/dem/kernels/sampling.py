"""Sampling and the energy ledger, shared by both integrators.

Both integrators land exactly on a grid of half sample intervals: the odd landings close
the window of the force on the container (the mean over the window centred on a sample,
an anti-aliased force), the even ones record a sample. Between landings the ledger
integrates, with the trapezoidal rule over each step, the power dissipated in the normal
damping and by friction, the power of the container walls on the particles and the force
on the container (its impulse). A sample also checks the run: non-finite states, particles
outside the container and an energy ledger that no longer closes stop it.
"""

from __future__ import annotations

import math

from numba import njit

from pdamper.dem.kernels.state import (
    ERR_ENERGY,
    ERR_ESCAPE,
    ERR_NAN,
    ERR_NONE,
    ERR_OVERLAP,
    ERR_SPEED,
)


@njit(cache=True, fastmath=False, error_model="numpy", _nrt=False)
def record_sample(k, t, pos, vel, omg, part, world, zc, vc, ac, eel, lg, samples, snaps,
                  snap_every):
    """Store sample ``k`` (state at time t) and, every ``snap_every`` samples, a snapshot.

    ``lg`` is the ledger record (running integrals [J]), ``eel`` the elastic energy of the
    last force evaluation. Returns an error code from the checks (NaN, particle outside the
    container, energy blow-up).
    """
    mass = part.mass
    inertia = part.inertia
    n = pos.shape[0]
    g = world.gravity
    ekt = 0.0
    ekr = 0.0
    epot = 0.0
    mt = 0.0
    cx = 0.0
    cy = 0.0
    cz = 0.0
    err = ERR_NONE
    lx = world.lx
    ly = world.ly
    lz = world.lz
    for i in range(n):
        m = mass[i]
        ekt += 0.5 * m * (vel[i, 0] ** 2 + vel[i, 1] ** 2 + vel[i, 2] ** 2)
        ekr += 0.5 * inertia[i] * (omg[i, 0] ** 2 + omg[i, 1] ** 2 + omg[i, 2] ** 2)
        epot += m * g * pos[i, 2]
        mt += m
        cx += m * pos[i, 0]
        cy += m * pos[i, 1]
        cz += m * pos[i, 2]
        x = pos[i, 0]
        y = pos[i, 1]
        z = pos[i, 2] - zc
        if not (math.isfinite(x) and math.isfinite(y) and math.isfinite(z)
                and math.isfinite(vel[i, 0] + vel[i, 1] + vel[i, 2])):
            return ERR_NAN
        if x < 0.0 or x > lx or y < 0.0 or y > ly or z < 0.0 or z > lz:
            err = ERR_ESCAPE
    s = samples
    s.time[k] = t
    s.zc[k] = zc
    s.vc[k] = vc
    s.ac[k] = ac
    s.com[k, 0] = cx / mt
    s.com[k, 1] = cy / mt
    s.com[k, 2] = cz / mt
    s.kinetic[k] = ekt
    s.rotational[k] = ekr
    s.potential[k] = epot
    s.elastic[k] = eel
    s.dissipated_normal[k] = lg.dn
    s.dissipated_friction[k] = lg.df
    s.container_work[k] = lg.wc
    if snap_every > 0 and k % snap_every == 0:
        q = k // snap_every
        if q < snaps.pos.shape[0]:
            s_pos = snaps.pos
            s_vel = snaps.vel
            s_omg = snaps.omg
            for i in range(n):
                for a in range(3):
                    s_pos[q, i, a] = pos[i, a]
                    s_vel[q, i, a] = vel[i, a]
                    s_omg[q, i, a] = omg[i, a]
    if err != ERR_NONE:
        return err
    # energy blow-up: the ledger residual must stay small against the energies in play
    e0 = s.kinetic[0] + s.rotational[0] + s.potential[0] + s.elastic[0]
    e1 = ekt + ekr + epot + eel
    res = abs((e1 - e0) - (lg.wc - lg.dn - lg.df))
    scale = (ekt + ekr + eel + s.kinetic[0] + s.rotational[0] + s.elastic[0] + abs(lg.wc)
             + lg.dn + lg.df + mt * g * lz + mt * 1e-4)
    if k > 0 and res > 0.5 * scale:
        return ERR_ENERGY
    return ERR_NONE


@njit(cache=True, fastmath=False, error_model="numpy", _nrt=False)
def close_window(k, t, t_win, lg, force):
    """Mean force on the container over the sample window that ends at ``t``; the impulse
    accumulator of the ledger starts again."""
    span = t - t_win
    if span > 0.0:
        force[k, 0] = lg.imp_x / span
        force[k, 1] = lg.imp_y / span
        force[k, 2] = lg.imp_z / span
    lg.imp_x = 0.0
    lg.imp_y = 0.0
    lg.imp_z = 0.0


@njit(cache=True, inline="always")
def _remember(lg, r):
    """Keep the rates ``r`` of this evaluation for the next trapezoid."""
    lg.p_dn = r.dn
    lg.p_df = r.df
    lg.p_wc = r.wc
    lg.p_fx = r.fx
    lg.p_fy = r.fy
    lg.p_fz = r.fz


@njit(cache=True, inline="always")
def ledger_start(lg, r):
    """Zero the running integrals and remember the rates ``r`` of the first evaluation."""
    lg.dn = 0.0
    lg.df = 0.0
    lg.wc = 0.0
    lg.imp_x = 0.0
    lg.imp_y = 0.0
    lg.imp_z = 0.0
    _remember(lg, r)


@njit(cache=True, inline="always")
def ledger_step(lg, r, hw):
    """Trapezoidal update over a step of length ``2 hw`` of the dissipation (normal,
    friction), the container work and the impulse on the container."""
    lg.dn += hw * (lg.p_dn + r.dn)
    lg.df += hw * (lg.p_df + r.df)
    lg.wc += hw * (lg.p_wc + r.wc)
    lg.imp_x += hw * (lg.p_fx + r.fx)
    lg.imp_y += hw * (lg.p_fy + r.fy)
    lg.imp_z += hw * (lg.p_fz + r.fz)
    _remember(lg, r)


@njit(cache=True, inline="always")
def step_failed(r, st, t, maxovl, vlim):
    """Record the largest overlap and the fastest impact; flag NaN and speed blow-ups, and
    overlaps beyond ``maxovl`` if that is finite (True: stop)."""
    if r.ovl > st.max_overlap:
        st.max_overlap = r.ovl
    if r.vimp > st.max_impact:
        st.max_impact = r.vimp
    if r.ovl > maxovl or r.vmax > vlim or not math.isfinite(r.fz):
        st.error = ERR_OVERLAP if r.ovl > maxovl else (ERR_SPEED if r.vmax > vlim else ERR_NAN)
        st.t_error = t
        st.error_value = r.ovl if r.ovl > maxovl else r.vmax
        return True
    return False


@njit(cache=True, inline="always")
def on_landing(j, t, t_win, pos, vel, omg, part, world, zc, vc, ac, eel, lg, samples, snaps,
               stp, st):
    """The ``j``-th landing on the half-sample grid: odd ones close a force window, even
    ones record sample ``j // 2``. Returns the start of the current window and whether the
    run must stop."""
    k = j // 2
    if j % 2 == 1:
        close_window(k, t, t_win, lg, samples.force)
        return t, False
    e = record_sample(k, t, pos, vel, omg, part, world, zc, vc, ac, eel, lg, samples, snaps,
                      stp.snap_every)
    if e != ERR_NONE:
        st.error = e
        st.t_error = t
        return t_win, True
    if k == stp.nsamp - 1:
        close_window(k, t, t_win, lg, samples.force)
    return t_win, False
