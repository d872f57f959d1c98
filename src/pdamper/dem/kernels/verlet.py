"""Velocity Verlet at a fixed step, advanced in chunks of landings.

:func:`verlet_start` evaluates the first forces and records sample 0;
:func:`verlet_resume` takes over a run that another integrator left at a landing;
:func:`verlet_advance` integrates until a given landing on the half-sample grid (or a
failure) and can be called again to continue: the state between calls is in the arrays and
records, so a run cut into chunks is bit-identical to one call.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from pdamper.dem.kernels.forces import FASTMATH, compute_forces
from pdamper.dem.kernels.modes import (
    modal_acceleration,
    modal_record,
    modal_verlet_drift,
    modal_verlet_kick,
)
from pdamper.dem.kernels.motion import (
    container_state,
    prescribed_state,
    structure_acceleration,
)
from pdamper.dem.kernels.sampling import (
    ledger_start,
    ledger_step,
    on_landing,
    record_sample,
    step_failed,
)
from pdamper.dem.kernels.search import max_displacement2, rebuild
from pdamper.dem.kernels.state import ERR_LIST, ERR_NONE, MOTION_STRUCTURE


@njit(cache=True, fastmath=FASTMATH, error_model="numpy")
def verlet_start(pos, vel, omg, world, law, part, pt, nbrs, walls, drive, stp, work, lg, rs,
                 st, samples, snaps, tang=None):
    """Build the contact list, evaluate the forces at ``stp.t0``, start the ledger and
    record sample 0. A structure's initial ``(z, v)`` is read from ``rs``. ``tang``: None
    (the tanh friction law) or ``(0.0, vel, omg)`` (the spring law, see
    :func:`pdamper.dem.kernels.forces.compute_forces`)."""
    t0 = stp.t0
    s = rs[0]
    zc, vc, ac = container_state(t0, drive, s)
    sta = st[0]
    if rebuild(pos, part.rad, zc, world, nbrs) < 0:
        sta.error = ERR_LIST
        return
    sta.rebuilds += 1
    n = pos.shape[0]
    r, ons = compute_forces(pos, vel, omg, zc, vc, 0.0, False, world, law, part, pt, nbrs,
                            walls, work.frc, work.trq, np.arange(n), n, np.zeros(n, np.int64),
                            tang)
    sta.onsets += ons
    if drive.kind == MOTION_STRUCTURE:
        if drive.nmodes == 0:
            ac = structure_acceleration(r.fz, zc, vc, drive, t0)
        else:
            ac = modal_acceleration(r.fz, drive.m_state, 0, 1, 1.0, drive, t0, drive.m_state)
            modal_record(0, drive.m_state, 1.0, drive)
    led = lg[0]
    ledger_start(led, r)
    e = record_sample(0, t0, pos, vel, omg, part, world, zc, vc, ac, r.eel, led, samples,
                      snaps, stp.snap_every)
    if e != ERR_NONE:
        sta.error = e
        sta.t_error = t0
        return
    s.t = t0
    s.t_win = t0
    s.zc = zc
    s.vc = vc
    s.ac = ac
    s.step = 0
    s.disp = 0.0
    s.countdown = int(round(stp.half / stp.dt))
    s.landing = 0
    s.dt = stp.dt
    s.v_design = stp.v_design
    s.t_base = t0
    s.j_base = 0
    sta.dt_lo = stp.dt
    sta.dt_hi = stp.dt


@njit(cache=True, fastmath=FASTMATH, error_model="numpy")
def verlet_resume(pos, vel, omg, world, law, part, pt, nbrs, walls, drive, stp, work, lg, rs,
                  st, tang=None):
    """Take over a run that another integrator (Gear) left at landing ``rs.landing``,
    time ``rs.t``: a fresh contact list, the forces at that state (the ledger's trapezoid
    restarts from their rates; its integrals, the samples and the contact histories go on)
    and the step that follows the fastest impact so far, as :func:`verlet_advance` would
    have chosen it."""
    s = rs[0]
    sta = st[0]
    t = s.t
    structure = drive.kind == MOTION_STRUCTURE
    zc, vc, ac = container_state(t, drive, s)
    if rebuild(pos, part.rad, zc, world, nbrs) < 0:
        sta.error = ERR_LIST
        sta.t_error = t
        return
    sta.rebuilds += 1
    v_design = stp.v_design
    if stp.follow_impacts != 0 and sta.max_impact > v_design:
        v_design = 1.25 * sta.max_impact
    dtn = stp.dt_design * (stp.v_design / v_design) ** 0.2
    m_half = max(1, int(math.ceil(stp.half / dtn - 1e-9)))
    dt = stp.half / m_half
    n = pos.shape[0]
    r, ons = compute_forces(pos, vel, omg, zc, vc, 0.5 / dt, False, world, law, part, pt, nbrs,
                            walls, work.frc, work.trq, np.arange(n), n, np.zeros(n, np.int64),
                            tang)
    sta.onsets += ons
    if structure:
        if drive.nmodes == 0:
            ac = structure_acceleration(r.fz, zc, vc, drive, t)
        else:
            ac = modal_acceleration(r.fz, drive.m_state, 0, 1, 1.0, drive, t, drive.m_state)
    ledger_step(lg[0], r, 0.0)  # adds nothing, remembers the rates
    s.zc = zc
    s.vc = vc
    s.ac = ac
    s.step = 0
    s.disp = 0.0
    s.countdown = m_half
    s.dt = dt
    s.v_design = v_design
    s.t_base = t
    s.j_base = s.landing
    if dt < sta.dt_lo:
        sta.dt_lo = dt
    if dt > sta.dt_hi:
        sta.dt_hi = dt


@njit(cache=True, fastmath=FASTMATH, error_model="numpy")
def verlet_advance(pos, vel, omg, world, law, part, pt, nbrs, walls, drive, stp, work, lg,
                   rs, st, samples, snaps, j_stop, tang=None):
    """Integrate with velocity Verlet up to landing ``j_stop``.

    Samples are taken every ``2 m`` steps, where ``m = stp.half / dt`` is an integer (the
    caller chooses dt so). The step follows the impacts: after a sample at which the
    fastest impact so far exceeds the design speed of the step, the step is made
    ``dt_design (v_design / v)^(1/5)`` for ``v = 1.25 x`` that impact (the Hertz contact
    time scales as ``v^(-1/5)``), rounded to divide the half sample interval. The update
    is the standard kick-drift-kick scheme. The
    velocities that enter the velocity-dependent forces (damping, friction) at ``t + dt``
    are predicted as ``v + dt a`` (local error O(dt^2); a higher extrapolation,
    ``+ dt/2 (a - a_prev)``, was tried and is unstable in stiff contact networks).
    ``tang``: None (the tanh friction law) or not (the spring law: each step moves the
    tangential displacements by the half-step velocities, those that move the positions).
    """
    n = pos.shape[0]
    m3 = 3 * n
    _verlet_steps(pos, vel, omg, world, law, part, pt, nbrs, walls, drive, stp, work, lg, rs,
                  st, samples, snaps, j_stop, np.empty(m3), np.empty(m3), np.arange(n),
                  np.zeros(n, np.int64), tang)


@njit(cache=True, fastmath=FASTMATH, error_model="numpy", _nrt=False)
def _verlet_steps(pos, vel, omg, world, law, part, pt, nbrs, walls, drive, stp, work, lg, rs,
                  st, samples, snaps, j_stop, im3, ii3, every, none, tang):
    """The steps of :func:`verlet_advance`, compiled without reference counting (see
    :func:`pdamper.dem.kernels.gear._gear_steps`); ``im3``, ``ii3`` work arrays of the
    3n components, ``every = arange(n)``, ``none = zeros(n)``."""
    # arrays out of their bundles once (an access inside the loops counts references)
    frc = work.frc
    trq = work.trq
    vel_pred = work.vel_pred
    omg_pred = work.omg_pred
    rad = part.rad
    pos_build = nbrs.pos_build
    n = pos.shape[0]
    half = stp.half
    dt = rs[0].dt
    m_half = int(round(half / dt))
    skin = world.skin
    structure = drive.kind == MOTION_STRUCTURE
    modal = structure and drive.nmodes > 0
    structure = structure and not modal  # the 1-DOF
    s = rs[0]
    sta = st[0]
    led = lg[0]
    zc = s.zc
    vc = s.vc
    ac = s.ac
    t_win = s.t_win
    step = s.step
    countdown = s.countdown
    disp = s.disp
    t = s.t
    t_base = s.t_base
    j_base = s.j_base
    v_design = s.v_design
    dt_lo = sta.dt_lo
    hdt = 0.5 * dt
    cap_h = 0.5 / dt
    # flat views (3n components) and per-component inverse masses: the kicks vectorise
    m3 = 3 * n
    fpos = pos.reshape(m3)
    fvel = vel.reshape(m3)
    fomg = omg.reshape(m3)
    fvev = vel_pred.reshape(m3)
    fwev = omg_pred.reshape(m3)
    ffrc = frc.reshape(m3)
    ftrq = trq.reshape(m3)
    for i in range(n):
        for a in range(3):
            im3[3 * i + a] = part.inv_mass[i]
            ii3[3 * i + a] = part.inv_inertia[i]
    # rebuild check: the exact test (some particle moved more than skin/2) only when the
    # bound disp >= largest displacement since the build (sum of sqrt(3) dt max|v_a|)
    # allows it: the same rebuild steps as testing every step
    disp_lim = 0.4999 * skin
    sqrt3 = math.sqrt(3.0)
    steps = 0
    onsets = 0
    rebuilds = 0
    j = j_base + step // m_half
    while j < j_stop:
        step += 1
        t = t_base + step * dt
        # translational and rotational kicks in separate loops (fewer arrays per loop for
        # the vectoriser's alias checks), the largest speed component in a third pass with
        # one max chain per component (the same value as a single running max)
        for q in range(m3):
            acc = ffrc[q] * im3[q]
            vh = fvel[q] + hdt * acc
            fvev[q] = fvel[q] + dt * acc
            fvel[q] = vh
            fpos[q] += dt * vh
        for q in range(m3):
            al = ftrq[q] * ii3[q]
            fwev[q] = fomg[q] + dt * al
            fomg[q] += hdt * al
        vmx0 = 0.0
        vmx1 = 0.0
        vmx2 = 0.0
        for i in range(n):
            vmx0 = max(vmx0, abs(fvel[3 * i]))
            vmx1 = max(vmx1, abs(fvel[3 * i + 1]))
            vmx2 = max(vmx2, abs(fvel[3 * i + 2]))
        vmx = max(vmx0, max(vmx1, vmx2))
        disp += sqrt3 * dt * vmx
        if structure:
            vch = vc + hdt * ac
            vce = vc + dt * ac
            zc += dt * vch
        elif modal:
            zc, vce = modal_verlet_drift(dt, drive, t)
        else:
            zc, vce, ac = prescribed_state(t, drive)
        if not disp <= disp_lim:
            d2 = max_displacement2(pos, pos_build)
            if d2 > 0.25 * skin * skin:
                if rebuild(pos, rad, zc, world, nbrs) < 0:
                    sta.error = ERR_LIST
                    sta.t_error = t
                    break
                rebuilds += 1
                disp = 0.0
            else:
                disp = math.sqrt(d2)
        if tang is None:
            r, ons = compute_forces(pos, vel_pred, omg_pred, zc, vce, cap_h, False,
                                    world, law, part, pt, nbrs, walls, frc, trq, every, n, none)
        else:
            # the spring law: the step and its half-step velocities (those that moved the
            # positions) move the tangential displacements
            r, ons = compute_forces(pos, vel_pred, omg_pred, zc, vce, cap_h, False, world,
                                    law, part, pt, nbrs, walls, frc, trq, every, n, none,
                                    (dt, vel, omg))
        onsets += ons
        for q in range(m3):
            fvel[q] += hdt * ffrc[q] * im3[q]
            fomg[q] += hdt * ftrq[q] * ii3[q]
        if structure:
            ac = structure_acceleration(r.fz, zc, vce, drive, t)
            vc = vch + hdt * ac
        elif modal:
            vc, ac = modal_verlet_kick(r.fz, dt, drive, t)
        else:
            vc = vce
        ledger_step(led, r, hdt)
        steps += 1
        if step_failed(r, sta, t, stp.max_overlap, stp.v_limit):
            break
        countdown -= 1
        if countdown == 0:
            countdown = m_half
            j = j_base + step // m_half
            t_win, stop = on_landing(j, t, t_win, pos, vel, omg, part, world, zc, vc, ac,
                                     r.eel, led, samples, snaps, stp, sta)
            if modal and j % 2 == 0:
                modal_record(j // 2, drive.m_state, 1.0, drive)
            if stop:
                break
            if stp.follow_impacts != 0 and j % 2 == 0 and sta.max_impact > v_design:
                v_design = 1.25 * sta.max_impact
                dtn = stp.dt_design * (stp.v_design / v_design) ** 0.2
                m_half = max(1, int(math.ceil(half / dtn - 1e-9)))
                dt = half / m_half
                hdt = 0.5 * dt
                cap_h = 0.5 / dt
                if dt < dt_lo:
                    dt_lo = dt
                t_base = t
                j_base = j
                step = 0
                countdown = m_half
    sta.steps += steps
    sta.onsets += onsets
    sta.rebuilds += rebuilds
    s.t = t
    s.t_win = t_win
    s.zc = zc
    s.vc = vc
    s.ac = ac
    s.step = step
    s.countdown = countdown
    s.disp = disp
    s.landing = j
    s.dt = dt
    s.t_base = t_base
    s.j_base = j_base
    s.v_design = v_design
    sta.dt_lo = dt_lo
