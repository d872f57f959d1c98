"""Motion modes from recorded bed motion (paper Sect. 3, Figs. 3-4): the
classifier on synthetic trajectories of every mode, and on DEM runs at the six example
points of Fig. 4."""

from __future__ import annotations

import numpy as np
import pytest
from synthetic_beds import block_in_box

from pdamper.analysis.dem_modes import BedSignals, classify_motion
from pdamper.analysis.modes import MotionMode
from pdamper.errors import InputError

M = MotionMode


@pytest.mark.parametrize(
    ("f", "x", "options", "mode", "order"),
    [
        (4.0, 0.015, {}, M.SOLID, -1),                                   # Fig. 4-1, A < g
        (6.0, 0.015, {}, M.SINGLE_CAC_HARMONIC, 0),                      # Fig. 4-2i
        (10.0, 0.015, {}, M.SINGLE_CAC_SUBHARMONIC, 1),                  # Fig. 4-2ii
        (18.0, 0.050, {}, M.DOUBLE_CAC_HARMONIC, 0),                     # Fig. 4-3i
        (18.0, 0.020, {}, M.DOUBLE_CAC_SUBHARMONIC, 1),                  # Fig. 4-3ii
        (14.0, 0.015, {"random_e": (0.0, 0.6)}, M.SCATTERING, -1),       # irregular impacts
        (10.0, 0.032, {"restitution": 0.6, "collect": 0.0}, M.RATTLING, 0),  # elastic bed
        (14.0, 0.015, {"restitution": 0.85, "collect": 0.0}, M.RATTLING, 1),
    ],
    ids=["solid", "single-harmonic", "single-subharmonic", "double-harmonic",
         "double-subharmonic", "scattering", "rattling", "rattling-period-2"],
)
def test_every_mode_from_its_synthetic_trajectory(f, x, options, mode, order):
    """An inelastic block (the paper's collect-and-collide assumption) at the Fig. 4
    points, a block with random restitution (scattering) and an elastic one (rattling)."""
    c = classify_motion(block_in_box(f, x, cycles=16, **options))
    assert c.mode is mode, c.reason
    assert c.subharmonic_order == order
    assert (c.period == 0) == (mode in (M.SOLID, M.SCATTERING))


def test_the_features_behind_the_decisions():
    single = classify_motion(block_in_box(6.0, 0.015))
    double = classify_motion(block_in_box(18.0, 0.050))
    assert single.lid_contacts_per_cycle == 0 and double.lid_contacts_per_cycle == pytest.approx(1)
    assert single.periodicity_residual < 0.01 and single.lift > 0.01  # flies ~2.7 cm
    rattle = classify_motion(block_in_box(10.0, 0.032, restitution=0.6, collect=0.0))
    assert rattle.contact_fraction < 0.05 < double.contact_fraction
    sub = classify_motion(block_in_box(10.0, 0.015))
    assert sub.period == 2 and sub.first_cycle == 5 and sub.last_cycle == 16


def test_window_and_input_errors():
    s = block_in_box(6.0, 0.015, cycles=6)
    assert classify_motion(s, 2, 4).first_cycle == 2
    with pytest.raises(InputError, match="cycles"):
        classify_motion(s, 3, 9)
    bad = BedSignals(s.time[:5], s.height[:5], s.force_z[:5], 6.0, 0.1, 0.005, 0.12)
    with pytest.raises(InputError, match="signals"):
        classify_motion(bad)


@pytest.mark.slow
@pytest.mark.parametrize("case", ["1", "2i", "2ii", "3i", "3ii", "3iii"])
def test_dem_runs_at_the_fig4_points(case):
    """The DEM of the benchmark damper (32 spheres, constant COR 0.6 / 0.85, random
    packing) run until steady at the six Fig. 4 points, and classified.

    Where the DEM bed moves as the paper's block (1, 2i, 3i, 3iii) the classifier names
    the paper's mode (3i runs in the large-overlap regime too). At 2ii the
    constant-COR bed does not repeat its motion (the cycle loss factors scatter,
    independent of the classifier): it is scattering, where the paper's DEM
    (velocity-dependent COR) shows subharmonic impacts. The independent evidence: the loss
    factor of single cycles scatters by more than 12 % about its mean there, by less than
    8 % in the repetitive motion of 2i. One packing in eight repeats just within the
    threshold there, so 2ii is judged on three packings (the majority scatters).

    3ii and 3iii sit on the repetition threshold: their mode depends on the last bits of
    a run. Of six runs at each (Gear tolerance 1e-5, 3e-6, 1e-6, free flights on and off),
    3ii scattered in five (one repeated every 3 cycles, residual 0.067 against the
    threshold 0.08) and 3iii in five (one repeated every 3 cycles); all eight runs at
    tolerances 3e-6 and 1e-6 scattered. So these two points run at 3e-6 and assert what
    the converged runs agree on: scattering, with about one lid impact per cycle at 3ii
    (the paper's double CaC subharmonic has one every cycle but does not repeat here).
    """
    from pdamper.analysis.stationarity import cycle_loss_factors
    from pdamper.models import DEMDamper
    from pdamper.parameters import PAPER_DAMPER
    from pdamper.parameters.vertical_dampers_paper import FIG4_EXAMPLES

    x, f, paper_mode, _ = next(e for e in FIG4_EXAMPLES if e[3] == case)
    tol = {"3ii": 3e-6, "3iii": 3e-6}.get(case, 1e-5)

    def steady(seed):
        model = DEMDamper(PAPER_DAMPER, packing="random", seed=seed, max_cycles=30,
                          gear_tolerance=tol)
        run = model.steady_run(f, x)
        assert run.stationarity.stationary, run.stationarity.reason
        res = run.result
        eta = cycle_loss_factors(res.time, -res.force[:, 2], res.container_velocity, f,
                                 res.bed_mass)[run.skip_cycles:]
        return run, (float(np.std(eta) / np.mean(eta)) if case != "1" else 0.0)

    if case == "2ii":
        # on the repetition threshold too: 7 of 8 packings (seeds 0-7) scatter, one
        # (seed 1) repeats within residual 0.071 < 0.08 and is called subharmonic; the
        # cycle loss factors scatter by 18-41 % in all eight
        runs = [steady(seed) for seed in (1, 2, 3)]
        modes = [run.motion.mode for run, _ in runs]
        assert sum(m is M.SCATTERING for m in modes) >= 2, modes
        assert all(scatter > 0.12 for _, scatter in runs), runs
        return
    run, scatter = steady(1)
    mode = run.motion.mode
    if case == "3ii":
        assert mode is M.SCATTERING, run.motion.reason
        assert run.motion.lid_contacts_per_cycle > 0.5
    else:
        assert mode is paper_mode, run.motion.reason
        if case == "2i":
            assert scatter < 0.08  # a repetitive motion: the same loss factor every cycle
