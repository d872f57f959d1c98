"""Public constructors and functions check their arguments and say what they expected:
an :class:`~pdamper.errors.InputError` naming the argument, never an
AttributeError from deep inside."""

from __future__ import annotations

import numpy as np
import pytest

from pdamper.errors import InputError
from pdamper.parameters import PAPER_DAMPER, PAPER_STRUCTURE


def _raises(fn, field: str, expected: str | None = None):
    with pytest.raises(InputError) as info:
        fn()
    assert info.value.field == field, str(info.value)
    if expected is not None:
        assert expected in info.value.message, str(info.value)
    assert "\n" not in str(info.value)


def test_analytical_damper_needs_a_particle_damper():
    from pdamper.models import AnalyticalDamper

    _raises(lambda: AnalyticalDamper(None), "damper", "ParticleDamper")
    _raises(lambda: AnalyticalDamper("paper"), "damper", "ParticleDamper")
    _raises(lambda: AnalyticalDamper(PAPER_DAMPER, gravity="9.81"), "gravity", "number")


def test_simulation_needs_a_structure_and_a_model():
    from pdamper.coupling import Simulation
    from pdamper.models import AnalyticalDamper

    _raises(lambda: Simulation(PAPER_STRUCTURE, "analytic", -0.058), "model", "DamperModel")
    _raises(lambda: Simulation(PAPER_STRUCTURE, PAPER_DAMPER, -0.058), "model",
            "AnalyticalDamper(damper)")
    _raises(lambda: Simulation("beam", AnalyticalDamper(PAPER_DAMPER), -0.058), "structure")
    sim = Simulation(PAPER_STRUCTURE, AnalyticalDamper(PAPER_DAMPER), -0.058)
    _raises(lambda: sim.run("2 s"), "simulation.duration", "number")
    _raises(lambda: sim.run(2.0, sample_rate=None), "simulation.sample_rate", "number")


def test_dem_engine_and_particle_set_reject_garbage():
    from dem_inputs import contact
    from pdamper.dem import Container, DEMEngine, ParticleSet
    from pdamper.materials import PVC, S235

    box = Container((0.04, 0.04, 0.12), PVC)
    _raises(lambda: DEMEngine([1, 2, 3], box, contact()), "particles", "ParticleSet")
    _raises(lambda: ParticleSet("abc", 0.005, S235), "particles.positions")
    _raises(lambda: ParticleSet([[0.01, 0.01, 0.01]], "big", S235), "particles.radius")
    _raises(lambda: ParticleSet([[0.01, 0.01, 0.01]], 0.005, "steel"), "particles.material",
            "Material")
    _raises(lambda: ParticleSet([[0.01, 0.01, 0.01]], 0.005, S235, velocities="fast"),
            "particles.velocities")
    _raises(lambda: Container("box", PVC), "container.box")


def test_effective_field_needs_a_model_and_grids():
    from pdamper.analysis.fields import effective_field
    from pdamper.models import AnalyticalDamper

    _raises(lambda: effective_field("analytic", [5.0], [0.01]), "model", "DamperModel")
    model = AnalyticalDamper(PAPER_DAMPER)
    _raises(lambda: effective_field(model, [], [0.01]), "frequency")
    _raises(lambda: effective_field(model, ["5 Hz"], [0.01]), "frequency")
    _raises(lambda: effective_field(model, [5.0], [[0.01, 0.02], [0.03, 0.04]]), "amplitude")


def test_complex_power_skip_cycles_must_be_whole():
    """``complex_power(skip_cycles=1.5)`` used to average over a fractional window."""
    from dem_inputs import engine_at

    res = engine_at(4, 10.0, 0.01).run(0.3, sample_rate=1000.0)
    _raises(lambda: res.complex_power(skip_cycles=1.5), "skip_cycles", "whole number")
    _raises(lambda: res.complex_power(skip_cycles=True), "skip_cycles", "whole number")
    _raises(lambda: res.complex_power(skip_cycles=1, cycles=0.5), "cycles", "whole number")
    assert res.complex_power(skip_cycles=np.int64(1)) == res.complex_power(skip_cycles=1)


def test_complex_power_function_checks_its_signals():
    from pdamper.analysis.complex_power import complex_power

    t = np.linspace(0, 1, 101)
    s = np.cos(2 * np.pi * t)
    _raises(lambda: complex_power(t, s, s, s, "1 Hz", 0.1), "frequency", "number")
    _raises(lambda: complex_power(t, s, s, s, 0.0, 0.1), "frequency")
    _raises(lambda: complex_power(t, s[:50], s, s, 1.0, 0.1), "force")
    _raises(lambda: complex_power(t, s, s, s, 1.0, "0.1 kg"), "bed_mass", "number")


def test_bed_response_refuses_text_and_answers_extremes_at_once():
    import time

    from pdamper.analysis.analytical import bed_response

    _raises(lambda: bed_response("10 Hz", 0.03, 0.1, 0.1), "frequency", "number")
    t0 = time.perf_counter()
    for f, x in ((1e300, 0.032), (10.0, 1e300), (1e7, 0.032), (5.56, 1e300)):
        try:
            bed_response(f, x, 0.1, 0.13)
        except InputError as exc:
            assert exc.field in ("frequency", "amplitude"), exc
    assert time.perf_counter() - t0 < 5.0


def test_structures_dampers_and_materials_check_types():
    from pdamper.damper import ParticleDamper
    from pdamper.materials import PVC, S235, Material
    from pdamper.structure import SingleDOFStructure

    _raises(lambda: SingleDOFStructure(mass="1 kg", damping=0.1, stiffness=1e3),
            "structure.mass", "number")
    _raises(lambda: ParticleDamper(0.12, 0.04, 0.04, 0.005, 1.5, S235, PVC), "particles.count",
            "whole number")
    _raises(lambda: ParticleDamper(0.12, 0.04, 0.04, 0.005, "32", S235, PVC), "particles.count")
    _raises(lambda: Material("x", "3 GPa", 0.3, 1000.0), "material x.youngs_modulus", "number")
    _raises(lambda: PAPER_DAMPER.with_count(2.5), "particles.count", "whole number")


def test_optimizer_checks_its_inputs():
    from pdamper.design import optimize_particle_count

    _raises(lambda: optimize_particle_count(PAPER_STRUCTURE, "damper", -0.058, 0.8), "damper",
            "ParticleDamper")
    _raises(lambda: optimize_particle_count(PAPER_STRUCTURE, PAPER_DAMPER, -0.058, 0.8,
                                            step=2.5), "optimization.step", "whole number")
