"""The fast paths of the DEM kernels reproduce the plain computations they replace."""

from __future__ import annotations

import numpy as np
import pytest

from dem_inputs import engine, random
from pdamper.contact.forces import onset_damping, onset_damping_cached
from pdamper.dem import HarmonicMotion


@pytest.mark.parametrize("model", [0, 1])
def test_onset_damping_memo_is_bit_identical(model):
    v_nodes = np.array([0.1, 1.0, 3.0])
    e_nodes = np.array([0.9, 0.7, 0.6])
    const_v = np.array([1.0])
    const_e = np.array([0.6])
    cache = np.full((2, 2), -1.0)
    rng = np.random.default_rng(3)
    for v0 in np.concatenate([rng.uniform(0.0, 4.0, 200), [0.0, 1e-4, 0.01, 5.0, 0.5, 0.5]]):
        for p, (vn, en) in enumerate(((v_nodes, e_nodes), (const_v, const_e))):
            d_ref = onset_damping(v0, vn, en, model, 0.01)
            d = onset_damping_cached(v0, vn, en, model, 0.01, cache, p)
            assert d == d_ref


def test_gear_rejections_and_rebuilds_keep_the_ledger():
    """A random bed (many onsets, rejected Gear steps, list rebuilds): the ledger closes and
    the mean Gear step stays well above the Verlet step."""
    res = {}
    for integ in ("gear", "verlet"):
        sim = engine(random(32, seed=2), motion=HarmonicMotion(0.032, 10.0), integrator=integ)
        res[integ] = sim.run(0.2)
    g = res["gear"]
    assert g.rejected_steps > 0 and g.rebuilds > 1
    assert g.energy_balance_error() < 1e-3
    assert res["verlet"].energy_balance_error() < 1e-2
    # mean Gear step well above the Verlet step
    assert g.simulated_time / g.steps > 2 * res["verlet"].time_step


def test_gear_corrector_by_rows_is_bit_identical():
    """Gear's corrector one Nordsieck row per loop (the vectorised path of all-stepped beds)
    gives the per-component corrector's values to the last bit."""
    from numba import njit

    from pdamper.dem.kernels.forces import FASTMATH
    from pdamper.dem.kernels.gear import _correct, _correct_rows

    # both inlined under the kernels' fast-math flags, as in gear_advance
    @njit(fastmath=FASTMATH)
    def per_component(fx, fw, fpos, fvel, fomg, ffrc, ftrq, im3, ii3, hh, h, ih):
        for q in range(fpos.shape[0]):
            _correct(q, fx, fw, fpos, fvel, fomg, ffrc, ftrq, im3, ii3, hh, h, ih)

    @njit(fastmath=FASTMATH)
    def by_rows(fx, fw, fpos, fvel, fomg, ffrc, ftrq, im3, ii3, hh, h, ih, cx, cw):
        _correct_rows(fx, fw, fpos, fvel, fomg, ffrc, ftrq, im3, ii3, hh, h, ih, cx, cw)

    rng = np.random.default_rng(7)
    m3 = 3 * 32
    h = 3.7e-7
    args = [rng.normal(size=(6, m3)), rng.normal(size=(5, m3))] + [
        rng.normal(size=m3) for _ in range(7)]
    a = [x.copy() for x in args]
    b = [x.copy() for x in args]
    per_component(*a, 0.5 * h * h, h, 1.0 / h)
    by_rows(*b, 0.5 * h * h, h, 1.0 / h, np.empty(m3), np.empty(m3))
    for x, y in zip(a, b, strict=True):
        assert np.array_equal(x, y)
    assert not np.array_equal(a[0], args[0])  # it corrected something


def test_step_loops_count_no_references():
    """The per-step loops and the functions they call per regroup, rebuild, onset or sample
    are compiled without numba's reference counting (``_nrt=False``): an atomic increment
    and decrement for every array taken out of a bundle, in each step, cost more than the
    step's work at the few stepped spheres of an impact (docs/performance.md, Kernels). The
    physics of these kernels is checked by every other DEM test; against a twin compiled
    with reference counting a 0.04 s random-bed run took the same steps and differed by
    2e-16 (relative) at most, measured once (the twin compiles for 40 s without a cache)."""
    from pdamper.dem.kernels import flights, forces, gear, sampling, search, verlet

    loops = [gear._gear_steps, verlet._verlet_steps, flights.regroup, flights.join_due,
             flights.place_all, search.rebuild, search.build_verlet_list,
             search.carry_history, forces.impact_damping, sampling.record_sample,
             sampling.close_window]
    for fn in loops:
        assert fn.targetoptions.get("_nrt") is False, fn.__name__
    # the allocating entry points keep it (np.empty needs the runtime)
    assert gear.gear_advance.targetoptions.get("_nrt") is not False
