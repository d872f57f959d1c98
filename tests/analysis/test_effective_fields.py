"""Effective fields on grids (Fig. 5): the vectorised path and the sweep engine give the
same variables; failed points are kept with their status and error."""

from __future__ import annotations

import numpy as np
import pytest

from pdamper.analysis.fields import effective_field, field_point, sweep_field
from pdamper.analysis.modes import MotionMode
from pdamper.errors import SimulationError
from pdamper.models import AnalyticalDamper
from pdamper.parameters import PAPER_DAMPER


class FlakyAnalytical(AnalyticalDamper):
    """The analytical model, failing at 10 Hz (a stand-in for an unstable DEM point)."""

    def response(self, frequency, amplitude):
        if np.any(np.asarray(frequency) == 10.0):
            raise SimulationError("unstable run at 10 Hz")
        return super().response(frequency, amplitude)


F, X = np.array([5.0, 10.0, 15.0]), np.array([0.01, 0.03])


def test_sweep_and_vectorised_fields_agree_point_for_point(tmp_path):
    model = AnalyticalDamper(PAPER_DAMPER)
    vec = effective_field(model, F, X)
    swept, sweep = sweep_field(model, F, X, store=tmp_path / "s", serial=True)
    for v in ("loss_factor", "effective_mass_ratio", "dissipated_energy_per_cycle",
              "motion_mode", "subharmonic_order", "stationary", "status"):
        np.testing.assert_array_equal(swept[v].values, vec[v].values, err_msg=v)
    assert sweep.computed == 6 and (swept["status"] == 0).all()
    assert (swept["stationary"] == 1).all() and swept["error"].values.tolist() == [[""] * 2] * 3


def test_failed_points_are_recorded_not_dropped(tmp_path):
    ds, sweep = sweep_field(FlakyAnalytical(PAPER_DAMPER), F, X, store=tmp_path / "s",
                            serial=True, retries=1)
    assert ds["status"].values.tolist() == [[0, 0], [1, 1], [0, 0]]
    assert ds["error"].values[1, 0] == "SimulationError: unstable run at 10 Hz"
    assert np.isnan(ds["loss_factor"].values[1]).all() and (ds["motion_mode"][1] == -1).all()
    assert (ds["attempts"].values[1] == 2).all() and ds.attrs["points_failed"] == 2
    ds.to_netcdf(tmp_path / "f.nc", engine="h5netcdf")  # strings and flags write cleanly


def test_particle_count_axis():
    model = AnalyticalDamper(PAPER_DAMPER)
    ds = effective_field(model, F, X, particles=[16, 32, 64])
    assert ds["loss_factor"].dims == ("particles", "frequency", "amplitude")
    one = effective_field(AnalyticalDamper(PAPER_DAMPER.with_count(64)), F, X)
    np.testing.assert_array_equal(ds["loss_factor"].sel(particles=64).values,
                                  one["loss_factor"].values)
    assert ds["bed_mass"].values == pytest.approx([PAPER_DAMPER.with_count(n).bed_mass
                                                   for n in (16, 32, 64)])
    swept, _ = sweep_field(model, F, X, particles=[16, 64], serial=True)
    np.testing.assert_array_equal(swept["loss_factor"].values,
                                  ds["loss_factor"].sel(particles=[16, 64]).values)


def test_field_point_returns_plain_numbers():
    out = field_point(AnalyticalDamper(PAPER_DAMPER), {"frequency": 10.0, "amplitude": 0.032,
                                                        "particles": 64})
    assert out["motion_mode"] == 3 and out["stationary"] == 1
    assert out["bed_mass"] == pytest.approx(PAPER_DAMPER.with_count(64).bed_mass)
    assert all(isinstance(v, int | float | str) for v in out.values())


def test_field_agreement_counts_modes_and_loss_factor_differences():
    from pdamper.analysis.fields import field_agreement

    model = AnalyticalDamper(PAPER_DAMPER)
    ref = effective_field(model, F, X)
    other = ref.copy(deep=True)
    assert field_agreement(other, ref)["mode_agreement"] == 1.0
    other["loss_factor"][0, 0] += 0.4
    other["motion_mode"][0, 0] = 5
    other["status"][2, 1] = 1  # a failed point does not count
    a = field_agreement(other, ref)
    assert a["cells"] == 5 and a["failed"] == 1
    assert a["mode_agreement"] == pytest.approx(4 / 5)
    by = a["by_mode"][MotionMode(int(ref["motion_mode"][0, 0])).label]
    assert by["mode_agreement"] < 1.0
    assert sum(v["cells"] for v in a["by_mode"].values()) == 5


def test_a_grid_no_machine_holds_is_refused_from_its_axes():
    """10^10 points (10^5 x 10^5) used to hang; the axes' lengths are judged by the hard
    limits of :mod:`pdamper.resources` before the grid exists, whatever form they have."""
    from answers import memory_headroom
    from pdamper.errors import InputError

    axis = np.linspace(1.0, 20.0, 100_000)
    with memory_headroom(2**30):
        for run in (effective_field, sweep_field):
            for f, x in ((axis, axis * 1e-3), (range(1, 10**10), [0.01])):
                with pytest.raises(InputError) as info:
                    run(AnalyticalDamper(PAPER_DAMPER), f, x)
                assert info.value.field == "frequency"
                assert "more than this machine has" in info.value.message
