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
