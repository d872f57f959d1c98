"""Hypothesis strategies for what a hostile but realistic user types: numbers in every
spelling, units right and wrong, decorations, ranges, option values and scenario files."""

from __future__ import annotations

import math

from hypothesis import strategies as st

#: Units by dimension, and the lot (a wrong dimension is a realistic mistake).
UNITS = {
    "Hz": ["Hz", "kHz", "MHz", "mHz", "1/s", "1/min", "s^-1", "rpm", "rad/s", "hertz"],
    "m": ["m", "mm", "cm", "um", "µm", "km", "in", "ft", "meter"],
    "s": ["s", "ms", "min", "h", "us", "second"],
    "kg": ["kg", "g", "mg", "lb"],
    "Pa": ["Pa", "GPa", "MPa", "psi"],
    "kg/m^3": ["kg/m^3", "g/cm^3", "kg/m³", "kg m^-3"],
    "N/m": ["N/m", "kN/m", "N/mm"],
    "kg/s": ["kg/s", "N*s/m", "g/s"],
}
ALL_UNITS = sorted({u for us in UNITS.values() for u in us} | {"", "furlong", "HZ", "%", "degC"})

#: Numbers as people write them, and as they should not.
NUMBERS = st.one_of(
    st.integers(-10**4, 10**4).map(str),
    st.floats(allow_nan=False, allow_infinity=False, width=64).map(repr),
    st.sampled_from(["0", "-0", ".5", "5.", "1e3", "1E-3", "+2", "1e-300", "1e300", "nan",
                     "inf", "-inf", "1e400", "0x10", "1_000", "\u0663", "", "\u221258",
                     "2*5", "(10)", "10**2"]),
)
DECORATIONS = st.sampled_from(["", "", "", "", " ", "\U0001f642", "!", " Hz", "*2", ")", "\t",
                               "/0", " per fortnight", ":", "e"])
SEPARATORS = st.sampled_from(["", " ", "  "])


#: Units that make a small number large: left out where a valid run must stay quick.
SLOW_UNITS = {"min", "h", "km", "ft", "in"}


def quantity(unit: str, numbers=NUMBERS, quick: bool = False) -> st.SearchStrategy[str]:
    """Text meant as a quantity of ``unit``: usually a number and a unit, sometimes not
    (``quick``: no unit that makes a small number large)."""
    right, anything = UNITS.get(unit, [unit]), ALL_UNITS
    if quick:
        right = [u for u in right if u not in SLOW_UNITS]
        anything = [u for u in anything if u not in SLOW_UNITS]
    units = st.one_of(st.sampled_from(right), st.sampled_from(anything))
    spelled = st.builds(lambda n, s, u, d: f"{n}{s}{u}{d}", numbers, SEPARATORS, units,
                        DECORATIONS)
    return st.one_of(spelled, spelled, spelled, st.text(max_size=12))


#: Grid counts: small ones (a fast valid map) and absurd ones, never the slow middle.
COUNTS = st.one_of(st.integers(-3, 24).map(str),
                   st.sampled_from(["99999999999999999999", "1000000000", "1e3", "", " 5",
                                    "x", "05", "3.0"]))


def grid(unit: str) -> st.SearchStrategy[str]:
    """``start:stop:count`` text, well-formed or not."""
    q = quantity(unit)
    return st.one_of(
        q,
        st.builds(lambda a, b, n: f"{a}:{b}:{n}", q, q, COUNTS),
        st.builds(lambda a, b, n: f"{a}:{b}:{n}",
                  st.floats(0.1, 50).map(lambda v: f"{v:.3g}{unit}"),
                  st.floats(0.1, 50).map(lambda v: f"{v:.3g}{unit}"), COUNTS),
        st.lists(q, min_size=0, max_size=5).map(":".join),
    )


def bounded_number(fast_max: float) -> st.SearchStrategy[str]:
    """Numbers whose valid values stay below ``fast_max`` (so that a valid run is quick),
    with absurd and malformed ones."""
    return st.one_of(
        st.floats(-fast_max, fast_max, allow_nan=False).map(lambda v: f"{v:.4g}"),
        st.floats(1e7, 1e300).map(lambda v: f"{v:.3g}"),
        st.sampled_from(["0", "-1", "nan", "inf", "", "1e400", "5e-324", "x"]),
    )


INTEGERS = st.one_of(st.integers(-10, 400), st.sampled_from([10**20, -(10**20), 2**63]))


def toml_value(v) -> str:
    """TOML spelling of a generated value (str, bool, int, float, list, dict)."""
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        if math.isnan(v):
            return "nan"
        if math.isinf(v):
            return "inf" if v > 0 else "-inf"
        return repr(v)
    if isinstance(v, str):
        return '"' + v.replace("\\", "\\\\").replace('"', '\\"').replace("\n", "\\n") \
            .replace("\t", "\\t").replace("\r", "\\r") + '"'
    if isinstance(v, list):
        return "[" + ", ".join(toml_value(x) for x in v) + "]"
    if isinstance(v, dict):
        return "{ " + ", ".join(f"{k} = {toml_value(x)}" for k, x in v.items()) + " }"
    raise TypeError(type(v))


def toml_document(doc: dict) -> str:
    lines = []
    for key, value in doc.items():
        if not isinstance(value, dict):
            lines.append(f"{key} = {toml_value(value)}")
    for key, value in doc.items():
        if isinstance(value, dict):
            lines.append(f"[{key}]")
            lines.extend(f"{k} = {toml_value(v)}" for k, v in value.items())
    return "\n".join(lines) + "\n"


#: Keys of every section and the kind of value each takes.
SECTIONS = {
    "container": {"length": "m", "width": "m", "depth": "m", "material": "material",
                  "mass": "kg"},
    "particles": {"count": "int", "radius": "m", "material": "material", "friction": "float"},
    "excitation": {"frequency": "Hz", "amplitude": "m"},
    "structure": {"mass": "kg", "stiffness": "N/m", "damping": "kg/s",
                  "initial_displacement": "m"},
    "simulation": {"model": "model", "duration": "s-fast", "sample_rate": "Hz-fast"},
    "optimization": {"at": "s-fast", "step": "int"},
    "map": {"frequency": "grid-Hz", "amplitude": "grid-m"},
    "dem": {"integrator": "name", "cycles": "int", "skip_cycles": "int",
            "restitution_pp": "float", "restitution_pw": "float", "damping_model": "name",
            "packing": "name", "seed": "int", "safety": "float", "sample_rate": "Hz",
            "snapshot_rate": "Hz"},
}
ANY_SCALAR = st.one_of(st.booleans(), st.integers(-10**6, 10**6),
                       st.floats(allow_nan=True, allow_infinity=True), st.text(max_size=10))


def _material() -> st.SearchStrategy:
    spec = st.fixed_dictionaries(
        {"name": st.text(min_size=1, max_size=8)},
        optional={"youngs_modulus": quantity("Pa"), "poisson_ratio": st.floats(-2, 1),
                  "density": quantity("kg/m^3"), "colour": st.text(max_size=5)})
    return st.one_of(st.sampled_from(["S235", "PVC", "s235", "unobtainium", ""]), spec,
                     ANY_SCALAR)


def value_of(kind: str) -> st.SearchStrategy:
    if kind == "material":
        return _material()
    if kind == "int":
        return st.one_of(INTEGERS, ANY_SCALAR)
    if kind == "float":
        return st.one_of(st.floats(-2, 2), st.floats(allow_nan=True, allow_infinity=True),
                         ANY_SCALAR)
    if kind == "model":
        return st.sampled_from(["analytic", "dem", "quantum", "", "Analytic"])
    if kind == "name":
        return st.sampled_from(["gear", "verlet", "exact", "gonthier", "lattice", "random",
                                "rk4", ""])
    if kind.startswith("grid-"):
        return grid(kind[5:])
    if kind.endswith("-fast"):  # valid values that keep a run quick, and absurd ones
        unit = kind[:-5]
        return st.one_of(quantity(unit, bounded_number(3.0 if unit == "s" else 5000.0),
                                  quick=True), st.floats(-3, 3), ANY_SCALAR)
    return st.one_of(quantity(kind), st.floats(allow_nan=True, allow_infinity=True),
                     ANY_SCALAR)


def _section(keys: dict) -> st.SearchStrategy[dict]:
    """Some of the section's keys with values of (mostly) their kind, sometimes a typo."""
    base = st.fixed_dictionaries({}, optional={k: value_of(v) for k, v in keys.items()})
    return st.one_of(base, base, st.builds(lambda d, junk: {**d, "bogus": junk}, base,
                                           ANY_SCALAR))


SCENARIOS = st.fixed_dictionaries({}, optional={
    **{name: st.one_of(_section(keys), _section(keys), ANY_SCALAR)
       for name, keys in SECTIONS.items()},
    "title": st.text(max_size=10),
    "bogus": st.dictionaries(st.text(min_size=1, max_size=5).filter(str.isidentifier),
                             ANY_SCALAR, max_size=2),
})
