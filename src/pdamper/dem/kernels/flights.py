"""Free flights: multiple time stepping in the Gear kernel.

A random bed of the paper's damper has only a few spheres in contact at any time (a median
of 3 of 32 at 10 Hz / 32 mm), yet a global step integrates all of them at the step of the
stiffest contact. A sphere in free flight needs no integrator: under gravity alone its
parabola ``x0 + v0 tau - g tau^2 / 2 e_z`` (and its constant spin) is exact. So at each
sample, every :data:`REGROUP_EVERY` steps and after each list rebuild, :func:`regroup`
gives every sphere a *horizon*, a time before which no contact of it is possible, and
takes the spheres with a horizon of at least :data:`MIN_STEPS` steps out of the step;
they rejoin on their parabola (:func:`join`) when the horizon ends, or at the next
regroup. The stepped spheres ("active") are integrated as before; forces are evaluated
only between them (:func:`~pdamper.dem.kernels.forces.compute_forces` skips a free
partner).

The horizon is a guarantee, not a prediction. It is computed in the free-fall frame
``w(t') = U - g (t' - t) e_z`` of the regroup at ``t``, ``U`` the spheres' mean velocity:
gravity drops out of every relative motion there, a free sphere's velocity ``u = v - w``
is constant, and a bed that flies as a block is nearly at rest in it (in the ground frame
its spheres move at metres per second, and every gap among them looked about to close).
Each sphere gets a speed limit in that frame ``ulim = SPEED_FACTOR |u| + SPEED_FLOOR``
(it holds while the sphere is stepped) and the container ``vc_lim = SPEED_FACTOR |v_c| +
|a_c| T + SPEED_FLOOR`` (``T`` the longest horizon, one sample interval); while every
stepped sphere and the container stay below their limits (checked at every step; a
violation regroups everything at once), no gap of a free sphere can close faster than
its own ``|u|`` plus its partner's limit, so the horizon of sphere ``i`` is the smallest of

* ``gap_ij / (|u_i| + ulim_j)`` over its Verlet-list partners (0 while in contact),
* ``gap / |v_x|`` and ``gap / |v_y|`` to the side walls (they move vertically, and a free
  sphere's horizontal velocity is constant), ``gap / (|v_z| + g T + vc_lim)`` to floor
  and lid,
* ``(skin / 2 - |x_i - x_build|) / (|v_i| + g T)``: it cannot trigger a list rebuild
  (pairs off the list stay more than the skin apart, as with every sphere stepped),
* ``T``.

A stepped sphere can still trigger a rebuild, and the new list may pair it with a free
sphere whose horizon knew only the old one: the Gear kernel then undoes that step, brings
every sphere back into it and takes it again (the rebuild sees every sphere, the forces
every new pair), and regroups after it.

A free sphere's trajectory is the one the Gear step would give it (Gear integrates a
constant acceleration exactly) up to rounding, so free flights change the cost of a step,
not its physics: the error control, the contacts and the ledger only ever see stepped
spheres, and free spheres exchange no force or energy.
"""

from __future__ import annotations

import math

from numba import njit

from pdamper.dem.kernels.forces import FASTMATH

#: A sphere's speed limit is SPEED_FACTOR x its speed + SPEED_FLOOR (in the free-fall frame):
#: the margin a stepped sphere may gain in contacts before everything is regrouped. Larger
#: limits give shorter horizons (more spheres stepped), smaller ones more regroups. Chosen,
#: not tuned; a floor of 0.25 m/s, or MIN_STEPS 4, changed the CPU time of twelve map
#: points by less than this VM's scatter (docs/dem.md).
SPEED_FACTOR = 1.5
#: [m/s], see SPEED_FACTOR
SPEED_FLOOR = 0.1
#: a sphere leaves the step only for a horizon of at least MIN_STEPS current steps: a
#: shorter flight would save little against the cost of a regroup (about 5 us at 32
#: spheres, measured, against ~0.1 us per sphere and step)
MIN_STEPS = 8.0
#: steps between regroups (besides samples, list rebuilds and violations): a sphere whose
#: horizon ended leaves the step again at the next regroup
REGROUP_EVERY = 16
#: while a regroup frees fewer than a quarter of the spheres, the periodic ones back off
#: (doubling) up to every REGROUP_MAX steps: beds where few spheres fly freely (a pressed
#: bed at the fast corner, a collected bed) then pay almost nothing for free flights
REGROUP_MAX = 1024


@njit(cache=True, fastmath=FASTMATH, inline="always")
def place(i, t, g, fl, pos, vel):
    """Position and velocity of free sphere ``i`` at time ``t`` [s] on its parabola."""
    tau = t - fl.t0[i]
    x0 = fl.x0
    v0 = fl.v0
    for a in range(3):
        pos[i, a] = x0[i, a] + v0[i, a] * tau
        vel[i, a] = v0[i, a]
    pos[i, 2] -= 0.5 * g * tau * tau
    vel[i, 2] -= g * tau


@njit(cache=True, fastmath=FASTMATH, _nrt=False)
def place_all(t, g, fl, pos, vel):
    """Every free sphere's position and velocity at ``t`` (a sample, a list rebuild)."""
    free = fl.free
    for i in range(free.shape[0]):
        if free[i] != 0:
            place(i, t, g, fl, pos, vel)


@njit(cache=True, fastmath=FASTMATH, inline="always")
def _parabola(i, h, g, pos, vel, omg, nx, nw):
    """The exact Nordsieck vectors of sphere ``i`` in free flight for the step ``h``
    (acceleration -g e_z, no higher derivatives; constant spin): a Gear step keeps them on
    the parabola, so the flat loops of the kernel may step a free sphere harmlessly."""
    for a in range(3):
        nx[0, i, a] = pos[i, a]
        nx[1, i, a] = h * vel[i, a]
        nx[2, i, a] = 0.0
        nx[3, i, a] = 0.0
        nx[4, i, a] = 0.0
        nx[5, i, a] = 0.0
        nw[0, i, a] = omg[i, a]
        nw[1, i, a] = 0.0
        nw[2, i, a] = 0.0
        nw[3, i, a] = 0.0
        nw[4, i, a] = 0.0
    nx[2, i, 2] = -0.5 * h * h * g


@njit(cache=True, fastmath=FASTMATH, inline="always")
def join(i, t, h, g, mass, fl, pos, vel, omg, nx, nw, frc, trq, vel_pred, omg_pred):
    """Free sphere ``i`` rejoins the step at time ``t``: its state on the parabola and the
    exact Nordsieck vectors of a parabola for the current step ``h``."""
    place(i, t, g, fl, pos, vel)
    _parabola(i, h, g, pos, vel, omg, nx, nw)
    for a in range(3):
        frc[i, a] = 0.0
        trq[i, a] = 0.0
        vel_pred[i, a] = vel[i, a]
        omg_pred[i, a] = omg[i, a]
    frc[i, 2] = -mass[i] * g
    fl.free[i] = 0


@njit(cache=True, fastmath=FASTMATH, inline="always")
def _list_active(fl):
    """The stepped spheres into ``fl.act``; the earliest horizon into ``fl.scal[0]``."""
    free = fl.free
    until = fl.until
    act = fl.act
    na = 0
    t_next = math.inf
    for i in range(free.shape[0]):
        if free[i] == 0:
            act[na] = i
            na += 1
        elif until[i] < t_next:
            t_next = until[i]
    fl.count[0] = na
    fl.scal[0] = t_next
    return na


@njit(cache=True, fastmath=FASTMATH, _nrt=False)
def join_due(t_end, t, h, g, mass, fl, pos, vel, omg, nx, nw, frc, trq, vel_pred, omg_pred):
    """The free spheres whose horizon ends before ``t_end`` rejoin at ``t``; returns the
    number of stepped spheres and the largest speed of those that joined."""
    free = fl.free
    until = fl.until
    vmax = 0.0
    for i in range(free.shape[0]):
        if free[i] != 0 and until[i] < t_end:
            join(i, t, h, g, mass, fl, pos, vel, omg, nx, nw, frc, trq, vel_pred, omg_pred)
            v = math.sqrt(vel[i, 0] ** 2 + vel[i, 1] ** 2 + vel[i, 2] ** 2)
            if v > vmax:
                vmax = v
    return _list_active(fl), vmax


@njit(cache=True, fastmath=FASTMATH, _nrt=False)
def regroup(t, h, vc, ac, on, pos, vel, omg, nx, nw, frc, trq, vel_pred, omg_pred, zc, world,
            part, nbrs, walls, fl, horizon):
    """Every sphere at time ``t``; then (``on``) the horizons of all spheres are computed
    (module docstring) and those with at least :data:`MIN_STEPS` steps ``h`` of horizon
    leave the step until it ends, the others are stepped. ``horizon`` is the longest
    flight ``T`` [s]. Returns the number of stepped spheres.

    A free sphere is only placed on its parabola to compute its horizon; it rejoins (its
    Nordsieck vectors written) only if it stays in the step: most stay free, and the
    result is the same as a rejoin of all followed by a new flight from ``t``."""
    g = world.gravity
    mass = part.mass
    rad = part.rad
    free = fl.free
    n = free.shape[0]
    if not on:
        for i in range(n):
            if free[i] != 0:
                join(i, t, h, g, mass, fl, pos, vel, omg, nx, nw, frc, trq, vel_pred,
                     omg_pred)
        return _list_active(fl)
    place_all(t, g, fl, pos, vel)
    vlim = fl.vlim
    hz = fl.until  # the horizons, relative, until they are made absolute below
    vcl = SPEED_FACTOR * abs(vc) + abs(ac) * horizon + SPEED_FLOOR
    fl.scal[1] = vcl
    # the free-fall frame w(t') = U - g (t' - t) e_z, U the mean velocity: gravity drops
    # out of the relative motion, so a free sphere's velocity in it is constant and a bed
    # that flies as a block is nearly at rest in it
    ux = 0.0
    uy = 0.0
    uz = 0.0
    for i in range(n):
        ux += vel[i, 0]
        uy += vel[i, 1]
        uz += vel[i, 2]
    ux /= n
    uy /= n
    uz /= n
    fl.scal[3] = ux
    fl.scal[4] = uy
    fl.scal[5] = uz
    fl.scal[6] = t
    lx = world.lx
    ly = world.ly
    lz = world.lz
    half_skin = 0.5 * world.skin
    pb = nbrs.pos_build
    w_act = walls.active
    vown = fl.vown
    for i in range(n):
        vx = vel[i, 0]
        vy = vel[i, 1]
        vz = vel[i, 2]
        v = math.sqrt(vx * vx + vy * vy + vz * vz)
        u = math.sqrt((vx - ux) ** 2 + (vy - uy) ** 2 + (vz - uz) ** 2)
        vlim[i] = SPEED_FACTOR * u + SPEED_FLOOR
        vown[i] = u
        vl = v + g * horizon + 1e-300  # (> 0: no division by zero)
        ri = rad[i]
        touching = False
        for w in range(6):
            if w_act[i, w] != 0:
                touching = True
        if touching:
            hz[i] = 0.0
            continue
        dx = pos[i, 0] - pb[i, 0]
        dy = pos[i, 1] - pb[i, 1]
        dz = pos[i, 2] - pb[i, 2]
        tt = (half_skin - math.sqrt(dx * dx + dy * dy + dz * dz)) / vl
        # the side walls move vertically: only the (constant) horizontal velocity of a
        # free sphere closes its gap to them
        tt = min(tt, (min(pos[i, 0], lx - pos[i, 0]) - ri) / (abs(vx) + 1e-300))
        tt = min(tt, (min(pos[i, 1], ly - pos[i, 1]) - ri) / (abs(vy) + 1e-300))
        zr = pos[i, 2] - zc
        gz = min(zr, lz - zr) - ri
        tt = min(tt, gz / (abs(vz) + g * horizon + vcl))
        hz[i] = min(tt, horizon)
    pairs = nbrs.pairs
    nb_start = pairs.start
    nb_j = pairs.j
    h_act = pairs.active
    for i in range(n):
        ri = rad[i]
        for b in range(nb_start[i], nb_start[i + 1]):
            j = nb_j[b]
            if h_act[b] != 0:
                ti = 0.0
                tj = 0.0
            else:
                dx = pos[j, 0] - pos[i, 0]
                dy = pos[j, 1] - pos[i, 1]
                dz = pos[j, 2] - pos[i, 2]
                gap = math.sqrt(dx * dx + dy * dy + dz * dz) - ri - rad[j]
                # in the free-fall frame a sphere in free flight keeps its own speed, its
                # partner stays below its limit (stepped or not)
                ti = gap / (vown[i] + vlim[j])
                tj = gap / (vown[j] + vlim[i])
            if ti < hz[i]:
                hz[i] = ti
            if tj < hz[j]:
                hz[j] = tj
    x0 = fl.x0
    v0 = fl.v0
    t0 = fl.t0
    lim = MIN_STEPS * h
    for i in range(n):
        if hz[i] >= lim:
            if free[i] == 0:
                # from the step: the spin must stay constant even where the kernel's flat
                # loops step free spheres (no contact, so no force but gravity, no torque)
                _parabola(i, h, g, pos, vel, omg, nx, nw)
                for a in range(3):
                    frc[i, a] = 0.0
                    trq[i, a] = 0.0
                frc[i, 2] = -mass[i] * g
            free[i] = 1
            t0[i] = t
            hz[i] += t
            for a in range(3):
                x0[i, a] = pos[i, a]
                v0[i, a] = vel[i, a]
        elif free[i] != 0:
            join(i, t, h, g, mass, fl, pos, vel, omg, nx, nw, frc, trq, vel_pred, omg_pred)
    return _list_active(fl)
