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
    engine = model.engine(motion)
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
