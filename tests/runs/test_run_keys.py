"""One meaning per JSON key: ``wall_seconds`` and ``steps`` are a DEM run's whole work,
settling included, in ``pdamper dem --json`` (:meth:`pdamper.dem.DEMResult.summary`, the
run keys of :func:`pdamper.runs.realisations.run_summary`) and in a map's diagnostics
(:func:`pdamper.models.dem.point_diagnostics`); the excitation's part is
``excitation_wall_seconds``, ``excitation_steps``."""

from __future__ import annotations

import dataclasses

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
