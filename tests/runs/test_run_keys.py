"""One meaning per JSON key: ``wall_seconds`` and ``steps`` are a DEM run's whole work,
settling included, in ``pdamper dem --json`` (:meth:`pdamper.dem.DEMResult.summary`, the
run keys of :func:`pdamper.runs.realisations.run_summary`) and in a map's diagnostics
(:func:`pdamper.models.dem.point_diagnostics`); the excitation's part is
``excitation_wall_seconds``, ``excitation_steps``."""

from __future__ import annotations

import dataclasses
import math

from dem_inputs import engine, lattice
from pdamper.dem import HarmonicMotion
from pdamper.models import DEMDamper
from pdamper.models.dem import point_diagnostics
from pdamper.parameters import PAPER_DAMPER


def test_wall_seconds_and_steps_mean_the_same_in_the_dem_json_and_the_map():
    # a run that settles its own bed: the settling's part is not zero
    own = engine(lattice(16), motion=HarmonicMotion(0.01, 20.0), integrator="gear",
                 settle_time=0.03).run(0.05, sample_rate=2000.0)
    assert own.settle_steps > 0 and own.settle_seconds > 0
    # a map point's diagnostics of that run (the verdicts of a steady run of the damper)
    steady = DEMDamper(PAPER_DAMPER.with_count(16), cycles=3, skip_cycles=1,
                       integrator="gear").steady_run(20.0, 0.01)
    point = point_diagnostics(dataclasses.replace(steady, result=own))
    dem_json = own.summary()
    whole = {"wall_seconds": own.wall_seconds + own.settle_seconds,
             "steps": own.steps + own.settle_steps}
    for key, value in whole.items():
        assert dem_json[key] == point[key] == value, key
        assert dem_json[f"excitation_{key}"] == getattr(own, key)  # the excitation's part
        assert dem_json[f"total_{key}"] == value  # the older name of the sum
    assert point["excitation_steps"] == own.steps
    # the run's NetCDF attributes say the same
    attrs = own.to_dataset().attrs
    assert attrs["wall_seconds"] == whole["wall_seconds"] and attrs["steps"] == whole["steps"]
    assert attrs["excitation_wall_seconds"] == own.wall_seconds


def test_a_run_counts_the_settling_done_for_it_and_a_later_run_reuses_it():
    """``pdamper dem --json``'s run keys (:func:`run_summary`): the first run of a process
    from a bed counts its settling (steps, wall time, not reused), though the model settled
    it through its memo; a second run of the same process from that bed reused it and
    counts none. ``settling`` holds the same values in one place."""
    from pdamper.models import dem as D
    from pdamper.runs.realisations import run_summary

    D._BEDS.clear()
    D._COUNTED.clear()
    model = DEMDamper(PAPER_DAMPER.with_count(8), cycles=2, skip_cycles=1, integrator="verlet",
                      settle_time=0.03)
    first = run_summary(model, model.response(20.0, 0.01))
    second = run_summary(model, model.response(20.0, 0.01))
    assert not first["settle_reused"] and first["settle_steps"] > 0
    assert first["settle_seconds"] > 0
    assert first["steps"] == first["excitation_steps"] + first["settle_steps"]
    assert first["settling"] == {"steps": first["settle_steps"],
                                 "wall_seconds": first["settle_seconds"],
                                 "simulated_time": first["settle_simulated_time"],
                                 "reused": False, "stop": "time"}
    assert math.isclose(first["settling"]["simulated_time"], 0.03)
    assert second["settle_reused"] and second["settling"]["reused"]
    assert second["settle_steps"] == 0 and second["settle_seconds"] == 0.0
    assert second["steps"] == second["excitation_steps"] == first["excitation_steps"]
    # the bed time is the bed's, reused or not
    assert second["settling"]["simulated_time"] == first["settling"]["simulated_time"]
