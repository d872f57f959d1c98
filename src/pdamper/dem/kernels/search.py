"""Contact search: a linked-cell grid builds a half Verlet list, whose contact history
survives each rebuild by a merge of the sorted per-particle lists.

The grid lives in the container frame (cells ``>= 2 r_max + skin``), so the cost is linear
in the particle count. A rebuild is due when a particle has moved more than ``skin / 2``
since the last build.
"""

from __future__ import annotations

from numba import njit


@njit(cache=True, fastmath=False, error_model="numpy")
def _cell_index(x, y, zr, cs, ncx, ncy, ncz):
    cx = int(x / cs)
    cy = int(y / cs)
    cz = int(zr / cs)
    cx = min(max(cx, 0), ncx - 1)
    cy = min(max(cy, 0), ncy - 1)
    cz = min(max(cz, 0), ncz - 1)
    return cx, cy, cz


@njit(cache=True, fastmath=False, error_model="numpy", _nrt=False)
def build_verlet_list(pos, rad, zc, world, head, nxt, nb_start, nb_j):
    """Half Verlet list (pairs i < j closer than r_i + r_j + skin) from a linked-cell grid.

    Cost O(n). Each particle's neighbours are sorted by index so that the contact history
    can be carried over by a merge. Returns the number of pairs, or -1 if ``nb_j`` is full.
    """
    n = pos.shape[0]
    cs = world.cell
    skin = world.skin
    ncx = world.ncx
    ncy = world.ncy
    ncz = world.ncz
    cap = nb_j.shape[0]
    for c in range(head.shape[0]):
        head[c] = -1
    # insert in reverse so that each cell's chain runs in increasing index order
    for i in range(n - 1, -1, -1):
        cx, cy, cz = _cell_index(pos[i, 0], pos[i, 1], pos[i, 2] - zc, cs, ncx, ncy, ncz)
        c = (cz * ncy + cy) * ncx + cx
        nxt[i] = head[c]
        head[c] = i
    cnt = 0
    for i in range(n):
        nb_start[i] = cnt
        cx, cy, cz = _cell_index(pos[i, 0], pos[i, 1], pos[i, 2] - zc, cs, ncx, ncy, ncz)
        for dz in range(-1, 2):
            z2 = cz + dz
            if z2 < 0 or z2 >= ncz:
                continue
            for dy in range(-1, 2):
                y2 = cy + dy
                if y2 < 0 or y2 >= ncy:
                    continue
                for dx in range(-1, 2):
                    x2 = cx + dx
                    if x2 < 0 or x2 >= ncx:
                        continue
                    j = head[(z2 * ncy + y2) * ncx + x2]
                    while j >= 0:
                        if j > i:
                            ddx = pos[j, 0] - pos[i, 0]
                            ddy = pos[j, 1] - pos[i, 1]
                            ddz = pos[j, 2] - pos[i, 2]
                            rc = rad[i] + rad[j] + skin
                            if ddx * ddx + ddy * ddy + ddz * ddz < rc * rc:
                                if cnt >= cap:
                                    return -1
                                # insertion into the sorted segment of i
                                k = cnt
                                while k > nb_start[i] and nb_j[k - 1] > j:
                                    nb_j[k] = nb_j[k - 1]
                                    k -= 1
                                nb_j[k] = j
                                cnt += 1
                        j = nxt[j]
    nb_start[n] = cnt
    return cnt


@njit(cache=True, fastmath=False, error_model="numpy", _nrt=False)
def carry_history(n, old, new):
    """Copy the contact history of pairs present in both lists (``old`` -> ``new``,
    :class:`~pdamper.dem.kernels.state.PairContacts`), the spring law's tangential
    displacements included; new pairs start without contact."""
    o_start, o_j, o_act, o_k, o_d, o_v = old.start, old.j, old.active, old.k, old.d, old.v0
    s_start, s_j, s_act, s_k, s_d, s_v = new.start, new.j, new.active, new.k, new.d, new.v0
    o_xi = old.xi
    s_xi = new.xi
    spring = s_xi.shape[0] > 0
    for i in range(n):
        a = o_start[i]
        a_end = o_start[i + 1]
        for b in range(s_start[i], s_start[i + 1]):
            jb = s_j[b]
            while a < a_end and o_j[a] < jb:
                a += 1
            if a < a_end and o_j[a] == jb:
                s_act[b] = o_act[a]
                s_k[b] = o_k[a]
                s_d[b] = o_d[a]
                s_v[b] = o_v[a]
                if spring:
                    for c in range(4):
                        s_xi[b, c] = o_xi[a, c]
            else:
                s_act[b] = 0
                s_k[b] = 0.0
                s_d[b] = 0.0
                s_v[b] = 0.0


@njit(cache=True, fastmath=False, error_model="numpy", _nrt=False)
def rebuild(pos, rad, zc, world, nbrs):
    """Rebuild the Verlet list keeping the contact history; returns the pair count or -1
    (list full)."""
    cur = nbrs.pairs
    new = nbrs.spare
    n = pos.shape[0]
    cnt = build_verlet_list(pos, rad, zc, world, nbrs.head, nbrs.nxt, new.start, new.j)
    if cnt < 0:
        return -1
    carry_history(n, cur, new)
    c_start, c_j, c_act, c_k, c_d, c_v = cur.start, cur.j, cur.active, cur.k, cur.d, cur.v0
    s_start, s_j, s_act, s_k, s_d, s_v = new.start, new.j, new.active, new.k, new.d, new.v0
    c_xi = cur.xi
    s_xi = new.xi
    for i in range(n + 1):
        c_start[i] = s_start[i]
    for b in range(cnt):
        c_j[b] = s_j[b]
        c_act[b] = s_act[b]
        c_k[b] = s_k[b]
        c_d[b] = s_d[b]
        c_v[b] = s_v[b]
    if c_xi.shape[0] > 0:
        for b in range(cnt):
            for c in range(4):
                c_xi[b, c] = s_xi[b, c]
    pb = nbrs.pos_build
    for i in range(n):
        pb[i, 0] = pos[i, 0]
        pb[i, 1] = pos[i, 1]
        pb[i, 2] = pos[i, 2]
    return cnt


@njit(cache=True, inline="always")
def needs_rebuild(pos, pos_build, skin, act, na):
    """Rebuild criterion: one of the particles ``act[:na]`` moved more than skin/2 since
    the last build (the others, in free flight, are known not to have)."""
    lim = 0.25 * skin * skin
    for k in range(na):
        i = act[k]
        dx = pos[i, 0] - pos_build[i, 0]
        dy = pos[i, 1] - pos_build[i, 1]
        dz = pos[i, 2] - pos_build[i, 2]
        if dx * dx + dy * dy + dz * dz > lim:
            return True
    return False


@njit(cache=True, inline="always")
def max_displacement2(pos, pos_build):
    """Largest squared displacement of a particle since the last build [m^2]."""
    d2max = 0.0
    for i in range(pos.shape[0]):
        dx = pos[i, 0] - pos_build[i, 0]
        dy = pos[i, 1] - pos_build[i, 1]
        dz = pos[i, 2] - pos_build[i, 2]
        d2 = dx * dx + dy * dy + dz * dz
        if d2 > d2max:
            d2max = d2
    return d2max
