"""The ``"plastic_bed"`` coupling: the plastic block of
:class:`~pdamper.models.plastic.PlasticBedDamper` integrated with the structure event by
event (:class:`~pdamper.analysis.plastic_bed.PlasticBedSystem`).

The structure (a 1-DOF of Eq. 23, or N mass-normalised modes, the beam's included) carries
the block at its damper point; between events (take-off, impact, release from the lid) the
equations are linear and are stepped exactly for inputs linear between samples
(first-order hold); each event is located inside its step and a plastic impact exchanges
momentum with the structure. There is no loss factor and no per-cycle update: the damper
force follows the container's motion itself, whatever it is (a beating decay of several
modes, a shock, a random record).

Coordinates: the modal coordinates ``q`` (the 1-DOF's x) from the static equilibrium with
the bed resting on the floor (the release ``x0`` and the reported displacements are from
there, as for the other couplings), the load from rest at that equilibrium.

Step: the output interval ``1 / sample_rate``, split into whole parts so that the fastest
mode gets at least :data:`STEPS_PER_PERIOD` steps a period and a load record is resolved at
its own sample interval (the events are located on a cubic Hermite of the container's path
inside the step).

Energy (a force, or a release): the input work ``int F (b_F . q') dt``, the structure's
damping ``int q'^T C q' dt``, the impacts' losses (exact, the sum over impacts), and the
change of the stored energy ``q'^T M q' / 2 + q^T K q / 2 + m_bed V^2 / 2 + m_bed g (Y -
x_c)`` (the block's kinetic energy and its height over the floor: the potential from the
equilibrium) close to the integration's accuracy.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from pdamper.errors import InputError, check_range

#: Least integration steps per period of the fastest mode.
STEPS_PER_PERIOD = 40


@dataclass(frozen=True)
class PlasticCouplingRun:
    """What the plastic-bed coupling computed (a result's ``details``).

    Attributes
    ----------
    modal
        Modal coordinates q at the output samples, shape (N, samples) (a 1-DOF: its x).
    damper_displacement
        The container's displacement ``phi_d . q`` (plus the base's) [m] at the samples.
    bed
        The :class:`~pdamper.analysis.plastic_bed.PlasticBedRun` on the integration grid.
    integration_step
        The step [s].
    """

    modal: np.ndarray = field(repr=False)
    damper_displacement: np.ndarray = field(repr=False)
    bed: Any = field(repr=False)
    integration_step: float


def _system(model, structure):
    """The structure's matrices (:class:`pdamper.coupling.loads._System`) and the block's
    :class:`~pdamper.analysis.plastic_bed.PlasticBedSystem` on them."""
    from pdamper.analysis.plastic_bed import PlasticBedSystem
    from pdamper.coupling.loads import _System

    sys_ = _System.of(structure)
    bed = PlasticBedSystem(sys_.mass, sys_.damping, sys_.stiffness, sys_.phi,
                           sys_.load_shape, sys_.base_shape, model.bed_mass,
                           model.damper.clearance, model.gravity)
    return sys_, bed


def _fastest(sys_) -> float:
    """The fastest undamped frequency of the structure with the bed attached [Hz]."""
    import scipy.linalg

    w2 = scipy.linalg.eigvalsh(sys_.stiffness, sys_.mass)
    return float(math.sqrt(max(float(np.max(w2)), 0.0)) / (2.0 * math.pi))


def _split(h_out: float, f_max: float, finest: float = math.inf) -> int:
    """Whole parts of the output interval that resolve the fastest mode and the record."""
    need = min(1.0 / (STEPS_PER_PERIOD * f_max), finest)
    return max(1, math.ceil(h_out / need * (1.0 - 1e-9)))


def _energy(sys_, bed, run, x_c: np.ndarray) -> np.ndarray:
    """Stored energy at each sample [J] from the equilibrium (module docstring)."""
    q, qd = run.q, run.qdot
    e = 0.5 * np.einsum("it,ij,jt->t", qd, sys_.mass, qd)
    e += 0.5 * np.einsum("it,ij,jt->t", q, sys_.stiffness, q)
    e += 0.5 * bed.m * run.bed_velocity ** 2 + bed.m * bed.g * (run.bed_position - x_c)
    return e


class PlasticBedCoupling:
    """The ``"plastic_bed"`` strategy: the block on the structure, for a release
    (:meth:`free_vibration`) and a load history (:meth:`load`)."""

    name = "plastic_bed"

    @staticmethod
    def free_vibration(model, structure, duration: float, initial_displacement: float,
                       sample_rate: float = 2000.0):
        """Free vibration of ``structure`` (1-DOF or N modes) carrying the block, released
        from rest with the release point at ``initial_displacement`` [m] from the static
        equilibrium; a :class:`~pdamper.coupling.results.FreeVibrationResult` of the output
        point (``details``: a :class:`PlasticCouplingRun`; ``inputs``: the impacts, the
        energy they dissipated and the energy balance's error)."""
        from pdamper import resources
        from pdamper.coupling.decrement import negative_peaks
        from pdamper.coupling.measurement import lobe_minima
        from pdamper.coupling.results import FreeVibrationResult
        from pdamper.structure.modal import ModalStructure

        check_range("simulation.duration", duration, low=0.0, low_inclusive=False, unit="s")
        check_range("simulation.sample_rate", sample_rate, low=0.0, low_inclusive=False,
                    unit="Hz")
        if not initial_displacement < 0:
            raise InputError("structure.initial_displacement", "must be < 0 m (released "
                             f"from a minimum), got {initial_displacement:g} m")
        sys_, bed = _system(model, structure)
        n = sys_.phi.size
        if isinstance(sys_.structure, ModalStructure):
            q0 = sys_.structure.release_state(initial_displacement)
            if not sys_.phi @ q0 < 0:
                raise InputError("structure.damper_position", "the damper point must be "
                                 "deflected downwards by the release (it is at or beyond a "
                                 "node of the release shape)")
        else:
            q0 = np.array([initial_displacement])
        f_max = _fastest(sys_)
        sub = _split(1.0 / sample_rate, f_max)
        h = 1.0 / sample_rate / sub
        steps = math.ceil(duration / h * (1.0 - 1e-12))
        resources.require(type(model).free_vibration_cost(
            model.damper, steps * h, 1.0 / h, structure.natural_frequency,
            drivers=(("simulation.duration", duration * structure.natural_frequency),
                     ("simulation.sample_rate", sample_rate / structure.natural_frequency))),
            force=True)
        u = np.zeros((steps + 1, 3))
        u[:, 2] = 1.0
        zero = np.zeros(steps + 1)
        run = bed.run(h, u, zero, zero, q0=q0)
        x_c = sys_.phi @ run.q
        e = _energy(sys_, bed, run, x_c)
        w_struct = float(np.trapezoid(np.einsum("it,ij,jt->t", run.qdot, sys_.damping,
                                                run.qdot), run.time))
        balance = float((e[0] - e[-1] - w_struct - run.dissipated_energy) / e[0]) \
            if e[0] > 0 else math.nan
        keep = slice(None, None, sub)
        t, q = run.time[keep], run.q[:, keep]
        x_out = sys_.out @ q
        x0_out = float(sys_.out @ q0)
        if isinstance(sys_.structure, ModalStructure) and not sys_.structure.coincident:
            tp, ap = lobe_minima(t, x_out, band=1e-9 * abs(x0_out))
        else:
            tp, ap = negative_peaks(t, x_out)
        keep_p = tp > 0.5 / structure.natural_frequency  # the release is the first peak
        return FreeVibrationResult(
            time=t, displacement=x_out, peak_times=np.concatenate([[0.0], tp[keep_p]]),
            peak_amplitudes=np.concatenate([[abs(x0_out)], ap[keep_p]]), cycles=(),
            model=model.fidelity,
            inputs={"duration": duration, "initial_displacement": initial_displacement,
                    "sample_rate": sample_rate, "modes": n, "integration_step": h,
                    "impacts": int(run.impact_times.size),
                    "dissipated_energy": run.dissipated_energy,
                    "structural_dissipation": w_struct,
                    "energy_balance_error": balance},
            details=PlasticCouplingRun(q, x_c[keep], run, h))

    @staticmethod
    def load_cost(model, structure, load, sample_rate: float = 2000.0, tail: float = 0.0):
        """What :meth:`load` costs: one integration step of about
        :data:`~pdamper.models.plastic.SECONDS_PER_STEP` per step of its grid."""
        from pdamper import resources
        from pdamper.coupling.loads import _time_grid
        from pdamper.models.plastic import BYTES_PER_SAMPLE, SECONDS_PER_STEP

        sys_, _ = _system(model, structure)
        _, h, _, steps = _time_grid(load, tail, sample_rate, sys_.phi.size)
        steps *= _split(h, _fastest(sys_))
        field = "load" if load.kind == "force" else "base_acceleration"
        f_n = structure.natural_frequency
        duration = load.duration + tail
        return resources.Cost("the plastic bed under the load", steps * SECONDS_PER_STEP,
                              steps * BYTES_PER_SAMPLE, f"{steps:.3g} steps",
                              ((field, duration * f_n),
                               ("simulation.sample_rate", sample_rate / f_n)))

    @staticmethod
    def load(model, structure, load, sample_rate: float = 2000.0, tail: float = 0.0):
        """Response of ``structure`` carrying the block to ``load`` (a
        :class:`~pdamper.coupling.loads.LoadHistory`: a force at the load point or a base
        acceleration) from rest at the equilibrium, over the record plus ``tail`` [s]; a
        :class:`~pdamper.coupling.loads.LoadResponse` whose ``dissipated_energy`` is the
        impacts' losses and whose energy terms (a force) close with them."""
        from pdamper.coupling.loads import LoadHistory, LoadResponse, _inputs, _time_grid

        check_range("simulation.sample_rate", sample_rate, low=0.0, low_inclusive=False,
                    unit="Hz")
        check_range("load.tail", tail, low=0.0, unit="s")
        if not isinstance(load, LoadHistory):
            raise InputError("load", f"must be a LoadHistory, got {type(load).__name__}")
        from pdamper import resources

        # what no run can do (more memory than the machine has), as the pseudo force
        resources.require(PlasticBedCoupling.load_cost(model, structure, load, sample_rate,
                                                       tail), force=True)
        sys_, bed = _system(model, structure)
        kind = load.kind
        if kind == "base_acceleration" and sys_.base_shape is None:
            raise InputError("base_acceleration", "base motion needs each mode's "
                             "participation factor, which a modes file does not give: use "
                             "one mode, the 1-DOF or [structure] beam, or a force (--load) "
                             "at the load point")
        n = sys_.phi.size
        t, h, sub, steps = _time_grid(load, tail, sample_rate, n)
        extra = _split(h, _fastest(sys_))
        if extra > 1:  # the fastest mode needs a finer step than the record's
            sub *= extra
            h /= extra
            steps = math.ceil((load.duration + tail) / h * (1.0 - 1e-12))
            t = np.arange(steps + 1) * h
        u, lv, v_b, y_b = _inputs(load, t)
        u[:, 2] = 1.0  # PlasticBedSystem's inputs: (F, a_b, 1)
        run = bed.run(h, u, v_b, y_b)
        q, qd, qdd = run.q, run.qdot, run.qddot
        x_c = sys_.phi @ q + y_b
        a_out = sys_.out @ qdd + (u[:, 1] if kind != "force" else 0.0)
        if kind == "force":
            w_in = float(np.trapezoid(lv * (sys_.load_shape @ qd), t))
            w_struct = float(np.trapezoid(np.einsum("it,ij,jt->t", qd, sys_.damping, qd), t))
            e = _energy(sys_, bed, run, x_c)
            e_change = float(e[-1] - e[0])
        else:
            w_in = w_struct = e_change = math.nan
        keep = slice(None, None, sub)
        return LoadResponse(
            time=t[keep], displacement=(sys_.out @ q)[keep], acceleration=a_out[keep],
            load=lv[keep], damper_displacement=x_c[keep],
            dissipated_energy=run.dissipated_energy, input_work=w_in,
            structural_dissipation=w_struct, energy_change=e_change, cycles=(),
            model=model.fidelity, kind=kind,
            inputs={"load": load.source, "load_kind": kind, "record_duration": load.duration,
                    "tail": tail, "sample_rate": sample_rate, "integration_step": h,
                    "interpolation": "linear", "steps": steps,
                    "impacts": int(run.impact_times.size)},
            details=PlasticCouplingRun(q[:, keep], x_c[keep], run, h))


# ----------------------------------------------------------------------------- stepped sine
#: Least integration steps per load cycle of the stepped sine (the first harmonic of each
#: cycle and the events inside it; more where the fastest mode needs
#: :data:`STEPS_PER_PERIOD`).
FRF_STEPS_PER_CYCLE = 64
#: Most load cycles per frequency of the stepped sine.
FRF_MAX_CYCLES = 600
#: Load cycles integrated per call between two judgements of the stationarity.
FRF_CHUNK_CYCLES = 8
#: Relative tolerance of the per-cycle stroke over the judged window (1 %).
FRF_RTOL = 0.01


def frf_criterion(structure, frequency: float):
    """The stationarity criterion of one step at ``frequency`` [Hz]: three windows that
    together span at least the slowest mode's decay time ``1 / (zeta w)`` (the beat of
    free and forced motion of a lightly damped structure is slower than a few cycles), the
    per-cycle strokes within :data:`FRF_RTOL` of the last."""
    from pdamper.analysis.stationarity import SteadyStateCriterion
    from pdamper.coupling.frf import _modal

    s = _modal(structure)
    w = s.angular_frequencies
    tau = float(np.max(1.0 / (s.damping_ratios * w)))
    window = max(3, math.ceil(frequency * tau / 3.0))
    return SteadyStateCriterion(rtol=FRF_RTOL, atol=FRF_RTOL, quiet_window_cycles=0,
                                window_cycles=window, skip_cycles=2)


def stepped_sine(model, structure, load, frequency, direction: str, *, criterion=None,
                 max_cycles: int = FRF_MAX_CYCLES, progress=None, **_):
    """Stepped sine of the plastic block on ``structure`` (1-DOF or N modes) under the
    harmonic ``load`` (:class:`~pdamper.coupling.frf.HarmonicLoad`) at ``frequency``
    [Hz] in ``direction`` ``"up"`` or ``"down"``: the block integrated event by event
    (:class:`~pdamper.analysis.plastic_bed.PlasticBedSystem`), each step starting where the
    previous one ended (structure, block and the load's phase), run in whole load cycles
    until the damper point's per-cycle first-harmonic amplitude is steady
    (:func:`frf_criterion`, or ``criterion``) or ``max_cycles`` have run. Results in
    ascending frequency order (a :class:`~pdamper.coupling.frf.FRFCurve`):

    - ``amplitude``, ``phase``, ``stroke``: first harmonics over the last judged cycles
      (at least one) of the output point and the damper point against the load;
    - ``loss_factor``: the impacts' losses per cycle over ``2 pi (1/2 m_bed (W X)^2)``
      (Eq. 3); ``effective_mass``: ``m_bed |Y*| / |X*|`` from the block's first harmonic
      (Eq. 4 with the block's momentum balance, ``F* = -W^2 m_bed Y*``);
    - ``mode``: the block's orbit over the step's last cycles (:func:`_orbit_mode`);
    - ``diagnostics["distortion"]``: the RMS of the damper point's motion less its first
      harmonic over those cycles, relative to the first harmonic's RMS [-] (0 for a
      harmonic motion; the impacts' harmonics and subharmonics raise it).

    A base motion acts as its equivalent force at the damper point (as the other stepped
    sines, :func:`~pdamper.coupling.frf.load_force`). ``progress(frequency, info)`` after
    each step.
    """
    from pdamper.analysis.plastic_bed import PlasticBedSystem
    from pdamper.coupling.frf import (
        SCATTER_WINDOWS,
        FRFCurve,
        _modal,
        _scatter,
        _sweep_order,
        load_force,
        steady_amplitudes,
    )

    check_range("max_cycles", max_cycles, low=1, unit="")
    s = _modal(structure)
    n = s.modes
    w = s.angular_frequencies
    phi, psi = s.damper_shape, s.output_shape
    at = s.load_shape if load.at_load_point else phi
    bed = PlasticBedSystem(np.eye(n), np.diag(2.0 * s.damping_ratios * w), np.diag(w * w),
                           phi, at, None, model.bed_mass, model.damper.clearance,
                           model.gravity)
    f_max = float(np.max(w)) / (2.0 * math.pi)
    freqs = np.atleast_1d(np.asarray(frequency, float))
    out = {k: np.full(freqs.size, np.nan) for k in ("amplitude", "phase", "stroke",
                                                    "loss_factor", "effective_mass",
                                                    "distortion")}
    steady = np.zeros(freqs.size, bool)
    cycles = np.zeros(freqs.size, int)
    spread = (np.full(freqs.size, np.nan), np.full(freqs.size, np.nan))
    walls = np.zeros(freqs.size)
    mode = np.full(freqs.size, -1)
    start = None
    import time

    for i in _sweep_order(freqs, direction):
        t_wall = time.perf_counter()
        f = float(freqs[i])
        om = 2.0 * math.pi * f
        force = load_force(s, load, f)
        crit = criterion or frf_criterion(s, f)
        spc = max(FRF_STEPS_PER_CYCLE, math.ceil(STEPS_PER_PERIOD * f_max / f))
        h = 1.0 / (f * spc)
        per: list[tuple] = []  # per cycle: (x_d*, x_o*, Y*, loss, rms of x_d - its harmonic)
        ok = False
        while len(per) < max_cycles:
            k = min(FRF_CHUNK_CYCLES, max_cycles - len(per))
            t = np.arange(k * spc + 1) * h
            u = np.zeros((t.size, 3))
            u[:, 0] = (force * np.exp(1j * om * t)).real  # whole cycles: the phase runs on
            u[:, 2] = 1.0
            zero = np.zeros(t.size)
            run = bed.run(h, u, zero, zero, start=start)
            start = run.end
            per += _cycle_harmonics(run, t, phi @ run.q, psi @ run.q, f, k, spc)
            if steady_amplitudes([abs(p[0]) for p in per], crit):
                ok = True
                break
        cycles[i], steady[i] = len(per), ok
        tail = per[-(crit.span if ok else min(len(per), 3)):]
        for key, value in _step_values(tail, om, model.bed_mass).items():
            out[key][i] = value
        spread[0][i], spread[1][i] = _scatter([abs(p[1]) for p in per[-SCATTER_WINDOWS:]])
        mode[i] = _orbit_mode([p[5] for p in per])
        walls[i] = time.perf_counter() - t_wall
        if progress is not None:
            progress(f, {"cycles": len(per), "steady": ok, "wall_seconds": walls[i]})
    return FRFCurve(amplitude=out["amplitude"], phase=out["phase"], stroke=out["stroke"],
                    loss_factor=out["loss_factor"], effective_mass=out["effective_mass"],
                    mode=mode, steady=steady, cycles=cycles,
                    amplitude_mean=spread[0], amplitude_std=spread[1],
                    diagnostics={"wall_seconds": walls, "distortion": out["distortion"]})


def _cycle_harmonics(run, t: np.ndarray, x_d: np.ndarray, x_o: np.ndarray, f: float,
                     k: int, spc: int) -> list[tuple]:
    """Per load cycle of a stepped sine's chunk of ``k`` cycles (``spc`` steps each, times
    ``t`` [s] from the chunk's start, load at ``f`` [Hz]): the first harmonics [m] of the
    damper point ``x_d``, the output point ``x_o`` and the block (``2 f int x e^{-i W t}
    dt``), the impacts' losses [J], the RMS [m] of ``x_d`` less its mean and first harmonic,
    and the impacts ``(phase in cycles, wall)``."""
    om = 2.0 * math.pi * f
    rot = np.exp(-1j * om * t)
    per = []
    for c in range(k):
        sl = slice(c * spc, (c + 1) * spc + 1)
        tt = t[sl]
        hd = 2.0 * f * np.trapezoid(x_d[sl] * rot[sl], tt)
        ho = 2.0 * f * np.trapezoid(x_o[sl] * rot[sl], tt)
        hy = 2.0 * f * np.trapezoid(run.bed_position[sl] * rot[sl], tt)
        t0, t1 = tt[0], tt[-1]
        hit = (run.impact_times >= t0) & (run.impact_times < t1)
        mean = f * np.trapezoid(x_d[sl], tt)
        resid = x_d[sl] - mean - (hd * np.exp(1j * om * tt)).real
        dist = math.sqrt(f * np.trapezoid(resid ** 2, tt))
        hits = tuple(zip(((run.impact_times[hit] - t0) * f).tolist(),
                         run.impact_walls[hit].tolist(), strict=True))
        per.append((hd, ho, hy, float(np.sum(run.impact_losses[hit])), dist, hits))
    return per


def _step_values(tail: list[tuple], om: float, m_bed: float) -> dict[str, float]:
    """A stepped sine's results at one frequency (``om`` [rad/s]) from the per-cycle values
    of its last judged cycles (:func:`_cycle_harmonics`) and the bed mass ``m_bed`` [kg]:
    output amplitude [m] and phase [rad], stroke [m], loss factor (Eq. 3), effective mass
    [kg] (Eq. 4) and distortion [-] (:func:`stepped_sine`)."""
    hd = complex(np.mean([p[0] for p in tail]))
    ho = complex(np.mean([p[1] for p in tail]))
    hy = complex(np.mean([p[2] for p in tail]))
    loss = float(np.mean([p[3] for p in tail]))
    x = abs(hd)
    v = om * x
    return {"amplitude": abs(ho), "phase": float(np.angle(ho)), "stroke": x,
            "loss_factor": loss / (math.pi * m_bed * v * v) if m_bed > 0 and v > 0 else 0.0,
            "effective_mass": m_bed * abs(hy) / x if x > 0 else m_bed,
            "distortion": (float(np.mean([p[4] for p in tail])) / (x / math.sqrt(2.0))
                           if x > 0 else 0.0)}


def _orbit_mode(hits: list) -> int:
    """Motion-mode code (:func:`pdamper.models.plastic.motion_modes`) of the block from its
    impacts per load cycle (``(phase in cycles, wall)`` each) over a step: the period is
    the least k <= :data:`~pdamper.analysis.plastic_bed.MAX_PERIOD_CYCLES` whose last k
    cycles repeat the k before (the same walls, phases within 1e-3 cycle); 0 (scattering)
    without one; no impact in those cycles: solid-like."""
    from pdamper.analysis.plastic_bed import LID, MAX_PERIOD_CYCLES
    from pdamper.models.plastic import motion_modes

    period = 0
    for k in range(1, MAX_PERIOD_CYCLES + 1):
        if len(hits) < 2 * k:
            break
        a, b = hits[-k:], hits[-2 * k:-k]
        if all(len(x) == len(y) and all(wx == wy and abs(px - py) < 1e-3
                                        for (px, wx), (py, wy) in zip(x, y, strict=True))
               for x, y in zip(a, b, strict=True)):
            period = k
            break
    window = hits[-max(period, 1):] if period else hits[-min(len(hits), 8):]
    n = max(len(window), 1)
    impacts = sum(len(c) for c in window) / n
    lid = sum(1 for c in window for _p, w in c if w == LID) / n
    if impacts == 0:
        period = 1
    return int(motion_modes([period], [lid], [impacts])[0])
