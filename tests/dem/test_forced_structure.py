"""The DEM's 1-DOF structure under a harmonic load (the forced response, docs/forced.md)."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from dem_inputs import engine, lattice
from pdamper.dem import StructureMotion
from pdamper.errors import InputError


@pytest.mark.parametrize("integrator", ["verlet", "gear"])
def test_forced_structure_with_a_resting_bed_is_the_linear_solution(integrator):
    """A bed that never lifts (accelerations below 0.1 g) moves with the container: the
    structure obeys (M + m_bed) x'' + D x' + K x = F cos(W t + phi) - m_bed g from rest,
    transient included."""
    ps = lattice(16)
    m, d, k = 1.514, 0.55, 1848.0
    f_load, amp, phase = 3.0, 0.3, 0.7
    st = StructureMotion(mass=m, damping=d, stiffness=k, force_amplitude=amp,
                         force_frequency=f_load, force_phase=phase)
    res = engine(ps, motion=st, integrator=integrator, settle_time=0.05).run(
        0.6, sample_rate=2000.0)
    mb = ps.masses.sum()
    w = 2 * np.pi * f_load

    def rhs(t, y):
        return [y[1], (amp * np.cos(w * t + phase) - mb * 9.81 - d * y[1] - k * y[0]) / (m + mb)]

    ref = solve_ivp(rhs, (0.0, res.time[-1]), [0.0, 0.0], t_eval=res.time, rtol=1e-10,
                    atol=1e-13).y[0]
    x = res.container_position
    assert np.max(np.abs(ref)) > 5e-4  # load and weight both move it
    assert np.max(np.abs(x - ref)) < 0.01 * np.max(np.abs(ref))
    assert res.attrs["structure_force_n"] == amp


def test_load_inputs_are_checked():
    with pytest.raises(InputError) as e:
        StructureMotion(mass=1.0, damping=0.0, stiffness=1.0, force_amplitude=-1.0)
    assert e.value.field == "force"
    with pytest.raises(InputError) as e:
        StructureMotion(mass=1.0, damping=0.0, stiffness=1.0, force_frequency=float("nan"))
    assert e.value.field == "frequency"
