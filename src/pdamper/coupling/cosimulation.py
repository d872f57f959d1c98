"""Co-simulation of the DEM damper and a 1-DOF structure (the paper's model 1, Sect. 4.1).

The container is the end-effector of ``M x'' + D x' + K x = F``: the structure is integrated
together with the particles by the DEM's own integrator (no pseudo force, no per-cycle
update), ``F`` being the force that the particles exert on the container.
"""

from __future__ import annotations

import numpy as np

from pdamper import resources
from pdamper.coupling.decrement import negative_peaks
from pdamper.coupling.results import FreeVibrationResult
from pdamper.errors import InputError, check_range


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
    """The 1-DOF that the co-simulation integrates: a
    :class:`~pdamper.structure.SingleDOFStructure`, or a one-mode
    :class:`~pdamper.structure.modal.ModalStructure` with the damper at its output and release
    point (Eq. 23); anything else is an error naming ``structure``."""
    from pdamper.structure import SingleDOFStructure
    from pdamper.structure.modal import ModalStructure

    if isinstance(structure, ModalStructure) and structure.modes == 1 \
            and structure.coincident:
        structure = structure.equivalent_single_dof()
    if not isinstance(structure, SingleDOFStructure):
        raise InputError("structure", "the DEM co-simulation needs a single-DOF structure (or "
                         "one mode with the damper at the output and release point); use a "
                         "pseudo-force model (analytic, fields) for N modes")
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
    return float(np.max(np.abs(np.diff(est.displacement)) / np.diff(est.time)))


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
