"""DEM inputs of the paper's benchmark damper for the tests (values from
:mod:`pdamper.parameters`): the engine itself has no paper defaults.

Importable from every test module: pytest puts this directory (that of the root
``conftest.py``) on ``sys.path``.
"""

from __future__ import annotations

import numpy as np

from pdamper.contact.restitution import ConstantRestitution
from pdamper.dem import ContactParameters, Container, DEMEngine, EngineSettings, ParticleSet
from pdamper.materials import PVC, S235
from pdamper.parameters import vertical_dampers_paper as paper

BOX = paper.PAPER_CONTAINER
R = paper.PAPER_PARTICLE_RADIUS
MU = paper.PAPER_FRICTION


def particles(positions, radius=R, material=S235, **kw) -> ParticleSet:
    return ParticleSet(np.asarray(positions, float), radius, material, **kw)


def lattice(n: int) -> ParticleSet:
    return ParticleSet.lattice(n, BOX, R, S235)


def random(n: int, seed: int = 0) -> ParticleSet:
    return ParticleSet.random(n, BOX, R, S235, seed=seed)


def contact(restitution_pp=None, restitution_pw=None, friction_pp=MU, friction_pw=MU,
            **kw) -> ContactParameters:
    return ContactParameters(
        restitution_pp or ConstantRestitution(paper.BENCHMARK_RESTITUTION_PP),
        restitution_pw or ConstantRestitution(paper.BENCHMARK_RESTITUTION_PW),
        friction_pp, friction_pw, **kw)


def container(box=BOX, material=PVC, **kw) -> Container:
    return Container(box, material, **kw)


def engine(ps: ParticleSet, box: Container | None = None, cp: ContactParameters | None = None,
           motion=None, **settings) -> DEMEngine:
    """An engine of ``ps``; ``settings``: the fields of :class:`EngineSettings`."""
    return DEMEngine(ps, box or container(), cp or contact(), motion, EngineSettings(**settings))


def engine_at(n: int, frequency: float, amplitude: float, **kw) -> DEMEngine:
    """A lattice of ``n`` benchmark spheres under harmonic excitation (Verlet)."""
    from pdamper.dem import HarmonicMotion

    kw.setdefault("integrator", "verlet")
    return engine(lattice(n), motion=HarmonicMotion(amplitude, frequency), **kw)
