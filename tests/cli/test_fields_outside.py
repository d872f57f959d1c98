"""A fields map read outside its (f, X) range by a load history: refused with
``extrapolation = "error"``; otherwise answered by the policy and said in the JSON
(``fields_outside``) and the text: how far outside and for what share of the record."""

from __future__ import annotations

import json

import pytest

from hostile_corpus import FILES


@pytest.fixture
def tiny_map(cli, tmp_path):
    """An analytical map over 4-6 Hz and 5-20 mm: the corpus' 2 N load at 5 Hz drives the
    paper's structure through strokes below 5 mm late in the record."""
    (tmp_path / "load_force.csv").write_text(FILES["load_force.csv"])
    code, _, err = cli("map", "--frequency", "4Hz:6Hz:3", "--amplitude", "5mm:20mm:3",
                       "--out", str(tmp_path / "m.nc"), "--json")
    assert code == 0, err
    return tmp_path


def _scenario(tmp, policy: str):
    path = tmp / f"{policy}.toml"
    path.write_text(f'[fields]\nfile = "{tmp / "m.nc"}"\nextrapolation = "{policy}"\n')
    return str(path)


@pytest.mark.parametrize("policy", ["clamp", "analytic"])
def test_a_load_history_outside_the_map_is_said(cli, tiny_map, policy):
    args = ("simulate", "--model", "fields", "--scenario", _scenario(tiny_map, policy),
            "--load", str(tiny_map / "load_force.csv"))
    code, out, err = cli(*args, "--json")
    assert code == 0, err
    rec = json.loads(out)["fields_outside"]
    assert rec["extrapolation"] == policy
    assert 0 < rec["outside"] <= rec["lookups"] and 0 < rec["fraction"] <= 1
    # the strokes below the map's 5 mm: how far outside is a factor above one
    assert rec["furthest"] > 1.0
    assert rec["amplitude_range"] == pytest.approx([0.005, 0.02])
    code, out, _ = cli(*args)
    assert code == 0
    warning = [ln for ln in out.splitlines() if "warning: the fields map was used outside" in ln]
    assert len(warning) == 1 and "%" in warning[0] and "beyond it" in warning[0]


def test_a_load_history_outside_the_map_is_refused_by_default(cli, tiny_map):
    code, _, err = cli("simulate", "--model", "fields", "--scenario",
                       _scenario(tiny_map, "error"), "--load",
                       str(tiny_map / "load_force.csv"))
    assert code == 2 and err.startswith("error: fields.file")
    assert len(err.strip().splitlines()) == 1


def test_a_load_history_inside_the_map_has_no_warning(cli, tmp_path):
    (tmp_path / "load_force.csv").write_text(FILES["load_force.csv"])
    code, _, err = cli("map", "--frequency", "3Hz:7Hz:5", "--amplitude", "0.1mm:40mm:8",
                       "--out", str(tmp_path / "m.nc"), "--json")
    assert code == 0, err
    code, out, err = cli("simulate", "--model", "fields", "--scenario",
                         _scenario(tmp_path, "clamp"), "--load",
                         str(tmp_path / "load_force.csv"), "--json")
    assert code == 0, err
    assert "fields_outside" not in json.loads(out)
