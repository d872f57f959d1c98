"""The arrays of a DEM run, built once before it starts (paper Sect. 3).

:func:`material_tables` turns the particles' materials, the wall material and the contact
law into the per-pair-type tables of the kernels (effective modulus, friction, the COR
curves); :func:`contact_time` is the shortest Hertz contact duration they imply (the time
scale of the step); :func:`allocate` builds every array of a :class:`~pdamper.dem.driver.Run`.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from pdamper.contact.elastic import effective_shear_modulus
from pdamper.contact.forces import DAMPING_CODES
from pdamper.contact.hertz import contact_duration, effective_modulus, hertz_stiffness
from pdamper.contact.law import ContactParameters
from pdamper.dem.driver import Run
from pdamper.dem.inputs import Container, ParticleSet
from pdamper.dem.kernels import state as K


class MaterialTables(NamedTuple):
    """Per-sphere material indices and the per-pair-type tables of the kernels."""

    pmat: np.ndarray          # material index of each sphere (int)
    materials: list           # the distinct particle materials, in order of appearance
    pair_types: K.PairTypes   # sphere pair a * nmat + b, sphere on the walls nmat^2 + a
    kwall: np.ndarray         # Hertz stiffness of each sphere against the wall [N/m^1.5]


def material_tables(p: ParticleSet, container: Container,
                    c: ContactParameters) -> MaterialTables:
    """The tables of the particles ``p`` in ``container`` under the contact law ``c``."""
    names: list[str] = []
    mats = []
    for m in p.material:
        if m.name not in names:
            names.append(m.name)
            mats.append(m)
    nm = len(mats)
    pmat = np.array([names.index(m.name) for m in p.material], dtype=np.int64)
    npair = nm * nm + nm
    wall = container.material
    curves = []
    estar = np.zeros(npair)
    gstar = np.zeros(npair)
    mu = np.zeros(npair)
    for a in range(nm):
        for b in range(nm):
            q = a * nm + b
            estar[q] = effective_modulus(mats[a], mats[b])
            gstar[q] = effective_shear_modulus(mats[a], mats[b])
            mu[q] = c.friction_pp
            curves.append(c.curve(mats[a].name, mats[b].name, wall=False))
    for a in range(nm):
        q = nm * nm + a
        estar[q] = effective_modulus(mats[a], wall)
        gstar[q] = effective_shear_modulus(mats[a], wall)
        mu[q] = c.friction_pw
        curves.append(c.curve(mats[a].name, wall.name, wall=True))
    tabs = [cv.tabulate() for cv in curves]
    nmax = max(len(v) for v, _ in tabs)
    cor_v = np.zeros((npair, nmax))
    cor_e = np.ones((npair, nmax))
    cor_n = np.zeros(npair, dtype=np.int64)
    for q, (v, e) in enumerate(tabs):
        cor_v[q, :len(v)] = v
        cor_e[q, :len(e)] = e
        cor_n[q] = len(v)
    # last entry: memo (COR, damping factor) per pair type for the kernels, emptied (-1)
    # at the start of every run (allocate), so that no state carries over between runs
    pair_types = K.PairTypes(estar, mu, cor_v, cor_e, cor_n, np.full((npair, 2), -1.0), gstar)
    kwall = np.array([hertz_stiffness(estar[nm * nm + a], float(ri))
                      for a, ri in zip(pmat, p.radius, strict=True)])
    return MaterialTables(pmat, mats, pair_types, kwall)


def contact_time(p: ParticleSet, tables: MaterialTables, v: float) -> float:
    """Shortest elastic Hertz contact duration of the pair types at speed ``v`` [m/s],
    for the lightest and the smallest sphere [s]."""
    estar = tables.pair_types.estar
    nm = len(tables.materials)
    masses = p.masses
    tc = math.inf
    i_small = int(np.argmin(masses))
    for i in {i_small, int(np.argmin(p.radius))}:
        m, r, a = float(masses[i]), float(p.radius[i]), int(tables.pmat[i])
        for b in range(nm):
            k = hertz_stiffness(estar[a * nm + b], 0.5 * r)
            tc = min(tc, contact_duration(0.5 * m, k, v))
        k = hertz_stiffness(estar[nm * nm + a], r)
        tc = min(tc, contact_duration(m, k, v))
    return tc


def allocate(p: ParticleSet, container: Container, c: ContactParameters,
             tables: MaterialTables, gravity: float, skin: float, z_start: float) -> Run:
    """Every array of a run, once: particles (positions shifted by the container's start
    position ``z_start`` [m]), contact lists, histories, work; ``gravity`` [m/s^2],
    Verlet-list ``skin`` [m]."""
    n = p.count
    tables.pair_types.memo[:] = -1.0  # the onset-damping memo starts empty in every run
    lx, ly, lz = container.box
    rmax = float(p.radius.max())
    rmin = float(p.radius.min())
    cell = 2.0 * rmax + skin
    ncx, ncy, ncz = (max(1, int(lx // cell)), max(1, int(ly // cell)), max(1, int(lz // cell)))
    bound = ((2 * rmax + skin + rmin) / rmin) ** 3
    cap = int(n * math.ceil(min(bound, n)) + 16)
    world = K.World(float(lx), float(ly), float(lz), float(gravity), float(skin),
                    float(cell), ncx, ncy, ncz)
    law = K.Law(DAMPING_CODES[c.damping_model], len(tables.materials),
                float(c.regularisation_velocity), float(c.min_impact_velocity),
                float(c.reimpact_factor))
    # the spring friction law's tangential displacements (their presence selects the law
    # in the kernels: Run.tangential)
    spring = c.friction_model == "spring"
    part = K.Particles(p.radius.copy(), p.masses, p.inertia, tables.kwall, tables.pmat,
                       1.0 / p.masses, 1.0 / p.inertia)
    nbrs = K.Neighbours(K.empty_pair_contacts(n, cap, spring),
                        K.empty_pair_contacts(n, cap, spring),
                        np.zeros(ncx * ncy * ncz, np.int64), np.zeros(n, np.int64),
                        np.zeros((n, 3)))
    walls = K.WallContacts(np.zeros((n, 6), np.int64), np.zeros((n, 6)), np.zeros((n, 6)),
                           np.zeros(4 * n + 64, np.int64), np.zeros((6 * n if spring else 0, 4)))
    work = K.Work(np.zeros((n, 3)), np.zeros((n, 3)), np.zeros((n, 3)), np.zeros((n, 3)))
    nord = K.Nordsieck(np.zeros((6, n, 3)), np.zeros((5, n, 3)), np.zeros(6), np.zeros(6))
    pos = p.positions.copy()
    pos[:, 2] += z_start
    return Run(pos=pos, vel=p.velocities.copy(), omg=p.angular_velocities.copy(),
               world=world, law=law, part=part, nbrs=nbrs, walls=walls, work=work,
               nord=nord, flights=K.empty_flights(n), z_start=z_start,
               pair_types=tables.pair_types)
