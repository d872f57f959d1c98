"""COR models in scenario files and COR tables from CSV files (docs/restitution.md)."""

from __future__ import annotations

import numpy as np
import pytest

from pdamper.contact.restitution import (
    ConstantRestitution,
    ExponentialRestitution,
    MeasuredRestitution,
    ScaledRestitution,
)
from pdamper.contact.thornton import ThorntonRestitution
from pdamper.errors import InputError
from pdamper.io.restitution import parse_model_text, read_cor_table, validate_spec
from pdamper.io.scenario import load_scenario
from pdamper.parameters import vertical_dampers_paper as paper

GOOD = "# drop tests, steel on PVC\nvelocity [m/s], cor [-], std [-]\n0.2, 0.89, 0.01\n" \
       "0.6, 0.86, 0.01\n\n1.0, 0.84, 0.02\n1.8, 0.80, 0.02\n"


def test_read_table(tmp_path):
    f = tmp_path / "cor.csv"
    f.write_text(GOOD)
    t = read_cor_table(f)
    assert t.velocity == (0.2, 0.6, 1.0, 1.8) and t.restitution == (0.89, 0.86, 0.84, 0.8)
    assert t.std == (0.01, 0.01, 0.02, 0.02) and t.source == "cor.csv"


def test_units_and_separators(tmp_path):
    """Velocities in any speed unit, COR as [-], [1] or [%]; ',' ';' or tab separated."""
    f = tmp_path / "t.csv"
    f.write_text("Velocity [mm/s]; COR [%]\n100; 90\n500; 80\n")
    t = read_cor_table(f)
    assert t.velocity == pytest.approx((0.1, 0.5)) and t.restitution == pytest.approx((0.9, 0.8))
    f.write_text("v [km/h]\te [1]\n3.6\t0.7\n")
    assert read_cor_table(f).velocity == pytest.approx((1.0,))


BAD = {
    "non-monotone velocity": ("velocity [m/s], cor [-]\n0.1, 0.9\n0.5, 0.8\n0.3, 0.85\n",
                              "row 4, column 1 'velocity [m/s]': velocities must increase"),
    "COR above 1": ("velocity [m/s], cor [-]\n0.1, 1.2\n",
                    "row 2, column 2 'cor [-]': COR must be in (0, 1]"),
    "COR zero": ("velocity [m/s], cor [-]\n0.1, 0\n", "row 2, column 2 'cor [-]': COR must be in (0, 1]"),
    "NaN": ("velocity [m/s], cor [-]\n0.1, 0.9\n0.2, nan\n", "row 3, column 2 'cor [-]': must be a finite"),
    "not a number": ("velocity [m/s], cor [-]\n0.1, 0.9x\n", "row 2, column 2 'cor [-]': not a number"),
    "missing column": ("velocity [m/s]\n0.1\n", "row 1: missing column 'cor'"),
    "unknown unit": ("velocity [blips/blorp], cor [-]\n0.1, 0.9\n",
                     "row 1, column 1 'velocity [blips/blorp]': unknown unit"),
    "wrong dimension": ("velocity [m], cor [-]\n0.1, 0.9\n", "row 1, column 1 'velocity [m]': unknown unit"),
    "velocity without unit": ("velocity, cor\n0.1, 0.9\n", "row 1, column 1 'velocity': needs a unit"),
    "unknown column": ("velocity [m/s], cor [-], temperature [K]\n0.1, 0.9, 300\n",
                       "row 1, column 3 'temperature [K]': unknown column"),
    "short row": ("velocity [m/s], cor [-]\n0.1\n", "row 2: 1 values, the header has 2 columns"),
    "negative std": ("velocity [m/s], cor [-], std [-]\n0.1, 0.9, -0.1\n", "row 2, column 3 'std [-]'"),
    "no data": ("# nothing\nvelocity [m/s], cor [-]\n", "no data rows"),
}


@pytest.mark.parametrize("case", list(BAD))
def test_bad_tables_are_one_line_naming_file_row_and_column(tmp_path, case):
    text, expected = BAD[case]
    f = tmp_path / "meas.csv"
    f.write_text(text)
    with pytest.raises(InputError) as err:
        read_cor_table(f, "restitution.particle_wall.file")
    msg = str(err.value)
    assert "\n" not in msg
    assert msg.startswith("restitution.particle_wall.file: meas.csv: ")
    assert expected in msg


def _scenario(tmp_path, body: str, name="s.toml"):
    f = tmp_path / name
    f.write_text(body)
    return load_scenario(f)


def test_scenario_models(tmp_path):
    """Every form of [restitution]: shorthand, tables relative to the scenario file, fits,
    Thornton from the materials, the paper's curves and scale."""
    (tmp_path / "data").mkdir()
    (tmp_path / "data" / "cor.csv").write_text(GOOD)
    sc = _scenario(tmp_path / "data", """
[restitution]
particle_particle = { model = "paper", scale = 1.5 }
particle_wall = { model = "table", file = "cor.csv" }
""")
    d = sc.damper()
    assert d.restitution_pp == ScaledRestitution(paper.PAPER_COR_PP, 1.5)
    assert isinstance(d.restitution_pw, MeasuredRestitution) and len(d.restitution_pw.velocity) == 4
    sc = _scenario(tmp_path, """
[particles]
material = "100Cr6"
[restitution]
particle_particle = "thornton"
particle_wall = { model = "table", file = "data/cor.csv", fit = "linear" }
""")
    d = sc.damper()
    assert d.restitution_pp == ThorntonRestitution.from_materials(d.particle_material,
                                                                  d.particle_material, 0.005, 0.005)
    assert d.restitution_pw.describe().startswith("linear fit of cor.csv")
    sc = _scenario(tmp_path, """
[restitution]
particle_particle = 0.7
particle_wall = { model = "exponential", e0 = 0.9, e_inf = 0.6, v_c = "300 mm/s" }
""")
    d = sc.damper()
    assert d.restitution_pp == ConstantRestitution(0.7)
    assert d.restitution_pw == ExponentialRestitution(0.9, 0.6, 0.3)


def test_legacy_dem_keys_and_precedence(tmp_path):
    """[dem] restitution_pp/pw still work; a pair given in both places is refused."""
    d = _scenario(tmp_path, "[dem]\nrestitution_pp = 0.5\n").damper()
    assert d.restitution_pp == ConstantRestitution(0.5)
    assert d.restitution_pw == ConstantRestitution(paper.BENCHMARK_RESTITUTION_PW)
    d = _scenario(tmp_path,
                  "[dem]\nrestitution_pp = 0.5\n[restitution]\nparticle_wall = 'paper'\n").damper()
    assert d.restitution_pp == ConstantRestitution(0.5) and d.restitution_pw == paper.PAPER_COR_PW
    with pytest.raises(InputError,
                       match="restitution.particle_particle: also given as dem.restitution_pp"):
        _scenario(tmp_path, "[dem]\nrestitution_pp = 0.5\n[restitution]\nparticle_particle = 0.6\n")


@pytest.mark.parametrize(("body", "match"), [
    ("particle_wall = { model = 'table' }", r"^restitution.particle_wall.file: Field required"),
    ("particle_wall = 'fancy'", r"^restitution.particle_wall: must be a number, \"paper\""),
    ("particle_wall = 1.5", r"^restitution.particle_wall.value"),
    ("particle_wall = { model = 'paper', scale = 6 }",
     r"^restitution.particle_wall.scale: must be in \[0, 5\)"),
    ("particle_wall = { model = 'table', file = 'nope.csv' }",
     r"^restitution.particle_wall.file: COR table not found"),
    ("particle_wall = { model = 'exponential', e0 = 0.9, e_inf = 0.5 }", r"^restitution.particle_wall.v_c"),
    ("wall = 0.5", r"^restitution.wall: unknown key"),
])
def test_bad_scenario_entries(tmp_path, body, match):
    with pytest.raises(InputError, match=match) as err:
        _scenario(tmp_path, f"[restitution]\n{body}\n")
    assert "\n" not in str(err.value)


def test_thornton_without_yield_strength_names_the_field(tmp_path):
    body = """
[particles]
material = "glass"
[container]
material = "alumina"
[restitution]
particle_wall = "thornton"
"""
    with pytest.raises(InputError, match="^restitution.particle_wall: Thornton's model needs"):
        _scenario(tmp_path, body)


def test_inline_material_with_yield_strength(tmp_path):
    body = """
[particles]
material = { name = "mine", youngs_modulus = "200 GPa", poisson_ratio = 0.3, \
density = "7800 kg/m^3", yield_strength = "1.2 GPa" }
"""
    assert _scenario(tmp_path, body).damper().particle_material.yield_strength == 1.2e9


def test_command_line_model_text(tmp_path):
    f = tmp_path / "m.csv"
    f.write_text(GOOD)
    assert parse_model_text("thornton") == {"model": "thornton"}
    assert parse_model_text(f"{f}*0.5") == {"model": "table", "file": str(f), "scale": 0.5}
    assert validate_spec(parse_model_text("0.6*2")).scale == 2.0
    with pytest.raises(InputError, match="unknown COR model 'fancy'"):
        parse_model_text("fancy")
    with pytest.raises(InputError, match="model.value"):
        validate_spec(parse_model_text("1.4"))
    assert np.isfinite(paper.PAPER_COR_PP(1.0))


def test_example_scenario_takes_a_restitution_entry(tmp_path):
    """Uncommenting an entry of the example's [restitution] section just works: the example
    does not also set the [dem] constants."""
    from pdamper.io.scenario import EXAMPLE_SCENARIO

    text = EXAMPLE_SCENARIO.replace('# particle_particle = "paper"', 'particle_particle = "paper"')
    assert text != EXAMPLE_SCENARIO
    d = _scenario(tmp_path, text).damper()
    assert d.restitution_pp == paper.PAPER_COR_PP
    assert d.restitution_pw == ConstantRestitution(paper.BENCHMARK_RESTITUTION_PW)
