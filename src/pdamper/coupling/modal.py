"""Pseudo-force coupling on an N-mode structure (paper Sect. 4.1 models 2 and 3, beyond
one mode), and the study of when one mode is enough.

The damper acts at its point as ``F = -(m_eff x_d'' + d x_d')`` (Sect. 4.1), updated at each
minimum of the damper point ``x_d = phi_d . q`` from that minimum's amplitude and the
effective first eigenfrequency (the first mode of the structure with m_eff at the damper
point, iterated with m_eff as for one mode). Between updates the modal equations are linear,

    (I + m_eff phi_d phi_d^T) q'' + (C + d phi_d phi_d^T) q' + W^2 q = 0,

and are solved in closed form: the state z = (q, q') evolves as ``z(tau) = V e^{L tau}
V^-1 z0`` with the eigen-decomposition ``A = V L V^-1`` of the 2N x 2N state matrix (a
matrix exponential if A is defective). There is no time step: the trajectory is exact
between updates.

Which minimum updates the damper: with higher modes, x_d can have small ripples with local
minima inside one cycle of the first mode. The update happens at the lowest point of each
*negative lobe* of x_d (between a downward and the next upward zero crossing), refined to
the zero of x_d' by Brent's method: one update per vibration cycle, as in the paper. With one
mode this is the minimum one damped period later, as in
:func:`pdamper.coupling.pseudo_force.simulate_pseudo_force` (tested equal).
"""

from __future__ import annotations

import logging
import math
from dataclasses import dataclass, field

import numpy as np

from pdamper.coupling.measurement import lobe_minima
from pdamper.coupling.pseudo_force import MAX_SAMPLES, _update, motion_mode
from pdamper.coupling.results import CycleUpdate, FreeVibrationResult
from pdamper.errors import InputError, SimulationError, check_range

logger = logging.getLogger(__name__)

#: Cycles of the first mode scanned for the next lobe before the motion counts as at rest.
_MAX_SCAN_PERIODS = 50
#: Samples of the scan per first-mode period, and per period of the fastest mode.
_SCAN_PER_PERIOD = 400
_SCAN_PER_FAST_PERIOD = 12
#: Condition number of the eigenvectors above which the state matrix counts as defective.
_DEFECTIVE = 1e10


@dataclass(frozen=True)
class ModalRun:
    """What the N-mode coupling computed (a result's ``details``).

    Attributes
    ----------
    modal
        Modal coordinates q at the sample times, shape (N, samples).
    damper_displacement
        x_d at the sample times [m].
    update_times
        Times of the damper updates [s].
    frequencies
        The structure's eigenfrequencies [Hz].
    """

    modal: np.ndarray = field(repr=False)
    damper_displacement: np.ndarray = field(repr=False)
    update_times: np.ndarray
    frequencies: np.ndarray


class _Segment:
    """Closed-form free motion of the modal equations with constant m_eff and d."""

    def __init__(self, structure, m_eff: float, d: float, z0: np.ndarray):
        n = structure.modes
        w = structure.angular_frequencies
        phi = structure.damper_shape
        mass = np.eye(n) + m_eff * np.outer(phi, phi)
        damping = np.diag(2.0 * structure.damping_ratios * w) + d * np.outer(phi, phi)
        minv = np.linalg.inv(mass)
        self.a = np.block([[np.zeros((n, n)), np.eye(n)],
                           [-minv @ np.diag(w * w), -minv @ damping]])
        self.n, self.z0, self.phi = n, z0, phi
        lam, vec = np.linalg.eig(self.a)
        self.defective = np.linalg.cond(vec) > _DEFECTIVE
        if not self.defective:
            self.lam, self.vec = lam, vec
            self.coef = np.linalg.solve(vec, z0.astype(complex))
        # slowest oscillation (first-mode period) and fastest rate, for the scan step
        osc = np.abs(lam.imag[lam.imag > 1e-12 * np.max(np.abs(lam))])
        self.period = 2.0 * math.pi / osc.min() if osc.size else math.inf
        self.fast = float(np.max(np.abs(lam)))

    def state(self, tau: np.ndarray) -> np.ndarray:
        """z(tau), shape (2N, len(tau))."""
        tau = np.atleast_1d(np.asarray(tau, float))
        if not self.defective:
            return (self.vec @ (self.coef[:, None] * np.exp(self.lam[:, None] * tau[None, :]))).real
        import scipy.linalg

        return np.stack([scipy.linalg.expm(self.a * t) @ self.z0 for t in tau], axis=1)

    def x_damper(self, tau):
        return self.phi @ self.state(tau)[: self.n]

    def v_damper(self, tau) -> float:
        return float(self.phi @ self.state(tau)[self.n:, 0])

    def next_minimum(self, amplitude: float) -> float | None:
        """Time after 0 of the lowest point of the next negative lobe of x_d, or None if
        x_d does not go round another cycle within the scan limit."""
        from scipy.optimize import brentq

        if not math.isfinite(self.period):
            return None
        dt = min(self.period / _SCAN_PER_PERIOD,
                 2.0 * math.pi / self.fast / _SCAN_PER_FAST_PERIOD)
        band = 1e-9 * amplitude
        phase = 0  # 0: rising from the minimum, 1: positive lobe, 2: negative lobe
        chunk = max(16, int(self.period / dt))
        start = 0.0
        best_tau, best_x = 0.0, math.inf
        while start < _MAX_SCAN_PERIODS * self.period:
            taus = start + dt * np.arange(1, chunk + 1)
            x = self.x_damper(taus)
            k = 0
            if phase == 0:
                hit = np.flatnonzero(x > band)
                if hit.size:
                    phase, k = 1, int(hit[0])
            if phase == 1:
                hit = np.flatnonzero(x[k:] < -band)
                if hit.size:
                    phase, k = 2, k + int(hit[0])
            if phase == 2:
                hit = np.flatnonzero(x[k:] > band)
                stop = k + int(hit[0]) if hit.size else x.size
                if stop > k:
                    i = k + int(np.argmin(x[k:stop]))
                    if x[i] < best_x:
                        best_tau, best_x = float(taus[i]), float(x[i])
                if hit.size:  # the lobe is closed: refine its minimum
                    lo, hi = best_tau - dt, best_tau + dt
                    v_lo, v_hi = self.v_damper(lo), self.v_damper(hi)
                    if v_lo <= 0.0 <= v_hi and v_lo < v_hi:
                        return float(brentq(self.v_damper, lo, hi, xtol=1e-15,
                                            rtol=1e-15, maxiter=200))
                    return best_tau
            start = float(taus[-1])
        return None


def simulate_modal_pseudo_force(model, structure, duration: float, initial_displacement: float,
                                sample_rate: float = 2000.0) -> FreeVibrationResult:
    """Free vibration of an N-mode ``structure`` (a
    :class:`~pdamper.structure.modal.ModalStructure`) carrying ``model`` at its damper point,
    released from rest with the release point at ``initial_displacement`` [m] (the static
    shape of the N-mode model under a point load there).

    The result reports the output point (``displacement``, negative peaks); ``cycles`` are
    the damper updates, ``details`` a :class:`ModalRun`.
    """
    check_range("simulation.duration", duration, low=0.0, low_inclusive=False, unit="s")
    check_range("simulation.sample_rate", sample_rate, low=0.0, low_inclusive=False, unit="Hz")
    check_range("structure.initial_displacement", initial_displacement, unit="m")
    if duration * sample_rate * structure.modes > MAX_SAMPLES:
        raise InputError("simulation.duration",
                         f"duration x sample_rate x modes must be <= {MAX_SAMPLES:.0e} samples, "
                         f"got {duration:g} s x {sample_rate:g} Hz x {structure.modes}")
    if initial_displacement >= 0:
        raise InputError("structure.initial_displacement",
                         f"must be < 0 m (released from a minimum), got {initial_displacement:g} m")
    n = structure.modes
    q0 = structure.release_state(initial_displacement)
    if not structure.damper_shape @ q0 < 0:
        raise InputError("structure.damper_position", "the damper point must be deflected "
                         "downwards by the release (it is at or beyond a node of the "
                         "release shape)")
    t_grid = np.arange(0.0, duration + 0.5 / sample_rate, 1.0 / sample_rate)
    q_grid = np.empty((n, t_grid.size))
    t0, z0 = 0.0, np.concatenate([q0, np.zeros(n)])
    cycles, updates = [], [0.0]
    m_eff = 0.0
    while True:
        amp = abs(float(structure.damper_shape @ z0[:n]))
        m_eff, d, freq, resp = _update(model, structure, amp, m_eff)
        cycles.append(CycleUpdate(t0, amp, freq, motion_mode(resp.mode), m_eff, d,
                                  float(resp.loss_factor)))
        seg = _Segment(structure, m_eff, d, z0)
        tau1 = seg.next_minimum(amp)
        t1 = math.inf if tau1 is None else t0 + tau1
        sel = (t_grid >= t0) & (t_grid < t1)
        if np.any(sel):
            q_grid[:, sel] = seg.state(t_grid[sel] - t0)[:n]
        if t1 > duration:
            break
        z0 = seg.state(np.array([tau1]))[:, 0]
        if not np.all(np.isfinite(z0)):
            raise SimulationError(f"the modal coupling diverged at t = {t1:g} s")
        t0 = t1
        updates.append(t0)
        if abs(float(structure.damper_shape @ z0[:n])) < 1e-12:  # at rest
            q_grid[:, t_grid >= t0] = 0.0
            break
    x_out = structure.output_shape @ q_grid
    x_d = structure.damper_shape @ q_grid
    if structure.coincident:  # the update points are the output's minima, exactly
        peak_t = np.array(updates)
        peak_a = np.array([c.amplitude for c in cycles])[: peak_t.size]
    else:
        tp, ap = lobe_minima(t_grid, x_out, band=1e-9 * abs(initial_displacement))
        keep = tp > 0.5 / structure.natural_frequency
        peak_t = np.concatenate([[0.0], tp[keep]])
        peak_a = np.concatenate([[abs(float(structure.output_shape @ q0))], ap[keep]])
    return FreeVibrationResult(
        time=t_grid, displacement=x_out, peak_times=peak_t, peak_amplitudes=peak_a,
        cycles=tuple(cycles), model=model.fidelity,
        inputs={"duration": duration, "initial_displacement": initial_displacement,
                "sample_rate": sample_rate, "modes": n,
                "positions": None if structure.positions is None else list(structure.positions)},
        details=ModalRun(q_grid, x_d, np.array(updates), structure.frequencies.copy()))


@dataclass(frozen=True)
class ModeCountStudy:
    """Amplitude at T of the output point against retained modes and damper position.

    Attributes
    ----------
    positions
        Damper positions from the clamp [m].
    modes
        Numbers of retained modes.
    amplitude
        ``amplitude[i][j]``: amplitude envelope of the output point at ``at`` with the damper
        at ``positions[i]`` and ``modes[j]`` modes [m].
    at
        T [s].
    relative_change
        ``|A(N) / A(1) - 1|`` per position and mode count [-].
    """

    positions: tuple[float, ...]
    modes: tuple[int, ...]
    amplitude: tuple[tuple[float, ...], ...]
    at: float

    @property
    def relative_change(self) -> np.ndarray:
        a = np.asarray(self.amplitude)
        return np.abs(a / a[:, :1] - 1.0)

    def as_dict(self) -> dict:
        return {"positions": list(self.positions), "modes": list(self.modes),
                "amplitude": [list(r) for r in self.amplitude], "at": self.at,
                "relative_change": self.relative_change.tolist()}


def mode_count_study(model, build_structure, positions, modes=(1, 2, 3, 4), at: float = 0.75,
                     initial_displacement: float = -0.058) -> ModeCountStudy:
    """Run ``model`` on ``build_structure(position, n_modes)`` for every damper position and
    mode count; the amplitude of the output point at ``at`` [s] tells when one mode is enough.

    ``build_structure`` returns a :class:`~pdamper.structure.modal.ModalStructure` (e.g. a
    ``lambda p, n: ModalStructure.from_beam(beam, tip, n, damper_position=p, ...)``).
    """
    duration = at + 0.5
    rows = []
    for p in positions:
        row = []
        for n in modes:
            res = simulate_modal_pseudo_force(model, build_structure(p, n), duration,
                                              initial_displacement, sample_rate=1000.0)
            row.append(res.amplitude_at(at))
        rows.append(tuple(row))
    return ModeCountStudy(tuple(float(p) for p in positions), tuple(int(n) for n in modes),
                          tuple(rows), at)
