"""The analytical bed integrated event by event: a perfectly plastic block in a moving
container (paper Sect. 3.1, without the closed forms' assumptions on the trajectory).

The bed is one rigid block of mass ``m_bed`` in a container with a gap ``h`` (the clearance)
between the bed and the lid. It is in one of three states:

- **riding the floor**: it moves with the container; the floor pushes it up with
  ``N = m_bed (a_c + g)``, and it takes off when that force would pull (``a_c < -g``, Eq. 5);
- **pinned to the lid**: it moves with the container while the lid decelerates it faster
  than gravity (``a_c < -g``, Eq. 13), and is released when ``a_c > -g``;
- **free flight** under gravity, until it reaches the floor or the lid.

An impact is perfectly plastic (collect-and-collide): the bed adopts the wall's velocity
after a momentum exchange with the container (zero relative rebound). Its energy loss is
``mu dv^2 / 2`` with the relative velocity ``dv`` and the reduced mass ``mu`` of bed and
container (``mu = m_bed`` for a container moving on a prescribed path, Eqs. 11, 16, 17).

Two uses:

- :func:`harmonic_plastic_bed`: the container moves as ``X sin(W t)``; the steady loss factor
  and effective mass from the dissipated energy and the bed's first harmonic (Eqs. 2-4). It
  reproduces the closed-form motion modes of :func:`pdamper.analysis.analytical.bed_response`
  where their trajectories repeat, and answers where the closed forms fall back on Eq. (8)
  (scattering) or on approximations (the single collect-and-collide impact after the next
  take-off; the effective-mass table of Eq. 22).
- :class:`PlasticBedSystem`: the bed on a linear structure (mass-normalised modes or a
  1-DOF), integrated exactly between events for inputs linear between steps (first-order
  hold), the events located inside the step: the damper force that follows any motion of
  the container (free decays of N modes, load histories, shocks).

Coordinates of the coupled form: the structure's ``q`` from its static equilibrium with the
bed resting on the floor (``K q_eq = -phi m_bed g``), the bed's bottom ``Y`` [m] from its
resting position at that equilibrium; the floor is at ``phi . q + y_base``, the lid's reach
at that plus ``h``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from pdamper.constants import STANDARD_GRAVITY
from pdamper.errors import InputError, SimulationError, check_range

#: Bed states.
FLOOR, LID, FREE = 0, 1, 2
_STATE_NAMES = {FLOOR: "floor", LID: "lid", FREE: "free"}

#: Phase steps per cycle of the scan for the next wall in a flight (harmonic form).
_SCAN = 256
#: Longest orbit [cycles] that :func:`harmonic_plastic_bed` recognises as periodic.
MAX_PERIOD_CYCLES = 8
#: Most events inside one integration step of the coupled form before it gives up.
_MAX_EVENTS_PER_STEP = 64


# ----------------------------------------------------------------- harmonic container
@dataclass(frozen=True)
class PlasticBedResponse:
    """Steady response of the plastic bed in a container moving as ``X sin(W t)``.

    Attributes
    ----------
    frequency, amplitude, clearance, bed_mass
        f [Hz], X [m], h [m], m_bed [kg] (broadcast shape of the inputs).
    loss_factor
        eta [-]: the energy the impacts dissipate per cycle over ``2 pi (1/2 m_bed V^2)``,
        averaged over the window (Eq. 3).
    loss_factor_complex_power
        eta from the bed's first harmonic, ``-Re(Y*) / X`` (Eqs. 1-3 with the bed's momentum
        balance); equal to ``loss_factor`` for a periodic orbit, a check.
    effective_mass_ratio
        ``|F* / A*| / m_bed = |Y*| / X`` [-] (Eq. 4): the bed's first harmonic over the
        container's.
    period_cycles
        Cycles after which the orbit repeats (1: harmonic, k + 1: subharmonic of order k,
        0: no period up to :data:`MAX_PERIOD_CYCLES`, i.e. scattering or a long orbit).
    impacts_per_cycle, lid_impacts_per_cycle
        Impacts (all, and with the lid) per excitation cycle [-] in the window.
    airborne_fraction
        Fraction of the window the bed spends in flight [-].
    cycles
        Cycles averaged (after the settling cycles).
    """

    frequency: np.ndarray
    amplitude: np.ndarray
    clearance: np.ndarray
    bed_mass: np.ndarray
    loss_factor: np.ndarray
    loss_factor_complex_power: np.ndarray
    effective_mass_ratio: np.ndarray
    period_cycles: np.ndarray
    impacts_per_cycle: np.ndarray
    lid_impacts_per_cycle: np.ndarray
    airborne_fraction: np.ndarray
    cycles: int
    gravity: float = STANDARD_GRAVITY

    @property
    def effective_mass(self) -> np.ndarray:
        """Effective particle mass [kg]."""
        return self.effective_mass_ratio * self.bed_mass

    @property
    def dissipated_energy_per_cycle(self) -> np.ndarray:
        """E~ [J] = 2 pi eta (1/2 m_bed V^2) (Eq. 3)."""
        v = self.amplitude * 2.0 * math.pi * self.frequency
        return 2.0 * math.pi * self.loss_factor * 0.5 * self.bed_mass * v * v


def harmonic_plastic_bed(frequency, amplitude, clearance, bed_mass,
                         gravity: float = STANDARD_GRAVITY, *, settle_cycles: int = 16,
                         cycles: int = 48, samples_per_cycle: int = 1024
                         ) -> PlasticBedResponse:
    """Steady response of the plastic bed in a container moving as ``X sin(2 pi f t)``.

    The bed starts at rest on the floor at ``t = 0``; after ``settle_cycles`` the next
    ``cycles`` (a multiple of every period up to :data:`MAX_PERIOD_CYCLES` by default: 48)
    are averaged. Vectorised by a loop over the broadcast points (about 10 ms a point).

    Parameters
    ----------
    frequency, amplitude, clearance, bed_mass
        f [Hz] > 0, X [m] > 0, h [m] >= 0, m_bed [kg] >= 0 (array_like, broadcast).
    gravity
        g [m/s^2] >= 0.

    Examples
    --------
    The paper's double collect-and-collide optimum (Eq. 21's 4/pi without gravity):

    >>> r = harmonic_plastic_bed(10.0, 0.1 / math.pi, 0.1, 0.132, gravity=0.0)
    >>> round(float(r.loss_factor), 3)  # 4 / pi: the zero-gravity optimum
    1.273
    """
    f, x, h, m = np.broadcast_arrays(*(np.asarray(v, float) for v in
                                       (frequency, amplitude, clearance, bed_mass)))
    for name, arr, strict in (("frequency", f, True), ("amplitude", x, True),
                              ("clearance", h, False), ("bed_mass", m, False)):
        ok = np.isfinite(arr) & ((arr > 0) if strict else (arr >= 0))
        if not np.all(ok):
            raise InputError(name, f"must be finite and {'>' if strict else '>='} 0, got "
                             f"{arr[~ok].ravel()[0]:g}")
    gravity = check_range("gravity", gravity, low=0.0, unit="m/s^2")
    check_range("cycles", cycles, low=1, unit="")
    check_range("settle_cycles", settle_cycles, low=0, unit="")
    shape = f.shape
    out = {k: np.empty(f.size) for k in ("eta", "eta_cp", "ratio", "period", "imp", "lid",
                                         "air")}
    for i, (fi, xi, hi) in enumerate(zip(f.ravel(), x.ravel(), h.ravel(), strict=True)):
        w = 2.0 * math.pi * fi
        inv_gam = gravity / (xi * w * w)  # 1 / Gamma
        res = _HarmonicRun(inv_gam, hi / xi).run(settle_cycles, cycles, samples_per_cycle)
        for k in out:
            out[k][i] = res[k]

    def o(a):
        return a.reshape(shape)

    return PlasticBedResponse(
        frequency=o(f.ravel().copy()), amplitude=o(x.ravel().copy()),
        clearance=o(h.ravel().copy()), bed_mass=o(m.ravel().copy()),
        loss_factor=o(out["eta"]), loss_factor_complex_power=o(out["eta_cp"]),
        effective_mass_ratio=o(out["ratio"]), period_cycles=o(out["period"].astype(int)),
        impacts_per_cycle=o(out["imp"]), lid_impacts_per_cycle=o(out["lid"]),
        airborne_fraction=o(out["air"]), cycles=int(cycles), gravity=gravity)


class _HarmonicRun:
    """One point of :func:`harmonic_plastic_bed` in the phase ``phi = W t``, positions in
    strokes, velocities in ``V = X W`` (as :mod:`pdamper.analysis.analytical`): the
    container at ``sin(phi)``, a flight ``y0 + v0 s - s^2 / (2 Gamma)``."""

    def __init__(self, inv_gam: float, ht: float):
        self.ig = inv_gam
        self.ht = ht
        # take-off phase, Eq. (5); never for Gamma <= 1 (solid-like)
        self.phi0 = math.asin(inv_gam) if inv_gam < 1.0 else math.nan

    def _next(self, phi: float, base: float) -> float:
        """First phase >= phi of the family ``base + 2 pi k``."""
        k = math.ceil((phi - base) / (2.0 * math.pi) - 1e-12)
        return base + 2.0 * math.pi * k

    def _flight_end(self, p0: float, y0: float, v0: float, end: float):
        """First wall the flight from (p0, y0, v0) reaches before ``end``: (phase, wall) or
        (None, None)."""
        from scipy.optimize import brentq

        ig, ht = self.ig, self.ht

        def floor(p):
            s = p - p0
            return y0 + v0 * s - 0.5 * ig * s * s - np.sin(p)

        def lid(p):
            s = p - p0
            return np.sin(p) + ht - (y0 + v0 * s - 0.5 * ig * s * s)

        step = 2.0 * math.pi / _SCAN
        start = p0
        tol = 1e-12
        while start < end:
            grid = start + step * np.arange(1, 4 * _SCAN + 1)
            gf, gl = floor(grid), lid(grid)
            hit_f = np.flatnonzero(gf < -tol)
            hit_l = np.flatnonzero(gl < -tol)
            jf = int(hit_f[0]) if hit_f.size else grid.size
            jl = int(hit_l[0]) if hit_l.size else grid.size
            j = min(jf, jl)
            if j < grid.size:
                a = grid[j - 1] if j > 0 else p0
                fn = floor if jf <= jl else lid
                wall = FLOOR if jf <= jl else LID
                if fn(a) <= 0.0:  # departure round-off: the crossing is at the start
                    return a, wall
                p = brentq(fn, a, grid[j], xtol=1e-14, rtol=1e-15, maxiter=200)
                return (p, wall) if p < end else (None, None)
            start = float(grid[-1])
        return None, None

    def run(self, settle: int, cycles: int, samples: int) -> dict:
        two_pi = 2.0 * math.pi
        p_start, p_end = two_pi * settle, two_pi * (settle + cycles)
        ig, ht, phi0 = self.ig, self.ht, self.phi0
        if ht <= 0.0:  # no gap: the bed moves with the container, a rigid mass
            return {"eta": 0.0, "eta_cp": 0.0, "ratio": 1.0, "period": 1, "imp": 0.0,
                    "lid": 0.0, "air": 0.0}
        state, p = FLOOR, 0.0
        y = v = 0.0
        segs: list[tuple[float, int, float, float]] = []  # (start phase, state, y0, v0)
        impacts: list[tuple[float, int, float]] = []  # (phase, wall, dv^2)
        while p < p_end:
            if state in (FLOOR, LID):
                segs.append((p, state, 0.0, 0.0))
                if math.isnan(phi0):  # Gamma <= 1: the floor holds the bed for ever
                    break
                # floor: holds while sin(p) <= 1/Gamma; lid: while sin(p) >= 1/Gamma
                base = phi0 if state == FLOOR else math.pi - phi0
                leave = self._next(p, base)
                holds = (math.sin(p) <= ig + 1e-12) if state == FLOOR else \
                    (math.sin(p) >= ig - 1e-12)
                if not holds:
                    leave = p
                elif state == FLOOR and phi0 < p % two_pi < math.pi - phi0:
                    leave = p  # on the take-off's own side of the sine (round-off)
                if leave >= p_end:
                    break
                p = leave
                if ht <= 0.0:  # no gap: the other wall takes the bed at once
                    state = LID if state == FLOOR else FLOOR
                    continue
                y = math.sin(p) + (ht if state == LID else 0.0)
                v = math.cos(p)
                state = FREE
            else:
                segs.append((p, FREE, y, v))
                hit, wall = self._flight_end(p, y, v, p_end)
                if hit is None:
                    break
                s = hit - p
                v_bed = v - ig * s
                dv = v_bed - math.cos(hit)
                impacts.append((hit, wall, dv * dv))
                p, state = hit, wall
        return self._averages(segs, impacts, p_start, p_end, cycles, samples)

    def _averages(self, segs, impacts, p_start, p_end, cycles, samples) -> dict:
        two_pi = 2.0 * math.pi
        imp = [(ph, wall, e) for ph, wall, e in impacts if p_start <= ph < p_end]
        eta = sum(e for _, _, e in imp) / (cycles * two_pi)
        starts = np.array([s[0] for s in segs])
        kinds = np.array([s[1] for s in segs])
        y0 = np.array([s[2] for s in segs])
        v0 = np.array([s[3] for s in segs])
        phi = np.linspace(p_start, p_end, cycles * samples + 1)
        j = np.searchsorted(starts, phi, side="right") - 1
        s = phi - starts[j]
        yc = np.sin(phi)
        y = np.where(kinds[j] == FLOOR, yc,
                     np.where(kinds[j] == LID, yc + self.ht,
                              y0[j] + v0[j] * s - 0.5 * self.ig * s * s))
        # first harmonic of the bed (cos convention: sin(phi) -> -i)
        y_star = 2.0 / (p_end - p_start) * np.trapezoid(y * np.exp(-1j * phi), phi)
        air = float(np.mean(kinds[j] == FREE))
        return {"eta": eta, "eta_cp": -y_star.real, "ratio": abs(y_star),
                "period": _period(imp, p_end), "imp": len(imp) / cycles,
                "lid": sum(1 for _, wall, _ in imp if wall == LID) / cycles, "air": air}


def _period(impacts, p_end: float) -> int:
    """Cycles after which the impacts of the window's end repeat (0: none found)."""
    two_pi = 2.0 * math.pi
    if not impacts:
        return 1  # no impact: riding (solid-like) repeats every cycle
    ph = np.array([i[0] for i in impacts])
    for k in range(1, MAX_PERIOD_CYCLES + 1):
        last = ph[ph >= p_end - two_pi * k]
        prev = ph[(ph >= p_end - 2 * two_pi * k) & (ph < p_end - two_pi * k)]
        if 2 * two_pi * k > p_end - ph[0] + two_pi * k:
            break
        if last.size and last.size == prev.size and \
                np.allclose(last - two_pi * k, prev, atol=1e-6, rtol=0.0):
            return k
    return 0


# ----------------------------------------------------------------- on a structure
def _expm_small(m: np.ndarray) -> np.ndarray:
    """``exp(m)`` of a small matrix: Taylor series of ``m / 2^s`` (norm <= 1/2, 24 terms:
    below 1e-30 relative) squared ``s`` times.

    Why not :func:`scipy.linalg.expm`: a run calls this at every event, and scipy's Pade
    kernel goes through its own threaded BLAS, which on a busy machine spends 20-40 ms a
    call on an 8 x 8 matrix (numpy's products here: microseconds)."""
    norm = float(np.max(np.sum(np.abs(m), axis=0))) if m.size else 0.0
    s = max(0, int(math.ceil(math.log2(norm))) + 1) if norm > 0.5 else 0
    a = m / (2.0 ** s)
    out = np.eye(m.shape[0])
    term = np.eye(m.shape[0])
    for k in range(1, 25):
        term = term @ a / k
        out = out + term
        if not np.any(np.abs(term) > 1e-18 * np.abs(out)):
            break
    for _ in range(s):
        out = out @ out
    return out


def _hold(a: np.ndarray, b: np.ndarray, h: float):
    """Exact step of ``z' = A z + B u`` for u linear over the step h (first-order hold,
    Van Loan 1978): ``z1 = P z0 + G0 u0 + G1 (u1 - u0)``."""
    n, m = b.shape
    e = np.zeros((n + 2 * m, n + 2 * m))
    e[:n, :n] = a * h
    e[:n, n:n + m] = b * h
    e[n:n + m, n + m:] = np.eye(m)
    x = _expm_small(e)
    return x[:n, :n].copy(), x[:n, n:n + m].copy(), x[:n, n + m:].copy()


@dataclass(frozen=True)
class PlasticBedState:
    """Where a run of :class:`PlasticBedSystem` ended, to continue it
    (:meth:`PlasticBedSystem.run`'s ``start``): the structure's state ``z = (q, q')``, the
    bed's state code, its bottom's position [m] and velocity [m/s]."""

    z: np.ndarray = field(repr=False)
    state: int
    bed_position: float
    bed_velocity: float


@dataclass(frozen=True)
class PlasticBedRun:
    """What :meth:`PlasticBedSystem.run` computed at the grid times.

    Attributes
    ----------
    time
        t [s].
    q, qdot, qddot
        Modal coordinates (or the 1-DOF's x) from the static equilibrium with the bed
        resting, their rates; shape (N, samples).
    bed_position, bed_velocity
        The bed's bottom from its resting position at the equilibrium [m], its velocity
        [m/s].
    state
        The bed's state at each sample (:data:`FLOOR`, :data:`LID`, :data:`FREE`).
    contact_force
        The force the bed exerts on the container between impacts [N], up positive, its
        weight included (``-m_bed (a_c + g)`` in contact, 0 in flight).
    impact_times, impact_walls, impulses, impact_losses
        Each impact: time [s], wall (:data:`FLOOR` / :data:`LID`), the impulse on the
        container [N s] (up positive) and the energy it dissipated [J].
    """

    time: np.ndarray
    q: np.ndarray = field(repr=False)
    qdot: np.ndarray = field(repr=False)
    qddot: np.ndarray = field(repr=False)
    bed_position: np.ndarray = field(repr=False)
    bed_velocity: np.ndarray = field(repr=False)
    state: np.ndarray = field(repr=False)
    contact_force: np.ndarray = field(repr=False)
    impact_times: np.ndarray
    impact_walls: np.ndarray
    impulses: np.ndarray
    impact_losses: np.ndarray
    end: PlasticBedState | None = field(default=None, repr=False)

    @property
    def dissipated_energy(self) -> float:
        """Energy the impacts dissipated [J]."""
        return float(np.sum(self.impact_losses))


class PlasticBedSystem:
    """A linear structure ``M q'' + C q' + K q = b_F F - b_B a_b + phi F_bed`` carrying the
    plastic bed at the point ``x_d = phi . q`` (module docstring).

    Parameters
    ----------
    mass, damping, stiffness
        M, C, K of the structure (N x N; mass-normalised modes: I, diag(2 zeta w),
        diag(w^2); a 1-DOF: [[M]], [[D]], [[K]]).
    phi
        The damper point's shape (N).
    load_shape
        Where a force F acts (N).
    base_shape
        The base acceleration's load ``b_B`` (N; participation factors), or None.
    bed_mass, clearance
        m_bed [kg], h [m] >= 0.
    gravity
        g [m/s^2] >= 0.
    """

    def __init__(self, mass, damping, stiffness, phi, load_shape, base_shape, bed_mass: float,
                 clearance: float, gravity: float = STANDARD_GRAVITY):
        self.m_s = np.atleast_2d(np.asarray(mass, float))
        self.c_s = np.atleast_2d(np.asarray(damping, float))
        self.k_s = np.atleast_2d(np.asarray(stiffness, float))
        self.phi = np.atleast_1d(np.asarray(phi, float))
        self.load_shape = np.atleast_1d(np.asarray(load_shape, float))
        self.base_shape = (np.zeros_like(self.phi) if base_shape is None
                           else np.atleast_1d(np.asarray(base_shape, float)))
        self.m = check_range("bed_mass", bed_mass, low=0.0, unit="kg")
        self.h = check_range("clearance", clearance, low=0.0, unit="m")
        self.g = check_range("gravity", gravity, low=0.0, unit="m/s^2")
        n = self.phi.size
        self.n = n
        pp = np.outer(self.phi, self.phi)
        # inputs u = (F, a_b, 1): the bed's weight, carried by the floor at the equilibrium,
        # pulls the spring back up while the bed flies (+phi m g)
        self._cfg = {}
        for attached in (False, True):
            mt = self.m_s + (self.m * pp if attached else 0.0)
            minv = np.linalg.inv(mt)
            a = np.block([[np.zeros((n, n)), np.eye(n)], [-minv @ self.k_s, -minv @ self.c_s]])
            cols = np.zeros((n, 3))
            cols[:, 0] = self.load_shape
            cols[:, 1] = -(self.base_shape + (self.m * self.phi if attached else 0.0))
            cols[:, 2] = 0.0 if attached else self.phi * self.m * self.g
            b = np.vstack([np.zeros((n, 3)), minv @ cols])
            self._cfg[attached] = (a, b, minv)
        # the container's inverse mass at the damper point (bed detached): impacts
        self._mob = float(self.phi @ self._cfg[False][2] @ self.phi)

    def run(self, dt: float, u: np.ndarray, v_base: np.ndarray, y_base: np.ndarray,
            q0: np.ndarray | None = None, start: PlasticBedState | None = None
            ) -> PlasticBedRun:
        """Integrate from rest (or ``q0``) with the bed resting on the floor, or from where
        an earlier run ended (``start``: its ``end``; the time then counts from 0 again),
        on the grid ``t = k dt`` of the inputs ``u[k] = (F, a_b, 1)`` (linear between
        samples), the base velocity and displacement at the samples."""
        steps = u.shape[0] - 1
        n = self.n
        z = np.zeros(2 * n)
        if q0 is not None:
            z[:n] = q0
        if start is not None:
            z = np.array(start.z, float)
        phi = self.phi
        z_out = np.empty((steps + 1, 2 * n))
        zd_out = np.empty((steps + 1, 2 * n))
        yb_out = np.empty(steps + 1)
        vb_out = np.empty(steps + 1)
        st_out = np.empty(steps + 1, int)
        fc_out = np.empty(steps + 1)
        impacts: list[tuple[float, int, float, float]] = []  # time, wall, impulse, loss
        holds = {att: _hold(*self._cfg[att][:2], dt) for att in (False, True)}
        # start: riding the floor at the equilibrium (or pinned, if the floor cannot hold)
        Y = float(phi @ z[:n]) + y_base[0]
        V = float(phi @ z[n:]) + v_base[0]
        state = self._settle(FLOOR, z, u[0])
        if self.h <= 0.0 and state == FREE:
            state = LID
        if start is not None:  # the bed as the earlier run left it
            state, Y, V = int(start.state), float(start.bed_position), float(start.bed_velocity)
        for k in range(steps + 1):
            att = state != FREE
            a, b, _ = self._cfg[att]
            zd = a @ z + b @ u[k]
            z_out[k], zd_out[k] = z, zd
            xc = float(phi @ z[:n]) + y_base[k]
            vc = float(phi @ z[n:]) + v_base[k]
            if att:
                Y, V = xc + (self.h if state == LID else 0.0), vc
                fc_out[k] = -self.m * (float(phi @ zd[n:]) + u[k, 1] + self.g)
            else:
                fc_out[k] = 0.0
            yb_out[k], vb_out[k], st_out[k] = Y, V, state
            if k == steps:
                break
            z, state, Y, V = self._step(k, dt, z, state, Y, V, u, v_base, y_base, holds,
                                        impacts)
            if not np.all(np.isfinite(z)):
                raise SimulationError(f"the plastic bed's run diverged at t = {k * dt:g} s")
        return PlasticBedRun(
            time=np.arange(steps + 1) * dt, q=z_out[:, :n].T.copy(),
            qdot=z_out[:, n:].T.copy(), qddot=zd_out[:, n:].T.copy(), bed_position=yb_out,
            bed_velocity=vb_out, state=st_out, contact_force=fc_out,
            impact_times=np.array([i[0] for i in impacts]),
            impact_walls=np.array([i[1] for i in impacts], int),
            impulses=np.array([i[2] for i in impacts]),
            impact_losses=np.array([i[3] for i in impacts]),
            end=PlasticBedState(z.copy(), int(state), float(Y), float(V)))

    def _step(self, k: int, dt: float, z: np.ndarray, state: int, Y: float, V: float,
              u: np.ndarray, v_base: np.ndarray, y_base: np.ndarray, holds: dict,
              impacts: list) -> tuple[np.ndarray, int, float, float]:
        """The step ``k`` of :meth:`run` (``dt`` [s]), the events inside it located and
        handled (:meth:`_event`, :meth:`_transition`, impacts appended to ``impacts``):
        the structure's state ``z`` and the bed's state, position ``Y`` [m] and velocity
        ``V`` [m/s] at its end. ``holds``: the exact whole-step maps of both
        configurations (:func:`_hold`)."""
        n, phi = self.n, self.phi
        tau, events = 0.0, 0
        while tau < dt * (1.0 - 1e-12):
            span = dt - tau
            att = state != FREE
            a, b, _ = self._cfg[att]
            ua = u[k] + (u[k + 1] - u[k]) * (tau / dt)
            ub = u[k + 1]
            p, g0, g1 = holds[att] if tau == 0.0 else _hold(a, b, span)
            z1 = p @ z + g0 @ ua + g1 @ (ub - ua)
            ev = self._event(state, z, z1, ua, ub, Y, V, span, k, tau, dt, v_base, y_base)
            if ev is None:
                if state == FREE:
                    Y, V = Y + V * span - 0.5 * self.g * span * span, V - self.g * span
                z = z1
                break
            s = ev  # the event's time inside the span
            p, g0, g1 = _hold(a, b, s)
            um = ua + (ub - ua) * (s / span)
            z = p @ z + g0 @ ua + g1 @ (um - ua)
            t_ev = (k * dt) + tau + s
            frac = (tau + s) / dt
            vb_ev = v_base[k] + (v_base[k + 1] - v_base[k]) * frac
            yb_ev = y_base[k] + (y_base[k + 1] - y_base[k]) * frac
            xc = float(phi @ z[:n]) + yb_ev
            vc = float(phi @ z[n:]) + vb_ev
            state, Y, V = self._transition(state, z, Y, V, s, xc, vc, um, vb_ev, yb_ev,
                                           t_ev, impacts)
            tau += s
            events += 1
            if events > _MAX_EVENTS_PER_STEP:
                raise SimulationError(f"more than {_MAX_EVENTS_PER_STEP} bed events in one "
                                      f"step at t = {t_ev:.6g} s: lower the time step")
        return z, state, Y, V

    def _transition(self, state: int, z: np.ndarray, Y: float, V: float, s: float,
                    xc: float, vc: float, um: np.ndarray, vb_ev: float, yb_ev: float,
                    t_ev: float, impacts: list) -> tuple[int, float, float]:
        """The bed's state, position and velocity after the event ``s`` into the span: a
        flight ending on a wall (a plastic impact: the impulse that makes the relative
        velocity zero, ``z`` updated in place, the impact recorded), or a contact letting
        go."""
        n, phi = self.n, self.phi
        if state == FREE:
            Y, V = Y + V * s - 0.5 * self.g * s * s, V - self.g * s
            wall = FLOOR if Y - xc < 0.5 * self.h else LID
            # the impulse on the bed that makes the relative velocity zero
            j = (vc - V) / (1.0 / self.m + self._mob)
            loss = 0.5 * (vc - V) ** 2 / (1.0 / self.m + self._mob)
            V += j / self.m
            z[n:] -= self._cfg[False][2] @ phi * j
            impacts.append((t_ev, wall, -j, loss))
            state = self._settle(wall, z, um, vb_ev=vb_ev, yb_ev=yb_ev)
            if state == FREE:
                V = float(phi @ z[n:]) + vb_ev
            return state, xc + (self.h if wall == LID else 0.0), V
        # the contact lets go
        Y, V = xc + (self.h if state == LID else 0.0), vc
        if self.h <= 0.0:
            return (LID if state == FLOOR else FLOOR), Y, V
        return FREE, Y, V

    def _normal(self, state: int, z: np.ndarray, u: np.ndarray) -> float:
        """The wall's push on the bed [N] (floor: up; lid: down) with the bed attached;
        negative: the contact cannot hold."""
        a, b, _ = self._cfg[True]
        acc = float(self.phi @ (a @ z + b @ u)[self.n:]) + u[1]
        nf = self.m * (acc + self.g)
        return nf if state == FLOOR else -nf

    def _settle(self, wall: int, z, u, vb_ev=None, yb_ev=None) -> int:
        """The state after reaching ``wall`` with zero relative velocity: pinned there if the
        wall can hold the bed, else flying (or the other wall, without a gap)."""
        if self.m <= 0.0:
            return wall
        if self._normal(wall, z, u) >= 0.0:
            return wall
        if self.h <= 0.0:
            return LID if wall == FLOOR else FLOOR
        return FREE

    def _event(self, state, z0, z1, ua, ub, Y, V, span, k, tau, dt, v_base, y_base):
        """Time inside the span of the first event (impact or release), or None."""
        n = self.n
        phi = self.phi
        if self.m <= 0.0:
            return None
        if state != FREE:
            n0, n1 = self._normal(state, z0, ua), self._normal(state, z1, ub)
            if n1 >= 0.0:
                return None
            if n0 <= 0.0:
                return 0.0
            return span * n0 / (n0 - n1)
        f0, f1 = (tau / dt), (tau + span) / dt
        yb0 = y_base[k] + (y_base[k + 1] - y_base[k]) * f0
        yb1 = y_base[k] + (y_base[k + 1] - y_base[k]) * f1
        vb0 = v_base[k] + (v_base[k + 1] - v_base[k]) * f0
        vb1 = v_base[k] + (v_base[k + 1] - v_base[k]) * f1
        x0, x1 = float(phi @ z0[:n]) + yb0, float(phi @ z1[:n]) + yb1
        v0, v1 = float(phi @ z0[n:]) + vb0, float(phi @ z1[n:]) + vb1
        g = self.g
        y1 = Y + V * span - 0.5 * g * span * span
        tol = 1e-12 * max(self.h, abs(x1), 1e-6)
        floor1, lid1 = y1 - x1, x1 + self.h - y1
        if floor1 >= -tol and lid1 >= -tol:
            return None

        def xc(s):  # cubic Hermite of the container over the span
            r = s / span
            h00, h10 = 2 * r**3 - 3 * r**2 + 1, r**3 - 2 * r**2 + r
            h01, h11 = -2 * r**3 + 3 * r**2, r**3 - r**2
            return h00 * x0 + h10 * span * v0 + h01 * x1 + h11 * span * v1

        def gap(s):
            yb = Y + V * s - 0.5 * g * s * s
            return (yb - xc(s)) if floor1 < -tol else (xc(s) + self.h - yb)

        from scipy.optimize import brentq

        if gap(0.0) <= 0.0:
            return 0.0
        return float(brentq(gap, 0.0, span, xtol=1e-15 * max(span, 1e-30), rtol=1e-14))


def state_name(code: int) -> str:
    """``"floor"``, ``"lid"`` or ``"free"``."""
    return _STATE_NAMES[int(code)]
