"""numba kernels of the DEM engine: contact search, forces, whole-run integrator loops.

Everything here is compiled with ``numba.njit(cache=True)``; the Python orchestration in
:mod:`pdamper.dem.simulation` allocates every array once and calls :func:`run_verlet` or
:func:`run_gear` for a whole run, so that no Python and no allocation happens per step.
The loops are serial and in a fixed order: the same inputs give bit-identical results.
:func:`compute_forces` is inlined into the run loops (``inline="always"``: no reference
counting of its ~30 array arguments per step) and the hot kernels use numpy's error model
(no zero-division branches; the NaN checks catch what a division by zero would produce).

Frames and signs
----------------
Particles move in the inertial frame, z up (gravity ``-g e_z``). The container's inner box
is ``[0, Lx] x [0, Ly] x [z_c, z_c + Lz]``; it moves only along z (position ``z_c``,
velocity ``v_c``). ``fpc`` is the force that the particles exert on the container.

Layout of the parameter arrays
------------------------------
``fp`` (float64): see the ``FP_*`` indices; ``ip`` (int64): see the ``IP_*`` indices.
``out`` (float64, length ``NOUT``) collects per evaluation: force on the container (3),
dissipation rates (normal, friction), power of the container on the particles, elastic
energy, the largest overlap / radius, the shortest time to a new contact and the largest
particle speed.

Friction and the step
---------------------
Below the regularisation velocity the tanh friction law is a viscous damper of coefficient
``mu F_n / v_reg``; under the large normal forces of an impact this can be far stiffer than
the step resolves, and an explicit step would reverse the slip velocity (numerical
chatter). The kernels therefore cap the friction force at ``0.5 m_t |v_t| / h`` (``m_t =
2/7 m*``, the tangential mass of two rolling spheres, ``h = fp[FP_H]`` the current step): a
force that at most halves the slip in one step. Where the tanh law is resolved the cap is
inactive; ``fp[FP_H] = 0`` disables it. The variable-step Gear integrator evaluates the cap
at ``max(h, fp[FP_HCAP])`` with ``FP_HCAP`` the Verlet step: the same friction law as the
default Verlet run, and the error control no longer chases the sub-0.1 us viscous time
scale of stuck contacts (which took more than half of the Gear steps).

Contact history and re-impacts
------------------------------
Each contact stores its active flag, Hertz stiffness, damping parameter ``d`` and impact
speed ``v0``. ``d`` is set at the onset from ``e(v0)``. A contact that persists (a bed
resting on the floor, spheres in a column) can later be hit hard through its neighbours;
with ``d`` from a gentle onset the damping term ``d delta_dot`` would then be orders of
magnitude larger than one, the force law would be stiff and the explicit integrators
unstable. So when the approach speed exceeds ``fp[FP_REIMPACT]`` (default 1.25) times the
stored ``v0``, the contact is treated as re-impacted: ``v0`` and ``d`` are reset from the
current speed. In an isolated impact the approach speed only falls after the onset, so the
prescribed COR is untouched (``inf`` disables the rule: pure onset history).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from pdamper.contact.forces import friction_magnitude, normal_force, onset_damping_cached
from pdamper.contact.hertz import hertz_stiffness

# ---- float parameters ------------------------------------------------------------------
FP_G = 0
FP_VREG = 1
FP_VMIN = 2
FP_LX = 3
FP_LY = 4
FP_LZ = 5
FP_SKIN = 6
FP_CELL = 7
FP_MAXOVL = 8
FP_VLIMIT = 9
FP_DT = 10
FP_DTMIN = 11
FP_DTMAX = 12
FP_TOL = 13
FP_VSCALE = 14
FP_T0 = 15
FP_HALF = 16
FP_SM = 17
FP_SD = 18
FP_SK = 19
FP_Z0 = 20
FP_X = 21
FP_W = 22
FP_DTC = 23
FP_TABDT = 24
FP_REIMPACT = 25
FP_H = 26
FP_HCAP = 27
NFP = 28

# ---- int parameters --------------------------------------------------------------------
IP_MODEL = 0
IP_NMAT = 1
IP_NCX = 2
IP_NCY = 3
IP_NCZ = 4
IP_MOTION = 5
IP_SNAPEVERY = 6
IP_ADAPTIVE = 7
IP_NSAMP = 8
IP_TTC = 9
NIP = 10

MOTION_HARMONIC = 0
MOTION_TABLE = 1
MOTION_STRUCTURE = 2

# ---- out slots -------------------------------------------------------------------------
O_FX = 0
O_FY = 1
O_FZ = 2
O_DN = 3
O_DF = 4
O_WC = 5
O_EEL = 6
O_OVL = 7
O_TTC = 8
O_VMAX = 9
NOUT = 10

# ---- stats slots (int64) ---------------------------------------------------------------
S_STEPS = 0
S_REBUILDS = 1
S_ERR = 2
S_ERRIDX = 3
S_ONSETS = 4
S_REJECTS = 5
NSTATS = 6

# ---- float stats -----------------------------------------------------------------------
F_TERR = 0
F_OVL = 1
F_DTLO = 2
F_DTHI = 3
F_ERRVAL = 4
NFSTATS = 5

ERR_NONE = 0
ERR_NAN = 1
ERR_OVERLAP = 2
ERR_ESCAPE = 3
ERR_LIST = 4
ERR_ENERGY = 5
ERR_SPEED = 6

# Gear coefficients (Gear 1971; Allen & Tildesley, App. E): 6-value Nordsieck vector of a
# second-order ODE, with 3/20 instead of 3/16 because the forces depend on the velocities.
#: a Gear step whose error estimate exceeds REJECT x tolerance is repeated with a smaller step
REJECT = 4.0
#: PI step-size control exponents (Gustafsson 1991; Hairer & Wanner II, IV.2), order 5 + 1
PI_KI = 0.7 / 6.0
PI_KP = 0.4 / 6.0
#: fast-math flags of the hot kernels: contractions and reassociation only, no
#: 'finite-math' assumptions, so that NaN checks keep working
FASTMATH = {"contract", "reassoc", "nsz", "arcp"}
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


# ======================================================================================
# container motion
# ======================================================================================
@njit(cache=True, inline="always")
def prescribed_state(t, kind, fp, tab):
    """Prescribed container position, velocity, acceleration at time ``t`` [s].

    ``kind`` MOTION_HARMONIC: ``z = z0 + X sin(W t)`` (rheonomic constraint, paper Sect. 3);
    MOTION_TABLE: linear interpolation of the uniformly sampled table ``tab = (z, v, a)``
    with step ``fp[FP_TABDT]`` from ``t = 0``.
    """
    if kind == MOTION_TABLE:
        tz, tv, ta = tab
        h = fp[FP_TABDT]
        s = t / h
        i = int(math.floor(s))
        nt = tz.shape[0]
        if i < 0:
            return tz[0], tv[0], ta[0]
        if i >= nt - 1:
            return tz[nt - 1], tv[nt - 1], ta[nt - 1]
        w = s - i
        return (tz[i] + w * (tz[i + 1] - tz[i]), tv[i] + w * (tv[i + 1] - tv[i]),
                ta[i] + w * (ta[i + 1] - ta[i]))
    x = fp[FP_X]
    om = fp[FP_W]
    s = math.sin(om * t)
    c = math.cos(om * t)
    return fp[FP_Z0] + x * s, x * om * c, -x * om * om * s


# ======================================================================================
# contact search: linked cells + Verlet list
# ======================================================================================
@njit(cache=True)
def _cell_index(x, y, zr, cs, ncx, ncy, ncz):
    cx = int(x / cs)
    cy = int(y / cs)
    cz = int(zr / cs)
    cx = min(max(cx, 0), ncx - 1)
    cy = min(max(cy, 0), ncy - 1)
    cz = min(max(cz, 0), ncz - 1)
    return cx, cy, cz


@njit(cache=True)
def build_verlet_list(pos, rad, zc, fp, ip, head, nxt, nb_start, nb_j):
    """Half Verlet list (pairs i < j closer than r_i + r_j + skin) from a linked-cell grid.

    Cost O(n). Each particle's neighbours are sorted by index so that the contact history
    can be carried over by a merge. Returns the number of pairs, or -1 if ``nb_j`` is full.
    """
    n = pos.shape[0]
    cs = fp[FP_CELL]
    skin = fp[FP_SKIN]
    ncx = ip[IP_NCX]
    ncy = ip[IP_NCY]
    ncz = ip[IP_NCZ]
    cap = nb_j.shape[0]
    for c in range(head.shape[0]):
        head[c] = -1
    # insert in reverse so that each cell's chain runs in increasing index order
    for i in range(n - 1, -1, -1):
        cx, cy, cz = _cell_index(pos[i, 0], pos[i, 1], pos[i, 2] - zc, cs, ncx, ncy, ncz)
        c = (cz * ncy + cy) * ncx + cx
        nxt[i] = head[c]
        head[c] = i
    cnt = 0
    for i in range(n):
        nb_start[i] = cnt
        cx, cy, cz = _cell_index(pos[i, 0], pos[i, 1], pos[i, 2] - zc, cs, ncx, ncy, ncz)
        for dz in range(-1, 2):
            z2 = cz + dz
            if z2 < 0 or z2 >= ncz:
                continue
            for dy in range(-1, 2):
                y2 = cy + dy
                if y2 < 0 or y2 >= ncy:
                    continue
                for dx in range(-1, 2):
                    x2 = cx + dx
                    if x2 < 0 or x2 >= ncx:
                        continue
                    j = head[(z2 * ncy + y2) * ncx + x2]
                    while j >= 0:
                        if j > i:
                            ddx = pos[j, 0] - pos[i, 0]
                            ddy = pos[j, 1] - pos[i, 1]
                            ddz = pos[j, 2] - pos[i, 2]
                            rc = rad[i] + rad[j] + skin
                            if ddx * ddx + ddy * ddy + ddz * ddz < rc * rc:
                                if cnt >= cap:
                                    return -1
                                # insertion into the sorted segment of i
                                k = cnt
                                while k > nb_start[i] and nb_j[k - 1] > j:
                                    nb_j[k] = nb_j[k - 1]
                                    k -= 1
                                nb_j[k] = j
                                cnt += 1
                        j = nxt[j]
    nb_start[n] = cnt
    return cnt


@njit(cache=True)
def carry_history(n, o_start, o_j, o_act, o_k, o_d, o_v, s_start, s_j, s_act, s_k, s_d, s_v):
    """Copy the contact history of pairs present in both lists (old ``o_*`` -> new ``s_*``)."""
    for i in range(n):
        a = o_start[i]
        a_end = o_start[i + 1]
        for b in range(s_start[i], s_start[i + 1]):
            jb = s_j[b]
            while a < a_end and o_j[a] < jb:
                a += 1
            if a < a_end and o_j[a] == jb:
                s_act[b] = o_act[a]
                s_k[b] = o_k[a]
                s_d[b] = o_d[a]
                s_v[b] = o_v[a]
            else:
                s_act[b] = 0
                s_k[b] = 0.0
                s_d[b] = 0.0
                s_v[b] = 0.0


@njit(cache=True)
def rebuild(pos, rad, zc, fp, ip, lists):
    """Rebuild the Verlet list keeping the contact history; returns pair count or -1."""
    (nb_start, nb_j, h_act, h_k, h_d, h_v, s_start, s_j, s_act, s_k, s_d, s_v, head, nxt,
     pos_build) = lists
    n = pos.shape[0]
    cnt = build_verlet_list(pos, rad, zc, fp, ip, head, nxt, s_start, s_j)
    if cnt < 0:
        return -1
    carry_history(n, nb_start, nb_j, h_act, h_k, h_d, h_v, s_start, s_j, s_act, s_k, s_d, s_v)
    for i in range(n + 1):
        nb_start[i] = s_start[i]
    for b in range(cnt):
        nb_j[b] = s_j[b]
        h_act[b] = s_act[b]
        h_k[b] = s_k[b]
        h_d[b] = s_d[b]
        h_v[b] = s_v[b]
    for i in range(n):
        pos_build[i, 0] = pos[i, 0]
        pos_build[i, 1] = pos[i, 1]
        pos_build[i, 2] = pos[i, 2]
    return cnt


@njit(cache=True, inline="always")
def needs_rebuild(pos, pos_build, skin):
    """Rebuild criterion: some particle moved more than skin/2 since the last build."""
    lim = 0.25 * skin * skin
    for i in range(pos.shape[0]):
        dx = pos[i, 0] - pos_build[i, 0]
        dy = pos[i, 1] - pos_build[i, 1]
        dz = pos[i, 2] - pos_build[i, 2]
        if dx * dx + dy * dy + dz * dz > lim:
            return True
    return False


@njit(cache=True, inline="always")
def max_displacement2(pos, pos_build):
    """Largest squared displacement of a particle since the last build [m^2]."""
    d2max = 0.0
    for i in range(pos.shape[0]):
        dx = pos[i, 0] - pos_build[i, 0]
        dy = pos[i, 1] - pos_build[i, 1]
        dz = pos[i, 2] - pos_build[i, 2]
        d2 = dx * dx + dy * dy + dz * dz
        if d2 > d2max:
            d2max = d2
    return d2max


# ======================================================================================
# forces
# ======================================================================================
@njit(cache=True, fastmath=FASTMATH, inline="always", error_model="numpy")
def compute_forces(pos, vel, omg, zc, vc, part, mats, lists, wall_hist, fp, ip, frc, trq,
                   out):
    """Forces and torques on all particles, force on the container, energy rates.

    Parameters
    ----------
    pos, vel, omg : (n, 3) arrays
        Positions [m], velocities [m/s], angular velocities [rad/s] (inertial frame).
    zc, vc : float
        Container position and velocity along z [m], [m/s].
    part : tuple
        ``(rad, mass, inertia, kwall, pmat)`` per particle.
    mats : tuple
        ``(estar, mu, cor_v, cor_e, cor_n, xcache)`` per material pair; sphere pair
        ``a * nmat + b``, sphere of material ``a`` on the walls ``nmat^2 + a``; ``xcache``
        (npair, 2) memo of the last COR and damping factor (see ``onset_damping_cached``).
    lists : tuple
        Verlet list and contact history (see :func:`rebuild`).
    wall_hist : tuple
        ``(w_act, w_d, olog, w_v)``: (n, 6) history of the sphere-wall contacts (active flag,
        damping parameter, impact speed) and a log of the contacts that start in this
        evaluation (pair entry ``b`` or ``-(6 i + wall) - 1``), so that a rejected Gear step
        can undo them.
    frc, trq : (n, 3) arrays
        Output: total force (gravity included) [N] and torque [N m].
    out : (NOUT,) array
        Output: see the module docstring.

    Returns
    -------
    int
        Number of contacts that started in this evaluation.
    """
    rad, mass, inertia, kwall, pmat, invm, invi = part
    estar, mu, cor_v, cor_e, cor_n, xcache = mats
    nb_start, nb_j, h_act, h_k, h_d, h_v = (lists[0], lists[1], lists[2], lists[3], lists[4],
                                            lists[5])
    w_act, w_d, olog, w_v = wall_hist
    reimp = fp[FP_REIMPACT]
    cap_h = 0.5 / fp[FP_H] if fp[FP_H] > 0.0 else 0.0
    nlog = olog.shape[0]
    n = pos.shape[0]
    g = fp[FP_G]
    vreg = fp[FP_VREG]
    vmin = fp[FP_VMIN]
    model = ip[IP_MODEL]
    nmat = ip[IP_NMAT]
    want_ttc = ip[IP_TTC] != 0
    lx = fp[FP_LX]
    ly = fp[FP_LY]
    lz = fp[FP_LZ]
    # margin of the wall pre-test along z [m]: far above the rounding of the gaps (~1e-17)
    zt = 1e-12 * (lz + abs(zc))
    fcx = 0.0
    fcy = 0.0
    fcz = 0.0
    dn = 0.0
    df = 0.0
    wc = 0.0
    eel = 0.0
    ovl = 0.0
    ttc = 1e300
    vmax2 = 0.0
    onsets = 0
    for i in range(n):
        frc[i, 0] = 0.0
        frc[i, 1] = 0.0
        frc[i, 2] = -mass[i] * g
        trq[i, 0] = 0.0
        trq[i, 1] = 0.0
        trq[i, 2] = 0.0
    # ---------------- sphere-sphere ----------------
    for i in range(n):
        ri = rad[i]
        for b in range(nb_start[i], nb_start[i + 1]):
            j = nb_j[b]
            rj = rad[j]
            dx = pos[j, 0] - pos[i, 0]
            dy = pos[j, 1] - pos[i, 1]
            dz = pos[j, 2] - pos[i, 2]
            d2 = dx * dx + dy * dy + dz * dz
            rs = ri + rj
            if d2 >= rs * rs:
                h_act[b] = 0
                if not want_ttc:
                    continue
                # time to contact (for the variable step): (dist - rs) / (approach speed),
                # the square root only for approaching pairs
                dvd = ((vel[i, 0] - vel[j, 0]) * dx + (vel[i, 1] - vel[j, 1]) * dy
                       + (vel[i, 2] - vel[j, 2]) * dz)
                if dvd > 0.0:
                    dist = math.sqrt(d2)
                    tt = (dist - rs) * dist / dvd
                    if tt < ttc:
                        ttc = tt
                continue
            dist = math.sqrt(d2)
            idist = 1.0 / dist
            nx = dx * idist
            ny = dy * idist
            nz = dz * idist
            delta = rs - dist
            # contact point velocity of i relative to j: v_i - v_j + (r_i w_i + r_j w_j) x n
            wx = ri * omg[i, 0] + rj * omg[j, 0]
            wy = ri * omg[i, 1] + rj * omg[j, 1]
            wz = ri * omg[i, 2] + rj * omg[j, 2]
            ux = vel[i, 0] - vel[j, 0] + wy * nz - wz * ny
            uy = vel[i, 1] - vel[j, 1] + wz * nx - wx * nz
            uz = vel[i, 2] - vel[j, 2] + wx * ny - wy * nx
            ddot = ux * nx + uy * ny + uz * nz
            p = pmat[i] * nmat + pmat[j]
            if h_act[b] == 0:
                h_act[b] = 1
                h_k[b] = hertz_stiffness(estar[p], ri * rj / rs)
                h_d[b] = onset_damping_cached(ddot, cor_v[p, :cor_n[p]], cor_e[p, :cor_n[p]],
                                              model, vmin, xcache, p)
                h_v[b] = max(ddot, vmin)
                if onsets < nlog:
                    olog[onsets] = b
                onsets += 1
            elif ddot > reimp * h_v[b]:
                # re-impact of a persisting contact: the impact speed is the largest
                # approach speed seen (keeps d * delta_dot = O(1), see module docstring)
                h_d[b] = onset_damping_cached(ddot, cor_v[p, :cor_n[p]], cor_e[p, :cor_n[p]],
                                              model, vmin, xcache, p)
                h_v[b] = ddot
            fn, fel = normal_force(delta, ddot, h_k[b], h_d[b])
            dn += (fn - fel) * ddot
            eel += 0.4 * fel * delta
            rmin = min(ri, rj)
            if delta > ovl * rmin:
                ovl = delta / rmin
            fx = -fn * nx
            fy = -fn * ny
            fz = -fn * nz
            tx = ux - ddot * nx
            ty = uy - ddot * ny
            tz = uz - ddot * nz
            vt2 = tx * tx + ty * ty + tz * tz
            if vt2 > 0.0 and mu[p] > 0.0:
                # the square root only for slipping contacts (most are at rest)
                vt = math.sqrt(vt2)
                ft = friction_magnitude(mu[p], fn, vt, vreg)
                if cap_h > 0.0:
                    # no reversal of the slip within one step (tangential mass 2/7 m*)
                    mij = mass[i] + mass[j]
                    fmax = 2.0 / 7.0 * mass[i] * mass[j] * vt * cap_h
                    if ft * mij > fmax:
                        ft = fmax / mij
                df += ft * vt
                s = ft / vt
                gx = -s * tx
                gy = -s * ty
                gz = -s * tz
                fx += gx
                fy += gy
                fz += gz
                # torque (-r n) x F on j equals (r_j/r_i) times torque r_i n x F on i
                cx = ny * gz - nz * gy
                cy = nz * gx - nx * gz
                cz = nx * gy - ny * gx
                trq[i, 0] += ri * cx
                trq[i, 1] += ri * cy
                trq[i, 2] += ri * cz
                trq[j, 0] += rj * cx
                trq[j, 1] += rj * cy
                trq[j, 2] += rj * cz
            frc[i, 0] += fx
            frc[i, 1] += fy
            frc[i, 2] += fz
            frc[j, 0] -= fx
            frc[j, 1] -= fy
            frc[j, 2] -= fz
    # ---------------- sphere-wall ----------------
    # largest particle speed: a separate short loop (in the wall loop the running maximum
    # is spilled to the stack)
    for i in range(n):
        v2 = vel[i, 0] ** 2 + vel[i, 1] ** 2 + vel[i, 2] ** 2
        if v2 > vmax2:
            vmax2 = v2
    nw = nmat * nmat
    for i in range(n):
        ri = rad[i]
        p = nw + pmat[i]
        # quick exit: no wall within reach (and no history to reset)
        px = pos[i, 0]
        py = pos[i, 1]
        pz = pos[i, 2] - zc
        gmin = min(min(px, lx - px), min(py, ly - py), min(pz, lz - pz))
        if gmin > ri:
            anyact = 0
            for w in range(6):
                anyact += w_act[i, w]
            if anyact == 0:
                if want_ttc:
                    # time to reach the nearest wall ahead on each axis
                    vx = vel[i, 0]
                    vy = vel[i, 1]
                    vz = vel[i, 2] - vc
                    if vx != 0.0:
                        tt = ((lx - px - ri) if vx > 0.0 else (px - ri)) / abs(vx)
                        if tt < ttc:
                            ttc = tt
                    if vy != 0.0:
                        tt = ((ly - py - ri) if vy > 0.0 else (py - ri)) / abs(vy)
                        if tt < ttc:
                            ttc = tt
                    if vz != 0.0:
                        tt = ((lz - pz - ri) if vz > 0.0 else (pz - ri)) / abs(vz)
                        if tt < ttc:
                            ttc = tt
                continue
        if not want_ttc:
            # straight-line pre-test of the six walls: reset the history of the walls out
            # of reach and skip the loop below when none is in contact (the common case of
            # a sphere at zero gap to a side wall). It never skips a wall that the loop
            # would find in contact: for the side walls ``ri - gap <= 0`` is ``ri <= gap``
            # (a rounded difference of two doubles is <= 0 iff a <= b), with the same
            # single-operation gap; the gaps to floor and lid take two operations
            # (reassociation may round them differently), so a wall within zt of contact
            # goes to the loop. A NaN takes the loop.
            touch = False
            if not ri <= pos[i, 0]:
                touch = True
            else:
                w_act[i, 0] = 0
            if not ri <= lx - pos[i, 0]:
                touch = True
            else:
                w_act[i, 1] = 0
            if not ri <= pos[i, 1]:
                touch = True
            else:
                w_act[i, 2] = 0
            if not ri <= ly - pos[i, 1]:
                touch = True
            else:
                w_act[i, 3] = 0
            if not ri + zt <= pz:
                touch = True
            else:
                w_act[i, 4] = 0
            if not ri + zt <= lz - pz:
                touch = True
            else:
                w_act[i, 5] = 0
            if not touch:
                continue
        for w in range(6):
            axis = w // 2
            if axis == 0:
                gap = pos[i, 0] if w == 0 else lx - pos[i, 0]
            elif axis == 1:
                gap = pos[i, 1] if w == 2 else ly - pos[i, 1]
            else:
                gap = pos[i, 2] - zc if w == 4 else zc + lz - pos[i, 2]
            delta = ri - gap
            sgn = -1.0 if w % 2 == 0 else 1.0
            if delta <= 0.0:
                w_act[i, w] = 0
                if want_ttc:
                    # normal approach speed towards the wall (rotation does not enter)
                    vn = sgn * (vel[i, axis] - (vc if axis == 2 else 0.0))
                    if vn > 0.0:
                        tt = -delta / vn
                        if tt < ttc:
                            ttc = tt
                continue
            nx = sgn if axis == 0 else 0.0
            ny = sgn if axis == 1 else 0.0
            nz = sgn if axis == 2 else 0.0
            # contact point velocity relative to the wall (wall velocity (0, 0, vc))
            wx = ri * omg[i, 0]
            wy = ri * omg[i, 1]
            wz = ri * omg[i, 2]
            ux = vel[i, 0] + wy * nz - wz * ny
            uy = vel[i, 1] + wz * nx - wx * nz
            uz = vel[i, 2] - vc + wx * ny - wy * nx
            ddot = ux * nx + uy * ny + uz * nz
            if w_act[i, w] == 0:
                w_act[i, w] = 1
                w_d[i, w] = onset_damping_cached(ddot, cor_v[p, :cor_n[p]], cor_e[p, :cor_n[p]],
                                                 model, vmin, xcache, p)
                w_v[i, w] = max(ddot, vmin)
                if onsets < nlog:
                    olog[onsets] = -(i * 6 + w) - 1
                onsets += 1
            elif ddot > reimp * w_v[i, w]:
                w_d[i, w] = onset_damping_cached(ddot, cor_v[p, :cor_n[p]], cor_e[p, :cor_n[p]],
                                                 model, vmin, xcache, p)
                w_v[i, w] = ddot
            fn, fel = normal_force(delta, ddot, kwall[i], w_d[i, w])
            dn += (fn - fel) * ddot
            eel += 0.4 * fel * delta
            if delta > ovl * ri:
                ovl = delta / ri
            fx = -fn * nx
            fy = -fn * ny
            fz = -fn * nz
            tx = ux - ddot * nx
            ty = uy - ddot * ny
            tz = uz - ddot * nz
            vt2 = tx * tx + ty * ty + tz * tz
            if vt2 > 0.0 and mu[p] > 0.0:
                # the square root only for slipping contacts (most are at rest)
                vt = math.sqrt(vt2)
                ft = friction_magnitude(mu[p], fn, vt, vreg)
                if cap_h > 0.0:
                    fmax = 2.0 / 7.0 * mass[i] * vt * cap_h
                    if ft > fmax:
                        ft = fmax
                df += ft * vt
                s = ft / vt
                gx = -s * tx
                gy = -s * ty
                gz = -s * tz
                fx += gx
                fy += gy
                fz += gz
                trq[i, 0] += ri * (ny * gz - nz * gy)
                trq[i, 1] += ri * (nz * gx - nx * gz)
                trq[i, 2] += ri * (nx * gy - ny * gx)
            frc[i, 0] += fx
            frc[i, 1] += fy
            frc[i, 2] += fz
            fcx -= fx
            fcy -= fy
            fcz -= fz
            wc += fz * vc
    out[O_FX] = fcx
    out[O_FY] = fcy
    out[O_FZ] = fcz
    out[O_DN] = dn
    out[O_DF] = df
    out[O_WC] = wc
    out[O_EEL] = eel
    out[O_OVL] = ovl
    out[O_TTC] = ttc
    out[O_VMAX] = math.sqrt(vmax2)
    return onsets


# ======================================================================================
# sampling and checks
# ======================================================================================
@njit(cache=True)
def record_sample(k, t, pos, vel, omg, part, fp, zc, vc, ac, out, led, samples, snaps, ip):
    """Store sample ``k`` (state at time t) and, every ``snapshot_every`` samples, a snapshot.

    ``led`` = (D_n, D_f, W_c) running integrals [J]. Returns an error code from the checks
    (NaN, particle outside the container, energy blow-up).
    """
    rad, mass, inertia, kwall, pmat, invm, invi = part
    ts, cont, fpc, com, en = samples
    s_pos, s_vel, s_omg = snaps
    n = pos.shape[0]
    g = fp[FP_G]
    ekt = 0.0
    ekr = 0.0
    epot = 0.0
    mt = 0.0
    cx = 0.0
    cy = 0.0
    cz = 0.0
    err = ERR_NONE
    lx = fp[FP_LX]
    ly = fp[FP_LY]
    lz = fp[FP_LZ]
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
    ts[k] = t
    cont[k, 0] = zc
    cont[k, 1] = vc
    cont[k, 2] = ac
    com[k, 0] = cx / mt
    com[k, 1] = cy / mt
    com[k, 2] = cz / mt
    en[k, 0] = ekt
    en[k, 1] = ekr
    en[k, 2] = epot
    en[k, 3] = out[O_EEL]
    en[k, 4] = led[0]
    en[k, 5] = led[1]
    en[k, 6] = led[2]
    every = ip[IP_SNAPEVERY]
    if every > 0 and k % every == 0:
        q = k // every
        if q < s_pos.shape[0]:
            for i in range(n):
                for a in range(3):
                    s_pos[q, i, a] = pos[i, a]
                    s_vel[q, i, a] = vel[i, a]
                    s_omg[q, i, a] = omg[i, a]
    if err != ERR_NONE:
        return err
    # energy blow-up: the ledger residual must stay small against the energies in play
    e0 = en[0, 0] + en[0, 1] + en[0, 2] + en[0, 3]
    e1 = ekt + ekr + epot + out[O_EEL]
    res = abs((e1 - e0) - (led[2] - led[0] - led[1]))
    scale = (ekt + ekr + out[O_EEL] + en[0, 0] + en[0, 1] + en[0, 3] + abs(led[2]) + led[0]
             + led[1] + mt * g * lz + mt * 1e-4)
    if k > 0 and res > 0.5 * scale:
        return ERR_ENERGY
    return ERR_NONE


@njit(cache=True)
def close_window(k, t, t_win, imp, fpc):
    """Mean force on the container over the sample window that ends at ``t``."""
    span = t - t_win
    if span > 0.0:
        fpc[k, 0] = imp[0] / span
        fpc[k, 1] = imp[1] / span
        fpc[k, 2] = imp[2] / span
    imp[0] = 0.0
    imp[1] = 0.0
    imp[2] = 0.0


@njit(cache=True, inline="always")
def _ledger_start(led, imp, prev, out):
    """Zero the running integrals and remember the rates of the first evaluation."""
    for q in range(3):
        led[q] = 0.0
        imp[q] = 0.0
    prev[0] = out[O_DN]
    prev[1] = out[O_DF]
    prev[2] = out[O_WC]
    prev[3] = out[O_FX]
    prev[4] = out[O_FY]
    prev[5] = out[O_FZ]


@njit(cache=True, inline="always")
def _ledger_step(led, imp, prev, out, hw):
    """Trapezoidal update over a step of length ``2 hw`` of the dissipation (normal,
    friction), the container work and the impulse on the container."""
    led[0] += hw * (prev[0] + out[O_DN])
    led[1] += hw * (prev[1] + out[O_DF])
    led[2] += hw * (prev[2] + out[O_WC])
    imp[0] += hw * (prev[3] + out[O_FX])
    imp[1] += hw * (prev[4] + out[O_FY])
    imp[2] += hw * (prev[5] + out[O_FZ])
    prev[0] = out[O_DN]
    prev[1] = out[O_DF]
    prev[2] = out[O_WC]
    prev[3] = out[O_FX]
    prev[4] = out[O_FY]
    prev[5] = out[O_FZ]


@njit(cache=True, inline="always")
def _step_failed(out, maxovl, vlim, t, stats, fstats):
    """Record the largest overlap; flag overlap, speed or NaN blow-ups (True: stop)."""
    if out[O_OVL] > fstats[F_OVL]:
        fstats[F_OVL] = out[O_OVL]
    if out[O_OVL] > maxovl or out[O_VMAX] > vlim or not math.isfinite(out[O_FZ]):
        stats[S_ERR] = ERR_OVERLAP if out[O_OVL] > maxovl else (
            ERR_SPEED if out[O_VMAX] > vlim else ERR_NAN)
        fstats[F_TERR] = t
        fstats[F_ERRVAL] = out[O_OVL] if out[O_OVL] > maxovl else out[O_VMAX]
        return True
    return False


@njit(cache=True, inline="always")
def _on_landing(j, t, t_win, pos, vel, omg, part, fp, zc, vc, ac, out, led, imp, fpc, samples,
                snaps, ip, stats, fstats):
    """The ``j``-th landing on the half-sample grid: odd ones close a force window, even
    ones record sample ``j // 2``. Returns the start of the current window and whether the
    run must stop."""
    k = j // 2
    if j % 2 == 1:
        close_window(k, t, t_win, imp, fpc)
        return t, False
    e = record_sample(k, t, pos, vel, omg, part, fp, zc, vc, ac, out, led, samples, snaps, ip)
    if e != ERR_NONE:
        stats[S_ERR] = e
        fstats[F_TERR] = t
        return t_win, True
    if k == ip[IP_NSAMP] - 1:
        close_window(k, t, t_win, imp, fpc)
    return t_win, False


@njit(cache=True)
def _struct_acc(fz, zc, vc, fp):
    """1-DOF structure: M a = -K z - D v + F_z (force of the particles on it)."""
    return (fz - fp[FP_SK] * zc - fp[FP_SD] * vc) / fp[FP_SM]


# ======================================================================================
# velocity Verlet
# ======================================================================================
@njit(cache=True, fastmath=FASTMATH, error_model="numpy")
def run_verlet(pos, vel, omg, cstate, part, mats, lists, wall_hist, fp, ip, tab, work,
               samples, snaps, stats, fstats):
    """Integrate a whole run with velocity Verlet at the fixed step ``fp[FP_DT]``.

    Samples are taken every ``2 * m`` steps, where ``m = fp[FP_HALF] / dt`` is an integer
    (the caller chooses dt so). The update is the standard kick-drift-kick scheme;
    ``cstate = (z_c, v_c, a_c)`` is read and written (structure mode).
    The velocities that enter the velocity-dependent forces (damping, friction) at
    ``t + dt`` are predicted as ``v + dt a`` (local error O(dt^2); a higher extrapolation,
    ``+ dt/2 (a - a_prev)``, was tried and is unstable in stiff contact networks).
    """
    rad, mass, inertia, kwall, pmat, invm, invi = part
    frc, trq, vev, wev, out, led, imp = work
    fpc = samples[2]
    n = pos.shape[0]
    dt = fp[FP_DT]
    t0 = fp[FP_T0]
    half = fp[FP_HALF]
    kind = ip[IP_MOTION]
    nsamp = ip[IP_NSAMP]
    m_half = int(round(half / dt))
    total = 2 * (nsamp - 1) * m_half
    skin = fp[FP_SKIN]
    maxovl = fp[FP_MAXOVL]
    vlim = fp[FP_VLIMIT]
    if kind == MOTION_STRUCTURE:
        zc = cstate[0]
        vc = cstate[1]
    else:
        zc, vc, ac = prescribed_state(t0, kind, fp, tab)
    if rebuild(pos, rad, zc, fp, ip, lists) < 0:
        stats[S_ERR] = ERR_LIST
        return
    stats[S_REBUILDS] += 1
    stats[S_ONSETS] += compute_forces(pos, vel, omg, zc, vc, part, mats, lists, wall_hist,
                                      fp, ip, frc, trq, out)
    if kind == MOTION_STRUCTURE:
        ac = _struct_acc(out[O_FZ], zc, vc, fp)
    prev = np.empty(6)
    _ledger_start(led, imp, prev, out)
    e = record_sample(0, t0, pos, vel, omg, part, fp, zc, vc, ac, out, led, samples, snaps,
                      ip)
    if e != ERR_NONE:
        stats[S_ERR] = e
        fstats[F_TERR] = t0
        return
    t_win = t0
    hdt = 0.5 * dt
    fp[FP_H] = dt
    # flat views (3n components) and per-component inverse masses: the kicks vectorise
    m3 = 3 * n
    fpos = pos.reshape(m3)
    fvel = vel.reshape(m3)
    fomg = omg.reshape(m3)
    fvev = vev.reshape(m3)
    fwev = wev.reshape(m3)
    ffrc = frc.reshape(m3)
    ftrq = trq.reshape(m3)
    im3 = np.empty(m3)
    ii3 = np.empty(m3)
    for i in range(n):
        for a in range(3):
            im3[3 * i + a] = invm[i]
            ii3[3 * i + a] = invi[i]
    # rebuild check: the exact test (some particle moved more than skin/2) only when the
    # bound disp >= largest displacement since the build (sum of sqrt(3) dt max|v_a|)
    # allows it: the same rebuild steps as testing every step
    disp = 0.0
    disp_lim = 0.4999 * skin
    sqrt3 = math.sqrt(3.0)
    countdown = m_half
    for step in range(1, total + 1):
        t = t0 + step * dt
        # translational and rotational kicks in separate loops (fewer arrays per loop for
        # the vectoriser's alias checks), the largest speed component in a third pass with
        # one max chain per component (the same value as a single running max)
        for j in range(m3):
            acc = ffrc[j] * im3[j]
            vh = fvel[j] + hdt * acc
            fvev[j] = fvel[j] + dt * acc
            fvel[j] = vh
            fpos[j] += dt * vh
        for j in range(m3):
            al = ftrq[j] * ii3[j]
            fwev[j] = fomg[j] + dt * al
            fomg[j] += hdt * al
        vmx0 = 0.0
        vmx1 = 0.0
        vmx2 = 0.0
        for i in range(n):
            vmx0 = max(vmx0, abs(fvel[3 * i]))
            vmx1 = max(vmx1, abs(fvel[3 * i + 1]))
            vmx2 = max(vmx2, abs(fvel[3 * i + 2]))
        vmx = max(vmx0, max(vmx1, vmx2))
        disp += sqrt3 * dt * vmx
        if kind == MOTION_STRUCTURE:
            vch = vc + hdt * ac
            vce = vc + dt * ac
            zc += dt * vch
        else:
            zc, vce, ac = prescribed_state(t, kind, fp, tab)
        if not disp <= disp_lim:
            d2 = max_displacement2(pos, lists[14])
            if d2 > 0.25 * skin * skin:
                if rebuild(pos, rad, zc, fp, ip, lists) < 0:
                    stats[S_ERR] = ERR_LIST
                    fstats[F_TERR] = t
                    return
                stats[S_REBUILDS] += 1
                disp = 0.0
            else:
                disp = math.sqrt(d2)
        stats[S_ONSETS] += compute_forces(pos, vev, wev, zc, vce, part, mats, lists,
                                          wall_hist, fp, ip, frc, trq, out)
        for j in range(m3):
            fvel[j] += hdt * ffrc[j] * im3[j]
            fomg[j] += hdt * ftrq[j] * ii3[j]
        if kind == MOTION_STRUCTURE:
            ac = _struct_acc(out[O_FZ], zc, vce, fp)
            vc = vch + hdt * ac
        else:
            vc = vce
        _ledger_step(led, imp, prev, out, hdt)
        stats[S_STEPS] += 1
        if _step_failed(out, maxovl, vlim, t, stats, fstats):
            break
        countdown -= 1
        if countdown == 0:
            countdown = m_half
            t_win, stop = _on_landing(step // m_half, t, t_win, pos, vel, omg, part, fp, zc,
                                      vc, ac, out, led, imp, fpc, samples, snaps, ip, stats,
                                      fstats)
            if stop:
                break
    cstate[0] = zc
    cstate[1] = vc
    cstate[2] = ac
    fstats[F_DTLO] = dt
    fstats[F_DTHI] = dt


# ======================================================================================
# variable-step fifth-order Gear predictor-corrector
# ======================================================================================
@njit(cache=True, fastmath=FASTMATH, error_model="numpy")
def run_gear(pos, vel, omg, cstate, part, mats, lists, wall_hist, fp, ip, tab, work,
             gwork, samples, snaps, stats, fstats):
    """Integrate a whole run with the variable-step fifth-order Gear predictor-corrector.

    Positions use the 6-value Nordsieck vector ``(x, h v, h^2 a/2, h^3 x'''/6, ...)`` of a
    second-order ODE; angular velocities the 5-value vector of a first-order ODE (Euler's
    equations of a sphere: ``I dw/dt = T``); the 1-DOF structure (if any) a 6-value vector.
    After each accepted step the step ``h`` is changed by the PI controller
    ``0.9 (tol / err)^(0.7/6) (err_prev / tol)^(0.4/6)`` (bounded to [0.3, 2]), where
    ``err = max_i |corr_i| / (h (v_scale + |v_i|))`` is the local error estimate from the
    corrector difference ``corr`` of the position (computed before the correction: a step
    with ``err > REJECT tol`` is undone by inverting the prediction and repeated with
    ``0.9 (tol / err)^(1/6)``, at least 0.1, times the step); the Nordsieck vectors are
    rescaled by ``ratio^k``. The friction cap uses ``max(h, fp[FP_HCAP])``. Steps are also
    bounded by ``skin / (4 v_max)``, by ``dt_max``, optionally (``ip[IP_TTC]``) by the time
    to the next contact (never below the contact step ``fp[FP_DTC]``),
    and land exactly on the sample grid. ``ip[IP_ADAPTIVE] = 0`` keeps ``fp[FP_DT]`` fixed.
    """
    rad, mass, inertia, kwall, pmat, invm, invi = part
    frc, trq, vev, wev, out, led, imp = work
    nx, nw, nc, bx, bw, bc = gwork  # bx, bw: unused (kept for the call signature)
    h_act = lists[2]
    w_act = wall_hist[0]
    olog = wall_hist[2]
    rejects = 0
    fpc = samples[2]
    n = pos.shape[0]
    t0 = fp[FP_T0]
    half = fp[FP_HALF]
    kind = ip[IP_MOTION]
    nsamp = ip[IP_NSAMP]
    adaptive = ip[IP_ADAPTIVE] != 0
    skin = fp[FP_SKIN]
    maxovl = fp[FP_MAXOVL]
    vlim = fp[FP_VLIMIT]
    tol = fp[FP_TOL]
    vscale = fp[FP_VSCALE]
    dtmin = fp[FP_DTMIN]
    dtmax = fp[FP_DTMAX]
    dtc = fp[FP_DTC]
    h = fp[FP_DT]
    hcap = fp[FP_HCAP]
    structure = kind == MOTION_STRUCTURE
    if structure:
        zc = cstate[0]
        vc = cstate[1]
    else:
        zc, vc, ac = prescribed_state(t0, kind, fp, tab)
    if rebuild(pos, rad, zc, fp, ip, lists) < 0:
        stats[S_ERR] = ERR_LIST
        return
    stats[S_REBUILDS] += 1
    stats[S_ONSETS] += compute_forces(pos, vel, omg, zc, vc, part, mats, lists, wall_hist,
                                      fp, ip, frc, trq, out)
    if structure:
        ac = _struct_acc(out[O_FZ], zc, vc, fp)
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
    prev = np.empty(6)
    _ledger_start(led, imp, prev, out)
    e = record_sample(0, t0, pos, vel, omg, part, fp, zc, vc, ac, out, led, samples, snaps,
                      ip)
    if e != ERR_NONE:
        stats[S_ERR] = e
        fstats[F_TERR] = t0
        return
    t_win = t0
    t = t0
    h_des = h
    # flat views (3n components) of the Nordsieck vectors: the predictor vectorises
    m3 = 3 * n
    fx = nx.reshape((6, m3))
    fw = nw.reshape((5, m3))
    fpos = pos.reshape(m3)
    fvev = vev.reshape(m3)
    fwev = wev.reshape(m3)
    fvel = vel.reshape(m3)
    fomg = omg.reshape(m3)
    ffrc = frc.reshape(m3)
    ftrq = trq.reshape(m3)
    im3 = np.empty(m3)
    ii3 = np.empty(m3)
    for i in range(n):
        for a in range(3):
            im3[3 * i + a] = invm[i]
            ii3[3 * i + a] = invi[i]
    j_land = 0
    total_half = 2 * (nsamp - 1)
    dtlo = 1e300
    le_prev = 0.0
    dthi = 0.0
    while j_land < total_half:
        t_land = t0 + (j_land + 1) * half
        hn = h_des
        if adaptive:
            lim = out[O_TTC]
            if lim < dtc:
                lim = dtc
            if hn > lim:
                hn = lim
            if out[O_VMAX] > 0.0 and hn > 0.25 * skin / out[O_VMAX]:
                hn = 0.25 * skin / out[O_VMAX]
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
        # ---- rescale (Nordsieck, ratio^k), back up (for a rejection), predict (Pascal
        # triangle): one pass over the particles
        q1 = hn / h
        q2 = q1 * q1
        q3 = q2 * q1
        q4 = q3 * q1
        q5 = q4 * q1
        h = hn
        # friction cap: never stiffer than at the step hcap (the Verlet step), so that the
        # error control does not chase the viscous time scale of the stuck tanh law
        fp[FP_H] = h if h > hcap else hcap
        ih = 1.0 / h
        for j in range(m3):
            x0 = fx[0, j]
            x1 = fx[1, j] * q1
            x2 = fx[2, j] * q2
            x3 = fx[3, j] * q3
            x4 = fx[4, j] * q4
            x5 = fx[5, j] * q5
            w0 = fw[0, j]
            w1 = fw[1, j] * q1
            w2 = fw[2, j] * q2
            w3 = fw[3, j] * q3
            w4 = fw[4, j] * q4
            p0 = x0 + x1 + x2 + x3 + x4 + x5
            p1 = x1 + 2.0 * x2 + 3.0 * x3 + 4.0 * x4 + 5.0 * x5
            fx[0, j] = p0
            fx[1, j] = p1
            fx[2, j] = x2 + 3.0 * x3 + 6.0 * x4 + 10.0 * x5
            fx[3, j] = x3 + 4.0 * x4 + 10.0 * x5
            fx[4, j] = x4 + 5.0 * x5
            fx[5, j] = x5
            fpos[j] = p0
            fvev[j] = p1 * ih
            p0 = w0 + w1 + w2 + w3 + w4
            fw[0, j] = p0
            fw[1, j] = w1 + 2.0 * w2 + 3.0 * w3 + 4.0 * w4
            fw[2, j] = w2 + 3.0 * w3 + 6.0 * w4
            fw[3, j] = w3 + 4.0 * w4
            fw[4, j] = w4
            fwev[j] = p0
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
        else:
            zc, vc, ac = prescribed_state(tn, kind, fp, tab)
        if needs_rebuild(pos, lists[14], skin):
            if rebuild(pos, rad, zc, fp, ip, lists) < 0:
                stats[S_ERR] = ERR_LIST
                fstats[F_TERR] = tn
                return
            stats[S_REBUILDS] += 1
        nons = compute_forces(pos, vev, wev, zc, vc, part, mats, lists, wall_hist, fp, ip, frc,
                              trq, out)
        # ---- error estimate from the corrector difference (before the correction, so
        # that a rejected step only has to undo the prediction)
        # err = max_i |corr_i| / (h (v_scale + |v_i|)), compared squared: one square root
        # per particle and no division
        e2 = 0.0
        hh = 0.5 * h * h
        for i in range(n):
            im = invm[i]
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
            ac = _struct_acc(out[O_FZ], zc, vc, fp)
            corr = hh * ac - nc[2]
            ec = abs(corr) / (h * (vscale + abs((nc[1] + G1 * corr) * ih)))
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
            # inverse of the Pascal-triangle prediction: the (rescaled) Nordsieck vectors
            # at the start of the step
            for i in range(n):
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
            for k in range(6):
                nc[k] = bc[k]
            fac = 0.9 * (tol / err) ** (1.0 / 6.0)
            if fac < 0.1:
                fac = 0.1
            h_des = h * fac
            if h_des < dtmin:
                h_des = dtmin
            rejects += 1
            continue
        # ---- correct (flat loop over the 3n components)
        for j in range(m3):
            corr = hh * ffrc[j] * im3[j] - fx[2, j]
            fx[0, j] += G0 * corr
            fx[1, j] += G1 * corr
            fx[2, j] += corr
            fx[3, j] += G3 * corr
            fx[4, j] += G4 * corr
            fx[5, j] += G5 * corr
            fpos[j] = fx[0, j]
            fvel[j] = fx[1, j] * ih
            cw = h * ftrq[j] * ii3[j] - fw[1, j]
            fw[0, j] += H0 * cw
            fw[1, j] += cw
            fw[2, j] += H2 * cw
            fw[3, j] += H3 * cw
            fw[4, j] += H4 * cw
            fomg[j] = fw[0, j]
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
        stats[S_ONSETS] += nons
        hl = 0.5 * h
        _ledger_step(led, imp, prev, out, hl)
        t = tn
        stats[S_STEPS] += 1
        if h < dtlo:
            dtlo = h
        if h > dthi:
            dthi = h
        if _step_failed(out, maxovl, vlim, t, stats, fstats):
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
        if landing:
            j_land += 1
            t_win, stop = _on_landing(j_land, t, t_win, pos, vel, omg, part, fp, zc, vc, ac,
                                      out, led, imp, fpc, samples, snaps, ip, stats, fstats)
            if stop:
                break
    cstate[0] = zc
    cstate[1] = vc
    cstate[2] = ac
    fstats[F_DTLO] = dtlo
    fstats[F_DTHI] = dthi
    stats[S_REJECTS] = rejects


def empty_samples(nsamp: int, nsnap: int, n: int):
    """Preallocated sample and snapshot arrays for the run kernels."""
    samples = (np.zeros(nsamp), np.zeros((nsamp, 3)), np.zeros((nsamp, 3)),
               np.zeros((nsamp, 3)), np.zeros((nsamp, 7)))
    snaps = (np.zeros((nsnap, n, 3)), np.zeros((nsnap, n, 3)), np.zeros((nsnap, n, 3)))
    return samples, snaps
