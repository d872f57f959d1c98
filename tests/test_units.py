"""Quantities with units at the edges, SI floats inside (:mod:`pdamper.units`)."""

from __future__ import annotations

import math

import pytest

from pdamper.errors import InputError
from pdamper.units import format_quantity, parse_quantity, parse_range


@pytest.mark.parametrize(("text", "unit", "si"), [
    ("32 mm", "m", 0.032), ("32mm", "m", 0.032), ("10 Hz", "Hz", 10.0),
    ("600 1/min", "Hz", 10.0), ("7.9 g/cm^3", "kg/m^3", 7900.0), ("7900 kg/m³", "kg/m^3", 7900.0),
    ("0.8 s", "s", 0.8), ("800 ms", "s", 0.8), ("208 GPa", "Pa", 208e9), ("-58 mm", "m", -0.058),
])
def test_quantities_convert_to_si(text, unit, si):
    assert parse_quantity(text, unit, "x") == pytest.approx(si, rel=1e-12)


def test_bare_numbers_are_si():
    assert parse_quantity(0.5, "s", "duration") == 0.5
    assert parse_quantity(3, "m", "x") == 3.0


@pytest.mark.parametrize("bad", ["3 s", "10 furlongs per fortnight", "", "  ", True, None,
                                 float("nan"), float("inf"), "nan Hz"])
def test_bad_quantities_name_the_field(bad):
    with pytest.raises(InputError) as info:
        parse_quantity(bad, "m", "container.length")
    assert str(info.value).startswith("container.length: ")


def test_ranges():
    assert parse_range("1mm:200mm:24", "m", "amplitude") == pytest.approx((0.001, 0.2, 24))
    assert parse_range("5 Hz", "Hz", "frequency") == (5.0, 5.0, 1)
    for bad in ("2Hz:20Hz", "2Hz:20Hz:0", "2Hz:20Hz:x"):
        with pytest.raises(InputError, match="^frequency: "):
            parse_range(bad, "Hz", "frequency")


def test_format_echoes_units():
    assert format_quantity(0.032, "mm") == "32 mm"
    assert format_quantity(math.pi, "Hz", digits=3) == "3.14 Hz"
    assert format_quantity(0.0131, "g") == "13.1 g"


@pytest.mark.parametrize("bad", [
    "Hz", " Hz ", "mm", "10Hz🙂", "10 Hz!", "10 Hz Hz", "10 Hz * 2", "2*5 Hz", "10 Hz + 1 Hz",
    "(10) Hz", "10**2 Hz", "10 Hz)", "inf Hz", "nan Hz", "1e400 Hz", "10", "10 per Hz",
    "62.8 rad/s", "10 turn/s", "600 rpm/s", "600 rad/min", "10 %", "0x10 Hz", "1.7e306 kHz",
])
def test_a_quantity_is_a_number_and_a_unit_and_nothing_else(bad):
    """``"Hz"`` was once read as 1 Hz, ``"10Hz🙂"`` as 10 Hz and ``"62.8 rad/s"`` as
    62.8 Hz (pint's radian is dimensionless)."""
    with pytest.raises(InputError) as info:
        parse_quantity(bad, "Hz", "excitation.frequency")
    assert info.value.field == "excitation.frequency" and "\n" not in str(info.value)


@pytest.mark.parametrize(("text", "si"), [
    ("1e3 mHz", 1.0), (".5 kHz", 500.0), ("5. Hz", 5.0), ("+5Hz", 5.0), ("600 1/min", 10.0),
    ("10 s^-1", 10.0), (" 10 Hz ", 10.0), ("600 rpm", 10.0), ("1440rpm", 24.0),
])
def test_number_forms_that_are_accepted(text, si):
    assert parse_quantity(text, "Hz", "f") == pytest.approx(si)


def test_pasted_characters():
    assert parse_quantity("\u221258 mm", "m", "x0") == pytest.approx(-0.058)
    assert parse_quantity("7.9 g\u00b7cm\u207b\u00b3", "kg/m^3", "rho") == pytest.approx(7900)


def test_dimensionless_quantities_take_bare_text_and_percent():
    assert parse_quantity("0.3", "", "nu") == 0.3
    assert parse_quantity("10 %", "", "nu") == pytest.approx(0.1)


@pytest.mark.parametrize("bad", ["2Hz::5", ":20Hz:5", "2Hz:20Hz:", "2Hz:20Hz:5:6",
                                 "2Hz:20Hz:1", "20Hz:2Hz:5", "2Hz:2Hz:5", "2Hz:20Hz:-3",
                                 "2Hz:20Hz:1e3", "2Hz:20Hz:5.0", "2:20Hz:5", "::", 5])
def test_ranges_must_be_well_formed(bad):
    """``'2Hz::5'`` was once read as one quantity, 10 Hz."""
    with pytest.raises(InputError) as info:
        parse_range(bad, "Hz", "map.frequency")
    assert info.value.field == "map.frequency"


def test_a_range_count_is_not_allocated():
    """The count is returned as is (the resource model judges it), not turned into a grid."""
    assert parse_range("2Hz:20Hz:99999999999999999999", "Hz", "f")[2] == 10**20 - 1


def test_rpm_is_a_frequency_of_one_cycle_per_revolution():
    """``rpm`` counts revolutions, one cycle each: 600 rpm is 10 Hz (not pint's 2 pi rad/min,
    62.8 Hz), in quantities and grids; an angle rate stays refused."""
    assert parse_quantity("600 rpm", "Hz", "speed") == pytest.approx(10.0, rel=1e-15)
    assert parse_range("400rpm:2400rpm:21", "Hz", "speed") == pytest.approx(
        (400 / 60, 40.0, 21), rel=1e-15)
    with pytest.raises(InputError, match="dimensionless"):
        parse_quantity("600 rpm", "m", "amplitude")   # not a frequency there
