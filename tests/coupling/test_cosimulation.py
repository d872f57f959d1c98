"""The paper's model 1: structure and DEM particles integrated together (Sect. 4.1)."""

import math

import numpy as np
import pytest

from pdamper.coupling import Simulation
from pdamper.materials import Material
from pdamper.models import AnalyticalDamper, DEMDamper
from pdamper.parameters import PAPER_DAMPER, PAPER_INITIAL_DISPLACEMENT, PAPER_STRUCTURE


def test_featherweight_bed_leaves_the_closed_form_oscillator_unchanged():
    """Eq. (23) with F -> 0: spheres of 1e-6 of steel's density do not disturb the
    structure, so the DEM-coupled end-effector follows the damped oscillator."""
    from dataclasses import replace

    foam = Material("feather", youngs_modulus=2e11, poisson_ratio=0.3, density=7.9e-3)
    damper = replace(PAPER_DAMPER, count=16, particle_material=foam)
    s = PAPER_STRUCTURE
    res = Simulation(s, DEMDamper(damper), -0.02).run(0.4)
    sigma = s.damping / (2 * s.mass)
    wd = math.sqrt(s.stiffness / s.mass - sigma**2)
    t = res.time
    exact = -0.02 * np.exp(-sigma * t) * (np.cos(wd * t) + sigma / wd * np.sin(wd * t))
    np.testing.assert_allclose(res.displacement, exact, atol=2e-6)
    assert res.details.steps == res.inputs["steps"]  # the DEM run travels with the result

@pytest.mark.long
def test_paper_level3_dem_model_1_against_analytical_model(paper_model1_ensemble):
    """Sect. 4.2.1 / Fig. 7, 32 spheres from -58 mm, two fidelities compared: the DEM
    (model 1, constant COR 0.6 / 0.85) and the analytical model (model 3) agree within
    12 % on the amplitude after 0.75 s, model 1 averaged over ten random packings
    (measured mean 21.35 mm, 20.11-22.35 mm; analytical 23.6 mm). One run is one realisation
    of a chaotic transient: from the paper's lattice the amplitude moved between 23.5 and
    27.7 mm with 1e-9 m moves of the spheres or last-bit changes of the code, a spread as
    wide as the band, so no single run is compared. Both decay slower than the paper's
    experiment (~19 mm), which the test does not hide: see the case-study table. Damping
    ratios of the first cycles of every run: 0.02-0.06 (measured 0.032-0.043)."""
    ana = Simulation(PAPER_STRUCTURE, AnalyticalDamper(PAPER_DAMPER),
                     PAPER_INITIAL_DISPLACEMENT).run(0.95)
    dem = np.mean([r.amplitude_at(0.75) for r in paper_model1_ensemble])
    assert dem == pytest.approx(ana.amplitude_at(0.75), rel=0.12)
    for run in paper_model1_ensemble:
        _, zeta = run.damping_ratio
        assert np.all((zeta[:4] > 0.02) & (zeta[:4] < 0.06))
        assert run.inputs["energy_balance_error"] < 0.01
