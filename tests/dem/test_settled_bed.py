"""Settled beds (:class:`pdamper.dem.SettledBed`): the settling under gravity does not depend
on the excitation, so one settled bed serves every frequency and amplitude of a map. A run
started from a bed must be the run that settles by itself, to the last bit."""

from __future__ import annotations

import pickle

import numpy as np
import pytest

from dem_inputs import engine, random
from pdamper.dem import HarmonicMotion, SettledBed
from pdamper.errors import InputError
from pdamper.models import DEMDamper
from pdamper.parameters import PAPER_DAMPER

SERIES = ("time", "force", "kinetic_energy", "center_of_mass", "dissipated_normal",
          "dissipated_friction", "container_work", "snapshot_positions",
          "snapshot_velocities")


def shaken(frequency, amplitude, integrator="gear", **kw):
    return engine(random(32), motion=HarmonicMotion(amplitude, frequency),
                  integrator=integrator, **kw)


@pytest.mark.parametrize("integrator", ["gear", "verlet"])
def test_a_bed_settled_under_another_motion_gives_the_same_run(integrator):
    """The bed of a 5 Hz / 100 mm engine, excited at 10 Hz / 30 mm: every series and counter
    equals that of the 10 Hz / 30 mm engine settling by itself (bit for bit)."""
    bed = shaken(5.0, 0.1, integrator).settle()
    assert isinstance(bed, SettledBed) and bed.steps > 0
    own = shaken(10.0, 0.03, integrator).run(0.1, sample_rate=4000.0)
    reused = shaken(10.0, 0.03, integrator).run(0.1, sample_rate=4000.0, start=bed)
    for name in SERIES:
        np.testing.assert_array_equal(getattr(reused, name), getattr(own, name), err_msg=name)
    assert (reused.steps, reused.contact_onsets) == (own.steps, own.contact_onsets)
    assert own.settle_steps == bed.steps and not own.settle_reused
    assert reused.settle_reused and reused.settle_steps == 0 and reused.settle_seconds == 0.0


@pytest.mark.parametrize("change", [{"safety": 0.01}, {"gear_tolerance": 1e-6},
                                    {"settle_time": 0.1}, {"integrator": "verlet"}])
def test_a_bed_of_other_settings_is_refused(change):
    """Step settings, settling time or integrator change the settled bed: refused, naming
    the field."""
    bed = shaken(10.0, 0.03).settle()
    kw = {"integrator": "gear", **change}
    integrator = kw.pop("integrator")
    with pytest.raises(InputError, match="^start: the bed was settled"):
        shaken(10.0, 0.03, integrator, **kw).run(0.01, start=bed)


def test_a_bed_of_other_particles_is_refused():
    bed = shaken(10.0, 0.03).settle()
    other = engine(random(32, seed=1), motion=HarmonicMotion(0.03, 10.0), integrator="gear")
    with pytest.raises(InputError, match="^start:"):
        other.run(0.01, start=bed)
    with pytest.raises(InputError, match="^start: must be a SettledBed"):
        other.run(0.01, start=bed.state)


def test_the_dem_model_settles_once_per_process_and_its_key_does_not_change():
    """DEMDamper settles once for all its points, also across copies of the model (a map's
    workers receive a fresh unpickled model with every point): the second point, run by an
    unpickled copy, reuses the bed and gives the values of a model that settles for that
    point alone; the model's pickle (the key of a map's points) does not change."""
    from pdamper.models import dem as D

    D._BEDS.clear()
    model = DEMDamper(PAPER_DAMPER, packing="random", cycles=3, skip_cycles=1)
    before = pickle.dumps(model, protocol=4)
    first = model.steady_run(10.0, 0.03)
    copy = pickle.loads(before)
    second = copy.steady_run(14.0, 0.05)
    assert len(D._BEDS) == 1
    assert first.result.settle_reused and second.result.settle_reused
    assert pickle.dumps(model, protocol=4) == before
    D._BEDS.clear()
    alone = DEMDamper(PAPER_DAMPER, packing="random", cycles=3, skip_cycles=1).steady_run(
        14.0, 0.05)
    assert second.power.loss_factor == alone.power.loss_factor
    assert second.power.effective_mass_ratio == alone.power.effective_mass_ratio
    assert second.result.steps == alone.result.steps


def test_a_moved_bed_starts_where_it_was_moved_to():
    """``SettledBed.moved``: a copy under the same key with every sphere moved; a zero move
    gives the run of the bed itself (bit for bit), a move shifts the start's positions by
    it and leaves the bed it came from as it was."""
    eng = shaken(10.0, 0.03)
    bed = eng.settle()
    start = bed.state.pos.copy()
    plain = eng.run(0.05, sample_rate=4000.0, snapshot_rate=4000.0, start=bed)
    same = eng.run(0.05, sample_rate=4000.0, snapshot_rate=4000.0,
                   start=bed.moved(np.zeros_like(start)))
    for name in SERIES:
        np.testing.assert_array_equal(getattr(same, name), getattr(plain, name), err_msg=name)
    move = np.random.default_rng(0).uniform(-1e-9, 1e-9, start.shape)
    moved = bed.moved(move)
    assert moved.key == bed.key and moved.steps == bed.steps
    np.testing.assert_array_equal(bed.state.pos, start)
    res = eng.run(0.05, sample_rate=4000.0, snapshot_rate=4000.0, start=moved)
    np.testing.assert_allclose(res.snapshot_positions[0], start + move, rtol=0, atol=1e-15)
    with pytest.raises(ValueError, match="shape"):
        bed.moved(np.zeros(3))
