"""Container motion in the kernels: prescribed (harmonic, sampled table) or a 1-DOF
structure driven by the particles (the paper's model 1)."""

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


@njit(cache=True, fastmath=False, error_model="numpy")
def structure_acceleration(fz, zc, vc, drive, t):
    """1-DOF structure (paper Eq. 23): ``M a = -K z - D v + F_z + F cos(W t + phi)``,
    ``F_z`` the force of the particles on the container, the last term a harmonic load at
    time ``t`` [s] (``drive.amplitude`` F [N], ``drive.omega`` W, ``drive.z0`` phi; F = 0:
    the free structure) [m/s^2]."""
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
