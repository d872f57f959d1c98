"""Contact search of the DEM kernels (:mod:`pdamper.dem.kernels.search`)."""

from __future__ import annotations

import numpy as np
import pytest

from pdamper.dem.kernels.search import build_verlet_list, carry_history
from pdamper.dem.kernels.state import PairContacts, World
from pdamper.dem.packing import random_packing


def brute_pairs(pos, rad, skin):
    d = np.linalg.norm(pos[:, None] - pos[None], axis=-1)
    cut = rad[:, None] + rad[None] + skin
    i, j = np.nonzero(np.triu(d < cut, 1))
    return set(zip(i.tolist(), j.tolist(), strict=True))


@pytest.mark.parametrize("n, seed, box", [(50, 1, (0.03, 0.03, 0.05)),
                                         (400, 2, (0.06, 0.06, 0.1))])
def test_verlet_list_equals_brute_force(n, seed, box):
    """Linked-cell search finds exactly the pairs closer than r_i + r_j + skin."""
    rng = np.random.default_rng(seed)
    rad = rng.uniform(0.002, 0.004, n)
    pos = random_packing(n, rad, box, seed=seed)
    skin = 0.001
    cell = 2 * rad.max() + skin
    ncx, ncy, ncz = (int(b // cell) for b in box)
    world = World(*box, 9.81, skin, cell, ncx, ncy, ncz)
    head = np.zeros(ncx * ncy * ncz, np.int64)
    nxt = np.zeros(n, np.int64)
    start = np.zeros(n + 1, np.int64)
    nb = np.zeros(40 * n, np.int64)
    cnt = build_verlet_list(pos, rad, 0.0, world, head, nxt, start, nb)
    found = {(i, int(nb[b])) for i in range(n) for b in range(start[i], start[i + 1])}
    assert cnt == len(found) > n / 4
    assert found == brute_pairs(pos, rad, skin)
    for i in range(n):  # sorted per particle (needed to carry the history over)
        seg = nb[start[i]:start[i + 1]]
        assert np.all(np.diff(seg) > 0)
    # a too small list is reported, not overrun
    assert build_verlet_list(pos, rad, 0.0, world, head, nxt, start,
                             np.zeros(max(cnt - 1, 0), np.int64)) == -1


def test_history_carried_over_by_merge():
    """Contact history survives a rebuild for pairs present in both lists."""
    o_start = np.array([0, 2, 3, 3])
    o_j = np.array([1, 2, 2])
    o_act = np.array([1, 0, 1])
    o_k = np.array([5.0, 0.0, 7.0])
    o_d = np.array([0.5, 0.0, 0.7])
    o_v = np.array([1.0, 0.0, 2.0])
    s_start = np.array([0, 1, 2, 2])
    s_j = np.array([2, 2])
    s_act = np.zeros(2, np.int64)
    s_k = np.zeros(2)
    s_d = np.zeros(2)
    s_v = np.zeros(2)
    carry_history(3, PairContacts(o_start, o_j, o_act, o_k, o_d, o_v),
                  PairContacts(s_start, s_j, s_act, s_k, s_d, s_v))
    assert s_act.tolist() == [0, 1] and s_k.tolist() == [0.0, 7.0] and s_d.tolist() == [0.0, 0.7]
    assert s_v.tolist() == [0.0, 2.0]


def test_spring_law_displacements_carried_over_by_merge():
    """The spring friction law's tangential displacements and damping factors move with
    their pairs at a rebuild (rows of ``xi``); a pair new to the list keeps what its row
    held until its onset zeroes it (``spring_onset``)."""
    o_start = np.array([0, 2, 3, 3])
    o_j = np.array([1, 2, 2])
    o_xi = np.array([[1.0, 2.0, 3.0, 0.1], [4.0, 5.0, 6.0, 0.2], [7.0, 8.0, 9.0, 0.3]])
    s_start = np.array([0, 1, 2, 2])
    s_j = np.array([2, 2])
    s_xi = np.full((2, 4), -1.0)
    z = np.zeros(3)
    carry_history(3, PairContacts(o_start, o_j, np.ones(3, np.int64), z, z, z, o_xi),
                  PairContacts(s_start, s_j, np.zeros(2, np.int64), np.zeros(2), np.zeros(2),
                               np.zeros(2), s_xi))
    # pair (0, 2) was entry 1, pair (1, 2) entry 2
    assert s_xi.tolist() == [[4.0, 5.0, 6.0, 0.2], [7.0, 8.0, 9.0, 0.3]]
