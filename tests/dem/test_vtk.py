"""Tests of pdamper.dem.vtk: ParaView .vtp/.pvd export."""

from __future__ import annotations

import xml.etree.ElementTree as ET

import numpy as np
import pytest

from pdamper.dem.vtk import read_pvd, read_vtp, write_container_vtk, write_vtk_series
from pdamper.errors import InputError

NT, N = 4, 7


@pytest.fixture
def series():
    rng = np.random.default_rng(0)
    times = np.array([0.0, 0.001, 0.0025, 0.1])
    pos = rng.uniform(0.0, 0.04, size=(NT, N, 3))
    vel = rng.normal(size=(NT, N, 3))
    omega = rng.normal(size=(NT, N, 3))
    return times, pos, vel, omega


@pytest.mark.parametrize("encoding", ["ascii", "binary"])
def test_vtp_files_parse_and_point_count_matches(tmp_path, series, encoding):
    times, pos, vel, omega = series
    pvd = write_vtk_series(tmp_path / "out", times, pos, velocities=vel, radii=0.005,
                           angular_velocities=omega, encoding=encoding)
    assert pvd == tmp_path / "out" / "particles.pvd"
    files = sorted((tmp_path / "out").glob("particles_*.vtp"))
    assert len(files) == NT
    for f in files:
        root = ET.parse(f).getroot()
        assert root.get("type") == "PolyData"
        piece = root.find("PolyData/Piece")
        assert int(piece.get("NumberOfPoints")) == N
        assert int(piece.get("NumberOfVerts")) == N
        names = {da.get("Name") for da in piece.findall("PointData/DataArray")}
        assert names == {"radius", "velocity", "speed", "angular_velocity"}


@pytest.mark.parametrize("encoding", ["ascii", "binary"])
def test_vtp_round_trip_values_are_exact(tmp_path, series, encoding):
    times, pos, vel, omega = series
    radii = np.linspace(0.004, 0.006, N)
    extra = {"contacts": np.arange(NT * N, dtype=float).reshape(NT, N)}
    pvd = write_vtk_series(tmp_path, times, pos, velocities=vel, radii=radii,
                           angular_velocities=omega, extra_point_data=extra,
                           encoding=encoding)
    for k, (_, path) in enumerate(read_pvd(pvd)):
        data = read_vtp(path)
        np.testing.assert_array_equal(data["Points"], pos[k])
        np.testing.assert_array_equal(data["velocity"], vel[k])
        np.testing.assert_array_equal(data["angular_velocity"], omega[k])
        np.testing.assert_array_equal(data["radius"], radii)
        np.testing.assert_allclose(data["speed"], np.linalg.norm(vel[k], axis=1))
        np.testing.assert_array_equal(data["contacts"], extra["contacts"][k])


def test_pvd_lists_every_timestep_with_its_time(tmp_path, series):
    times, pos, _, _ = series
    pvd = write_vtk_series(tmp_path, times, pos, prefix="run1")
    root = ET.parse(pvd).getroot()
    assert root.get("type") == "Collection"
    datasets = root.findall("Collection/DataSet")
    assert [float(ds.get("timestep")) for ds in datasets] == times.tolist()
    for ds in datasets:
        assert (tmp_path / ds.get("file")).is_file()
    assert not list(tmp_path.glob("*.tmp"))  # no temporary files left behind


def test_positions_only_writes_points_without_point_data(tmp_path, series):
    times, pos, _, _ = series
    pvd = write_vtk_series(tmp_path, times, pos)
    data = read_vtp(read_pvd(pvd)[0][1])
    assert set(data) == {"Points"}


def test_shape_mismatch_of_velocities_raises_input_error(tmp_path, series):
    times, pos, vel, _ = series
    with pytest.raises(InputError, match=r"vtk\.velocities.*shape"):
        write_vtk_series(tmp_path, times, pos, velocities=vel[:, :-1])


def test_shape_mismatch_of_times_raises_input_error(tmp_path, series):
    times, pos, _, _ = series
    with pytest.raises(InputError, match=r"vtk\.times"):
        write_vtk_series(tmp_path, times[:-1], pos)


def test_positions_of_wrong_rank_raise_input_error(tmp_path, series):
    times, pos, _, _ = series
    with pytest.raises(InputError, match=r"vtk\.positions"):
        write_vtk_series(tmp_path, times, pos[..., :2])


def test_radii_of_wrong_length_raise_input_error(tmp_path, series):
    times, pos, _, _ = series
    with pytest.raises(InputError, match=r"vtk\.radii"):
        write_vtk_series(tmp_path, times, pos, radii=np.ones(N + 1))


def test_non_finite_positions_raise_input_error(tmp_path, series):
    times, pos, _, _ = series
    pos = pos.copy()
    pos[1, 2, 0] = np.nan
    with pytest.raises(InputError, match=r"vtk\.positions"):
        write_vtk_series(tmp_path, times, pos)


def test_reserved_extra_name_raises_input_error(tmp_path, series):
    times, pos, _, _ = series
    with pytest.raises(InputError, match=r"extra_point_data"):
        write_vtk_series(tmp_path, times, pos,
                         extra_point_data={"speed": np.zeros((NT, N))})


def test_container_outline_has_8_points_and_12_edges(tmp_path):
    path = write_container_vtk(tmp_path / "box.vtp", (0.04, 0.04, 0.12), z_offset=0.01)
    piece = ET.parse(path).getroot().find("PolyData/Piece")
    assert piece.get("NumberOfPoints") == "8"
    assert piece.get("NumberOfLines") == "12"
    pts = read_vtp(path)["Points"]
    np.testing.assert_allclose(pts.min(axis=0), [0.0, 0.0, 0.01])
    np.testing.assert_allclose(pts.max(axis=0), [0.04, 0.04, 0.13])
    conn = np.array(piece.find("Lines/DataArray[@Name='connectivity']").text.split(),
                    dtype=int).reshape(12, 2)
    lengths = np.linalg.norm(pts[conn[:, 0]] - pts[conn[:, 1]], axis=1)
    np.testing.assert_allclose(np.sort(lengths), [0.04] * 8 + [0.12] * 4)
