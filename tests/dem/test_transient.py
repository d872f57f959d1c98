"""The start from rest at its own Gear tolerance (``transient_cycles``,
``gear_transient_tolerance`` of :class:`pdamper.dem.DEMEngine`): the first cycles run at
the transient tolerance exactly as a run at that tolerance would, the rest at
``gear_tolerance``, and the switch, at a fixed landing, changes no bit however the run is
chunked."""

from __future__ import annotations

import math

import numpy as np
import pytest

from dem_inputs import engine, random
from pdamper.dem import HarmonicMotion
from pdamper.errors import InputError

F = 15.0
SERIES = ("time", "force", "center_of_mass", "kinetic_energy", "elastic_energy",
          "dissipated_normal", "dissipated_friction", "container_work", "steps",
          "rejected_steps", "max_overlap_ratio")


def assert_identical(a, b):
    for name in SERIES:
        assert np.array_equal(getattr(a, name), getattr(b, name)), name


def _run(cycles, chunk_seconds=math.inf, **kw):
    return engine(random(24, seed=3), motion=HarmonicMotion(0.02, F), integrator="gear",
                  settle_time=0.05, **kw).run(cycles / F, sample_rate=1500.0,
                                              chunk_seconds=chunk_seconds)


def test_first_cycle_runs_at_the_transient_tolerance():
    """A one-cycle transient at 1e-3 takes fewer steps over that cycle than Gear's 1e-5
    (a fifth-order step: ~2x the steps per decade of tolerance), and the first cycle of a
    longer run is, bit for bit, that one-cycle run: nothing after the transient reaches
    back into it."""
    short = _run(1, transient_cycles=1, gear_transient_tolerance=1e-3)
    plain = _run(1)
    assert short.steps < 0.8 * plain.steps
    long = _run(3, transient_cycles=1, gear_transient_tolerance=1e-3)
    k = short.time.size - 1  # (a run's last force window is half a window)
    for name in SERIES[:-3]:
        assert np.array_equal(getattr(long, name)[:k], getattr(short, name)[:k]), name
    eng = engine(random(4, seed=1), integrator="gear", transient_cycles=1,
                 gear_transient_tolerance=1e-3)
    assert eng.describe()["gear_transient_tolerance"] == 1e-3  # recorded with the run
    assert "transient_cycles" not in engine(random(4, seed=1), integrator="gear").describe()


def test_after_the_transient_the_run_is_held_to_gear_tolerance():
    """Three cycles: the steps lie between those of the run at 1e-3 throughout and of the
    run at 1e-5 throughout (a fifth-order step: ~2x the steps per decade of tolerance),
    and the chunks of two landings give the bits of one call."""
    mixed = _run(3, transient_cycles=1, gear_transient_tolerance=1e-3)
    loose = _run(3, gear_tolerance=1e-3)
    tight = _run(3)
    assert loose.steps < mixed.steps < tight.steps
    assert mixed.steps - loose.steps > 0.3 * (tight.steps - loose.steps)
    assert_identical(mixed, _run(3, chunk_seconds=1e-9, transient_cycles=1,
                                 gear_transient_tolerance=1e-3))


def test_no_transient_is_the_plain_run():
    """Zero transient cycles, or a transient tolerance equal to Gear's: the plain run."""
    plain = _run(2)
    assert_identical(plain, _run(2, transient_cycles=0, gear_transient_tolerance=1e-3))
    assert_identical(plain, _run(2, transient_cycles=1, gear_transient_tolerance=1e-5))


@pytest.mark.parametrize("field, value", [("transient_cycles", -1), ("transient_cycles", 1.5),
                                          ("gear_transient_tolerance", 0.0),
                                          ("gear_transient_tolerance", math.nan)])
def test_bad_transient_is_an_input_error(field, value):
    with pytest.raises(InputError) as err:
        engine(random(4, seed=1), **{field: value})
    assert err.value.field == field
