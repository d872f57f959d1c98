"""Level III experiments (pdamper.coupling.experiments) handed to one Simulation: a release,
a load history (a record or a run-up), a harmonic sweep; each against the closed form of the
structure without particles, and against the functions they replace; refusals before any
run; a new experiment and a new load type as one class each."""

import dataclasses
import math

import numpy as np
import pytest

from pdamper.coupling import (
    Experiment,
    HarmonicSweep,
    LoadHistory,
    Loading,
    Release,
    Simulation,
    run_load,
)
from pdamper.coupling.frf import FRFResult, HarmonicLoad, frequency_response
from pdamper.coupling.loads import LoadResponse, RunUp
from pdamper.coupling.registry import RELEASE
from pdamper.coupling.results import FreeVibrationResult
from pdamper.errors import InputError
from pdamper.models import AnalyticalDamper, DEMDamper, PlasticBedDamper
from pdamper.parameters import PAPER_DAMPER, PAPER_STRUCTURE
from pdamper.structure import SingleDOFStructure
from pdamper.structure.modal import ModalStructure

ZETA = 0.05
#: The paper's 1-DOF with 5 % damping (the start-up transient of a harmonic record is gone
#: within seconds).
STRUCTURE = SingleDOFStructure(
    mass=PAPER_STRUCTURE.mass, stiffness=PAPER_STRUCTURE.stiffness,
    damping=2 * ZETA * math.sqrt(PAPER_STRUCTURE.stiffness * PAPER_STRUCTURE.mass))
NO_PARTICLES = AnalyticalDamper(dataclasses.replace(PAPER_DAMPER, count=0))
TWO_MODES = ModalStructure([5.0, 40.0], [0.01, 0.01], [0.8, 0.5])


def _dynamic_stiffness(s, f):
    w = 2 * math.pi * f
    return abs(s.stiffness - w * w * s.mass + 1j * w * s.damping)


def test_a_release_without_particles_is_the_damped_oscillator():
    """``x(t) = x0 e^(-zeta w t) (cos w_d t + zeta / sqrt(1 - zeta^2) sin w_d t)``."""
    res = Simulation(STRUCTURE, NO_PARTICLES, Release(-0.05, duration=1.0,
                                                      sample_rate=4000.0)).solve()
    assert isinstance(res, FreeVibrationResult)
    w = math.sqrt(STRUCTURE.stiffness / STRUCTURE.mass)
    wd = w * math.sqrt(1 - ZETA**2)
    t = res.time
    x = -0.05 * np.exp(-ZETA * w * t) * (np.cos(wd * t)
                                         + ZETA / math.sqrt(1 - ZETA**2) * np.sin(wd * t))
    assert t[-1] == pytest.approx(1.0) and t[1] == pytest.approx(1 / 4000.0)
    np.testing.assert_allclose(res.displacement, x, atol=1e-6 * 0.05)


def test_the_release_and_the_earlier_call_give_the_same_answer():
    m = AnalyticalDamper(PAPER_DAMPER)
    new = Simulation(PAPER_STRUCTURE, m, Release(-0.058, 1.0)).solve()
    old = Simulation(PAPER_STRUCTURE, m, -0.058).run(1.0)
    kw = Simulation(PAPER_STRUCTURE, m, initial_displacement=-0.058).run(1.0)
    for r in (old, kw):
        np.testing.assert_array_equal(r.displacement, new.displacement)
        np.testing.assert_array_equal(r.peak_amplitudes, new.peak_amplitudes)


def test_a_load_history_without_particles_is_the_closed_form():
    """2 N sin(2 pi f t): the steady amplitude of ``F / |K - W^2 M + i W D|`` to 2e-4."""
    f = 5.0
    h = LoadHistory.harmonic(2.0, f, 10.0)
    res = Simulation(STRUCTURE, NO_PARTICLES, Loading(h, sample_rate=2000.0)).solve()
    assert isinstance(res, LoadResponse)
    x = res.displacement[res.time >= res.time[-1] - 4 / f]
    assert 0.5 * (x.max() - x.min()) == pytest.approx(2.0 / _dynamic_stiffness(STRUCTURE, f),
                                                      rel=2e-4)
    # the earlier call, and a bare record handed to Simulation, run the same
    np.testing.assert_array_equal(run_load(NO_PARTICLES, STRUCTURE, h).displacement,
                                  res.displacement)
    np.testing.assert_array_equal(Simulation(STRUCTURE, NO_PARTICLES, h).solve().displacement,
                                  res.displacement)


def test_a_run_up_is_a_load_of_its_own():
    """A run-up hands its record to the experiment; the tail extends the run."""
    r = RunUp(1.76e-3, 2.0, 8.0, 3.0)
    res = Simulation(STRUCTURE, AnalyticalDamper(PAPER_DAMPER), Loading(r, tail=0.5)).solve()
    ref = run_load(AnalyticalDamper(PAPER_DAMPER), STRUCTURE, r.history(), 2000.0, 0.5)
    np.testing.assert_array_equal(res.displacement, ref.displacement)
    assert res.time[-1] == pytest.approx(3.5)


def test_a_harmonic_sweep_without_particles_is_the_closed_form():
    """A force and an unbalance: the linear FRF and harmonic balance equal
    ``F / |K - W^2 M + i W D|`` with F = 2 N and ``F = m e W^2``; a HarmonicLoad given
    as it is runs as frequency_response does."""
    f = np.array([4.0, 5.56, 7.0])
    w = 2 * math.pi * f
    s = STRUCTURE
    den = np.array([_dynamic_stiffness(s, v) for v in f])
    for kw, expected in (({"force": 2.0}, 2.0 / den),
                         ({"unbalance": 1.76e-3}, 1.76e-3 * w * w / den)):
        res = Simulation(s, NO_PARTICLES, HarmonicSweep(f, direction="none", **kw)).solve()
        assert isinstance(res, FRFResult)
        np.testing.assert_allclose(np.abs(res.linear), expected, rtol=1e-9)
        np.testing.assert_allclose(res.harmonic_balance.amplitude[:, 0], expected, rtol=1e-6)
    res = Simulation(s, NO_PARTICLES, HarmonicSweep(f, load=HarmonicLoad("force", 2.0),
                                                    direction="none")).solve()
    ref = frequency_response(NO_PARTICLES, s, HarmonicLoad("force", 2.0), f, sweep="none")
    np.testing.assert_array_equal(res.linear, ref.linear)


def test_a_sweep_without_frequencies_spans_the_structure():
    res = Simulation(TWO_MODES, NO_PARTICLES, HarmonicSweep(force=1.0, direction="none",
                                                            with_harmonic_balance=False)).solve()
    assert res.frequency[0] < 0.6 * 5.0 and res.frequency[-1] > 1.4 * 40.0


def test_what_a_coupling_cannot_run_is_refused_before_any_run():
    h = LoadHistory.harmonic(1.0, 5.0, 1.0)
    with pytest.raises(InputError) as e:  # the DEM: a 1-DOF or N modes
        Simulation("a beam", DEMDamper(PAPER_DAMPER), Loading(h))
    assert e.value.field == "structure"
    Simulation(TWO_MODES, DEMDamper(PAPER_DAMPER), Loading(h))  # N modes: accepted
    # the plastic block answers a harmonic sweep (its stepped sine): accepted, not run here
    Simulation(PAPER_STRUCTURE, PlasticBedDamper(PAPER_DAMPER), HarmonicSweep([5.0], force=1.0))
    sim = Simulation(PAPER_STRUCTURE, NO_PARTICLES, Release(-0.05))
    with pytest.raises(InputError) as e:  # a release needs a duration
        sim.solve()
    assert e.value.field == "simulation.duration"
    assert sim.run(0.1).time[-1] == pytest.approx(0.1)
    with pytest.raises(InputError) as e:
        Simulation(PAPER_STRUCTURE, NO_PARTICLES, Loading(h)).run(1.0)
    assert e.value.field == "experiment"


@pytest.mark.parametrize(("make", "field"), [
    (lambda: Release(0.01), "structure.initial_displacement"),
    (lambda: Release(-0.05, duration=0.0), "simulation.duration"),
    (lambda: Loading("a file"), "load"),
    (lambda: Loading(LoadHistory.harmonic(1.0, 5.0, 1.0), tail=-1.0), "load.tail"),
    (lambda: HarmonicSweep([5.0]), "load"),
    (lambda: HarmonicSweep([5.0], force=1.0, base=1e-3), "load"),
    (lambda: HarmonicSweep([5.0], force=1.0, direction="sideways"), "sweep"),
    (lambda: Simulation(PAPER_STRUCTURE, NO_PARTICLES, "x"), "experiment"),
    (lambda: Simulation(PAPER_STRUCTURE, NO_PARTICLES), "experiment"),
])
def test_experiments_check_their_inputs(make, field):
    with pytest.raises(InputError) as e:
        make()
    assert e.value.field == field


def test_a_new_experiment_and_a_new_load_type_are_one_class_each():
    class Twice(Experiment):
        """Two releases from the same deflection, the second twice as long."""

        name = RELEASE

        def solve(self, strategy, model, structure):
            return [strategy(model, structure, d, -0.05, 2000.0) for d in (0.2, 0.4)]

    a, b = Simulation(STRUCTURE, NO_PARTICLES, Twice()).solve()
    np.testing.assert_array_equal(b.displacement[:a.displacement.size], a.displacement)

    @dataclasses.dataclass(frozen=True)
    class Step:
        """A force step of ``size`` [N] held for ``duration`` [s]."""

        size: float
        duration: float

        def history(self):
            return LoadHistory([0.0, 1e-4, self.duration], [0.0, self.size, self.size])

    res = Simulation(STRUCTURE, NO_PARTICLES, Loading(Step(2.0, 8.0))).solve()
    # the static deflection F / K after the step's transient
    assert res.displacement[-1] == pytest.approx(2.0 / STRUCTURE.stiffness, rel=1e-4)
