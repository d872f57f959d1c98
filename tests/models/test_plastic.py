"""The plastic-bed fidelity (pdamper.models.plastic): registered, its Level II answers
against the analytical closed forms where their assumptions hold, its declarations."""

import dataclasses

import numpy as np
import pytest

from pdamper.analysis.modes import MotionMode
from pdamper.models import AnalyticalDamper, PlasticBedDamper
from pdamper.models.registry import DAMPER_MODELS, get_damper_model, input_users, not_used
from pdamper.parameters import PAPER_DAMPER

#: 20 points over the closed forms' repetitive motion modes (f [Hz], X [m]) of the paper's
#: damper: single and double collect-and-collide, harmonic and subharmonic of orders 1-3.
POINTS = [
    (4.0, 0.020), (4.0, 0.032), (6.0, 0.010), (6.0, 0.020), (8.0, 0.005), (8.0, 0.010),
    (10.0, 0.005),                                                     # single, harmonic
    (4.0, 0.050), (6.0, 0.050), (8.0, 0.032), (10.0, 0.032), (14.0, 0.080),
    (18.0, 0.050), (25.0, 0.120),                                      # double, harmonic
    (8.0, 0.020), (10.0, 0.020), (14.0, 0.010), (25.0, 0.005),         # single, subharmonic
    (25.0, 0.020), (4.0, 0.120),                                       # double, sub / harm.
]


def test_registered_under_its_fidelity_name():
    assert DAMPER_MODELS["plastic"] is PlasticBedDamper
    assert get_damper_model("plastic") is PlasticBedDamper
    assert PlasticBedDamper.coupling == "plastic_bed"


def test_friction_and_cor_are_declared_unused():
    for f in ("particles.friction", "restitution.particle_wall", "dem.restitution_pp"):
        assert "plastic" not in input_users(f)
    assert input_users("particles.friction") == ["dem"]
    assert "plastic" in input_users("particles.count")
    assert "plastic" in input_users("container.length")
    why = not_used(PlasticBedDamper, ["particles.friction", "particles.count"])
    assert list(why) == ["particles.friction"]
    assert why["particles.friction"]["fidelity"] == "plastic"
    assert why["particles.friction"]["used_by"] == ["dem"]


def test_help_and_scenario_choices_list_every_fidelity(cli):
    from pdamper.io.scenario import SimulationSpec

    choices = SimulationSpec.model_fields["model"].json_schema_extra["choices"]
    assert set(choices) == set(DAMPER_MODELS)
    code, out, _ = cli("simulate", "--help")
    assert code == 0
    assert "plastic" in out


def test_twenty_points_eta_within_2_percent_of_the_closed_form_where_it_holds():
    f, x = np.array(POINTS).T
    closed = AnalyticalDamper(PAPER_DAMPER).response(f, x)
    ours = PlasticBedDamper(PAPER_DAMPER).response(f, x)
    holds = closed.diagnostics["assumptions_hold"]
    assert holds.sum() == 20  # the points are inside the closed forms' assumptions
    rel = np.abs(ours.loss_factor / closed.loss_factor - 1.0)
    assert rel.max() < 0.02, rel
    # the same motion mode and subharmonic order (the orbit's period 1 + n_s)
    np.testing.assert_array_equal(ours.mode, closed.mode)
    np.testing.assert_array_equal(ours.subharmonic_order, closed.subharmonic_order)
    assert {MotionMode(int(c)) for c in ours.mode} == {
        MotionMode.SINGLE_CAC_HARMONIC, MotionMode.DOUBLE_CAC_HARMONIC,
        MotionMode.SINGLE_CAC_SUBHARMONIC, MotionMode.DOUBLE_CAC_SUBHARMONIC}
    # Eq. (2): E~ = 2 pi eta (1/2 m_bed V^2), Eq. (4) the block's first harmonic
    v = x * 2 * np.pi * f
    np.testing.assert_allclose(ours.dissipated_energy_per_cycle,
                               np.pi * ours.loss_factor * PAPER_DAMPER.bed_mass * v * v,
                               rtol=1e-12)
    assert ours.diagnostics["assumptions_hold"].all()
    np.testing.assert_allclose(ours.diagnostics["loss_factor_complex_power"],
                               ours.loss_factor, rtol=1e-3)


def test_answers_where_the_closed_forms_do_not():
    """25 Hz / 10 mm: the closed forms fall back on Eq. (8)'s 1e-3 (scattering, their
    assumptions do not hold); the block dissipates as the DEM does there (0.13-0.3)."""
    closed = AnalyticalDamper(PAPER_DAMPER).response(25.0, 0.010)
    ours = PlasticBedDamper(PAPER_DAMPER).response(25.0, 0.010)
    assert not bool(closed.diagnostics["assumptions_hold"])
    assert 0.1 < float(ours.loss_factor) < 0.4
    assert bool(ours.diagnostics["assumptions_hold"])
    # solid-like: no loss at all (not Eq. 8's convention)
    solid = PlasticBedDamper(PAPER_DAMPER).response(4.0, 0.01)
    assert float(solid.loss_factor) == 0.0 and int(solid.mode) == int(MotionMode.SOLID)


def test_a_single_ball_is_outside_the_blocks_assumption():
    ball = dataclasses.replace(PAPER_DAMPER, length=0.041, width=0.041, depth=0.041,
                               particle_radius=0.02, count=1)
    r = PlasticBedDamper(ball).response(10.0, 0.01)
    assert not bool(r.diagnostics["assumptions_hold"])
    assert "use dem" in str(r.diagnostics["assumptions"])


def test_gravity_is_an_option_and_zero_gravity_gives_four_over_pi():
    m = PlasticBedDamper(PAPER_DAMPER, gravity=0.0)
    h = PAPER_DAMPER.clearance
    r = m.response(10.0, h / np.pi)
    assert float(r.loss_factor) == pytest.approx(4.0 / np.pi, rel=1e-4)  # Eq. (21)
    assert m.clone(gravity=9.81).gravity == 9.81


def test_map_of_the_plastic_fidelity_through_the_cli(cli, tmp_path):
    import xarray as xr

    out = tmp_path / "plastic.nc"
    code, _, err = cli("map", "--model", "plastic", "--frequency", "6Hz:25Hz:3",
                       "--amplitude", "10mm:32mm:2", "--out", out)
    assert code == 0, err
    ds = xr.open_dataset(out)
    f, x = np.meshgrid(ds["frequency"].values, ds["amplitude"].values, indexing="ij")
    ref = PlasticBedDamper(PAPER_DAMPER).response(f, x)
    eta = ds["loss_factor"].transpose("frequency", "amplitude").values
    np.testing.assert_allclose(eta, ref.loss_factor, rtol=1e-12)
    modes = ds["motion_mode"].transpose("frequency", "amplitude").values
    np.testing.assert_array_equal(modes, ref.mode)
