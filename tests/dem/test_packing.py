"""Tests of pdamper.dem.packing: lattice and random initial positions, container sizes."""

from __future__ import annotations

import math
import re
import time

import numpy as np
import pytest
from scipy.spatial import cKDTree

from pdamper.dem.packing import (
    RANDOM_FILL_LIMIT,
    dense_packing,
    lattice_layers,
    max_layers,
    max_particles,
    random_packing,
    scaled_box,
    sequential_packing,
    spheres_per_layer,
)
from pdamper.errors import InputError

BOX = (0.04, 0.04, 0.12)  # benchmark container [m]
R = 0.005  # benchmark sphere radius [m]


def min_pair_distance(x: np.ndarray) -> float:
    d, _ = cKDTree(x).query(x, k=2)
    return float(d[:, 1].min())


def assert_inside(x: np.ndarray, radius, box, tol: float = 1e-12) -> None:
    r = np.broadcast_to(np.asarray(radius, dtype=float), (x.shape[0],))[:, None]
    assert np.all(x - r >= -tol)
    assert np.all(x + r <= np.asarray(box) + tol)


def test_benchmark_capacity_is_16_per_layer_12_layers_192_spheres():
    assert spheres_per_layer(BOX, R) == 16
    assert max_layers(BOX, R) == 12
    assert max_particles(BOX, R) == 192


def test_capacity_counts_exact_fit_despite_rounding():
    # 0.3 / 0.1 is 2.9999999999999996 in floating point
    assert spheres_per_layer((0.3, 0.3, 0.3), 0.05) == 9
    assert max_layers((0.3, 0.3, 0.3), 0.05) == 3


def test_capacity_with_gap_is_smaller():
    assert max_particles(BOX, R, gap=1e-4) == 3 * 3 * 11


def test_lattice_32_spheres_are_two_full_touching_layers_inside_the_walls():
    x = lattice_layers(32, R, BOX)
    assert x.shape == (32, 3)
    assert_inside(x, R, BOX)
    assert min_pair_distance(x) >= 2 * R - 1e-12
    z_levels = np.unique(np.round(x[:, 2], 12))
    np.testing.assert_allclose(z_levels, [R, 3 * R], rtol=0, atol=1e-15)
    assert np.sum(np.isclose(x[:, 2], R)) == 16
    # each layer is the full 4 x 4 grid, i.e. 16 columns of two spheres
    cols = {(round(a, 9), round(b, 9)) for a, b in x[:, :2]}
    assert len(cols) == 16


def test_lattice_bottom_layer_rests_on_floor():
    x = lattice_layers(5, R, BOX)
    np.testing.assert_array_equal(x[:, 2], np.full(5, R))


def test_lattice_full_box_fills_192_without_overlap():
    x = lattice_layers(192, R, BOX)
    assert_inside(x, R, BOX)
    assert min_pair_distance(x) >= 2 * R - 1e-12
    assert x[:, 2].max() == pytest.approx(BOX[2] - R, abs=1e-12)


def test_lattice_partial_last_layer_is_deterministic_and_centred_layers():
    a = lattice_layers(21, R, BOX)
    b = lattice_layers(21, R, BOX)
    np.testing.assert_array_equal(a, b)
    assert np.sum(a[:, 2] > 2 * R) == 5
    # first 16 are the 40 mm x 40 mm layer, centred in x and y
    np.testing.assert_allclose(a[:16, :2].mean(axis=0), [0.02, 0.02], atol=1e-15)


def test_lattice_with_gap_keeps_the_gap_and_stays_centred():
    gap = 1e-4
    box = (0.05, 0.05, 0.1)
    x = lattice_layers(40, R, box, gap=gap)
    assert min_pair_distance(x) >= 2 * R + gap - 1e-12
    assert_inside(x, R, box)
    layer = x[np.isclose(x[:, 2], R)]
    np.testing.assert_allclose(layer[:, :2].mean(axis=0), [0.025, 0.025], atol=1e-12)


def test_lattice_zero_spheres_gives_empty_array():
    assert lattice_layers(0, R, BOX).shape == (0, 3)


def test_lattice_too_many_spheres_raises_count_error_with_range():
    with pytest.raises(InputError, match=r"particles\.count.*\[0, 192\].*200") as info:
        lattice_layers(200, R, BOX)
    assert info.value.field == "particles.count"


@pytest.mark.parametrize("n", [-1, 2.5, "3", True])
def test_lattice_bad_count_raises_count_error(n):
    with pytest.raises(InputError, match=r"particles\.count"):
        lattice_layers(n, R, BOX)


@pytest.mark.parametrize("radius", [-0.005, 0.0, math.nan, math.inf])
def test_lattice_bad_radius_raises_radius_error(radius):
    with pytest.raises(InputError, match=r"particles\.radius"):
        lattice_layers(10, radius, BOX)


@pytest.mark.parametrize(
    "box", [(0.04, 0.04, math.nan), (0.04, -0.04, 0.12), (0.04, 0.04), (0.04, 0.008, 0.12)]
)
def test_lattice_bad_box_raises_box_error(box):
    with pytest.raises(InputError, match=r"container\.box"):
        lattice_layers(10, R, box)


def test_lattice_negative_gap_raises_gap_error():
    with pytest.raises(InputError, match=r"particles\.gap"):
        lattice_layers(10, R, BOX, gap=-1e-4)


def test_random_packing_has_no_overlaps_and_stays_inside():
    x = random_packing(64, R, BOX, seed=3)
    assert x.shape == (64, 3)
    assert_inside(x, R, BOX, tol=0.0)
    assert min_pair_distance(x) >= 2 * R


def test_random_packing_same_seed_same_positions_other_seed_different():
    a = random_packing(50, R, BOX, seed=42)
    b = random_packing(50, R, BOX, seed=42)
    c = random_packing(50, R, BOX, seed=43)
    np.testing.assert_array_equal(a, b)
    assert not np.allclose(a, c)


def test_random_packing_per_particle_radii_respected():
    rng = np.random.default_rng(0)
    radii = rng.uniform(0.002, 0.005, size=80)
    x = random_packing(80, radii, BOX, seed=1)
    assert_inside(x, radii, BOX, tol=0.0)
    d = np.linalg.norm(x[:, None, :] - x[None, :, :], axis=-1)
    contact = radii[:, None] + radii[None, :]
    off = ~np.eye(80, dtype=bool)
    assert np.all(d[off] >= contact[off])


def test_random_packing_per_particle_radii_wrong_length_raises():
    with pytest.raises(InputError, match=r"particles\.radius"):
        random_packing(10, np.full(9, R), BOX, seed=0)


def test_random_packing_10000_spheres_in_scaled_box_is_fast():
    box = scaled_box(10_000, R)
    random_packing(10, R, box, seed=0)  # compile (or load) the kernel outside the timing
    t0 = time.perf_counter()
    x = random_packing(10_000, R, box, seed=7)
    elapsed = time.perf_counter() - t0
    assert elapsed < 5.0
    assert x.shape == (10_000, 3)
    assert_inside(x, R, box, tol=0.0)
    assert min_pair_distance(x) >= 2 * R


def test_random_packing_refuses_more_than_fill_limit():
    n = 192  # lattice capacity: fills pi/6 = 0.52 of the box
    with pytest.raises(InputError, match=r"particles\.count.*fill 0\.52"):
        random_packing(n, R, BOX, seed=0)
    assert RANDOM_FILL_LIMIT < math.pi / 6


def test_random_packing_gives_up_cleanly_after_max_attempts():
    # 120 spheres fill 0.33 < limit of the narrow benchmark box, but the walls make it jam
    with pytest.raises(InputError, match=r"particles\.count.*could place only"):
        sequential_packing(120, R, BOX, seed=0, max_attempts=2000)


@pytest.mark.parametrize("seed", [-1, 1.5, None, True])
def test_random_packing_bad_seed_raises_seed_error(seed):
    with pytest.raises(InputError, match=r"particles\.seed"):
        random_packing(5, R, BOX, seed=seed)


def test_random_packing_nan_radius_raises_radius_error():
    with pytest.raises(InputError, match=r"particles\.radius"):
        random_packing(5, math.nan, BOX, seed=0)


# ------------------------------------------------------------------------- dense beds

FRAME_BOX = (0.040, 0.041, 0.041)  # the machine frame's container [m]: 4 x 4 x 4 = 64 sites


def lattice_share(x: np.ndarray, radius: float, box) -> float:
    """Share of the centres within radius / 10 of a site of the container's lattice."""
    sites = lattice_layers(max_particles(box, radius), radius, box)
    d, _ = cKDTree(sites).query(x)
    return float(np.mean(d < 0.1 * radius))


def test_40_tungsten_spheres_in_the_frames_box_pack_at_random():
    from pdamper.dem import ParticleSet
    from pdamper.materials import get_material

    # sequential addition alone jams here (a third of the lattice's fill)
    with pytest.raises(InputError, match=r"particles\.count"):
        sequential_packing(40, R, FRAME_BOX, seed=0)
    ps = ParticleSet.random(40, FRAME_BOX, R, get_material("tungsten"), seed=0)
    x = ps.positions
    assert x.shape == (40, 3)
    assert_inside(x, R, FRAME_BOX, tol=1e-12)
    assert min_pair_distance(x) >= 2 * R
    # not a lattice: few centres on the lattice's sites, heights spread over many levels
    assert lattice_share(x, R, FRAME_BOX) < 0.25
    assert np.unique(np.round(x[:, 2] / R, 2)).size > 20


@pytest.mark.parametrize("box", [
    (0.04, 0.04, 0.12),   # tall: the benchmark box, 192 sites
    (0.10, 0.10, 0.02),   # flat: two layers of 10 x 10
    FRAME_BOX,            # cubic: 64 sites
], ids=["tall", "flat", "cubic"])
def test_ninety_percent_of_the_lattice_count_packs_at_random(box):
    n = math.ceil(0.9 * max_particles(box, R))
    for seed in (0, 1):
        x = random_packing(n, R, box, seed=seed)
        assert x.shape == (n, 3)
        assert_inside(x, R, box, tol=1e-12)
        assert min_pair_distance(x) >= 2 * R * (1 + 1e-6)
        assert lattice_share(x, R, box) < 0.5


def test_dense_bed_is_reproducible_from_its_seed():
    a = random_packing(58, R, FRAME_BOX, seed=5)
    b = random_packing(58, R, FRAME_BOX, seed=5)
    c = random_packing(58, R, FRAME_BOX, seed=6)
    np.testing.assert_array_equal(a, b)
    assert not np.allclose(a, c)
    np.testing.assert_array_equal(dense_packing(58, R, FRAME_BOX, seed=5), a)


@pytest.mark.parametrize("n, seed", [(64, 3), (50, 42), (100, 0)])
def test_random_packing_is_sequential_addition_where_that_places_every_sphere(n, seed):
    np.testing.assert_array_equal(random_packing(n, R, BOX, seed=seed),
                                  sequential_packing(n, R, BOX, seed=seed))


def test_a_growth_that_jams_early_grows_again_from_new_centres():
    """60 of the frame box's 64 sites: the first growth from seed 3 jams at 0.94 of the
    volume, a second one from new random centres packs them."""
    from pdamper.dem.packing import _grow

    radii = np.full(60, R)
    fill = 60 * 4 / 3 * math.pi * R**3 / math.prod(FRAME_BOX)
    bed, share = _grow(radii, FRAME_BOX, np.random.default_rng([3, 1]), fill, 1e-6)
    assert bed is None and share < 0.97
    x = random_packing(60, R, FRAME_BOX, seed=3)
    assert_inside(x, R, FRAME_BOX, tol=1e-12)
    assert min_pair_distance(x) >= 2 * R * (1 + 1e-6)


def test_dense_bed_of_unequal_spheres_keeps_their_distances():
    radii = np.random.default_rng(2).uniform(0.003, 0.005, size=120)
    x = random_packing(120, radii, BOX, seed=1)
    assert_inside(x, radii, BOX, tol=1e-12)
    d = np.linalg.norm(x[:, None, :] - x[None, :, :], axis=-1)
    contact = radii[:, None] + radii[None, :]
    off = ~np.eye(120, dtype=bool)
    assert np.all(d[off] >= contact[off])


INTERNAL = ("attempt", "max_attempts", "margin", "RANDOM_FILL_LIMIT", "lattice_layers",
            "step", "relax")


def test_more_spheres_than_the_container_holds_are_refused_by_user_keys():
    with pytest.raises(InputError, match=r"particles\.count.*\[0, 64\].*40x41x41 mm.*65"):
        random_packing(65, R, FRAME_BOX, seed=0)


def test_a_bed_too_dense_for_random_is_refused_with_the_count_that_fits():
    with pytest.raises(InputError) as info:
        random_packing(64, R, FRAME_BOX, seed=0)
    err = info.value
    assert err.field == "particles.count"
    text = str(err)
    assert "--particles" in text and "container.box" in text and "40x41x41 mm" in text
    fits = int(re.search(r"holds about (\d+)", text).group(1))
    assert 0.85 * 64 <= fits < 64
    assert not any(word in text for word in INTERNAL)
    # asked again (a map's points with packing "auto"): the same refusal, without the growths
    t0 = time.perf_counter()
    with pytest.raises(InputError) as again:
        random_packing(64, R, FRAME_BOX, seed=0)
    assert time.perf_counter() - t0 < 0.05
    assert str(again.value) == text


def test_scaled_box_reproduces_benchmark_for_32_spheres():
    assert scaled_box(32, R) == pytest.approx(BOX, abs=1e-15)


@pytest.mark.parametrize("n", [1, 16, 32, 100, 192, 193, 1000, 10_000])
def test_scaled_box_is_square_whole_diameters_and_holds_n(n):
    lx, ly, lz = scaled_box(n, R)
    d = 2 * R
    assert lx == ly
    for length in (lx, lz):
        assert length / d == pytest.approx(round(length / d), abs=1e-9)
    assert max_particles((lx, ly, lz), R) >= n
    per_layer = spheres_per_layer((lx, ly, lz), R)
    bed_layers = math.ceil(n / per_layer)
    assert bed_layers <= 12
    assert bed_layers * d / lz <= 1 / 6 + 1e-12
    if n <= 192:
        assert lx == pytest.approx(0.04)


def test_scaled_box_widens_above_192_spheres():
    assert scaled_box(10_000, R) == pytest.approx((0.29, 0.29, 0.72))


@pytest.mark.long
def test_dense_tungsten_bed_settles_in_the_dem_inside_the_frames_box():
    """The DEM starts from the dense random bed (90 % of the lattice's count) and settles it
    under gravity: every sphere stays inside the walls, overlaps stay elastic-small and the
    bed comes to rest below its height when it started."""
    from dem_inputs import container, engine
    from pdamper.dem import HarmonicMotion, ParticleSet
    from pdamper.materials import get_material

    tungsten = get_material("tungsten")
    ps = ParticleSet.random(58, FRAME_BOX, R, tungsten, seed=0)
    # the settling does not depend on the motion; it only fixes the sampling
    bed = engine(ps, container(FRAME_BOX), motion=HarmonicMotion(0.01, 10.0),
                 settle_time=0.5).settle()
    x = bed.state.pos
    assert_inside(x, R, FRAME_BOX, tol=0.01 * R)
    assert min_pair_distance(x) >= 2 * R * (1 - 0.01)
    weight = 58 * float(ps.masses[0]) * 9.81
    assert bed.kinetic_energy < 1e-3 * weight * R
    assert x[:, 2].mean() < ps.positions[:, 2].mean()
