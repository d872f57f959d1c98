"""Variable-step fifth-order Gear predictor-corrector (the paper's integrator), advanced
in chunks of landings.

Positions use the 6-value Nordsieck vector ``(x, h v, h^2 a/2, h^3 x'''/6, ...)`` of a
second-order ODE; angular velocities the 5-value vector of a first-order ODE (Euler's
equations of a sphere: ``I dw/dt = T``); the 1-DOF structure (if any) a 6-value vector,
each mode of an N-mode structure its own (:mod:`pdamper.dem.kernels.modes`, its error in
the step control as the container's).
After each accepted step the step ``h`` is changed by the PI controller
``0.9 (tol / err)^(0.7/6) (err_prev / tol)^(0.4/6)`` (bounded to [0.3, 2]), where
``err = max_i |corr_i| / (h (v_scale + |v_i|))`` is the local error estimate from the
corrector difference ``corr`` of the position (computed before the correction: a step with
``err > REJECT tol`` is undone by inverting the prediction and repeated with
``0.9 (tol / err)^(1/6)``, at least 0.1, times the step); the Nordsieck vectors are
rescaled by ``ratio^k``. The friction cap uses ``max(h, stp.h_cap)``. Steps are also
bounded by ``skin / (4 v_max)``, by ``dt_max``, optionally (``stp.contact_bound``) by the
time to the next contact (never below ``stp.dt_contact``), and land exactly on the sample
grid. ``stp.adaptive = 0`` keeps ``stp.dt`` fixed.

With ``stp.free_flight`` the step integrates only the spheres that may touch something;
the others fly their exact parabola (:mod:`pdamper.dem.kernels.flights`: regroups at each
sample, after list rebuilds and periodically, rejoining when a horizon ends, speed limits
checked after each correction).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from pdamper.dem.kernels.flights import (
    REGROUP_EVERY,
    REGROUP_MAX,
    join_due,
    regroup,
)
from pdamper.dem.kernels.forces import FASTMATH, compute_forces
from pdamper.dem.kernels.modes import (
    modal_gear_begin,
    modal_gear_correct,
    modal_gear_error,
    modal_gear_predict,
    modal_gear_restore,
    modal_gear_store,
    modal_record,
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
from pdamper.dem.kernels.search import needs_rebuild, rebuild
from pdamper.dem.kernels.state import ERR_LIST, ERR_NONE, MOTION_STRUCTURE, Rates

# Gear coefficients (Gear 1971; Allen & Tildesley, App. E): 6-value Nordsieck vector of a
# second-order ODE, with 3/20 instead of 3/16 because the forces depend on the velocities.
G0 = 3.0 / 20.0
G1 = 251.0 / 360.0
G3 = 11.0 / 18.0
G4 = 1.0 / 6.0
G5 = 1.0 / 60.0
# 5-value Nordsieck vector of a first-order ODE (angular velocities)
H0 = 251.0 / 720.0
H2 = 11.0 / 12.0
H3 = 1.0 / 3.0
H4 = 1.0 / 24.0
#: the corrector's coefficients of each Nordsieck row (1.0 where :func:`_correct` adds the
#: difference itself: the product is exact)
GX = np.array([G0, G1, 1.0, G3, G4, G5])
GW = np.array([H0, 1.0, H2, H3, H4])
#: a Gear step whose error estimate exceeds REJECT x tolerance is repeated with a smaller step
REJECT = 4.0
#: PI step-size control exponents (Gustafsson 1991; Hairer & Wanner II, IV.2), order 5 + 1
PI_KI = 0.7 / 6.0
PI_KP = 0.4 / 6.0


@njit(cache=True, fastmath=FASTMATH, inline="always", error_model="numpy")
def _begin(t, h, pos, vel, omg, world, law, part, pt, nbrs, walls, drive, stp, work, nord, fl,
           s, sta):
    """Build the contact list, evaluate the forces of all particles at time ``t`` (every
    particle stepped: ``pos``, ``vel`` hold the state of all) and fill the Nordsieck vectors
    for a first step ``h`` (the derivatives above the acceleration zero). Returns
    ``(rates, zc, vc, ac, ok)``."""
    n = pos.shape[0]
    free = fl.free
    for i in range(n):
        free[i] = 0
        fl.act[i] = i
    fl.count[0] = n
    fl.scal[2] = REGROUP_EVERY
    structure = drive.kind == MOTION_STRUCTURE
    zc, vc, ac = container_state(t, drive, s)
    if rebuild(pos, part.rad, zc, world, nbrs) < 0:
        sta.error = ERR_LIST
        sta.t_error = t
        return Rates(0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0), zc, vc, ac, False
    sta.rebuilds += 1
    want_ttc = stp.adaptive != 0 and stp.contact_bound != 0
    r, ons = compute_forces(pos, vel, omg, zc, vc, 0.0, want_ttc, world, law, part, pt, nbrs,
                            walls, work.frc, work.trq, fl.act, n, free, None)
    sta.onsets += ons
    if structure:
        if drive.nmodes == 0:
            ac = structure_acceleration(r.fz, zc, vc, drive, t)
        else:
            ac = modal_gear_begin(r.fz, h, drive, t)
    nx = nord.x
    nw = nord.w
    nc = nord.c
    frc = work.frc
    trq = work.trq
    mass = part.mass
    inertia = part.inertia
    for k in range(6):
        nc[k] = 0.0
        for i in range(n):
            for a in range(3):
                nx[k, i, a] = 0.0
                if k < 5:
                    nw[k, i, a] = 0.0
    for i in range(n):
        for a in range(3):
            nx[0, i, a] = pos[i, a]
            nx[1, i, a] = h * vel[i, a]
            nx[2, i, a] = 0.5 * h * h * frc[i, a] / mass[i]
            nw[0, i, a] = omg[i, a]
            nw[1, i, a] = h * trq[i, a] / inertia[i]
    nc[0] = zc
    nc[1] = h * vc
    nc[2] = 0.5 * h * h * ac
    return r, zc, vc, ac, True


@njit(cache=True, inline="always")
def _set_state(s, r, zc, vc, ac, h, v_design, h_cap, dt_min):
    """The run-state record after a (re)start: container, first step ``h`` with no error
    history, the impact speed the bounds are designed for and the bounds themselves."""
    s.zc = zc
    s.vc = vc
    s.ac = ac
    s.h = h
    s.h_des = h
    s.le_prev = 0.0
    s.v_design = v_design
    s.h_cap = h_cap
    s.dt_min = dt_min
    s.ttc = r.ttc
    s.vmax = r.vmax


@njit(cache=True, fastmath=FASTMATH, inline="always")
def _regroup(t, h, vc, ac, pos, vel, omg, zc, world, part, nbrs, walls, stp, work, nord, fl,
             sta):
    """:func:`~pdamper.dem.kernels.flights.regroup` with the kernel's arrays; returns
    the number of stepped spheres and their largest speed."""
    na = regroup(t, h, vc, ac, stp.free_flight != 0, pos, vel, omg, nord.x, nord.w, work.frc,
                 work.trq, work.vel_pred, work.omg_pred, zc, world, part, nbrs, walls, fl,
                 2.0 * stp.half)
    sta.regroups += 1
    act = fl.act
    v2 = 0.0
    for k in range(na):
        i = act[k]
        v2 = max(v2, vel[i, 0] ** 2 + vel[i, 1] ** 2 + vel[i, 2] ** 2)
    return na, math.sqrt(v2)


@njit(cache=True, fastmath=FASTMATH, error_model="numpy")
def gear_start(pos, vel, omg, world, law, part, pt, nbrs, walls, drive, stp, work, nord, fl,
               lg, rs, st, samples, snaps):
    """Build the contact list, evaluate the forces at ``stp.t0``, fill the Nordsieck
    vectors for the first step ``stp.dt``, start the ledger and record sample 0."""
    t0 = stp.t0
    h = stp.dt
    s = rs[0]
    sta = st[0]
    r, zc, vc, ac, ok = _begin(t0, h, pos, vel, omg, world, law, part, pt, nbrs, walls, drive,
                               stp, work, nord, fl, s, sta)
    if not ok:
        return
    led = lg[0]
    ledger_start(led, r)
    e = record_sample(0, t0, pos, vel, omg, part, world, zc, vc, ac, r.eel, led, samples,
                      snaps, stp.snap_every)
    if drive.nmodes > 0:
        modal_record(0, drive.m_nord, 1.0 / h, drive)
    if e != ERR_NONE:
        sta.error = e
        sta.t_error = t0
        return
    s.t = t0
    s.t_win = t0
    s.landing = 0
    _set_state(s, r, zc, vc, ac, h, stp.v_design, stp.h_cap, stp.dt_min)
    sta.dt_lo = 1e300
    sta.dt_hi = 0.0
    if stp.free_flight != 0:
        _, s.vmax = _regroup(t0, h, vc, ac, pos, vel, omg, zc, world, part, nbrs, walls, stp,
                             work, nord, fl, sta)


@njit(cache=True, fastmath=FASTMATH, error_model="numpy")
def gear_resume(pos, vel, omg, world, law, part, pt, nbrs, walls, drive, stp, work, nord, fl,
                lg, rs, st, h):
    """Take over a run that velocity Verlet left at landing ``rs.landing``, time ``rs.t``,
    with a first step ``h`` [s]: a fresh contact list, the forces and Nordsieck vectors at
    that state (the ledger's trapezoid restarts from their rates; its integrals, the samples
    and the contact histories go on), the friction cap and smallest step following the
    fastest impact so far as :func:`gear_advance` would have set them."""
    s = rs[0]
    sta = st[0]
    r, zc, vc, ac, ok = _begin(s.t, h, pos, vel, omg, world, law, part, pt, nbrs, walls,
                               drive, stp, work, nord, fl, s, sta)
    if not ok:
        return
    ledger_step(lg[0], r, 0.0)  # adds nothing, remembers the rates
    v_design = max(stp.v_design, s.v_design)
    scale = (stp.v_design / v_design) ** 0.2
    _set_state(s, r, zc, vc, ac, h, v_design, stp.h_cap * scale, stp.dt_min * scale)
    if stp.free_flight != 0:
        _, s.vmax = _regroup(s.t, h, vc, ac, pos, vel, omg, zc, world, part, nbrs, walls, stp,
                             work, nord, fl, sta)


@njit(cache=True, fastmath=FASTMATH, inline="always")
def _undo_prediction(nx, nw, act, na):
    """Inverse of the Pascal-triangle prediction of the stepped particles ``act[:na]``:
    the (rescaled) Nordsieck vectors at the start of the step."""
    for k in range(na):
        i = act[k]
        for a in range(3):
            x5 = nx[5, i, a]
            x4 = nx[4, i, a] - 5.0 * x5
            x3 = nx[3, i, a] - 4.0 * x4 - 10.0 * x5
            x2 = nx[2, i, a] - 3.0 * x3 - 6.0 * x4 - 10.0 * x5
            x1 = nx[1, i, a] - 2.0 * x2 - 3.0 * x3 - 4.0 * x4 - 5.0 * x5
            nx[0, i, a] -= x1 + x2 + x3 + x4 + x5
            nx[1, i, a] = x1
            nx[2, i, a] = x2
            nx[3, i, a] = x3
            nx[4, i, a] = x4
            w4 = nw[4, i, a]
            w3 = nw[3, i, a] - 4.0 * w4
            w2 = nw[2, i, a] - 3.0 * w3 - 6.0 * w4
            w1 = nw[1, i, a] - 2.0 * w2 - 3.0 * w3 - 4.0 * w4
            nw[0, i, a] -= w1 + w2 + w3 + w4
            nw[1, i, a] = w1
            nw[2, i, a] = w2
            nw[3, i, a] = w3


@njit(cache=True, fastmath=FASTMATH, inline="always")
def _predict(q, fx, fw, fpos, fvev, fwev, q1, q2, q3, q4, q5, ih):
    """Rescale (ratio^k) and predict (Pascal triangle) component ``q`` in one pass."""
    x0 = fx[0, q]
    x1 = fx[1, q] * q1
    x2 = fx[2, q] * q2
    x3 = fx[3, q] * q3
    x4 = fx[4, q] * q4
    x5 = fx[5, q] * q5
    w0 = fw[0, q]
    w1 = fw[1, q] * q1
    w2 = fw[2, q] * q2
    w3 = fw[3, q] * q3
    w4 = fw[4, q] * q4
    p0 = x0 + x1 + x2 + x3 + x4 + x5
    p1 = x1 + 2.0 * x2 + 3.0 * x3 + 4.0 * x4 + 5.0 * x5
    fx[0, q] = p0
    fx[1, q] = p1
    fx[2, q] = x2 + 3.0 * x3 + 6.0 * x4 + 10.0 * x5
    fx[3, q] = x3 + 4.0 * x4 + 10.0 * x5
    fx[4, q] = x4 + 5.0 * x5
    fx[5, q] = x5
    fpos[q] = p0
    fvev[q] = p1 * ih
    p0 = w0 + w1 + w2 + w3 + w4
    fw[0, q] = p0
    fw[1, q] = w1 + 2.0 * w2 + 3.0 * w3 + 4.0 * w4
    fw[2, q] = w2 + 3.0 * w3 + 6.0 * w4
    fw[3, q] = w3 + 4.0 * w4
    fw[4, q] = w4
    fwev[q] = p0


@njit(cache=True, fastmath=FASTMATH, inline="always")
def _correct(q, fx, fw, fpos, fvel, fomg, ffrc, ftrq, im3, ii3, hh, h, ih):
    """Correct component ``q`` from the new force and torque."""
    corr = hh * ffrc[q] * im3[q] - fx[2, q]
    fx[0, q] += G0 * corr
    fx[1, q] += G1 * corr
    fx[2, q] += corr
    fx[3, q] += G3 * corr
    fx[4, q] += G4 * corr
    fx[5, q] += G5 * corr
    fpos[q] = fx[0, q]
    fvel[q] = fx[1, q] * ih
    cw = h * ftrq[q] * ii3[q] - fw[1, q]
    fw[0, q] += H0 * cw
    fw[1, q] += cw
    fw[2, q] += H2 * cw
    fw[3, q] += H3 * cw
    fw[4, q] += H4 * cw
    fomg[q] = fw[0, q]


@njit(cache=True, fastmath=FASTMATH, inline="always")
def _correct_rows(fx, fw, fpos, fvel, fomg, ffrc, ftrq, im3, ii3, hh, h, ih, cx, cw):
    """:func:`_correct` of all 3n components, one Nordsieck row at a time: each loop
    touches two or three arrays and vectorises, where one loop over every row keeps ~20
    array pointers live and runs scalar (a fifth of a step's time, measured with perf).
    Same operations in the same order: the result is bit-identical."""
    m3 = cx.shape[0]
    for q in range(m3):
        cx[q] = hh * ffrc[q] * im3[q] - fx[2, q]
        cw[q] = h * ftrq[q] * ii3[q] - fw[1, q]
    for k in range(6):
        g = GX[k]
        for q in range(m3):
            fx[k, q] += g * cx[q]
    for k in range(5):
        g = GW[k]
        for q in range(m3):
            fw[k, q] += g * cw[q]
    for q in range(m3):
        fpos[q] = fx[0, q]
        fvel[q] = fx[1, q] * ih
        fomg[q] = fw[0, q]


@njit(cache=True, fastmath=FASTMATH, error_model="numpy")
def gear_advance(pos, vel, omg, world, law, part, pt, nbrs, walls, drive, stp, work, nord,
                 fl, lg, rs, st, samples, snaps, j_stop):
    """Integrate with the variable-step Gear predictor-corrector up to landing ``j_stop``
    (see the module docstring); spheres in free flight (``fl``,
    :mod:`pdamper.dem.kernels.flights`) are left out of the steps."""
    m3 = 3 * pos.shape[0]
    _gear_steps(pos, vel, omg, world, law, part, pt, nbrs, walls, drive, stp, work, nord, fl,
                lg, rs, st, samples, snaps, j_stop, np.empty(m3), np.empty(m3), np.empty(m3),
                np.empty(m3))


@njit(cache=True, fastmath=FASTMATH, error_model="numpy", _nrt=False)
def _gear_steps(pos, vel, omg, world, law, part, pt, nbrs, walls, drive, stp, work, nord,
                fl, lg, rs, st, samples, snaps, j_stop, im3, ii3, cx3, cw3):
    """The steps of :func:`gear_advance`; ``im3``, ``ii3``, ``cx3``, ``cw3`` work arrays
    of the 3n components.

    Compiled without numba's reference counting (``_nrt=False``): the loop allocates
    nothing, and with it every array taken out of a bundle in the inlined per-step
    functions (``compute_forces`` takes ~25) cost an atomic increment and decrement per
    step that LLVM cannot remove: 165 ns of a force evaluation of no sphere, more than a
    step's whole work at the ~5 stepped spheres of an impact (measured). The callers
    keep the arrays alive. Not bit-identical to the earlier single function (one that
    allocated the work arrays itself and counted references): the compiled code rounds
    differently (3e-13 m at a run's first sample), and a chaotic bed then follows another
    realisation (docs/performance.md, Kernels).
    """
    # arrays out of their bundles once (an access inside the loops counts references)
    frc = work.frc
    trq = work.trq
    vel_pred = work.vel_pred
    omg_pred = work.omg_pred
    inv_mass = part.inv_mass
    rad = part.rad
    pos_build = nbrs.pos_build
    nx = nord.x
    nw = nord.w
    nc = nord.c
    bc = nord.c_backup
    h_act = nbrs.pairs.active
    w_act = walls.active
    olog = walls.onset_log
    n = pos.shape[0]
    t0 = stp.t0
    half = stp.half
    adaptive = stp.adaptive != 0
    want_ttc = adaptive and stp.contact_bound != 0
    skin = world.skin
    tol = stp.tol
    vscale = stp.v_scale
    dtmin = rs[0].dt_min
    dtmax = stp.dt_max
    dtc = stp.dt_contact
    hcap = rs[0].h_cap
    structure = drive.kind == MOTION_STRUCTURE
    modal = structure and drive.nmodes > 0
    structure = structure and not modal  # the 1-DOF
    s = rs[0]
    sta = st[0]
    led = lg[0]
    zc = s.zc
    vc = s.vc
    ac = s.ac
    t = s.t
    t_win = s.t_win
    h = s.h
    h_des = s.h_des
    le_prev = s.le_prev
    ttc = s.ttc
    vmax = s.vmax
    j_land = s.landing
    v_design = s.v_design
    dtlo = sta.dt_lo
    dthi = sta.dt_hi
    steps = 0
    onsets = 0
    rebuilds = 0
    rejects = 0
    stepped = 0
    g = world.gravity
    mass = part.mass
    free = fl.free
    act = fl.act
    vlim = fl.vlim
    na = fl.count[0]
    t_next = fl.scal[0]
    vcl = fl.scal[1]
    ff = stp.free_flight != 0
    due = False
    since = 0
    every = int(fl.scal[2])
    # flat views (3n components) of the Nordsieck vectors: the predictor vectorises
    m3 = 3 * n
    fx = nx.reshape((6, m3))
    fw = nw.reshape((5, m3))
    fpos = pos.reshape(m3)
    fvev = vel_pred.reshape(m3)
    fwev = omg_pred.reshape(m3)
    fvel = vel.reshape(m3)
    fomg = omg.reshape(m3)
    ffrc = frc.reshape(m3)
    ftrq = trq.reshape(m3)
    for i in range(n):
        for a in range(3):
            im3[3 * i + a] = part.inv_mass[i]
            ii3[3 * i + a] = part.inv_inertia[i]
    while j_land < j_stop:
        t_land = t0 + (j_land + 1) * half
        hn = h_des
        if t_next < t + max(h_des, dtmin):
            # free flights whose horizon ends within this step rejoin at its start
            na, vj = join_due(t + max(h_des, dtmin), t, h, g, mass, fl, pos, vel, omg, nx, nw,
                              frc, trq, vel_pred, omg_pred)
            t_next = fl.scal[0]
            if vj > vmax:
                vmax = vj
        if adaptive:
            lim = ttc
            if lim < dtc:
                lim = dtc
            if hn > lim:
                hn = lim
            if vmax > 0.0 and hn > 0.25 * skin / vmax:
                hn = 0.25 * skin / vmax
            if hn > dtmax:
                hn = dtmax
            if hn < dtmin:
                hn = dtmin
        landing = False
        rem = t_land - t
        if hn >= rem - 1e-9 * hn:
            hn = rem
            landing = True
        elif 2.0 * hn > rem:
            # split what is left evenly: no tiny step before the landing (a tiny step would
            # amplify the noise of the higher Nordsieck derivatives on the next rescaling)
            hn = 0.5 * rem
        # ---- rescale (Nordsieck, ratio^k) and predict (Pascal triangle): one pass
        q1 = hn / h
        q2 = q1 * q1
        q3 = q2 * q1
        q4 = q3 * q1
        q5 = q4 * q1
        h = hn
        # friction cap: never stiffer than at the step hcap (GEAR_FRICTION_CAP_FACTOR x the
        # Verlet step, pdamper.dem.simulation), so that the error control does not chase
        # the viscous time scale of the stuck tanh law
        cap_h = 0.5 / (h if h > hcap else hcap)
        ih = 1.0 / h
        if 2 * na > n:
            # most spheres stepped: the flat loop vectorises (a free sphere's Nordsieck
            # vectors follow its parabola too; join() overwrites them)
            for q in range(m3):
                _predict(q, fx, fw, fpos, fvev, fwev, q1, q2, q3, q4, q5, ih)
        else:
            for k in range(na):
                for q in range(3 * act[k], 3 * act[k] + 3):
                    _predict(q, fx, fw, fpos, fvev, fwev, q1, q2, q3, q4, q5, ih)
        c1 = nc[1] * q1
        c2 = nc[2] * q2
        c3 = nc[3] * q3
        c4 = nc[4] * q4
        c5 = nc[5] * q5
        bc[0] = nc[0]
        bc[1] = c1
        bc[2] = c2
        bc[3] = c3
        bc[4] = c4
        bc[5] = c5
        nc[1] = c1
        nc[2] = c2
        nc[3] = c3
        nc[4] = c4
        nc[5] = c5
        tn = t_land if landing else t + h
        if structure:
            c0, c1, c2, c3, c4, c5 = nc[0], nc[1], nc[2], nc[3], nc[4], nc[5]
            nc[0] = c0 + c1 + c2 + c3 + c4 + c5
            nc[1] = c1 + 2.0 * c2 + 3.0 * c3 + 4.0 * c4 + 5.0 * c5
            nc[2] = c2 + 3.0 * c3 + 6.0 * c4 + 10.0 * c5
            nc[3] = c3 + 4.0 * c4 + 10.0 * c5
            nc[4] = c4 + 5.0 * c5
            zc = nc[0]
            vc = nc[1] / h
        elif modal:
            zc, vc = modal_gear_predict(q1, q2, q3, q4, q5, ih, drive, tn)
        else:
            zc, vc, ac = prescribed_state(tn, drive)
        if needs_rebuild(pos, pos_build, skin, act, na):
            if na < n:
                # The free spheres' horizons hold only for the old list: a pair the new
                # list adds may join a free sphere and a stepped one closing within this
                # very step, unseen by the forces (a sphere overlapping another by 2 % of
                # its radius at the next regroup: elastic energy out of nothing, 2.4 % of
                # the ledger at 7.5 Hz / 44 mm). So the step is undone and taken again with
                # every sphere stepped; it rebuilds the list then, and regroups after.
                _undo_prediction(nx, nw, act, na)
                for k in range(6):
                    nc[k] = bc[k]
                if modal:
                    modal_gear_restore(drive)
                na = regroup(t, h, vc, ac, False, pos, vel, omg, nx, nw, frc, trq, vel_pred,
                             omg_pred, zc, world, part, nbrs, walls, fl, 2.0 * half)
                t_next = fl.scal[0]
                v2 = 0.0
                for i in range(n):
                    v2 = max(v2, vel[i, 0] ** 2 + vel[i, 1] ** 2 + vel[i, 2] ** 2)
                vmax = max(vmax, math.sqrt(v2))
                h_des = h
                due = True
                continue
            if rebuild(pos, rad, zc, world, nbrs) < 0:
                sta.error = ERR_LIST
                sta.t_error = tn
                break
            rebuilds += 1
        r, nons = compute_forces(pos, vel_pred, omg_pred, zc, vc, cap_h, want_ttc,
                                 world, law, part, pt, nbrs, walls, frc, trq, act, na, free,
                                 None)
        ttc = r.ttc
        vmax = r.vmax
        # ---- error estimate from the corrector difference (before the correction, so
        # that a rejected step only has to undo the prediction)
        # err = max_i |corr_i| / (h (v_scale + |v_i|)), compared squared: one square root
        # per particle and no division
        e2 = 0.0
        hh = 0.5 * h * h
        for k in range(na):
            i = act[k]
            im = inv_mass[i]
            c2 = 0.0
            v2 = 0.0
            for a in range(3):
                corr = hh * frc[i, a] * im - nx[2, i, a]
                c2 += corr * corr
                va = (nx[1, i, a] + G1 * corr) * ih
                v2 += va * va
            den = vscale + math.sqrt(v2)
            if c2 > e2 * den * den:
                e2 = c2 / (den * den)
        err = math.sqrt(e2) * ih
        if structure:
            ac = structure_acceleration(r.fz, zc, vc, drive, tn)
            corr = hh * ac - nc[2]
            ec = abs(corr) / (h * (vscale + abs((nc[1] + G1 * corr) * ih)))
            if ec > err:
                err = ec
        elif modal:
            ac, ec = modal_gear_error(r.fz, hh, h, ih, vscale, G1, drive, tn)
            if ec > err:
                err = ec
        # ---- reject a step whose error is far beyond the tolerance: undo and retry
        if (adaptive and err > REJECT * tol and h > 2.0 * dtmin and nons <= olog.shape[0]
                and math.isfinite(err)):
            for q in range(nons):
                code = olog[q]
                if code >= 0:
                    h_act[code] = 0
                else:
                    code = -code - 1
                    w_act[code // 6, code % 6] = 0
            _undo_prediction(nx, nw, act, na)
            for k in range(6):
                nc[k] = bc[k]
            if modal:
                modal_gear_restore(drive)
            fac = 0.9 * (tol / err) ** (1.0 / 6.0)
            if fac < 0.1:
                fac = 0.1
            h_des = h * fac
            if h_des < dtmin:
                h_des = dtmin
            rejects += 1
            continue
        # ---- correct (flat loop over the 3n components when all are stepped)
        if 2 * na > n:
            _correct_rows(fx, fw, fpos, fvel, fomg, ffrc, ftrq, im3, ii3, hh, h, ih, cx3, cw3)
        else:
            for k in range(na):
                for q in range(3 * act[k], 3 * act[k] + 3):
                    _correct(q, fx, fw, fpos, fvel, fomg, ffrc, ftrq, im3, ii3, hh, h, ih)
        if na < n:
            # a stepped sphere faster in the free-fall frame than the horizons assumed:
            # regroup after the step
            wx = fl.scal[3]
            wy = fl.scal[4]
            wz = fl.scal[5] - g * (tn - fl.scal[6])
            for k in range(na):
                i = act[k]
                if ((vel[i, 0] - wx) ** 2 + (vel[i, 1] - wy) ** 2
                        + (vel[i, 2] - wz) ** 2) > vlim[i] * vlim[i]:
                    due = True
        if structure:
            corr = hh * ac - nc[2]
            nc[0] += G0 * corr
            nc[1] += G1 * corr
            nc[2] += corr
            nc[3] += G3 * corr
            nc[4] += G4 * corr
            nc[5] += G5 * corr
            zc = nc[0]
            vc = nc[1] * ih
        elif modal:
            zc, vc = modal_gear_correct(hh, ih, drive, tn, G0, G1, G3, G4, G5)
        onsets += nons
        ledger_step(led, r, 0.5 * h)
        t = tn
        steps += 1
        stepped += na
        if na < n and abs(vc) > vcl:
            due = True
        if h < dtlo:
            dtlo = h
        if h > dthi:
            dthi = h
        if step_failed(r, sta, t, stp.max_overlap, stp.v_limit):
            break
        # ---- step-size control
        if adaptive:
            # PI control (Gustafsson): exponents 0.7/6 and 0.4/6 on this and the last
            # accepted error, log(err / tol) bounded to keep exp finite
            le = math.log(err / tol) if err > 1e-30 * tol else -69.0
            fac = 0.9 * math.exp(-PI_KI * le + PI_KP * le_prev)
            le_prev = le
            if fac > 2.0:
                fac = 2.0
            if fac < 0.3:
                fac = 0.3
            hnew = h * fac
            if landing and hnew > h_des:
                hnew = h_des
            if hnew > dtmax:
                hnew = dtmax
            if hnew < dtmin:
                hnew = dtmin
            h_des = hnew
        since += 1
        if ff and (due or since >= every or (landing and j_land % 2 == 1)):
            since = 0
            # after a rebuild, a speed beyond its limit, and at each sample: every sphere
            # on the step's time, new horizons
            na, vj = _regroup(t, h, vc, ac, pos, vel, omg, zc, world, part, nbrs, walls, stp,
                              work, nord, fl, sta)
            t_next = fl.scal[0]
            vcl = fl.scal[1]
            # periodic regroups back off while they free few spheres (their cost is that of
            # a step of all spheres)
            every = REGROUP_EVERY if 4 * (n - na) >= n else min(2 * every, REGROUP_MAX)
            if vj > vmax:
                vmax = vj
            due = False
        if landing:
            j_land += 1
            t_win, stop = on_landing(j_land, t, t_win, pos, vel, omg, part, world, zc, vc, ac,
                                     r.eel, led, samples, snaps, stp, sta)
            if modal and j_land % 2 == 0:
                modal_record(j_land // 2, drive.m_nord, ih, drive)
            if stop:
                break
            if (stp.follow_impacts != 0 and j_land % 2 == 0 and hcap > 0.0
                    and sta.max_impact > v_design):
                # the friction cap and the smallest step follow the fastest impact, as the
                # Verlet step does
                v_design = 1.25 * sta.max_impact
                hcap = stp.h_cap * (stp.v_design / v_design) ** 0.2
                dtmin = stp.dt_min * (stp.v_design / v_design) ** 0.2
    if modal:
        modal_gear_store(h, drive)
    sta.steps += steps
    sta.onsets += onsets
    sta.rebuilds += rebuilds
    sta.rejects += rejects
    sta.stepped += stepped
    sta.gear_steps += steps
    sta.dt_lo = dtlo
    sta.dt_hi = dthi
    s.t = t
    s.t_win = t_win
    s.zc = zc
    s.vc = vc
    s.ac = ac
    s.h = h
    s.h_des = h_des
    s.le_prev = le_prev
    s.ttc = ttc
    s.vmax = vmax
    s.landing = j_land
    s.v_design = v_design
    s.h_cap = hcap
    s.dt_min = dtmin
    fl.scal[2] = every
