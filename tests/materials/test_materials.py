"""Materials of the paper's Fig. 2-left and their validation."""

import pytest

from pdamper.errors import InputError
from pdamper.materials import PVC, S235, Material, get_material


def test_paper_materials():
    assert (S235.youngs_modulus, S235.poisson_ratio, S235.density) == (208e9, 0.3, 7900.0)
    assert (PVC.youngs_modulus, PVC.poisson_ratio, PVC.density) == (3e9, 0.38, 1400.0)
    assert S235.shear_modulus == pytest.approx(208e9 / 2.6)
    assert get_material("pvc") is PVC


@pytest.mark.parametrize(("kw", "field"), [({"youngs_modulus": -1.0}, "youngs_modulus"),
                                           ({"poisson_ratio": 0.5}, "poisson_ratio"),
                                           ({"density": float("nan")}, "density")])
def test_bad_material(kw, field):
    args = {"name": "x", "youngs_modulus": 1e9, "poisson_ratio": 0.3, "density": 1000.0, **kw}
    with pytest.raises(InputError, match=field):
        Material(**args)
    with pytest.raises(InputError, match="unknown material"):
        get_material("unobtainium")
