"""The ``plastic_bed`` coupling (pdamper.coupling.plastic): the plastic block on the
structure for a release (1-DOF, N modes) and under load histories, through Simulation,
run_load and the command line."""

import json
import math
from pathlib import Path

import numpy as np
import pytest

from pdamper.coupling import Simulation, run_load
from pdamper.coupling.loads import LoadHistory
from pdamper.models import AnalyticalDamper, PlasticBedDamper
from pdamper.parameters import PAPER_DAMPER, PAPER_STRUCTURE
from pdamper.structure.modal import ModalStructure

FRAME = Path(__file__).resolve().parents[2] / "examples" / "machine-frame"


def _frame(load_at_tip: bool = False) -> ModalStructure:
    """The machine frame's two modes (examples/machine-frame/modes.csv), the load at the
    motor or the tip."""
    tip = np.array([0.2582, -0.3162])
    return ModalStructure(frequencies=np.array([12.0, 31.0]),
                          damping_ratios=np.array([0.010, 0.008]), damper_shape=tip,
                          output_shape=tip,
                          load_shape=tip if load_at_tip else np.array([0.15, 0.24]))


def test_free_decay_of_a_1dof_damps_and_closes_its_energy():
    res = Simulation(PAPER_STRUCTURE, PlasticBedDamper(PAPER_DAMPER), -0.058).run(1.0)
    assert res.model == "plastic"
    _, zeta = res.damping_ratio
    assert zeta.size >= 3 and np.all(np.isfinite(zeta)) and np.all(zeta > 0)
    assert res.inputs["impacts"] > 5 and res.inputs["dissipated_energy"] > 0
    assert abs(res.inputs["energy_balance_error"]) < 1e-4
    # the pseudo force of the closed forms on the same release: the same decay within 10 %
    ref = Simulation(PAPER_STRUCTURE, AnalyticalDamper(PAPER_DAMPER), -0.058).run(1.0)
    assert res.amplitude_at(0.8) == pytest.approx(ref.amplitude_at(0.8), rel=0.10)
    # the bed damps: the bare structure's own decay is far slower
    assert res.amplitude_at(0.8) < 0.6 * 0.058 * math.exp(
        -PAPER_STRUCTURE.damping / (2 * PAPER_STRUCTURE.mass) * 0.8)


def test_free_decay_of_two_modes_reports_each_modes_damping():
    """The machine frame's scenario (two modes, 190 steel spheres) released from -3 mm at
    the tip: each mode's damping ratio from its own coordinate, mode 1 damped more than
    without the bed (the same coupling with no spheres gives the modes' own ratios)."""
    from pdamper.io.scenario import load_scenario

    sc = load_scenario(FRAME / "scenario.toml")
    s = sc.structure_model()
    res = Simulation(s, sc.model("plastic"), -0.003).run(1.0)
    bare = Simulation(s, sc.model("plastic", sc.damper().with_count(0)), -0.003).run(1.0)
    assert res.inputs["modes"] == 2 and abs(res.inputs["energy_balance_error"]) < 1e-4
    assert res.inputs["impacts"] > 5 and bare.inputs["impacts"] == 0
    per_mode, own = res.damping_per_mode, bare.damping_per_mode
    assert per_mode is not None and len(per_mode) == 2
    assert own[0].damping_ratio == pytest.approx(0.010, rel=5e-3)
    assert own[1].damping_ratio == pytest.approx(0.008, rel=5e-3)
    assert math.isfinite(per_mode[0].damping_ratio)
    assert per_mode[0].damping_ratio > own[0].damping_ratio
    assert res.final_amplitude < 0.95 * bare.final_amplitude
    assert np.all(np.isfinite(res.displacement))


def test_force_pulse_on_two_modes_closes_its_energy_balance():
    t = np.linspace(0.0, 0.01, 41)
    pulse = LoadHistory(t, 1000.0 * np.sin(np.pi * t / 0.01), "force", "half-sine")
    r = run_load(PlasticBedDamper(PAPER_DAMPER.with_count(32)), _frame(True), pulse,
                 tail=0.5)
    assert r.model == "plastic" and r.inputs["impacts"] > 0
    s = r.summary()
    assert all(math.isfinite(v) for k, v in s.items() if k != "not_applicable")
    # W_in = Delta E + E_struct + E_bed
    assert abs(r.input_work - r.energy_change - r.structural_dissipation
               - r.dissipated_energy) < 1e-3 * r.input_work
    assert r.dissipated_energy > 0.05 * r.input_work


def test_base_acceleration_on_a_1dof_runs():
    t = np.linspace(0.0, 0.05, 101)
    shock = LoadHistory(t, 30.0 * np.sin(np.pi * t / 0.05), "base_acceleration", "shock")
    r = run_load(PlasticBedDamper(PAPER_DAMPER), PAPER_STRUCTURE, shock, tail=0.3)
    assert np.all(np.isfinite(r.displacement)) and r.peak > 0
    assert r.dissipated_energy > 0 and r.kind == "base_acceleration"
    assert set(r.not_applicable()) >= {"input_work", "energy_balance_error"}


def test_machine_frame_shock_end_to_end_through_the_cli(cli):
    """``pdamper simulate --scenario examples/machine-frame/scenario.toml --model plastic``:
    the 1 kN shock on the frame's two modes."""
    code, out, err = cli("simulate", "--scenario", FRAME / "scenario.toml", "--model",
                         "plastic", "--json")
    assert code == 0, err
    d = json.loads(out)
    for k in ("peak", "rms", "peak_acceleration", "rms_acceleration", "dissipated_energy",
              "input_work", "structural_dissipation", "energy_change"):
        assert math.isfinite(d[k]) and d[k] != 0.0, k
    assert abs(d["energy_balance_error"]) < 1e-3
    assert d["dissipated_energy"] > 0.2 * d["input_work"]
    code, text, _ = cli("simulate", "--scenario", FRAME / "scenario.toml", "--model",
                        "plastic")
    assert code == 0 and "PlasticBedDamper" in text


def test_release_on_the_machine_frame_modes_file_through_the_cli(cli, tmp_path):
    sc = tmp_path / "sc.toml"
    sc.write_text(f'[structure]\nmodes = "{FRAME / "modes.csv"}"\n'
                  'initial_displacement = "-3 mm"\n'
                  '[simulation]\nmodel = "plastic"\nduration = "0.5 s"\n')
    code, out, err = cli("simulate", "--scenario", sc, "--json")
    assert code == 0, err
    d = json.loads(out)
    assert d["damping_per_mode"] is not None and len(d["damping_per_mode"]) == 2
    assert math.isfinite(d["final_amplitude"]) and d["final_amplitude"] < 0.003


def test_beam_modes_release_and_base_shock():
    """The beam's three modes (the FE cantilever of the paper's kind, damper at 650 mm):
    a release closes its energy and decays near the pseudo force; base motion runs with
    the beam's participation factors."""
    from pdamper.structure.beam import TimoshenkoBeam, TipMass

    beam = TimoshenkoBeam(length=0.7, width=0.08, height=0.006, youngs_modulus=210e9,
                          poisson_ratio=0.29, density=7800.0, elements=40)
    s = ModalStructure.from_beam(beam, TipMass(1.3), 3, damper_position=0.65,
                                 output_position=0.7, release_position=0.65,
                                 damping_ratio=[0.005, 0.01, 0.02])
    r = Simulation(s, PlasticBedDamper(PAPER_DAMPER), -0.058).run(1.0)
    assert r.inputs["modes"] == 3 and abs(r.inputs["energy_balance_error"]) < 1e-4
    # the fastest mode (151 Hz) sets the step: 40 steps a period
    assert r.inputs["integration_step"] <= 1.0 / (40 * 150.0)
    ref = Simulation(s, AnalyticalDamper(PAPER_DAMPER), -0.058).run(1.0)
    assert r.amplitude_at(0.8) == pytest.approx(ref.amplitude_at(0.8), rel=0.15)
    t = np.linspace(0.0, 0.05, 101)
    shock = LoadHistory(t, 30.0 * np.sin(np.pi * t / 0.05), "base_acceleration", "shock")
    load = run_load(PlasticBedDamper(PAPER_DAMPER), s, shock, tail=0.3)
    assert np.all(np.isfinite(load.displacement)) and load.dissipated_energy > 0


@pytest.mark.long
def test_shock_on_the_paper_structure_against_the_dem():
    """The paper's 1-DOF and 32 spheres under a 40 N half-sine of 40 ms (docs/forced.md):
    the block's peak equals the DEM's within 1 % and its RMS over the first 0.5 s (while
    the bed flies) within 15 % of the DEM's, nearer than the closed forms' pseudo force.
    (Over the whole 2.5 s this lattice start is not the DEM's answer for a poured bed:
    its columns dissipate more near take-off; the random packings' test below.)"""
    from pdamper.models import DEMDamper

    t = np.arange(0.0, 1.5005, 1e-3)
    shock = LoadHistory(t, np.where(t < 0.04, 40.0 * np.sin(np.pi * t / 0.04), 0.0),
                        "force", "shock")
    runs = {n: run_load(m(PAPER_DAMPER), PAPER_STRUCTURE, shock, tail=1.0)
            for n, m in (("plastic", PlasticBedDamper), ("dem", DEMDamper),
                         ("analytic", AnalyticalDamper))}

    def rms(r, until=0.5):
        sel = r.time <= until
        return math.sqrt(np.trapezoid(r.displacement[sel] ** 2, r.time[sel]) / until)

    assert runs["plastic"].peak == pytest.approx(runs["dem"].peak, rel=0.01)
    err = abs(rms(runs["plastic"]) / rms(runs["dem"]) - 1.0)
    assert err < 0.15
    assert err < abs(rms(runs["analytic"]) / rms(runs["dem"]) - 1.0)


def _rms(r):
    return math.sqrt(np.trapezoid(r.displacement ** 2, r.time) / (r.time[-1] - r.time[0]))


@pytest.mark.long
@pytest.mark.parametrize("case", ["paper", "machine-frame"])
def test_shock_rms_within_the_spread_of_the_dems_poured_beds(case):
    """The whole record's RMS against the DEM from random packings (seeds 0-2, the poured
    beds a user fills): within their spread or 15 % of their mean, on the paper's 1-DOF
    (40 N half-sine of 40 ms, 2.5 s) and on the machine frame's mode 1 at the tip (the 1-DOF
    equivalent the DEM runs: 15 kg, 12 Hz, 1 %; its 190 steel spheres; the 1 kN half-sine
    of 10 ms, 2.5 s). docs/analytical.md: measured +0.4 % and -0.3 %; the paper's lattice
    start is the outlier (its columns dissipate more near take-off)."""
    from pdamper.io.scenario import load_scenario
    from pdamper.models import DEMDamper
    from pdamper.structure import SingleDOFStructure

    if case == "paper":
        damper, structure = PAPER_DAMPER, PAPER_STRUCTURE
        t = np.arange(0.0, 1.5005, 1e-3)
        shock = LoadHistory(t, np.where(t < 0.04, 40.0 * np.sin(np.pi * t / 0.04), 0.0),
                            "force", "shock")
    else:
        damper = load_scenario(FRAME / "scenario.toml").damper()
        m, w = 1.0 / 0.2582 ** 2, 2.0 * math.pi * 12.0
        structure = SingleDOFStructure(mass=m, damping=2 * 0.01 * m * w, stiffness=m * w * w)
        t = np.arange(0.0, 0.5005, 1e-4)
        shock = LoadHistory(t, np.where(t < 0.01, 1000.0 * np.sin(np.pi * t / 0.01), 0.0),
                            "force", "shock")
    tail = 2.5 - shock.duration
    block = _rms(run_load(PlasticBedDamper(damper), structure, shock, tail=tail))
    dem = np.array([_rms(run_load(DEMDamper(damper, packing="random", seed=k), structure,
                                  shock, tail=tail)) for k in range(3)])
    inside = dem.min() <= block <= dem.max()
    assert inside or abs(block / dem.mean() - 1.0) < 0.15
