"""Contact forces: one per-contact law shared by sphere-sphere and sphere-wall contacts,
and the loop over all contacts.

Frames and signs
----------------
Particles move in the inertial frame, z up (gravity ``-g e_z``). The container's inner box
is ``[0, Lx] x [0, Ly] x [z_c, z_c + Lz]``; it moves only along z (position ``z_c``,
velocity ``v_c``). The normal ``n`` of a contact points from particle ``i`` to its partner
(the other sphere, or the wall); ``u`` is the velocity of the contact point of ``i``
relative to the partner, so that ``delta_dot = u . n`` is positive while approaching.

Friction and the step
---------------------
Below the regularisation velocity the tanh friction law is a viscous damper of coefficient
``mu F_n / v_reg``; under the large normal forces of an impact this can be far stiffer than
the step resolves, and an explicit step would reverse the slip velocity (numerical
chatter). The force is therefore capped at ``0.5 m_t |v_t| / h`` (``m_t = 2/7 m*``, the
tangential mass of two rolling spheres, ``h`` the step): a force that at most halves the
slip in one step. Where the tanh law is resolved the cap is inactive; ``cap_h = 0``
disables it.

Contact history and re-impacts
------------------------------
Each contact stores its Hertz stiffness, damping parameter ``d`` and impact speed ``v0``.
``d`` is set at the onset from ``e(v0)``. A contact that persists (a bed resting on the
floor, spheres in a column) can later be hit hard through its neighbours; with ``d`` from a
gentle onset the damping term ``d delta_dot`` would then be orders of magnitude larger than
one, the force law would be stiff and the explicit integrators unstable. So when the
approach speed exceeds ``law.reimpact`` (default 1.25) times the stored ``v0``, the contact
is treated as re-impacted: ``v0`` and ``d`` are reset from the current speed. In an
isolated impact the approach speed only falls after the onset, so the prescribed COR is
untouched (``inf`` disables the rule: pure onset history).

The spring friction law
-----------------------
With a ``tang`` argument to :func:`compute_forces` (:func:`spring_tangential_force`, added
to the normal force of :func:`contact_force` called without friction) each contact also
keeps its elastic tangential displacement and its tangential damping factor (``xi`` of
:class:`~pdamper.dem.kernels.state.PairContacts` and of the wall contacts): zeroed at the
onset, carried across list rebuilds, advanced by ``dt_xi`` times the slip velocity at
each force evaluation of a step (``dt_xi = 0``: an evaluation of the same state, which
leaves it unchanged). The tanh law passes no ``tang``: its branches are pruned when the
kernel compiles, so its code is the one without them, and its arrays are empty.
"""

from __future__ import annotations

import math
from typing import NamedTuple

from numba import njit

from pdamper.contact.damping import tsuji_damping_ratio_scalar
from pdamper.contact.forces import (
    cor_at,
    friction_per_slip,
    normal_force,
    onset_damping_cached,
    tangential_damping,
    tangential_stiffness,
)
from pdamper.contact.hertz import hertz_stiffness
from pdamper.dem.kernels.state import Rates

#: fast-math flags of the hot kernels: contractions and reassociation only, no
#: 'finite-math' assumptions, so that NaN checks keep working
FASTMATH = {"contract", "reassoc", "nsz", "arcp"}


class ContactForce(NamedTuple):
    """Result of :func:`contact_force` for one contact."""

    fx: float       # force on particle i [N]
    fy: float
    fz: float
    cx: float       # n x F_t: the torque on a sphere of unit radius [N]
    cy: float
    cz: float
    slip: bool      # a friction force acts (the torque is non-zero)
    p_damp: float   # power dissipated by the normal damping [W]
    p_fric: float   # power dissipated by friction [W]
    e_el: float     # elastic energy [J]


@njit(cache=True, fastmath=False, error_model="numpy", _nrt=False)
def impact_damping(fresh, ddot, p, pt, law, k, m_eff):
    """New contact history ``(d, v0)`` at an onset (``fresh``) or a re-impact: the damping
    parameter from the COR curve of pair type ``p`` at the approach speed ``ddot`` [m/s]
    (Tsuji's law also needs the stiffness ``k`` and the effective mass ``m_eff``).

    Called only when the history changes: a function that takes the curve arrays costs
    reference counting at each call, so the test stays in the caller.
    """
    d = onset_damping_cached(ddot, pt.cor_v[p, :pt.cor_n[p]], pt.cor_e[p, :pt.cor_n[p]],
                             law.model, law.v_min, pt.memo, p, k, m_eff)
    return d, (max(ddot, law.v_min) if fresh else ddot)


@njit(cache=True, fastmath=False, error_model="numpy", _nrt=False)
def spring_onset(xi, b, fresh, v, p, pt, law):
    """The spring friction law's history of contact row ``b`` of ``xi`` at an onset
    (``fresh``: the displacement zeroed) or a re-impact: LIGGGHTS' tangential damping
    factor ``2 sqrt(5/6) |beta|`` of pair type ``p`` at the approach speed ``v`` [m/s]
    (the COR at ``max(v, law.v_min)``, as Tsuji's normal damping)."""
    if fresh:
        xi[b, 0] = 0.0
        xi[b, 1] = 0.0
        xi[b, 2] = 0.0
    e = cor_at(max(v, law.v_min), pt.cor_v[p, :pt.cor_n[p]], pt.cor_e[p, :pt.cor_n[p]])
    xi[b, 3] = tsuji_damping_ratio_scalar(e)


@njit(cache=True, fastmath=FASTMATH, inline="always", error_model="numpy")
def spring_tangential_force(delta, ddot, nx, ny, nz, ux, uy, uz, k, d, law, mu, g_star, r_star,
                            m_eff, xi, b, dt_xi, hx, hy, hz):
    """The tangential force of the spring friction law (:mod:`pdamper.contact.forces`) on
    particle ``i`` of one contact, to be added to the normal force of
    :func:`contact_force` (called with ``mu = 0``); the arguments as :func:`contact_force`,
    and

    Parameters
    ----------
    g_star, r_star, m_eff
        Effective shear modulus [Pa], radius [m] and mass [kg] of the contact.
    xi, b
        Row ``b`` of ``xi`` holds the contact's elastic tangential displacement [m] (3)
        and its damping factor [-]; the displacement is updated in place.
    dt_xi, hx, hy, hz
        The step [s] (0 leaves the displacement as it is) and the velocity of the contact
        point of ``i`` relative to the partner over it [m/s] (velocity Verlet: at the half
        step, the velocity that moved the positions, so that the displacement is the
        contacts' own to second order; ``u`` enters the damping).

    Returns
    -------
    ContactForce
        The tangential force and its torque ``n x F_t``; ``p_damp`` 0, ``p_fric`` the power
        dissipated by slip (``mu |F_n|`` times the slip distance of the step over
        ``dt_xi``) or by the tangential damper, ``e_el`` the spring's ``k_t |xi|^2 / 2``.
    """
    fn, _ = normal_force(delta, ddot, k, d, law.model)
    tx = ux - ddot * nx
    ty = uy - ddot * ny
    tz = uz - ddot * nz
    # the slip of the step added (its tangential part: the normal one is projected out
    # with the rest), then projected onto the current tangent plane (the contact turns
    # with the spheres; LIGGGHTS' order)
    sx = xi[b, 0] + dt_xi * hx
    sy = xi[b, 1] + dt_xi * hy
    sz = xi[b, 2] + dt_xi * hz
    sn = sx * nx + sy * ny + sz * nz
    sx -= sn * nx
    sy -= sn * ny
    sz -= sn * nz
    kt = tangential_stiffness(g_star, r_star, delta)
    flim = mu * abs(fn)
    s2 = sx * sx + sy * sy + sz * sz
    if kt * kt * s2 > flim * flim:
        # sliding: the spring scaled back to the Coulomb limit, no damping
        smag = math.sqrt(s2)
        ratio = flim / (kt * smag)
        p_fric = flim * smag * (1.0 - ratio) / dt_xi if dt_xi > 0.0 else 0.0
        sx *= ratio
        sy *= ratio
        sz *= ratio
        gx = -kt * sx
        gy = -kt * sy
        gz = -kt * sz
    else:
        gt = tangential_damping(xi[b, 3], kt, m_eff)
        gx = -kt * sx - gt * tx
        gy = -kt * sy - gt * ty
        gz = -kt * sz - gt * tz
        p_fric = gt * (tx * tx + ty * ty + tz * tz)
    xi[b, 0] = sx
    xi[b, 1] = sy
    xi[b, 2] = sz
    return ContactForce(gx, gy, gz, ny * gz - nz * gy, nz * gx - nx * gz, nx * gy - ny * gx,
                        True, 0.0, p_fric, 0.5 * kt * (sx * sx + sy * sy + sz * sz))


@njit(cache=True, fastmath=FASTMATH, inline="always", error_model="numpy")
def contact_force(delta, ddot, nx, ny, nz, ux, uy, uz, k, d, law, mu, m_a, m_b, m_sum, cap_h):
    """The contact law (paper Sect. 3) for one contact of particle ``i``: normal force with
    its damping, regularised friction with the step cap, and the energy rates.

    Parameters
    ----------
    delta, ddot
        Overlap [m] (> 0) and its rate ``u . n`` [m/s] (positive while approaching).
    nx, ny, nz
        Unit normal from ``i`` to its partner.
    ux, uy, uz
        Velocity of the contact point of ``i`` relative to the partner [m/s].
    k, d
        Hertz stiffness [N/m^1.5] and damping parameter of the contact's history.
    law
        :class:`~pdamper.dem.kernels.state.Law`.
    mu
        Friction coefficient of the pair type [-].
    m_a, m_b, m_sum
        The friction cap's tangential mass is ``2/7 m_a m_b / m_sum`` (two spheres:
        ``m_i, m_j, m_i + m_j``; a sphere on a wall: ``m_i, 1, 1``).
    cap_h
        ``0.5 / h`` of the friction cap, 0: no cap.

    Returns
    -------
    ContactForce
    """
    fn, fel = normal_force(delta, ddot, k, d, law.model)
    p_damp = (fn - fel) * ddot
    e_el = 0.4 * fel * delta
    fx = -fn * nx
    fy = -fn * ny
    fz = -fn * nz
    tx = ux - ddot * nx
    ty = uy - ddot * ny
    tz = uz - ddot * nz
    vt2 = tx * tx + ty * ty + tz * tz
    if vt2 > 0.0 and mu > 0.0:
        # force per slip speed: no square root in the slow (resting) contacts
        s = friction_per_slip(mu, fn, vt2, law.v_reg)
        if cap_h > 0.0:
            # no reversal of the slip within one step (tangential mass 2/7 m*): |F_t| at
            # most 2/7 m* |v_t| cap_h, i.e. s at most 2/7 m* cap_h
            smax = 2.0 / 7.0 * m_a * m_b * cap_h / m_sum
            if s > smax:
                s = smax
        gx = -s * tx
        gy = -s * ty
        gz = -s * tz
        fx += gx
        fy += gy
        fz += gz
        return ContactForce(fx, fy, fz, ny * gz - nz * gy, nz * gx - nx * gz,
                            nx * gy - ny * gx, True, p_damp, s * vt2, e_el)
    return ContactForce(fx, fy, fz, 0.0, 0.0, 0.0, False, p_damp, 0.0, e_el)


@njit(cache=True, fastmath=FASTMATH, inline="always", error_model="numpy")
def _add_to_pair(frc, trq, i, j, ri, rj, t):
    """Add the spring law's tangential force ``t`` of pair ``(i, j)`` (on ``i``; minus it
    on ``j``) and its torques (``r n x F_t`` on each sphere of radius ``r``)."""
    trq[i, 0] += ri * t.cx
    trq[i, 1] += ri * t.cy
    trq[i, 2] += ri * t.cz
    trq[j, 0] += rj * t.cx
    trq[j, 1] += rj * t.cy
    trq[j, 2] += rj * t.cz
    frc[i, 0] += t.fx
    frc[i, 1] += t.fy
    frc[i, 2] += t.fz
    frc[j, 0] -= t.fx
    frc[j, 1] -= t.fy
    frc[j, 2] -= t.fz


@njit(cache=True, fastmath=FASTMATH, inline="always", error_model="numpy")
def compute_forces(pos, vel, omg, zc, vc, cap_h, want_ttc, world, law, part, pt, nbrs,
                   walls, frc, trq, act, na, free, tang=None):
    """Forces and torques on the stepped particles, force on the container, energy rates.

    Parameters
    ----------
    pos, vel, omg : (n, 3) arrays
        Positions [m], velocities [m/s], angular velocities [rad/s] (inertial frame).
    zc, vc : float
        Container position and velocity along z [m], [m/s].
    cap_h : float
        ``0.5 / h`` of the friction cap (0: none).
    want_ttc : bool
        Also compute the shortest time to a new contact (the Gear contact bound).
    world, law, part, pt, nbrs, walls
        The bundles of :mod:`pdamper.dem.kernels.state`; the contact histories in ``nbrs``
        and ``walls`` are updated, ``walls.onset_log`` lists the contacts that start.
    frc, trq : (n, 3) arrays
        Output: total force (gravity included) [N] and torque [N m].
    act, na, free
        The stepped particles ``act[:na]``; ``free[j] != 0`` marks a particle in free flight
        (:mod:`pdamper.dem.kernels.flights`), which no stepped particle can touch: its
        pairs are skipped and its force, torque and contact history are left as they are.
        All particles: ``arange(n), n, zeros(n)``.
    tang : None or (float, (n, 3) array, (n, 3) array)
        None: the tanh friction law. The spring friction law: ``(dt_xi, vel_h, omg_h)``,
        the step that moves the tangential displacements [s] (0: an evaluation that
        leaves them as they are) and the velocities over it (velocity Verlet: the
        half-step ones). A None here is known when the kernel compiles: its branches are
        pruned, and the tanh law's code is the same as without them.

    Returns
    -------
    (Rates, int)
        The rates of this evaluation and the number of contacts that started.
    """
    # arrays out of their bundles once (an access inside the loops would count
    # references at each contact)
    rad = part.rad
    mass = part.mass
    pmat = part.pmat
    kwall = part.kwall
    mu = pt.mu
    estar = pt.estar
    pairs = nbrs.pairs
    nb_start = pairs.start
    nb_j = pairs.j
    h_act = pairs.active
    h_k = pairs.k
    h_d = pairs.d
    h_v = pairs.v0
    w_act = walls.active
    w_d = walls.d
    w_v = walls.v0
    olog = walls.onset_log
    nlog = olog.shape[0]
    g = world.gravity
    nmat = law.nmat
    lx = world.lx
    ly = world.ly
    lz = world.lz
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
    vimp = 0.0
    onsets = 0
    for k in range(na):
        i = act[k]
        frc[i, 0] = 0.0
        frc[i, 1] = 0.0
        frc[i, 2] = -mass[i] * g
        trq[i, 0] = 0.0
        trq[i, 1] = 0.0
        trq[i, 2] = 0.0
    # ---------------- sphere-sphere ----------------
    for k in range(na):
        i = act[k]
        ri = rad[i]
        for b in range(nb_start[i], nb_start[i + 1]):
            j = nb_j[b]
            if free[j] != 0:
                continue
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
            p = pmat[i] * nmat + pmat[j]
            fresh = h_act[b] == 0
            if fresh:
                h_act[b] = 1
                h_k[b] = hertz_stiffness(estar[p], ri * rj / rs)
                if onsets < nlog:
                    olog[onsets] = b
                onsets += 1
            ddot = ux * nx + uy * ny + uz * nz
            if fresh or ddot > law.reimpact * h_v[b]:
                h_d[b], h_v[b] = impact_damping(fresh, ddot, p, pt, law, h_k[b],
                                                mass[i] * mass[j] / (mass[i] + mass[j]))
                if ddot > vimp:
                    vimp = ddot
                if tang is not None:
                    spring_onset(nbrs.pairs.xi, b, fresh, ddot, p, pt, law)
            if tang is not None:
                # the spring law: the normal force here (no tanh friction), its
                # tangential force below
                c = contact_force(delta, ddot, nx, ny, nz, ux, uy, uz, h_k[b], h_d[b], law,
                                  0.0, mass[i], mass[j], mass[i] + mass[j], cap_h)
            else:
                c = contact_force(delta, ddot, nx, ny, nz, ux, uy, uz, h_k[b], h_d[b], law,
                                  mu[p], mass[i], mass[j], mass[i] + mass[j], cap_h)
            dn += c.p_damp
            eel += c.e_el
            rmin = min(ri, rj)
            if delta > ovl * rmin:
                ovl = delta / rmin
            if c.slip:
                df += c.p_fric
                # torque (-r n) x F on j equals (r_j/r_i) times torque r_i n x F on i
                trq[i, 0] += ri * c.cx
                trq[i, 1] += ri * c.cy
                trq[i, 2] += ri * c.cz
                trq[j, 0] += rj * c.cx
                trq[j, 1] += rj * c.cy
                trq[j, 2] += rj * c.cz
            frc[i, 0] += c.fx
            frc[i, 1] += c.fy
            frc[i, 2] += c.fz
            frc[j, 0] -= c.fx
            frc[j, 1] -= c.fy
            frc[j, 2] -= c.fz
            if tang is not None:
                dt_xi, vel_h, omg_h = tang
                wx = ri * omg_h[i, 0] + rj * omg_h[j, 0]
                wy = ri * omg_h[i, 1] + rj * omg_h[j, 1]
                wz = ri * omg_h[i, 2] + rj * omg_h[j, 2]
                t = spring_tangential_force(delta, ddot, nx, ny, nz, ux, uy, uz, h_k[b],
                                            h_d[b], law, mu[p], pt.gstar[p], ri * rj / rs,
                                            mass[i] * mass[j] / (mass[i] + mass[j]),
                                            nbrs.pairs.xi, b, dt_xi,
                                            vel_h[i, 0] - vel_h[j, 0] + wy * nz - wz * ny,
                                            vel_h[i, 1] - vel_h[j, 1] + wz * nx - wx * nz,
                                            vel_h[i, 2] - vel_h[j, 2] + wx * ny - wy * nx)
                df += t.p_fric
                eel += t.e_el
                _add_to_pair(frc, trq, i, j, ri, rj, t)
    # ---------------- sphere-wall ----------------
    # largest particle speed: a separate short loop (in the wall loop the running maximum
    # is spilled to the stack)
    for k in range(na):
        i = act[k]
        v2 = vel[i, 0] ** 2 + vel[i, 1] ** 2 + vel[i, 2] ** 2
        if v2 > vmax2:
            vmax2 = v2
    nw = nmat * nmat
    for k in range(na):
        i = act[k]
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
            fresh = w_act[i, w] == 0
            if fresh:
                w_act[i, w] = 1
                if onsets < nlog:
                    olog[onsets] = -(i * 6 + w) - 1
                onsets += 1
            ddot = ux * nx + uy * ny + uz * nz
            if fresh or ddot > law.reimpact * w_v[i, w]:
                w_d[i, w], w_v[i, w] = impact_damping(fresh, ddot, p, pt, law, kwall[i], mass[i])
                if ddot > vimp:
                    vimp = ddot
                if tang is not None:
                    spring_onset(walls.xi, 6 * i + w, fresh, ddot, p, pt, law)
            if tang is not None:
                c = contact_force(delta, ddot, nx, ny, nz, ux, uy, uz, kwall[i], w_d[i, w],
                                  law, 0.0, mass[i], 1.0, 1.0, cap_h)
            else:
                c = contact_force(delta, ddot, nx, ny, nz, ux, uy, uz, kwall[i], w_d[i, w],
                                  law, mu[p], mass[i], 1.0, 1.0, cap_h)
            dn += c.p_damp
            eel += c.e_el
            if delta > ovl * ri:
                ovl = delta / ri
            if c.slip:
                df += c.p_fric
                trq[i, 0] += ri * c.cx
                trq[i, 1] += ri * c.cy
                trq[i, 2] += ri * c.cz
            frc[i, 0] += c.fx
            frc[i, 1] += c.fy
            frc[i, 2] += c.fz
            fcx -= c.fx
            fcy -= c.fy
            fcz -= c.fz
            wc += c.fz * vc
            if tang is not None:
                dt_xi, vel_h, omg_h = tang
                wx = ri * omg_h[i, 0]
                wy = ri * omg_h[i, 1]
                wz = ri * omg_h[i, 2]
                t = spring_tangential_force(delta, ddot, nx, ny, nz, ux, uy, uz, kwall[i],
                                            w_d[i, w], law, mu[p], pt.gstar[p], ri, mass[i],
                                            walls.xi, 6 * i + w, dt_xi,
                                            vel_h[i, 0] + wy * nz - wz * ny,
                                            vel_h[i, 1] + wz * nx - wx * nz,
                                            vel_h[i, 2] - vc + wx * ny - wy * nx)
                df += t.p_fric
                eel += t.e_el
                trq[i, 0] += ri * t.cx
                trq[i, 1] += ri * t.cy
                trq[i, 2] += ri * t.cz
                frc[i, 0] += t.fx
                frc[i, 1] += t.fy
                frc[i, 2] += t.fz
                fcx -= t.fx
                fcy -= t.fy
                fcz -= t.fz
                wc += t.fz * vc
    return Rates(fcx, fcy, fcz, dn, df, wc, eel, ovl, ttc, math.sqrt(vmax2), vimp), onsets
