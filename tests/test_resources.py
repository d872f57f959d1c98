"""The resource and physics model (:mod:`pdamper.resources`): what a run implies is judged
before it starts; physically meaningless inputs are refused with the reason, costly ones
above documented limits unless forced."""

from __future__ import annotations

import math
import time
from dataclasses import replace

import pytest

from answers import refused
from pdamper import resources
from pdamper.errors import InputError
from pdamper.io.scenario import load_scenario
from pdamper.parameters import PAPER_DAMPER
from pdamper.parameters.vertical_dampers_paper import PAPER_MAP_AMPLITUDE, PAPER_MAP_FREQUENCY
from pdamper.runs.resources import check_resources, check_runs


def test_every_limit_is_documented_with_its_reason():
    doc = resources.__doc__
    for name in ("MIN_PARTICLE_RADIUS", "MAX_STROKE", "MAX_SPEED_FRACTION",
                 "MAX_CONTACT_RADIUS_RATIO", "MEMORY_LIMIT", "TIME_LIMIT", "SWEEP_TIME_LIMIT",
                 "FORCE_TIME_LIMIT", "MAX_SCENARIO_BYTES"):
        assert f":data:`{name}`" in doc, name


# ---------------------------------------------------------------- the Hertz closed forms
def test_contact_time_is_the_dem_engines():
    """The step the resource model assumes is the DEM engine's own: its contact time at its
    reference speed (the shortest over sphere-sphere and sphere-wall pairs)."""
    from dem_inputs import engine_at

    eng = engine_at(32, 10.0, 0.032)
    speed = resources.impact_speed(0.032, 10.0, PAPER_DAMPER.length)
    assert speed == pytest.approx(eng.reference_velocity, rel=1e-12)
    imp = resources.hertz_impact(PAPER_DAMPER, speed)
    assert imp.shortest_contact == pytest.approx(eng.contact_time, rel=1e-12)


def test_hertz_overlap_closed_form():
    """Energy balance of an elastic Hertz impact: m v^2 / 2 = 2/5 K delta_max^(5/2), and the
    contact radius a = sqrt(R* delta_max) (Hertz)."""
    from pdamper.contact.elastic import effective_modulus, effective_radius, hertz_stiffness

    r, v = PAPER_DAMPER.particle_radius, 3.0
    m = PAPER_DAMPER.particle_mass
    k = hertz_stiffness(effective_modulus(PAPER_DAMPER.particle_material,
                                          PAPER_DAMPER.wall_material), effective_radius(r))
    delta = (resources.hertz_impact(PAPER_DAMPER, v).contact_radius_ratio * r) ** 2 / r
    assert 0.4 * k * delta**2.5 == pytest.approx(0.5 * m * v**2, rel=1e-12)


# ---------------------------------------------------------------- physical meaning
def test_the_papers_envelope_is_meaningful_for_every_model():
    f0, f1, _ = PAPER_MAP_FREQUENCY
    x0, x1, _ = PAPER_MAP_AMPLITUDE
    resources.check_grid(PAPER_DAMPER, (f0, f1), (x0, x1), contact_law=True)
    imp = resources.check_motion(PAPER_DAMPER, f1, x1, contact_law=True)
    assert imp.contact_radius_ratio == pytest.approx(0.475, abs=0.005)  # documented


def test_spheres_below_a_tenth_of_a_millimetre():
    refused(lambda: resources.check_particles(replace(PAPER_DAMPER, particle_radius=1e-6)),
             "particles.radius", "adhesion")
    resources.check_particles(replace(PAPER_DAMPER, particle_radius=1e-4))


def test_strokes_longer_than_any_structure():
    refused(lambda: resources.check_motion(PAPER_DAMPER, 10.0, 1e300), "excitation.amplitude",
             "10 m")
    refused(lambda: resources.check_release(PAPER_DAMPER, 5.56, -1e300),
             "structure.initial_displacement", "10 m")


@pytest.mark.parametrize("frequency", [1e300, 1e7, 5e4])
def test_frequencies_above_the_contact_frequency(frequency):
    msg = refused(lambda: resources.check_motion(PAPER_DAMPER, frequency, 1e-5),
                   "excitation.frequency", "contact frequency")
    assert "longer than a period" in msg.message


def test_contact_frequency_at_the_implied_speed():
    """10 kHz is below the highest contact frequency of the spheres (19 kHz at the fastest
    admissible impact) but above the one at the slow impacts 0.01 mm implies."""
    refused(lambda: resources.check_motion(PAPER_DAMPER, 1e4, 1e-5), "excitation.frequency",
            "at the implied impact speed")


def test_impacts_faster_than_a_tenth_of_the_wave_speed():
    msg = refused(lambda: resources.check_motion(PAPER_DAMPER, 100.0, 0.2),
                   "excitation.frequency", "PVC", "bar wave speed")
    assert "146 m/s" in msg.message  # 0.1 sqrt(E / rho) of PVC


def test_dem_at_200hz_32mm_is_refused_with_the_true_reason():
    """The 'DEM advice' row: at 200 Hz / 32 mm the DEM stopped at start-up advising a
    smaller Gear tolerance or safety factor, which changes nothing. The impacts implied
    (82 m/s) are beyond Hertz's law: the contact radius would be 0.57 of the radius."""
    msg = refused(lambda: resources.check_motion(PAPER_DAMPER, 200.0, 0.032, contact_law=True),
                   "excitation.frequency", "Hertz contact radius", "0.57")
    assert "tolerance" not in msg.message and "safety" not in msg.message
    resources.check_motion(PAPER_DAMPER, 200.0, 0.032)  # the analytical model: no contact law


# ---------------------------------------------------------------- cost
def _cost(seconds=1.0, memory=1.0, **kw):
    return resources.Cost("the run", seconds, memory, "detail",
                          (("a", 2.0), ("b", 1e9), ("c", 1.0)), **kw)


def test_cost_limits_name_the_input_furthest_from_usual():
    refused(lambda: resources.require(_cost(seconds=2 * 3600)), "b", "2 h", "--force",
             "lower b, a")
    refused(lambda: resources.require(_cost(memory=3 * 2**30)), "b", "3 GiB", "--force")
    assert resources.require(_cost(seconds=2 * 3600, memory=3 * 2**30), force=True)


def test_sweeps_are_judged_per_run_and_in_all():
    resources.require(_cost(seconds=20 * 3600, runs=100, longest=0.2 * 3600))
    refused(lambda: resources.require(_cost(seconds=10, runs=2, longest=2 * 3600)), "b",
             "per run")
    refused(lambda: resources.require(_cost(seconds=30 * 3600, runs=100, longest=600)), "b",
             "in all", "sweep")


def test_what_cannot_run_is_refused_even_when_forced():
    ram = resources.physical_memory()
    if ram is not None:
        refused(lambda: resources.require(_cost(memory=2 * ram), force=True), "b",
                 "more than this machine has")
    refused(lambda: resources.require(_cost(seconds=1e9), force=True), "b", "even with --force")
    refused(lambda: resources.require(_cost(seconds=math.inf), force=True), "b")


def test_dem_cost_grows_with_what_it_should():
    base = dict(sample_rate=4000.0, safety=0.02, frequency=10.0)
    one = resources.dem_cost(PAPER_DAMPER, 0.8, 5.56, **base)
    assert resources.dem_cost(PAPER_DAMPER, 8.0, 5.56, **base).seconds > 8 * one.seconds
    assert resources.dem_cost(PAPER_DAMPER.with_count(64), 0.8, 5.56, **base).seconds == \
        pytest.approx(2 * one.seconds)
    assert resources.dem_cost(PAPER_DAMPER, 0.8, 5.56, sample_rate=4e6, safety=0.02,
                              frequency=10.0).memory > 500 * one.memory / 2


# ---------------------------------------------------------------- through the scenario
def test_the_papers_case_passes_every_run():
    sc = load_scenario(None)
    for run, model in (("excitation", "analytic"), ("excitation", "dem"), ("map", "analytic"),
                       ("map", "dem"), ("simulation", "analytic"), ("simulation", "dem"),
                       ("optimization", None), ("case_study", None), ("case_study_dem", None)):
        check_resources(sc, run, model)


@pytest.mark.parametrize(("overrides", "run", "model", "field"), [
    ({"excitation.frequency": "1e-9 Hz"}, "excitation", "dem", "excitation.frequency"),
    ({"dem.cycles": 10**20}, "excitation", "dem", "dem.cycles"),
    ({"dem.sample_rate": "1e12 Hz"}, "excitation", "dem", "dem.sample_rate"),
    ({"dem.safety": 1e-9}, "excitation", "dem", "dem.safety"),
    ({"map.frequency": "2Hz:20Hz:1000000000"}, "map", "analytic", "map.frequency"),
    ({"map.amplitude": "1mm:2mm:100000"}, "map", "dem", "map.amplitude"),
    ({"simulation.duration": "1e9 s"}, "simulation", "analytic", "simulation.duration"),
    ({"simulation.duration": "1e5 s"}, "simulation", "dem", "simulation.duration"),
    ({"optimization.at": "1e8 s"}, "optimization", None, "optimization.at"),
    ({"particles.radius": "0.15 mm", "optimization.step": 1}, "optimization", None,
     "optimization.step"),
], ids=["1e-9Hz", "cycles-1e20", "sample-rate", "safety", "map-1e9", "dem-map", "duration",
        "dem-duration", "at", "step"])
def test_absurd_work_is_refused_at_once_naming_the_input(overrides, run, model, field):
    sc = load_scenario(None, overrides)
    t0 = time.perf_counter()
    refused(lambda: check_resources(sc, run, model), field)
    assert time.perf_counter() - t0 < 1.0


def test_force_allows_what_this_machine_can_do():
    sc = load_scenario(None, {"simulation.duration": "3e4 s"})
    refused(lambda: check_resources(sc, "simulation"), "simulation.duration", "--force")
    check_resources(sc, "simulation", force=True)
    check_runs(load_scenario(None, {"simulation.duration": "3e4 s"}), ("simulation",),
               force=True)
    with pytest.raises(InputError):
        check_runs(load_scenario(None, {"simulation.duration": "3e4 s"}), ("simulation",))


def test_unknown_run_isrefused():
    refused(lambda: check_resources(load_scenario(None), "everything"), "run")


# -- the physics limits wherever a run is made (the models, the free vibration)
def test_every_model_refuses_spheres_below_a_tenth_of_a_millimetre():
    from pdamper.models import AnalyticalDamper, DEMDamper

    tiny = replace(PAPER_DAMPER, particle_radius=1e-9)
    for make in (lambda: AnalyticalDamper(tiny), lambda: DEMDamper(tiny),
                 lambda: AnalyticalDamper(PAPER_DAMPER).with_damper(tiny)):
        refused(make, "particles.radius", "0.1 mm")


def test_every_free_vibration_obeys_the_release_limits():
    """A Level III run of any model is judged where it is made (:class:`Simulation`), the
    DEM's also by Hertz's law: the API and every command inherit it."""
    from pdamper.coupling import Simulation
    from pdamper.models import AnalyticalDamper, DEMDamper
    from pdamper.parameters import PAPER_STRUCTURE
    from pdamper.structure import SingleDOFStructure

    refused(lambda: Simulation(PAPER_STRUCTURE, AnalyticalDamper(PAPER_DAMPER), -20.0),
             "structure.initial_displacement", "10 m")
    # a release the analytical model may describe, not the contact law: a/R above 0.5
    stiff = SingleDOFStructure(mass=PAPER_STRUCTURE.mass, damping=0.0,
                               stiffness=PAPER_STRUCTURE.stiffness * 400)
    Simulation(stiff, AnalyticalDamper(PAPER_DAMPER), -0.07)
    refused(lambda: Simulation(stiff, DEMDamper(PAPER_DAMPER), -0.07),
             "structure.initial_displacement", "contact radius")


def test_the_analytical_model_refuses_excitations_outside_the_limits():
    """The Python API's Level II run of the analytical model is judged as `pdamper
    analytic` is (at the fastest frequency with the extreme strokes of its arrays)."""
    import numpy as np

    from pdamper.models import AnalyticalDamper

    model = AnalyticalDamper(PAPER_DAMPER)
    refused(lambda: model.response(10.0, 20.0), "amplitude", "10 m")
    refused(lambda: model.response(np.array([10.0, 5e4]), np.array([1e-5, 0.01])),
             "frequency", "contact frequency")
    assert float(model.response(20.0, 0.2).loss_factor) > 0  # the paper's corner
