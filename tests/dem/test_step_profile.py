"""The step profile of a DEM run (``DEMEngine.run(..., step_profile=True)``,
:meth:`DEMResult.step_profile`): per-sample counts that add up to the run's own, the same
run to the bit, and steps that follow the contacts (a free parabola needs only the steps
its bounds impose, an impact many more)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from dem_inputs import engine, lattice, random
from pdamper.dem import HarmonicMotion, StructureMotion
from pdamper.errors import InputError

SERIES = ("time", "force", "kinetic_energy", "elastic_energy", "dissipated_normal",
          "dissipated_friction", "container_work", "snapshot_positions")


@pytest.mark.parametrize("integrator", ["gear", "verlet", "auto"])
def test_profile_adds_up_and_changes_no_bit(integrator):
    """One kernel call per sample gives the bits of the default chunks, and the
    per-sample steps, rejected steps and sphere-steps add up to the run's totals."""
    def run(profile):
        # "auto" hands over at its first judgement (a run that switches both ways)
        kw = {"auto_cost_ratio": math.inf} if integrator == "auto" else {}
        return engine(random(24, seed=3), motion=HarmonicMotion(0.02, 15.0),
                      integrator=integrator, settle_time=0.05, **kw).run(
            0.02 if integrator == "verlet" else 0.08, sample_rate=1500.0,
            step_profile=profile)

    plain, prof = run(False), run(True)
    for name in SERIES:
        assert np.array_equal(getattr(plain, name), getattr(prof, name)), name
    assert plain.steps == prof.steps > 100 and plain.steps_per_sample is None
    assert prof.steps_per_sample.shape == prof.time.shape and prof.steps_per_sample[0] == 0
    assert prof.steps_per_sample.sum() == prof.steps
    assert prof.rejected_per_sample.sum() == prof.rejected_steps
    n = len(prof.radius)
    gear_steps = prof.steps - (prof.steps if integrator == "verlet" else 0)
    if integrator == "auto":
        assert prof.verlet_time > 0  # the hand-over happened
    if integrator == "gear":
        # Gear's own count: stepped_fraction = sphere-steps / (n x Gear steps)
        assert prof.stepped_per_sample.sum() == pytest.approx(
            prof.stepped_fraction * n * gear_steps, rel=1e-12)
    if integrator == "verlet":
        assert np.array_equal(prof.stepped_per_sample, n * prof.steps_per_sample)
    assert np.all(prof.stepped_per_sample <= n * prof.steps_per_sample)
    assert np.all(prof.kernel_seconds_per_sample[1:] > 0)


def test_a_free_parabola_takes_only_the_bounded_steps_and_an_impact_many():
    """A sphere bouncing on a shaken floor (Gear): between two samples of free flight the
    step is Gear's largest (``max_step``, landing on every half sample: exactly
    2 ceil(half / max_step) steps), while the intervals that hold a Hertz impact take
    several times more (the step follows the contact time)."""
    sim = engine(lattice(1), motion=HarmonicMotion(0.01, 10.0), integrator="gear",
                 settle_time=0.05)
    res = sim.run(0.3, sample_rate=2000.0, step_profile=True)
    gap = res.center_of_mass[:, 2] - res.container_position - res.radius[0]
    lid = sim.container.box[2] - res.radius[0]
    flying = (gap > 1e-3) & (gap < lid - 1e-3)
    free = flying[1:] & flying[:-1]          # both ends of the interval in flight
    hits = ~free
    steps = res.steps_per_sample[1:]
    half = 0.5 / 2000.0
    assert free.sum() > 500 and hits.sum() >= 3
    assert np.all(steps[free] == 2 * math.ceil(half / sim.max_step - 1e-9))
    assert steps[hits].mean() > 3 * steps[free].mean()
    # the impacts' share of the steps is far above their share of the time
    assert steps[hits].sum() / steps.sum() > 3 * hits.sum() / len(steps)


def test_step_profile_bins_the_window():
    """Bins over the phase: the steps of the binned window, once each; mean step = bin
    duration over its steps."""
    f = 15.0
    res = engine(random(24, seed=3), motion=HarmonicMotion(0.02, f), integrator="gear",
                 settle_time=0.05).run(4 / f, sample_rate=1500.0, step_profile=True)
    p = res.step_profile(10, skip_cycles=1)
    assert p.attrs["cycles"] == 3
    in_window = res.time > 1 / f + 1e-9
    assert p.attrs["steps"] == res.steps_per_sample[in_window].sum()
    steps = p["steps"].values * 3
    assert steps.sum() == p.attrs["steps"]
    np.testing.assert_allclose(p["mean_step"].values, 3 / (f * 10) / steps, rtol=1e-12)
    assert p["step_share"].sum() == pytest.approx(1.0)
    assert p["wall_share"].sum() == pytest.approx(1.0)
    # the container acceleration of z = X sin(2 pi f t): -(2 pi f)^2 X sin at the bins
    a = -(2 * np.pi * f) ** 2 * 0.02 * np.sin(2 * np.pi * p["phase"].values)
    np.testing.assert_allclose(p["container_acceleration"].values, a, atol=0.05 * np.abs(a).max())


def test_step_profile_needs_a_profiled_run():
    res = engine(lattice(4), motion=HarmonicMotion(0.01, 10.0), settle_time=0.02).run(
        0.1, sample_rate=1000.0)
    with pytest.raises(InputError, match="step_profile"):
        res.step_profile()
    prof = engine(lattice(4), motion=HarmonicMotion(0.01, 10.0), settle_time=0.02).run(
        0.1, sample_rate=1000.0, step_profile=True)
    with pytest.raises(InputError, match="bins"):
        prof.step_profile(0)
    with pytest.raises(InputError, match="skip_cycles"):
        prof.step_profile(skip_cycles=1)  # a run of one cycle
    free = engine(lattice(4), motion=StructureMotion(1.0, 0.1, 100.0), settle_time=0.02).run(
        0.05, sample_rate=1000.0, step_profile=True)
    assert free.steps_per_sample.sum() == free.steps
    with pytest.raises(InputError, match="harmonic"):
        free.step_profile()
