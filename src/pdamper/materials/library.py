"""The materials library: the paper's S235 and PVC and the materials particle dampers use.

Every number has its source, named beside the constant (a key of :data:`REFERENCES`) and
tabulated in ``docs/materials.md`` (:func:`materials_table` writes that table; a test keeps
the two equal). The values are typical room-temperature values of the named grade and
temper; a real batch differs (yield strength most of all): give measured data as an inline
material in the scenario file (``material = { name = ..., youngs_modulus = ..., ... }``).

Lookup (:func:`get_material`) is by name or alias, ignoring case, spaces, hyphens,
underscores and dots: ``"aisi 52100"``, ``"100cr6"`` and ``"100Cr6"`` are the same material.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass, field

from pdamper.errors import InputError
from pdamper.materials.base import Material

GPa = 1e9
MPa = 1e6
G_CM3 = 1000.0  # g/cm^3 -> kg/m^3

#: Sources of the library's numbers, by key.
REFERENCES: dict[str, str] = {
    "paper": "The reference paper, Fig. 2-left (E, nu, rho of the S235 spheres and the PVC walls).",
    "EN10025-2": "EN 10025-2:2019, hot rolled structural steels: S235, minimum upper yield strength "
                 "R_eH = 235 MPa for nominal thickness <= 16 mm.",
    "Callister": "W. D. Callister, D. G. Rethwisch, Materials Science and Engineering: An "
                 "Introduction, 10th ed., Wiley 2018, Appendix B: Tables B.1 (density), B.2 "
                 "(modulus of elasticity), B.3 (Poisson's ratio), B.4 (yield strength). Where the "
                 "table gives a range, the library takes its middle.",
    "52100-balls": "AISI 52100 chrome steel balls (through-hardened, HRC 60-67), supplier's "
                   "'Materials & Specifications' sheet: modulus 29.5e6 psi (203 GPa), yield "
                   "strength 295 ksi (2034 MPa), density 0.283 lb/in^3 (7833 kg/m^3); "
                   "https://ja.scribd.com/document/252517093/ASTM-52100-Material-Del-Tornillo-de-Potencia",
    "MakeItFrom-52100": "MakeItFrom.com, SAE-AISI 52100 (G52986) chromium steel: Poisson's ratio "
                        "0.29; https://www.makeitfrom.com/compare/SAE-AISI-52100-G52986-Chromium-"
                        "Steel/4032-4032-T6-AlSi12.5MgCuNi-Aluminum",
    "ASTM-A240": "ASTM A240 / A213, annealed type 304 austenitic stainless steel: minimum 0.2 % "
                 "offset yield strength 205 MPa (30 ksi).",
    "Cardarelli": "F. Cardarelli, Materials Handbook: A Concise Desktop Reference, 3rd ed., "
                  "Springer 2018, and CRC Handbook of Chemistry and Physics, 97th ed., as "
                  "tabulated at https://matmake.com/materials-data/ (tungsten: E 411 GPa, nu 0.28, "
                  "19 300 kg/m^3; lead: E 16.1 GPa, nu 0.44, 11 350 kg/m^3).",
    "Callister-1994": "W. D. Callister, Materials Science and Engineering, Wiley 1994, as quoted "
                      "by the Princeton MAE 324 glossary: lead yield stress 11 MPa; "
                      "https://princeton.edu/~maelabs/mae324/glos324/lead.htm",
    "MakeItFrom-WC": "MakeItFrom.com, tungsten carbide (cemented WC): E 630 GPa, nu 0.24, "
                     "15 g/cm^3; https://www.makeitfrom.com/material-properties/Tungsten-Carbide-WC",
    "POM-C": "Acetal (polyoxymethylene) copolymer, unreinforced, typical datasheet values: "
             "density 1.41 g/cm^3, modulus 2.82 GPa, tensile yield 59.3 MPa, Poisson's ratio "
             "0.363; http://apacinfrastructure.com.au/material-specifications-acetal-polyoxymethylene",
    "MatWeb-NR": "MatWeb, natural rubber, vulcanized (NR): density 0.950 g/cm^3 (uncompounded), "
                 "shear modulus 0.5 MPa; E = 2 G (1 + nu) with nu = 0.499 (rubber is nearly "
                 "incompressible; pdamper needs nu < 0.5); https://www.matweb.com/search/"
                 "datasheet_print.aspx?matguid=6588439546ac4492965c894ddff3f5da",
}


@dataclass(frozen=True)
class LibraryEntry:
    """A material of the library with its aliases and the source of each number.

    ``sources`` maps the field names of :class:`Material` (``youngs_modulus``,
    ``poisson_ratio``, ``density``, ``yield_strength``) to keys of :data:`REFERENCES`.
    """

    material: Material
    description: str
    sources: dict[str, str]
    aliases: tuple[str, ...] = ()
    note: str = ""
    names: tuple[str, ...] = field(init=False)

    def __post_init__(self) -> None:
        object.__setattr__(self, "names", (self.material.name, *self.aliases))


def _entry(name, description, e, nu, rho, y, sources, aliases=(), note=""):
    return LibraryEntry(Material(name, e, nu, rho, y), description, sources, tuple(aliases), note)


_C = {"youngs_modulus": "Callister", "poisson_ratio": "Callister", "density": "Callister",
      "yield_strength": "Callister"}
_C_ELASTIC = {k: v for k, v in _C.items() if k != "yield_strength"}

#: The library, in the order of ``docs/materials.md``.
LIBRARY: tuple[LibraryEntry, ...] = (
    # --- the paper's two materials (Fig. 2-left) ---
    _entry("S235", "structural steel (the paper's spheres)", 208 * GPa, 0.30, 7900.0, 235 * MPa,
           {"youngs_modulus": "paper", "poisson_ratio": "paper", "density": "paper",
            "yield_strength": "EN10025-2"}, ("S235JR",)),
    _entry("PVC", "rigid polyvinyl chloride (the paper's container walls)", 3 * GPa, 0.38, 1400.0,
           43 * MPa,  # Callister B.4: 40.7 - 44.8 MPa
           {"youngs_modulus": "paper", "poisson_ratio": "paper", "density": "paper",
            "yield_strength": "Callister"}, ("PVC-U", "polyvinyl chloride")),
    # --- steels ---
    _entry("100Cr6", "through-hardened bearing steel (AISI 52100, 1.3505), bearing balls",
           203 * GPa, 0.29, 7833.0, 2034 * MPa,
           {"youngs_modulus": "52100-balls", "poisson_ratio": "MakeItFrom-52100",
            "density": "52100-balls", "yield_strength": "52100-balls"},
           ("AISI 52100", "52100", "1.3505", "SUJ2", "chrome steel", "bearing steel"),
           "hardened; annealed 52100 yields at about 360-560 MPa (MakeItFrom)"),
    _entry("AISI 304", "austenitic stainless steel, annealed (1.4301, X5CrNi18-10)", 193 * GPa,
           0.30, 8000.0, 205 * MPa,
           {**_C_ELASTIC, "yield_strength": "ASTM-A240"},
           ("304", "1.4301", "X5CrNi18-10", "stainless steel", "SS304")),
    # --- heavy metals ---
    _entry("tungsten", "pure tungsten (W)", 411 * GPa, 0.28, 19300.0, None,
           {"youngs_modulus": "Cardarelli", "poisson_ratio": "Cardarelli", "density": "Cardarelli"},
           ("W", "wolfram"),
           "brittle below its ductile-brittle transition (100-400 C): no yield strength; "
           "tungsten heavy alloys (W-Ni-Fe, 17-18.5 g/cm^3) are not in the library"),
    _entry("WC-Co", "cemented tungsten carbide (hard metal)", 630 * GPa, 0.24, 15000.0, None,
           {"youngs_modulus": "MakeItFrom-WC", "poisson_ratio": "MakeItFrom-WC",
            "density": "MakeItFrom-WC"},
           ("tungsten carbide", "WC", "hard metal", "cemented carbide"),
           "brittle: no yield strength"),
    _entry("lead", "pure lead (Pb)", 16.1 * GPa, 0.44, 11350.0, 11 * MPa,
           {"youngs_modulus": "Cardarelli", "poisson_ratio": "Cardarelli", "density": "Cardarelli",
            "yield_strength": "Callister-1994"}, ("Pb",),
           "creeps at room temperature; its yield strength depends on the strain rate"),
    # --- non-ferrous ---
    _entry("aluminium", "aluminium alloy 6061-T6 (EN AW-6061 T6)", 69 * GPa, 0.33, 2700.0,
           276 * MPa, _C, ("aluminum", "6061-T6", "AlMg1SiCu", "EN AW-6061")),
    _entry("brass", "cartridge brass C26000 (CuZn30), annealed", 110 * GPa, 0.35, 8530.0, 75 * MPa,
           _C, ("C26000", "CuZn30")),
    _entry("copper", "electrolytic tough pitch copper C11000 (Cu-ETP), annealed", 115 * GPa, 0.34,
           8890.0, 69 * MPa, _C, ("Cu", "C11000", "Cu-ETP")),
    # --- glass and ceramics (brittle: no yield strength) ---
    _entry("soda-lime glass", "soda-lime glass", 69 * GPa, 0.23, 2500.0, None, _C_ELASTIC,
           ("glass",), "brittle: no yield strength"),
    _entry("alumina", "aluminium oxide, 99.9 % (Al2O3)", 380 * GPa, 0.22, 3980.0, None, _C_ELASTIC,
           ("Al2O3", "aluminium oxide", "aluminum oxide"), "brittle: no yield strength"),
    _entry("zirconia", "zirconia, 3 mol% Y2O3 (3Y-TZP)", 205 * GPa, 0.31, 6000.0, None,
           _C_ELASTIC, ("ZrO2", "3Y-TZP", "YTZP"), "brittle: no yield strength"),
    # --- polymers and rubber ---
    _entry("POM", "polyoxymethylene (acetal) copolymer, unreinforced", 2.82 * GPa, 0.363, 1410.0,
           59.3 * MPa,
           {"youngs_modulus": "POM-C", "poisson_ratio": "POM-C", "density": "POM-C",
            "yield_strength": "POM-C"}, ("acetal", "POM-C", "polyoxymethylene")),
    _entry("PA66", "polyamide 6,6 (nylon 6,6)", 2.69 * GPa, 0.39, 1140.0, 63.8 * MPa,
           _C,  # Callister: E 1.59 - 3.79 GPa, yield 44.8 - 82.8 MPa (middles)
           ("nylon", "nylon 6,6", "polyamide"),
           "absorbs water: modulus and yield strength fall by about half when conditioned"),
    _entry("PMMA", "polymethyl methacrylate (acrylic glass)", 2.74 * GPa, 0.405, 1190.0,
           63.5 * MPa,
           _C,  # Callister: E 2.24 - 3.24 GPa, nu 0.37 - 0.44, yield 53.8 - 73.1 MPa (middles)
           ("acrylic", "plexiglas", "polymethyl methacrylate")),
    _entry("natural rubber", "natural rubber, vulcanized, unfilled (NR)", 1.499 * MPa, 0.499,
           950.0, None, {"youngs_modulus": "MatWeb-NR", "poisson_ratio": "MatWeb-NR",
                         "density": "MatWeb-NR"}, ("NR", "rubber", "polyisoprene"),
           "hyperelastic: Hertz contact holds for small strains only; no yield strength"),
)

#: The library's materials by name.
MATERIALS: dict[str, Material] = {e.material.name: e.material for e in LIBRARY}

#: Structural steel of the spheres (paper Fig. 2-left; yield strength EN 10025-2).
S235 = MATERIALS["S235"]
#: Polyvinyl chloride of the container walls (paper Fig. 2-left; yield strength Callister).
PVC = MATERIALS["PVC"]


def _key(name: str) -> str:
    return "".join(c for c in str(name).lower() if c not in " -_.,")


_BY_KEY: dict[str, LibraryEntry] = {}
for _e in LIBRARY:
    for _n in _e.names:
        if _key(_n) in _BY_KEY:  # pragma: no cover - a library bug, caught at import
            raise RuntimeError(f"material name {_n!r} is ambiguous")
        _BY_KEY[_key(_n)] = _e


def known_names() -> list[str]:
    """The library's material names (aliases not included)."""
    return [e.material.name for e in LIBRARY]


def library_entry(name: str, field: str = "material") -> LibraryEntry:
    """The :class:`LibraryEntry` of ``name`` or one of its aliases (case-insensitive)."""
    try:
        return _BY_KEY[_key(name)]
    except KeyError:
        raise InputError(field, f"unknown material {name!r}; known: {', '.join(known_names())} "
                         "(or give an inline material)") from None


def get_material(name: str, field: str = "material") -> Material:
    """Look up a library material by name or alias, ignoring case and punctuation.

    >>> get_material("aisi 52100").name, get_material("pvc") is PVC
    ('100Cr6', True)
    """
    return library_entry(name, field).material


def _fmt(v: float | None, scale: float, digits: int = 4) -> str:
    return "-" if v is None else f"{v / scale:.{digits}g}"


def materials_table(entries: Iterable[LibraryEntry] = LIBRARY) -> str:
    """The library as a Markdown table (the one in ``docs/materials.md``)."""
    lines = ["| name | aliases | material | E [GPa] | nu [-] | rho [kg/m^3] | yield [MPa] | "
             "sources (E, nu, rho, yield) | note |",
             "|---|---|---|---|---|---|---|---|---|"]
    for e in entries:
        m, s = e.material, e.sources
        src = ", ".join(s.get(k, "-") for k in ("youngs_modulus", "poisson_ratio", "density",
                                                "yield_strength"))
        lines.append(f"| {m.name} | {', '.join(e.aliases)} | {e.description} | "
                     f"{_fmt(m.youngs_modulus, GPa)} | {m.poisson_ratio:g} | {m.density:g} | "
                     f"{_fmt(m.yield_strength, MPa)} | {src} | {e.note} |")
    return "\n".join(lines) + "\n"


__all__ = ["LIBRARY", "LibraryEntry", "MATERIALS", "PVC", "REFERENCES", "S235", "get_material",
           "known_names", "library_entry", "materials_table"]
