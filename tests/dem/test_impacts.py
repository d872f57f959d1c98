"""Single impacts of the DEM contact law against the COR curves that set its damping
(paper Sects. 2-3): the calibration holds for every curve model, both integrators, sphere-
wall and sphere-sphere, over 0.01-3 m/s."""

from __future__ import annotations

import numpy as np
import pytest

from pdamper.contact.restitution import MeasuredRestitution
from pdamper.contact.thornton import ThorntonRestitution
from pdamper.dem.impacts import check_restitution, simulate_impact
from pdamper.errors import InputError
from pdamper.materials import PVC, S235, get_material
from pdamper.parameters import vertical_dampers_paper as paper

V = np.geomspace(0.01, 3.0, 12)
STEEL = get_material("100Cr6")
CASES = {
    "paper steel-steel": (paper.PAPER_COR_PP, S235, S235),
    "paper steel-PVC": (paper.PAPER_COR_PW, S235, PVC),
    "Thornton S235 spheres": (ThorntonRestitution.from_materials(S235, S235, 0.005, 0.005),
                              S235, S235),
    "Thornton 100Cr6 on PVC": (ThorntonRestitution.from_materials(STEEL, PVC, 0.005), STEEL, PVC),
    "measured, scaled": (MeasuredRestitution((0.05, 0.5, 2.0), (0.9, 0.7, 0.6)).scaled(1.2),
                         get_material("lead"), get_material("brass")),
}


@pytest.mark.parametrize("integrator", ["gear", "verlet"])
@pytest.mark.parametrize("case", list(CASES))
def test_simulated_impacts_follow_the_curve(case, integrator):
    curve, a, b = CASES[case]
    check = check_restitution(V, curve, a, b, 0.005, integrator=integrator)
    assert check.sphere_sphere == (a is b)
    assert check.max_deviation < 0.01 if integrator == "verlet" else check.max_deviation < 2e-4


def test_head_on_spheres_give_the_constant_cor():
    """Two equal spheres head-on: the relative rebound speed over the approach speed is the
    constant COR asked for."""
    from pdamper.contact.restitution import ConstantRestitution

    e = simulate_impact(0.5, ConstantRestitution(0.6), S235, S235, 0.005, sphere_sphere=True)
    assert e == pytest.approx(0.6, abs=1e-4)


def test_bad_velocities():
    with pytest.raises(InputError, match="velocity"):
        check_restitution([0.1, -1.0], paper.PAPER_COR_PW, S235, PVC, 0.005)
    # faster than a quasi-static impact (0.1 of PVC's bar wave speed): refused before any
    # run (1e305 m/s overflowed the Hertz closed forms with a traceback)
    for v in ([1e305], [1.0, 1e3]):
        with pytest.raises(InputError, match=r"^velocity: impacts at up to .* bar wave speed "
                                             r"of PVC \(146 m/s\)"):
            check_restitution(v, paper.PAPER_COR_PW, S235, PVC, 0.005)


def test_speeds_are_judged_before_the_first_impact():
    """The physics limits of every DEM run (a tenth of the bar wave speed: 146 m/s for a
    PVC wall) and the number of runs (hard limits) are judged before anything runs."""
    from answers import memory_headroom

    curve = paper.PAPER_COR_PW
    with pytest.raises(InputError) as info:
        check_restitution([1.0, 1000.0], curve, S235, PVC, paper.PAPER_PARTICLE_RADIUS)
    assert info.value.field == "velocity" and "bar wave speed of PVC" in info.value.message
    many = np.broadcast_to(1.0, (10**10,))  # a view: no memory
    with memory_headroom(2**30), pytest.raises(InputError) as info:
        check_restitution(many, curve, S235, PVC, paper.PAPER_PARTICLE_RADIUS)
    assert info.value.field == "velocity"
