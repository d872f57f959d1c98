"""The physical damper (:mod:`pdamper.damper`): lattice capacity, clearance (Sect. 3.1.1),
optimal stroke (Eq. 19), bed mass."""

from __future__ import annotations

import math
from dataclasses import replace

import pytest

from pdamper.contact.restitution import ConstantRestitution
from pdamper.damper import ParticleDamper, lattice_fit, max_layers, max_particles, spheres_per_layer
from pdamper.errors import InputError
from pdamper.materials import PVC, S235


def damper(**kw):
    base = dict(length=0.120, width=0.040, depth=0.040, particle_radius=0.005, count=32,
                particle_material=S235, wall_material=PVC)
    return ParticleDamper(**{**base, **kw})


def test_lattice_capacity_counts_whole_diameters():
    assert lattice_fit(0.04, 0.005) == 4          # 0.04 / 0.01 despite rounding
    assert lattice_fit(0.0399, 0.005) == 3
    assert spheres_per_layer((0.05, 0.03, 0.1), 0.005) == 5 * 3
    assert max_layers((0.05, 0.03, 0.1), 0.005) == 10
    assert max_particles((0.05, 0.03, 0.1), 0.005) == 150
    assert spheres_per_layer((0.04, 0.04, 0.12), 0.005, gap=0.001) == 9  # (40 + 1) / 11


def test_clearance_and_optimal_stroke_closed_forms():
    """h = L (1 - n_p / n_max) and X_opt = h / pi (Eq. 19), for other containers too."""
    d = damper(length=0.2, width=0.03, count=18)   # 3 x 4 per layer, 20 layers: n_max 240
    assert d.per_layer == 12 and d.max_count == 240
    assert d.clearance == pytest.approx(0.2 * (1 - 18 / 240))
    assert d.optimal_stroke == pytest.approx(d.clearance / math.pi)
    assert d.bed_mass == pytest.approx(18 * 4 / 3 * math.pi * 0.005**3 * 7900)
    assert d.with_count(0).clearance == pytest.approx(0.2)
    assert d.with_count(240).clearance == 0.0


@pytest.mark.parametrize(("kw", "field"), [
    ({"count": 193}, "particles.count"), ({"count": -1}, "particles.count"),
    ({"count": 2.5}, "particles.count"), ({"count": True}, "particles.count"),
    ({"particle_radius": 0.03}, "particles.radius"), ({"length": -0.1}, "container.length"),
    ({"width": float("nan")}, "container.width"), ({"friction": -0.1}, "particles.friction"),
    ({"particle_material": "S235"}, "particles.material"),
    ({"restitution_pp": 0.6}, "particles.restitution_pp"),
])
def test_bad_dampers_name_the_field(kw, field):
    with pytest.raises(InputError) as info:
        damper(**kw)
    assert str(info.value).startswith(field + ":")


def test_contact_description_is_optional_and_kept():
    d = damper()
    assert d.friction is None and d.restitution_pp is None  # the analytical model needs none
    e = replace(d, friction=0.1, restitution_pp=ConstantRestitution(0.6))
    assert e.with_count(64).restitution_pp == ConstantRestitution(0.6)
