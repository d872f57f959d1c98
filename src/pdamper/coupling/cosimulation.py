"""Co-simulation of the DEM damper and a structure (the paper's model 1, Sect. 4.1), of
one DOF or of N modes.

The container is the end-effector of ``M x'' + D x' + K x = F``: the structure is integrated
together with the particles by the DEM's own integrator (no pseudo force, no per-cycle
update), ``F`` being the force that the particles exert on the container.

On N mass-normalised modes (:class:`~pdamper.structure.modal.ModalStructure`, a beam's or
a modes file's) the container moves with the modal sum at the damper's point,
``z_c = phi_d . q``, and the particles' force is projected on every mode,

    q_j'' + 2 zeta_j w_j q_j' + w_j^2 q_j = phi_d,j F + phi_L,j F_load(t) - Gamma_j a_b(t),

each mode integrated by the DEM's integrator with its own Nordsieck vector and its error in
the step control (:mod:`pdamper.dem.kernels.modes`). The bed's weight deflects the
structure to ``q_eq = -phi_d m_bed g / w^2``; a release from ``x0`` at the release point is
the static state under the bed's weight and a point load there that brings that point to
``x0`` (one coincident mode: the 1-DOF's release, exactly), and amplitudes are measured
from ``q_eq``. A one-mode structure whose points coincide runs as its 1-DOF (Eq. 23).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from pdamper import resources
from pdamper.coupling.decrement import negative_peaks
from pdamper.coupling.results import FreeVibrationResult
from pdamper.errors import InputError, check_range


@dataclass(frozen=True)
class ModalCoSimulation:
    """What the co-simulation on N modes computed (a result's ``details``).

    Attributes
    ----------
    modal
        Modal coordinates from the static equilibrium with the bed, ``q - q_eq``, at the
        sample times, shape (N, samples) [m sqrt(kg)] (relative to the base under base
        motion).
    static_equilibrium
        ``q_eq`` [m sqrt(kg)].
    frequencies
        The structure's eigenfrequencies [Hz].
    dem
        The DEM run (:class:`~pdamper.dem.result.ModalDEMResult`); its other attributes
        are this object's too (``details.energy_balance_error()``, ...).
    """

    modal: np.ndarray = field(repr=False)
    static_equilibrium: np.ndarray
    frequencies: np.ndarray
    dem: Any = field(repr=False)

    def __getattr__(self, name: str):
        # only what the dataclass lacks; never during (un)pickling, before "dem" is set
        dem = self.__dict__.get("dem")
        if name.startswith("__") or dem is None:
            raise AttributeError(name)
        return getattr(dem, name)


def _runs_as_single_dof(structure) -> bool:
    """Whether ``structure`` is a 1-DOF, or one mode whose points coincide (Eq. 23)."""
    from pdamper.structure.modal import ModalStructure

    return not isinstance(structure, ModalStructure) or (structure.modes == 1
                                                         and structure.coincident)


def _bed_equilibrium(model, structure) -> np.ndarray:
    """``q_eq = -phi_d m_bed g / w^2``: the bed's weight at the damper point [m sqrt(kg)]."""
    w = structure.angular_frequencies
    return -structure.damper_shape * model.bed_mass * model.gravity / (w * w)


def _modal_speed(structure, dq: np.ndarray) -> float:
    """Largest speed of the damper point in a free vibration from the modal deflection
    ``dq`` at rest, ``sum_j |phi_d,j dq_j| w_j`` [m/s]."""
    return float(np.sum(np.abs(structure.damper_shape * dq) * structure.angular_frequencies))


def co_simulate_modes(model, structure, duration: float, initial_displacement: float,
                      sample_rate: float = 2000.0) -> FreeVibrationResult:
    """Free vibration of an N-mode ``structure`` (a
    :class:`~pdamper.structure.modal.ModalStructure`) with the particles of ``model`` (a
    :class:`~pdamper.models.DEMDamper`) integrated together (module docstring), released
    from rest with the release point at ``initial_displacement`` [m].

    The result reports the output point (absolute ``displacement``; negative peaks from
    its static equilibrium with the bed); ``details`` is a :class:`ModalCoSimulation`, so
    that :attr:`~pdamper.coupling.results.FreeVibrationResult.damping_per_mode` gives each
    mode's damping ratio from its own coordinate. A one-mode structure whose points
    coincide runs as its 1-DOF (:func:`co_simulate`).
    """
    from pdamper.coupling.measurement import lobe_minima
    from pdamper.dem import ModalStructureMotion

    if _runs_as_single_dof(structure):
        return co_simulate(model, single_dof(structure), duration, initial_displacement,
                           sample_rate)
    check_range("simulation.duration", duration, low=0.0, low_inclusive=False, unit="s")
    check_range("simulation.sample_rate", sample_rate, low=0.0, low_inclusive=False, unit="Hz")
    if not initial_displacement < 0:
        raise InputError("structure.initial_displacement",
                         f"must be < 0 m (released from a minimum), got {initial_displacement:g} m")
    q_eq = _bed_equilibrium(model, structure)
    psi = structure.release_shape
    dq = structure.release_state(initial_displacement - float(psi @ q_eq))
    if not structure.damper_shape @ dq < 0:
        raise InputError("structure.damper_position", "the damper point must be deflected "
                         "downwards by the release (it is at or beyond a node of the "
                         "release shape)")
    q0 = q_eq + dq
    f1 = structure.natural_frequency
    v0 = _modal_speed(structure, dq)
    resources.require(resources.dem_cost(
        model.damper, duration,
        resources.impact_speed(v0 / (2.0 * np.pi * f1), f1, model.damper.length),
        sample_rate=sample_rate, safety=model.safety,
        drivers=(("simulation.duration", duration * f1),
                 ("simulation.sample_rate", sample_rate / f1))),
        force=True)
    motion = ModalStructureMotion.of(structure, q0)
    engine = model.build_engine(motion)
    res = engine.run(duration, sample_rate=sample_rate)
    t = res.time
    q = res.modal_coordinates
    out = structure.output_shape
    x = out @ q
    x_eq = float(out @ q_eq)
    tp, ap = lobe_minima(t, x - x_eq, band=1e-9 * abs(initial_displacement))
    keep = tp > 0.5 / f1  # the release is the first peak
    peak_t = np.concatenate([[0.0], tp[keep]])
    peak_a = np.concatenate([[abs(float(out @ dq))], ap[keep]])
    return FreeVibrationResult(
        time=t, displacement=x, peak_times=peak_t, peak_amplitudes=peak_a,
        model=model.fidelity,
        inputs={"duration": duration, "initial_displacement": initial_displacement,
                "sample_rate": sample_rate, "integrator": model.integrator, "seed": model.seed,
                "steps": res.steps, "wall_seconds": res.wall_seconds, "modes": structure.modes,
                "positions": None if structure.positions is None
                else list(structure.positions),
                "static_equilibrium": x_eq, "energy_balance_error": res.energy_balance_error()},
        details=ModalCoSimulation(q - q_eq[:, None], q_eq, structure.frequencies.copy(), res))


def co_simulate(model, structure, duration: float, initial_displacement: float,
                sample_rate: float = 2000.0) -> FreeVibrationResult:
    """Structure and particles of ``model`` (a :class:`~pdamper.models.DEMDamper`)
    integrated together, released from rest at ``initial_displacement`` [m].

    The particles' weight shifts the static equilibrium by ``-m_bed g / K``; peak
    amplitudes are measured from that equilibrium. The DEM run is the result's ``details``.
    """
    from pdamper.dem import StructureMotion

    check_range("simulation.duration", duration, low=0.0, low_inclusive=False, unit="s")
    check_range("simulation.sample_rate", sample_rate, low=0.0, low_inclusive=False, unit="Hz")
    if not initial_displacement < 0:
        raise InputError("structure.initial_displacement",
                         f"must be < 0 m (released from a minimum), got {initial_displacement:g} m")
    # what no run can do; the edges hold runs to the lower limits unless forced
    f_n = structure.natural_frequency
    resources.require(resources.dem_cost(
        model.damper, duration,
        resources.impact_speed(abs(initial_displacement), f_n, model.damper.length),
        sample_rate=sample_rate, safety=model.safety,
        drivers=(("simulation.duration", duration * f_n),
                 ("simulation.sample_rate", sample_rate / f_n))),
        force=True)
    motion = StructureMotion(mass=structure.mass, damping=structure.damping,
                             stiffness=structure.stiffness, x0=initial_displacement)
    engine = model.build_engine(motion)
    res = engine.run(duration, sample_rate=sample_rate)
    x_eq = -model.bed_mass * engine.gravity / structure.stiffness
    t, x = res.time, res.container_position
    tp, ap = negative_peaks(t, x - x_eq)
    keep = tp > 0.5 / structure.natural_frequency  # the release is the first peak
    peak_t = np.concatenate([[0.0], tp[keep]])
    peak_a = np.concatenate([[abs(initial_displacement - x_eq)], ap[keep]])
    return FreeVibrationResult(
        time=t, displacement=x, peak_times=peak_t, peak_amplitudes=peak_a,
        model=model.fidelity,
        inputs={"duration": duration, "initial_displacement": initial_displacement,
                "sample_rate": sample_rate, "integrator": model.integrator, "seed": model.seed,
                "steps": res.steps, "wall_seconds": res.wall_seconds,
                "static_equilibrium": x_eq, "energy_balance_error": res.energy_balance_error()},
        details=res)


#: Finest step of the kernels' load table [s] (a coarser record is split into whole parts).
LOAD_TABLE_STEP = 1e-4
#: Most entries of the kernels' load table (each 24 bytes): a finer record is resampled.
MAX_LOAD_TABLE = 5_000_000


def single_dof(structure):
    """The structure that the co-simulation integrates: a
    :class:`~pdamper.structure.SingleDOFStructure`; a one-mode
    :class:`~pdamper.structure.modal.ModalStructure` with the damper at its output and
    release point as its 1-DOF (Eq. 23); any other ``ModalStructure`` as it is (the DEM
    runs on its N modes, :func:`co_simulate_modes`); anything else is an error naming
    ``structure``."""
    from pdamper.structure import SingleDOFStructure
    from pdamper.structure.modal import ModalStructure

    if isinstance(structure, ModalStructure):
        if structure.modes == 1 and structure.coincident:
            return structure.equivalent_single_dof()
        return structure
    if not isinstance(structure, SingleDOFStructure):
        raise InputError("structure", "the DEM co-simulation needs a SingleDOFStructure or a "
                         f"ModalStructure, got {type(structure).__name__}")
    return structure


def load_speed(model, structure, load, sample_rate: float, tail: float) -> float:
    """Fastest speed of the container relative to the base [m/s] that the cheapest model
    predicts under ``load`` (the analytical damper on the same structure): the speed that
    a DEM run of a load history is planned and judged at."""
    from pdamper.coupling.loads import simulate_load
    from pdamper.models import AnalyticalDamper

    try:
        est = simulate_load(AnalyticalDamper(model.damper), structure, load, sample_rate,
                            tail)
    except InputError as exc:  # the motion the load implies is beyond the models
        if exc.field.startswith(("simulation.", "load", "base_acceleration", "structure")):
            raise
        field = "load" if load.kind == "force" else "base_acceleration"
        raise InputError(field, "the motion it drives (the analytical model's estimate) is "
                         f"out of range: {exc.field}: {exc.message}") from None
    x = est.displacement
    if not _runs_as_single_dof(structure):  # N modes: the damper's point moves too
        x = np.vstack([x, est.damper_displacement])
    return float(np.max(np.abs(np.diff(x)) / np.diff(est.time)))


def load_cost(model, structure, load, sample_rate: float, tail: float):
    """What the co-simulation of ``load`` costs: the DEM free vibration
    (:meth:`~pdamper.models.DEMDamper.free_vibration_cost`) over the record plus ``tail``,
    at the release whose speed is :func:`load_speed` (its physics limits included);
    ``(cost, speed)``."""
    structure = single_dof(structure)
    duration = load.duration + tail
    f_n = structure.natural_frequency
    v = load_speed(model, structure, load, sample_rate, tail)
    x_rel = -max(v / (2.0 * np.pi * f_n), 1e-6)
    field = "load" if load.kind == "force" else "base_acceleration"
    try:
        cost = type(model).free_vibration_cost(
            model.damper, duration, sample_rate, f_n, model.settings, x0=x_rel,
            drivers=((field, duration * f_n), ("simulation.sample_rate", sample_rate / f_n)))
    except InputError as exc:  # the release stands in for the load: name the load
        if exc.field != "structure.initial_displacement":
            raise
        raise InputError(field, f"drives the container at up to {v:.3g} m/s (the analytical "
                         f"model's estimate), as a release from {x_rel:.3g} m would: "
                         + exc.message) from None
    return cost, v


def co_simulate_load(model, structure, load, sample_rate: float = 2000.0,
                     tail: float = 0.0):
    """Structure and particles of ``model`` (a :class:`~pdamper.models.DEMDamper`)
    integrated together under a load history (:class:`~pdamper.coupling.loads.LoadHistory`)
    over the record plus ``tail`` [s]; a :class:`~pdamper.coupling.loads.LoadResponse`.

    The record, linear between its samples and zero after the last, is resampled on its
    median interval split into whole parts down to :data:`LOAD_TABLE_STEP` (exact for a
    uniform record) into the kernels' table
    (:class:`~pdamper.dem.StructureMotion` ``force`` / ``base_acceleration``). A force acts
    on M; a base acceleration moves the base from rest, and the container's absolute
    motion, base included, is what the particles feel. The structure starts at rest at its
    static equilibrium with the bed resting on the floor, ``-m_bed g / K`` (relative to
    the base), after the bed has settled; the displacement is reported from there
    (relative to the base for base motion) and the acceleration absolute.
    Energies: the damper dissipates the DEM ledger's normal and friction dissipation; for
    a force, ``input_work = int F v dt``, ``structural_dissipation = int D v^2 dt`` and
    ``energy_change`` = the structure's kinetic and strain energy change plus the energy
    stored in the bed (the containers' work on it less its dissipation), so that
    :attr:`~pdamper.coupling.loads.LoadResponse.energy_balance_error` checks the structure
    against the DEM's ledger. The DEM run is the result's ``details``.
    """
    from pdamper.coupling.loads import LoadHistory, LoadResponse
    from pdamper.dem import StructureMotion

    check_range("simulation.sample_rate", sample_rate, low=0.0, low_inclusive=False, unit="Hz")
    check_range("load.tail", tail, low=0.0, unit="s")
    if not isinstance(load, LoadHistory):
        raise InputError("load", f"must be a LoadHistory, got {type(load).__name__}")
    structure = single_dof(structure)
    if not _runs_as_single_dof(structure):
        return _co_simulate_load_modes(model, structure, load, sample_rate, tail)
    duration = load.duration + tail
    cost, v_ref = load_cost(model, structure, load, sample_rate, tail)
    # what no run can do (the edges hold runs to the lower limits unless forced)
    resources.require(cost, force=True)
    # the record's interval, split in whole parts down to LOAD_TABLE_STEP (a uniform record
    # stays exact; the base position, interpolated linearly by the kernels, errs by
    # a_b h^2 / 8 at most)
    h = float(np.median(np.diff(load.time)))
    h /= max(1, int(np.ceil(h / LOAD_TABLE_STEP - 1e-9)))
    h = max(h, duration / MAX_LOAD_TABLE)
    grid = np.arange(int(np.ceil(duration / h)) + 2) * h
    table = (h, load.at(grid))
    gravity = model.gravity
    x_eq = -model.bed_mass * gravity / structure.stiffness
    motion = StructureMotion(
        mass=structure.mass, damping=structure.damping, stiffness=structure.stiffness,
        x0=x_eq, force=table if load.kind == "force" else None,
        base_acceleration=table if load.kind != "force" else None)
    th, zb, vb, _ = motion.load_tables(duration)
    v_base = float(np.max(np.abs(vb)))
    speed = np.sqrt(2.0 * gravity * model.damper.length) + 2.0 * (v_ref + v_base)
    engine = model.build_engine(motion, reference_velocity=float(speed))
    res = engine.run(duration, sample_rate=sample_rate)
    t = res.time
    z_b = np.interp(t, np.arange(zb.size) * th, zb)  # as the kernels interpolate it
    z, v = res.container_position, res.container_velocity
    y = z - z_b - x_eq
    lv = load.at(t)
    dissipated = float(res.dissipated_normal[-1] + res.dissipated_friction[-1])
    if load.kind == "force":
        w_in = float(np.trapezoid(lv * v, t))
        w_struct = float(np.trapezoid(structure.damping * v * v, t))
        k, m = structure.stiffness, structure.mass
        e_struct = 0.5 * m * v * v + 0.5 * k * z * z  # from the spring's rest
        stored = float(res.container_work[-1]) - dissipated
        e_change = float(e_struct[-1] - e_struct[0]) + stored
    else:
        w_in = w_struct = e_change = np.nan
    return LoadResponse(
        time=t, displacement=y, acceleration=res.container_acceleration, load=lv,
        damper_displacement=z - x_eq, dissipated_energy=dissipated, input_work=w_in,
        structural_dissipation=w_struct, energy_change=e_change, cycles=(),
        model=model.fidelity, kind=load.kind,
        inputs={"load": load.source, "load_kind": load.kind,
                "record_duration": load.duration, "tail": tail, "sample_rate": sample_rate,
                "load_table_step": h, "interpolation": "linear",
                "integrator": model.integrator, "seed": model.seed, "steps": res.steps,
                "wall_seconds": res.wall_seconds, "static_equilibrium": x_eq,
                "reference_velocity": float(speed),
                "dem_energy_balance_error": res.energy_balance_error()},
        details=res)


def _load_table(load, duration: float) -> tuple[float, tuple[float, np.ndarray]]:
    """The record resampled for the kernels (:func:`co_simulate_load`): ``(h, (h,
    values))``."""
    h = float(np.median(np.diff(load.time)))
    h /= max(1, int(np.ceil(h / LOAD_TABLE_STEP - 1e-9)))
    h = max(h, duration / MAX_LOAD_TABLE)
    grid = np.arange(int(np.ceil(duration / h)) + 2) * h
    return h, (h, load.at(grid))


def _co_simulate_load_modes(model, structure, load, sample_rate: float, tail: float):
    """:func:`co_simulate_load` on N modes: the force acts at the structure's load point
    (``load_shape``), a base acceleration on every mode through its participation factor
    (one mode without it: ``1 / phi_d``, all the mass at the damper point, as
    :func:`~pdamper.coupling.loads.simulate_load`);
    the structure starts at rest at its static equilibrium with the bed, ``q_eq``.
    Reported: the output point from that equilibrium (relative to the base under base
    motion), its absolute acceleration, the container's displacement from equilibrium
    (absolute), the energies as for one DOF with the modal kinetic and strain energy
    ``sum (q_j'^2 + w_j^2 q_j^2) / 2``, the input work ``int F phi_L . q' dt`` and the
    structural dissipation ``int sum 2 zeta_j w_j q_j'^2 dt``; ``details`` a
    :class:`ModalCoSimulation`."""
    from pdamper.coupling.loads import LoadResponse
    from pdamper.dem import ModalStructureMotion

    duration = load.duration + tail
    if load.kind != "force" and structure.participation is None and structure.modes > 1:
        raise InputError("base_acceleration", "base motion needs each mode's participation "
                         "factor, which a modes file does not give: use one mode, the 1-DOF "
                         "or [structure] beam, or a force (--load) at the load point")
    cost, v_ref = load_cost(model, structure, load, sample_rate, tail)
    resources.require(cost, force=True)
    h, table = _load_table(load, duration)
    gravity = model.gravity
    q_eq = _bed_equilibrium(model, structure)
    motion = ModalStructureMotion.of(
        structure, q_eq, force=table if load.kind == "force" else None,
        base_acceleration=table if load.kind != "force" else None)
    th, zb, vb, _, ab = motion.modal_tables(duration)
    v_base = float(np.max(np.abs(vb)))
    speed = np.sqrt(2.0 * gravity * model.damper.length) + 2.0 * (v_ref + v_base)
    engine = model.build_engine(motion, reference_velocity=float(speed))
    res = engine.run(duration, sample_rate=sample_rate)
    t = res.time
    tt = np.arange(zb.size) * th
    z_b = np.interp(t, tt, zb)  # as the kernels interpolate them
    a_b = np.interp(t, tt, ab)
    q, qd, qdd = res.modal_coordinates, res.modal_velocities, res.modal_accelerations
    dq = q - q_eq[:, None]
    out, phi = structure.output_shape, structure.damper_shape
    y = out @ dq
    lv = load.at(t)
    dissipated = float(res.dissipated_normal[-1] + res.dissipated_friction[-1])
    if load.kind == "force":
        w = structure.angular_frequencies
        c = 2.0 * structure.damping_ratios * w
        w_in = float(np.trapezoid(lv * (structure.load_shape @ qd), t))
        w_struct = float(np.trapezoid(c @ (qd * qd), t))
        e_struct = 0.5 * np.sum(qd * qd + (w * w)[:, None] * q * q, axis=0)  # from rest
        stored = float(res.container_work[-1]) - dissipated
        e_change = float(e_struct[-1] - e_struct[0]) + stored
    else:
        w_in = w_struct = e_change = np.nan
    return LoadResponse(
        time=t, displacement=y, acceleration=out @ qdd + a_b, load=lv,
        damper_displacement=phi @ dq + z_b, dissipated_energy=dissipated, input_work=w_in,
        structural_dissipation=w_struct, energy_change=e_change, cycles=(),
        model=model.fidelity, kind=load.kind,
        inputs={"load": load.source, "load_kind": load.kind,
                "record_duration": load.duration, "tail": tail, "sample_rate": sample_rate,
                "load_table_step": h, "interpolation": "linear", "modes": structure.modes,
                "integrator": model.integrator, "seed": model.seed, "steps": res.steps,
                "wall_seconds": res.wall_seconds, "static_equilibrium": float(out @ q_eq),
                "reference_velocity": float(speed),
                "dem_energy_balance_error": res.energy_balance_error()},
        details=ModalCoSimulation(dq, q_eq, structure.frequencies.copy(), res))
