"""Scenario inputs given as "value +- sd"."""

import pytest

from pdamper.errors import InputError
from pdamper.io.scenario import load_scenario
from pdamper.io.uncertain import parse_uncertain


@pytest.mark.parametrize("text", ["0.1 +- 0.03", "0.1+-0.03", "0.1 ± 0.03", "0.1 +/- 0.03"])
def test_syntax(text):
    u = parse_uncertain(text, "particles.friction")
    assert (u.value, u.sd, u.low) == (0.1, 0.03, 0.0)


def test_units_of_both_parts():
    u = parse_uncertain("120 mm +- 100 um", "container.length")
    assert u.value == pytest.approx(0.12) and u.sd == pytest.approx(1e-4)


@pytest.mark.parametrize("text, field", [
    ("0.1 +- -0.03", "particles.friction"), ("0.1 +- 0", "particles.friction"),
    ("+- 0.03", "particles.friction"), ("0.1 +- ", "particles.friction"),
    ("-0.1 +- 0.03", "particles.friction"), ("120 mm +- 0.1", "container.length"),
    ("1.2 +- 0.1", "dem.restitution_pw"), ("64 +- 2", "particles.count")])
def test_bad_inputs_name_the_field(text, field):
    with pytest.raises(InputError) as exc:
        parse_uncertain(text, field)
    assert exc.value.field == field


def test_scenario_takes_the_nominal_value_and_keeps_the_input(tmp_path):
    p = tmp_path / "s.toml"
    p.write_text('[particles]\nfriction = "0.1 +- 0.03"\n[container]\n'
                 'length = "120 mm +- 0.2 mm"\n')
    sc = load_scenario(p)
    assert sc.particles.friction == 0.1 and sc.container.length == pytest.approx(0.12)
    assert [u.field for u in sc.uncertain_inputs()] == ["particles.friction",
                                                        "container.length"]
    assert load_scenario(None).uncertain_inputs() == ()


def test_a_dict_scenario_takes_the_same_syntax_and_stays_as_given():
    from pdamper.io.scenario import scenario_from_dict

    data = {"particles": {"friction": "0.2 ± 0.01"}}
    sc = scenario_from_dict(data)
    assert sc.particles.friction == 0.2 and sc.uncertain_inputs()[0].sd == 0.01
    assert data == {"particles": {"friction": "0.2 ± 0.01"}}
