"""Motion modes of a vertically driven particle bed (paper Sect. 3.1, Fig. 4) and the
effective-mass approximation of Eq. (22)."""

from __future__ import annotations

from enum import IntEnum


class MotionMode(IntEnum):
    """Motion mode of the particle bed; integer codes are stable (stored in NetCDF)."""

    SOLID = 0
    SINGLE_CAC_HARMONIC = 1
    SINGLE_CAC_SUBHARMONIC = 2
    DOUBLE_CAC_HARMONIC = 3
    DOUBLE_CAC_SUBHARMONIC = 4
    SCATTERING = 5
    #: Not in the paper: a bed that repeats its motion but rebounds elastically from the
    #: walls instead of collecting (the locked columns of a constant-COR lattice bed).
    #: Only the DEM classifier (:mod:`pdamper.analysis.dem_modes`) reports it.
    RATTLING = 6

    @property
    def label(self) -> str:
        """Short name used in JSON output, e.g. ``"double_cac_harmonic"``."""
        return self.name.lower()

    @property
    def title(self) -> str:
        """Human-readable name as in the paper's Fig. 5a legend."""
        return _TITLES[self]

    @classmethod
    def from_label(cls, label: str) -> MotionMode:
        return cls[label.upper()]


_TITLES = {
    MotionMode.SOLID: "solid-like",
    MotionMode.SINGLE_CAC_HARMONIC: "single CaC, harmonic",
    MotionMode.SINGLE_CAC_SUBHARMONIC: "single CaC, subharmonic",
    MotionMode.DOUBLE_CAC_HARMONIC: "double CaC, harmonic",
    MotionMode.DOUBLE_CAC_SUBHARMONIC: "double CaC, subharmonic",
    MotionMode.SCATTERING: "scattering",
    MotionMode.RATTLING: "rattling (not in the paper)",
}

#: The modes the paper names (Sect. 3.1.1, Fig. 4); the analytical model reports only these.
PAPER_MODES: tuple[MotionMode, ...] = tuple(m for m in MotionMode if m is not MotionMode.RATTLING)

#: Effective particle mass over bed mass per motion mode, paper Eq. (22) (the paper's modes).
EFFECTIVE_MASS_RATIO: dict[MotionMode, float] = {
    MotionMode.SOLID: 0.75,
    MotionMode.DOUBLE_CAC_HARMONIC: 0.75,
    MotionMode.SINGLE_CAC_HARMONIC: 0.65,
    MotionMode.DOUBLE_CAC_SUBHARMONIC: 0.2,
    MotionMode.SINGLE_CAC_SUBHARMONIC: 0.2,
    MotionMode.SCATTERING: 0.1,
}

#: CF-style attributes describing the integer mode codes in NetCDF files.
#: ``-1`` marks points without a mode (not classified, or the run failed).
MODE_FLAG_ATTRS = {
    "flag_values": [-1] + [int(m) for m in MotionMode],
    "flag_meanings": " ".join(["unclassified"] + [m.label for m in MotionMode]),
}
