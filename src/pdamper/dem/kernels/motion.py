"""Container motion in the kernels: prescribed (harmonic, sampled table) or a 1-DOF
structure driven by the particles (the paper's model 1), optionally under a load history
(an external force and a base motion, tabulated)."""

from __future__ import annotations

import math

from numba import njit

from pdamper.dem.kernels.state import MOTION_STRUCTURE, MOTION_TABLE


@njit(cache=True, inline="always")
def prescribed_state(t, drive):
    """Prescribed container position, velocity, acceleration at time ``t`` [s].

    Harmonic: ``z = z0 + X sin(W t)`` (rheonomic constraint, paper Sect. 3); table: linear
    interpolation of the uniformly sampled ``(z, v, a)`` with step ``drive.table_dt``
    from ``t = 0``, constant beyond its ends.
    """
    if drive.kind == MOTION_TABLE:
        tz = drive.table_z
        tv = drive.table_v
        ta = drive.table_a
        s = t / drive.table_dt
        i = int(math.floor(s))
        nt = tz.shape[0]
        if i < 0:
            return tz[0], tv[0], ta[0]
        if i >= nt - 1:
            return tz[nt - 1], tv[nt - 1], ta[nt - 1]
        w = s - i
        return (tz[i] + w * (tz[i + 1] - tz[i]), tv[i] + w * (tv[i + 1] - tv[i]),
                ta[i] + w * (ta[i + 1] - ta[i]))
    x = drive.amplitude
    om = drive.omega
    s = math.sin(om * t)
    c = math.cos(om * t)
    return drive.z0 + x * s, x * om * c, -x * om * om * s


@njit(cache=True, inline="always")
def structure_load(t, drive):
    """Base position [m], base velocity [m/s] and external force [N] on a loaded structure
    at time ``t`` [s]: linear interpolation of the tables ``table_z``, ``table_v``,
    ``table_a`` (uniform step ``drive.table_dt`` from ``t = 0``), constant beyond their ends
    (the tables cover the whole run)."""
    tz = drive.table_z
    tv = drive.table_v
    tf = drive.table_a
    s = t / drive.table_dt
    i = int(math.floor(s))
    nt = tz.shape[0]
    if i < 0:
        return tz[0], tv[0], tf[0]
    if i >= nt - 1:
        return tz[nt - 1], tv[nt - 1], tf[nt - 1]
    w = s - i
    return (tz[i] + w * (tz[i + 1] - tz[i]), tv[i] + w * (tv[i + 1] - tv[i]),
            tf[i] + w * (tf[i + 1] - tf[i]))


@njit(cache=True, fastmath=False, error_model="numpy")
def structure_acceleration(fz, zc, vc, drive, t):
    """1-DOF structure (paper Eq. 23): ``M a = -K z - D v + F_z + F cos(W t + phi)``,
    ``F_z`` the force of the particles on the container, the last term a harmonic load at
    time ``t`` [s] (``drive.amplitude`` F [N], ``drive.omega`` W, ``drive.z0`` phi; F = 0:
    the free structure) [m/s^2]. Under a load history (``drive.loaded``) the spring and the
    damper hang from a base at ``z_b(t)``, and a force ``F(t)`` acts on M:
    ``M a = F_z + F(t) - K (z - z_b) - D (v - v_b)``, ``z`` the container's absolute
    position (the one the particles feel)."""
    if drive.loaded != 0:
        zb, vb, fe = structure_load(t, drive)
        return (fz + fe - drive.stiffness * (zc - zb) - drive.damping * (vc - vb)) / drive.mass
    load = drive.amplitude * math.cos(drive.omega * t + drive.z0)
    return (fz - drive.stiffness * zc - drive.damping * vc + load) / drive.mass


@njit(cache=True, inline="always")
def container_state(t, drive, s):
    """Container ``(z, v, a)`` at time ``t`` [s] where a run starts or resumes: a
    structure's position and velocity from its state record ``s`` (its acceleration needs
    the forces, 0 until then), a prescribed motion's from :func:`prescribed_state`."""
    if drive.kind == MOTION_STRUCTURE:
        return s.zc, s.vc, 0.0
    return prescribed_state(t, drive)
