"""The materials library (Level I): the paper's Fig. 2-left materials, the sources of every
number, lookup by name and alias, and the table of docs/materials.md."""

from pathlib import Path

import pytest

from pdamper.errors import InputError
from pdamper.materials import LIBRARY, PVC, REFERENCES, S235, Material, get_material, known_names
from pdamper.materials.library import materials_table

DOCS = Path(__file__).resolve().parents[2] / "docs" / "materials.md"


def test_paper_materials():
    """Fig. 2-left: S235 spheres and PVC walls as printed."""
    assert (S235.youngs_modulus, S235.poisson_ratio, S235.density) == (208e9, 0.3, 7900.0)
    assert (PVC.youngs_modulus, PVC.poisson_ratio, PVC.density) == (3e9, 0.38, 1400.0)
    assert S235.yield_strength == 235e6  # EN 10025-2
    assert S235.shear_modulus == pytest.approx(208e9 / 2.6)
    assert get_material("pvc") is PVC


def test_library_covers_the_issue_list():
    """Steels, tungsten and its carbide, lead, aluminium, brass, copper, glass, alumina,
    zirconia, POM, nylon, PMMA and natural rubber are in the library."""
    for name in ("S235", "PVC", "100Cr6", "AISI 304", "tungsten", "tungsten carbide", "lead",
                 "aluminium", "brass", "copper", "glass", "alumina", "zirconia", "POM", "nylon",
                 "PMMA", "natural rubber"):
        assert isinstance(get_material(name), Material)


def test_every_number_has_a_source():
    """E, nu and rho always, the yield strength when given, each with a known reference."""
    for entry in LIBRARY:
        m = entry.material
        needed = {"youngs_modulus", "poisson_ratio", "density"}
        if m.yield_strength is not None:
            needed.add("yield_strength")
        assert set(entry.sources) == needed, m.name
        assert all(key in REFERENCES for key in entry.sources.values()), m.name


def test_lookup_ignores_case_spaces_and_hyphens():
    assert get_material("aisi 52100") is get_material("100CR6") is get_material("AISI-52100")
    assert get_material("Tungsten Carbide").name == "WC-Co"
    assert get_material("NYLON").name == "PA66"
    assert get_material("x5crni18_10").name == "AISI 304"


def test_unknown_material_is_one_line_listing_known_names():
    with pytest.raises(InputError) as err:
        get_material("unobtainium", "particles.material")
    msg = str(err.value)
    assert "\n" not in msg and msg.startswith("particles.material: unknown material 'unobtainium'")
    assert all(name in msg for name in known_names())


def test_docs_table_is_the_library():
    """docs/materials.md shows exactly the library's numbers (one home, one table)."""
    assert materials_table() in DOCS.read_text()


@pytest.mark.parametrize(("kw", "field"), [({"youngs_modulus": -1.0}, "youngs_modulus"),
                                           ({"poisson_ratio": 0.5}, "poisson_ratio"),
                                           ({"density": float("nan")}, "density"),
                                           ({"yield_strength": 0.0}, "yield_strength")])
def test_bad_material(kw, field):
    args = {"name": "x", "youngs_modulus": 1e9, "poisson_ratio": 0.3, "density": 1000.0, **kw}
    with pytest.raises(InputError, match=field):
        Material(**args)
