"""Every number of "Systematic design of particle dampers for transient vertical vibrations"
(the reference paper), Sects. 2-4: its inputs, the numbers it reports and the tolerance each
comparison of ``pdamper paper`` uses. This module is their one home; the rest of pdamper
takes them as arguments.

Structure mass
--------------
The paper prints M = 1.139 kg, K = 1848 N/m, D = 0.55 kg/s and f0 = 5.56 Hz, but
sqrt(K/M)/(2 pi) = 6.41 Hz. We take **M = K / (2 pi 5.56 Hz)^2 = 1.514 kg**: the
eigenfrequency is the number measured (5.56 +/- 0.02 Hz) and this M reproduces every other
reported number: the undamped damping ratio 0.0052 (~0.005), the undamped amplitude
40 mm after 2 s from x0 = -58 mm, and X_min = g / w^2 = 8.8 mm with the 32 particles as
static mass. (With 1.139 kg: 6.4 Hz, 0.006, 37 mm and 6.7 mm.) A plausible reading is that
1.139 kg excludes the container. The particles are not part of M; the damper model adds
their effective mass.

Coefficients of restitution (Sect. 2, Fig. 2-right)
---------------------------------------------------
The paper's DEM uses measured, velocity-dependent COR curves (Fig. 2-right) from impact
tests and FE simulations of its reference [23]; it prints no table and no formula, and the
figure is not available to pdamper. :data:`PAPER_COR_PP` and :data:`PAPER_COR_PW` are
**reconstructed from the text of Sect. 2**, one parameter per statement:

* steel-steel (sphere-sphere): "starts close to one for small impact velocities and drops
  rapidly when the impact velocity is increased. Finally, the COR converges below 0.5."
  -> ``e(v) = e_inf + (e0 - e_inf) exp(-v / v_c)`` with e0 = 0.98 ("close to one"),
  e_inf = 0.45 ("converges below 0.5") and v_c = 0.2 m/s ("drops rapidly": e = 0.64 at
  0.2 m/s, within 0.05 of e_inf from 0.5 m/s on, inside the measured range up to 1.8 m/s).
* steel-PVC (sphere-wall): "starts at about 0.9 for small impact velocities. For increasing
  impact velocities a slight almost linear reduction is observed. At the highest measurable
  impact velocity of 1.8 m/s the COR still has a value of 0.8." -> linear from 0.90 at 0 to
  0.80 at 1.8 m/s, held at 0.80 beyond 1.8 m/s (pdamper's extrapolation of measured curves).

The shapes follow the text; the exact numbers of Fig. 2 (and so e.g. how fast the steel
curve drops) are not known. ``pdamper cor-sensitivity`` and the scaled curves
(``scale`` in ``[restitution]``) measure how much the results depend on them.

The benchmark runs of pdamper's DEM (tests, benchmarks, the ``[dem]`` defaults) use the
constant values 0.6 (sphere-sphere) and 0.85 (sphere-wall) with which two independent open
DEM codes were run on this damper for comparison (they agree closely with each other; with
these values the 32-sphere bed rattles as locked columns at small strokes, see docs/dem.md).
``pdamper paper`` runs DEM model 1 with both.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from pdamper.analysis.modes import MotionMode
from pdamper.contact.restitution import (
    ConstantRestitution,
    ExponentialRestitution,
    LinearRestitution,
)
from pdamper.damper import ParticleDamper
from pdamper.materials import PVC, S235
from pdamper.structure import SingleDOFStructure
from pdamper.structure.beam import TimoshenkoBeam, TipMass

# ------------------------------------------------------------------------- Level II damper
#: Inner container dimensions (width x depth x length) [m]; the 120 mm side is vertical.
PAPER_CONTAINER = (0.040, 0.040, 0.120)
#: Radius of the steel spheres [m] ("steel particles of 5 mm radius").
PAPER_PARTICLE_RADIUS = 0.005
#: Particle count of the verification case (Sect. 4.2.1, Figs. 5, 7, 8) [-].
PAPER_PARTICLE_COUNT = 32
#: Friction coefficient mu of every contact (Sect. 2) [-].
PAPER_FRICTION = 0.1
#: Constant sphere-sphere and sphere-wall COR of the benchmark runs (module docstring) [-].
BENCHMARK_RESTITUTION_PP = 0.6
BENCHMARK_RESTITUTION_PW = 0.85
#: Fig. 2-right, steel-steel (sphere-sphere), reconstructed from the text (module docstring).
PAPER_COR_PP = ExponentialRestitution(
    e0=0.98, e_inf=0.45, v_c=0.2, name="paper Fig. 2, steel-steel (reconstructed from the text)")
#: Fig. 2-right, steel-PVC (sphere-wall), reconstructed from the text (module docstring).
PAPER_COR_PW = LinearRestitution(
    e0=0.90, slope=(0.90 - 0.80) / 1.8, v_hold=1.8,
    name="paper Fig. 2, steel-PVC (reconstructed from the text)")
#: The highest impact speed the paper measured (Sect. 2) [m/s].
PAPER_COR_MAX_VELOCITY = 1.8

#: The benchmark damper: PVC box 40 x 40 x 120 mm, 32 steel spheres of 5 mm radius.
PAPER_DAMPER = ParticleDamper(
    length=PAPER_CONTAINER[2], width=PAPER_CONTAINER[0], depth=PAPER_CONTAINER[1],
    particle_radius=PAPER_PARTICLE_RADIUS, count=PAPER_PARTICLE_COUNT,
    particle_material=S235, wall_material=PVC, friction=PAPER_FRICTION,
    restitution_pp=ConstantRestitution(BENCHMARK_RESTITUTION_PP),
    restitution_pw=ConstantRestitution(BENCHMARK_RESTITUTION_PW))
#: The benchmark damper with the paper's COR curves (Fig. 2), as the paper's DEM ran it.
PAPER_DAMPER_CURVES = PAPER_DAMPER.with_restitution(PAPER_COR_PP, PAPER_COR_PW)

#: The Level II benchmark point of pdamper's DEM checks: 10 Hz at the paper's X_opt = 32 mm
#: (frequency [Hz], stroke [m]).
BENCHMARK_EXCITATION = (10.0, 0.032)

#: Level II grid of Fig. 5: 14 frequencies in 2-20 Hz x 24 strokes in 1-200 mm.
PAPER_MAP_FREQUENCY = (2.0, 20.0, 14)
PAPER_MAP_AMPLITUDE = (0.001, 0.200, 24)

#: The example points of Fig. 4 (h = 0.1 m): (X [m], f [Hz], mode the paper names, case).
FIG4_EXAMPLES = (
    (0.015, 4.0, MotionMode.SOLID, "1"),
    (0.015, 6.0, MotionMode.SINGLE_CAC_HARMONIC, "2i"),
    (0.015, 10.0, MotionMode.SINGLE_CAC_SUBHARMONIC, "2ii"),
    (0.050, 18.0, MotionMode.DOUBLE_CAC_HARMONIC, "3i"),
    (0.020, 18.0, MotionMode.DOUBLE_CAC_SUBHARMONIC, "3ii"),
    (0.015, 14.0, MotionMode.SCATTERING, "3iii"),
)

# ------------------------------------------------------------------------ Level III structure
#: Measured first eigenfrequency of the beam-like structure without particles [Hz].
PAPER_EIGENFREQUENCY = 5.56
PAPER_STIFFNESS = 1848.0
PAPER_DAMPING = 0.55
#: The mass as printed [kg]; inconsistent with K and f0 (module docstring).
PAPER_PRINTED_MASS = 1.139
#: See the module docstring for why not the printed 1.139 kg.
PAPER_MASS = PAPER_STIFFNESS / (2.0 * math.pi * PAPER_EIGENFREQUENCY) ** 2
#: Reduced model of the beam-like structure, Eq. (23), with M as argued above.
PAPER_STRUCTURE = SingleDOFStructure(mass=PAPER_MASS, damping=PAPER_DAMPING,
                                     stiffness=PAPER_STIFFNESS)
#: Initial deflection of the end-effector [m] (Sect. 4: counterweight of 11 kg).
PAPER_INITIAL_DISPLACEMENT = -0.058
#: Simulated and measured time span of Figs. 7 and 8 [s].
PAPER_DURATION = 2.0
#: Objective time of the optimisation (Sect. 4.2.2) [s].
PAPER_OBJECTIVE_TIME = 0.8
#: Time at which the paper compares amplitudes (Sect. 4.2.2, Fig. 9) [s].
PAPER_COMPARISON_TIME = 0.75
#: Increment of the particle count in the optimisation: one layer (Sect. 4.2.2) [-].
PAPER_COUNT_STEP = 16
#: The optimum the paper finds [-].
PAPER_OPTIMAL_COUNT = 64

#: Damper plus additional mass at the free end of the paper's beam [kg] (Sect. 4).
PAPER_TIP_MASS = 1.270


def paper_beam(elements: int = 100) -> tuple[TimoshenkoBeam, TipMass]:
    """The paper's beam-like structure (Sect. 4): beam and 1.27 kg point mass at the tip.

    680 mm x 80 mm x 6 mm steel (6 mm in the bending direction), E = 200 GPa (paper);
    nu = 0.3 and rho = 7850 kg/m^3 are pdamper's documented choices, not from the paper.

    Parameters
    ----------
    elements
        Number of Timoshenko elements (paper: 100) [-].

    Examples
    --------
    >>> beam, tip = paper_beam()
    >>> beam.length, tip.mass
    (0.68, 1.27)
    """
    beam = TimoshenkoBeam(length=0.680, width=0.080, height=0.006, youngs_modulus=200e9,
                          poisson_ratio=0.3, density=7850.0, elements=elements)
    return beam, TipMass(PAPER_TIP_MASS)


# ---------------------------------------------------------------- reported numbers
@dataclass(frozen=True)
class Within:
    """Acceptance interval of a compared number (SI units); ``open`` ends exclude."""

    low: float = -math.inf
    high: float = math.inf
    low_open: bool = False
    high_open: bool = False

    def __call__(self, value: float) -> bool:
        v = float(value)
        lo = v > self.low if self.low_open else v >= self.low
        hi = v < self.high if self.high_open else v <= self.high
        return bool(lo and hi)


def near(value: float, tolerance: float, closed: bool = False) -> Within:
    """``|x - value| < tolerance`` (``<=`` if ``closed``)."""
    return Within(value - tolerance, value + tolerance, not closed, not closed)


@dataclass(frozen=True)
class Reported:
    """A number the paper reports and how close ours must be to count as agreeing.

    Parameters
    ----------
    key
        Identifier used by the case study.
    quantity
        What it is (row label of the comparison table).
    paper
        The paper's number as printed.
    source
        Where the paper gives it.
    accept
        :class:`Within` for one number, a tuple of them for a range (low, high), the
        expected value of a category (a motion mode), or None where the paper gives no
        number to compare with (the row reports ours, without a verdict).
    note
        Why the tolerance is what it is, or what differs.
    """

    key: str
    quantity: str
    paper: str
    source: str
    accept: object
    note: str = ""

    def agrees(self, ours) -> bool | None:
        """Whether ``ours`` (a number, a (low, high) pair, or a category) agrees (None: no
        verdict)."""
        if self.accept is None:
            return None
        if isinstance(self.accept, Within):
            return self.accept(ours)
        if isinstance(self.accept, tuple):
            return all(w(v) for w, v in zip(self.accept, ours, strict=True))
        return ours == self.accept


_ETA_MAX = 4.0 / math.pi
_CONSTANT_COR_NOTE = (f"constant COR {BENCHMARK_RESTITUTION_PP} / {BENCHMARK_RESTITUTION_PW} "
                      "(the paper's DEM: measured e(v) curves)")

#: The paper's reported numbers, in the order of the case-study table.
PAPER_REPORTED: tuple[Reported, ...] = (
    *(Reported(f"fig4_{case}", f"Fig. 4-{case} mode (X = {x * 1e3:g} mm, f = {f:g} Hz)",
               mode.title, "Sect. 3.1.1, Fig. 4", mode)
      for x, f, mode, case in FIG4_EXAMPLES),
    Reported("x_opt", "optimal stroke X_opt = h / pi (Eq. 19)", "32 mm", "Sect. 3.1.2",
             near(0.032, 0.0005)),
    Reported("eta_max", "eta at X_opt for A >> g (Eq. 21)", f"4/pi = {_ETA_MAX:.3f}",
             "Eqs. 19-21", near(_ETA_MAX, 0.01)),
    Reported("double_cac_harmonic_eta", "double CaC harmonic eta range (Fig. 5)",
             "0.25 - 1.25", "Sect. 3.1.2, Fig. 5b/c",
             (Within(0.2, low_open=True), Within(1.15, _ETA_MAX, low_open=True))),
    Reported("single_cac_harmonic_eta", "single CaC harmonic eta max (Fig. 5)", "up to 0.7",
             "Sect. 3.1.2, Fig. 5b/c", (Within(), Within(0.6, 0.85, True, True))),
    Reported("subharmonic_eta", "subharmonic modes eta range (Fig. 5)", "0.1 - 0.3 or below",
             "Sect. 3.1.2, Fig. 5b/c", (Within(), Within(high=0.4, high_open=True))),
    Reported("eta_max_grid", "maximum eta on the {grid} grid", "1.25 (DEM) vs 4/pi",
             "Sect. 3.1.2", near(1.25, 0.05), "analytical model; grid point nearest X_opt"),
    # Fig. 5b/5d: the DEM map against the analytical one (on the DEM map's grid)
    Reported("dem_map_steady", "steady DEM cells of the {grid} DEM map",
             "(8 cycles, first 2 cut off)", "Sect. 3.1.2", None,
             "pdamper runs each point until its loss factor is steady (docs/fields.md)"),
    Reported("dem_mode_agreement", "DEM cells whose motion mode equals the analytical one",
             "'good agreement' (no number)", "Sect. 3.1.2, Fig. 5a", None,
             f"{_CONSTANT_COR_NOTE}; modes from the DEM classifier (docs/fields.md)"),
    *(Reported(f"dem_delta_eta_{mode.label}",
               f"median |eta DEM - eta analytical|, {mode.title} cells",
               claim, "Sect. 3.1.2, Fig. 5b/c", accept, note)
      for mode, claim, accept, note in (
          (MotionMode.SOLID, "both < 0.1 (dark blue)", Within(high=0.1),
           "pdamper: within 0.1"),
          (MotionMode.SINGLE_CAC_HARMONIC, "good agreement", Within(high=0.15),
           "pdamper's reading of 'good agreement': within 0.15, a third of the mode's range"),
          (MotionMode.SINGLE_CAC_SUBHARMONIC, "higher local discrepancies", None, ""),
          (MotionMode.DOUBLE_CAC_HARMONIC, "good agreement", Within(high=0.15),
           "pdamper's reading of 'good agreement': within 0.15"),
          (MotionMode.DOUBLE_CAC_SUBHARMONIC, "higher local discrepancies", None, ""),
          (MotionMode.SCATTERING, "both < 0.1 (dark blue)", Within(high=0.1),
           f"{_CONSTANT_COR_NOTE}"))),
    Reported("dem_eta_xopt", "DEM eta at the stroke nearest X_opt, f >= 8 Hz (maximum)",
             "1.25 (the DEM maximum)", "Sect. 3.1.2, Fig. 5b", near(1.25, 0.1),
             f"{_CONSTANT_COR_NOTE}; tolerance: the resolution of Fig. 5b's colour scale near 1"),
    Reported("eigenfrequency", "eigenfrequency f0 without particles",
             f"{PAPER_EIGENFREQUENCY} Hz", "Sect. 4.2", near(PAPER_EIGENFREQUENCY, 0.02),
             "M = K / (2 pi f0)^2 = 1.514 kg, see parameters"),
    Reported("beam_eigenfrequency",
             "f0 of the Timoshenko FE beam model (100 elements, 1.27 kg tip)",
             f"{PAPER_EIGENFREQUENCY} Hz (M = {PAPER_PRINTED_MASS} kg, K = {PAPER_STIFFNESS:g} N/m)",
             "Sect. 4.1", near(PAPER_EIGENFREQUENCY, 0.1),
             "the stated beam data give a stiffer beam; independent check: Euler-Bernoulli "
             f"tip-mass equation 6.085 Hz; see docs/beam.md. Level III uses K = {PAPER_STIFFNESS:g} N/m"),
    Reported("undamped_zeta", "damping ratio without particles", "~0.005", "Sect. 4.2.1",
             near(0.005, 0.001)),
    Reported("undamped_amplitude_2s", "amplitude without particles after 2 s", "~40 mm",
             "Sect. 4.2.1", near(0.040, 0.002)),
    Reported("x_min", "X_min = g / w^2, particles as static mass", "8.8 mm", "Sect. 4.2.1",
             near(0.0088, 0.0002)),
    Reported("zeta_53mm", "damping ratio near 53 mm, 32 spheres (Fig. 8)", "~0.035",
             "Sect. 4.2.1, Fig. 8", Within(0.03, 0.055), "paper: experiment; double CaC"),
    Reported("zeta_41mm", "damping ratio near 41 mm, 32 spheres (Fig. 8)", "~0.05",
             "Sect. 4.2.1, Fig. 8", Within(0.03, 0.055), "paper: experiment; double CaC"),
    Reported("cac_switch", "double -> single CaC switch, 32 spheres",
             "just below ~41 mm, near X_opt", "Sect. 4.2.1", Within(0.025, 0.041, True, True)),
    Reported("amplitude_32_0p75s", "amplitude at 0.75 s, 32 spheres", "~19 mm (experiment)",
             "Sect. 4.2.2", near(0.019, 0.3 * 0.019),
             "the analytical single-CaC dissipation just below X_opt is lower than "
             "measured (paper: 'two damping values are slightly off')"),
    Reported("dem_cor_calibration", "Fig. 2 COR curves in single DEM impacts, "
             "0.01-2 m/s (max |e_DEM - e|)", "Fig. 2-right (measured curves)", "Sect. 2, Fig. 2",
             Within(high=0.01), "the curves are reconstructed from the text (see parameters); "
             "the DEM's damping follows them (exact COR-damping relation)"),
    Reported("dem_amplitude_32_0p75s", "amplitude at 0.75 s, 32 spheres, DEM model 1, {cor}",
             "~19 mm (experiment)", "Sect. 4.2.1, Fig. 7", near(0.019, 0.3 * 0.019),
             f"default: {_CONSTANT_COR_NOTE}; DEM and analytical agree within 10 %, both decay "
             "slower than measured"),
    Reported("dem_curves_amplitude_32_0p75s",
             "amplitude at 0.75 s, 32 spheres, DEM model 1, the paper's COR curves (Fig. 2)",
             "~19 mm (experiment)", "Sect. 4.2.1, Figs. 2, 7", near(0.019, 0.3 * 0.019),
             "as the paper ran its DEM (curves reconstructed from the text): within a few % of "
             "the constant-COR run, still slower than measured"),
    Reported("dem_zeta_53mm", "damping ratio near 53 mm, DEM model 1, {cor}", "~0.035",
             "Fig. 8", Within(0.02, 0.06)),
    Reported("dem_zeta_41mm", "damping ratio near 41 mm, DEM model 1, {cor}", "~0.05", "Fig. 8",
             Within(0.02, 0.06)),
    Reported("dem_curves_zeta_53mm", "damping ratio near 53 mm, DEM model 1, the paper's COR "
             "curves", "~0.035", "Figs. 2, 8", Within(0.02, 0.06)),
    Reported("dem_curves_zeta_41mm", "damping ratio near 41 mm, DEM model 1, the paper's COR "
             "curves", "~0.05", "Figs. 2, 8", Within(0.02, 0.06)),
    Reported("optimal_count", "optimal particle count (amplitude at {at} s)", "64 (265 g)",
             "Sect. 4.2.2", near(PAPER_OPTIMAL_COUNT, PAPER_COUNT_STEP, closed=True),
             "objective landscape in optimization.png / results.json"),
    Reported("amplitude_64_0p75s", "amplitude at 0.75 s, 64 spheres (Fig. 9)",
             "~10 mm (experiment)", "Sect. 4.2.2, Fig. 9", near(0.010, 0.003)),
    Reported("bed_mass_64", "bed mass of 64 spheres", "265 g", "Sect. 4.2.2",
             near(0.265, 0.002)),
)

#: The reported numbers by key.
REPORTED = {r.key: r for r in PAPER_REPORTED}

__all__ = [
    "BENCHMARK_EXCITATION",
    "BENCHMARK_RESTITUTION_PP",
    "BENCHMARK_RESTITUTION_PW",
    "FIG4_EXAMPLES",
    "PAPER_COMPARISON_TIME",
    "PAPER_CONTAINER",
    "PAPER_COR_MAX_VELOCITY",
    "PAPER_COR_PP",
    "PAPER_COR_PW",
    "PAPER_COUNT_STEP",
    "PAPER_DAMPER",
    "PAPER_DAMPER_CURVES",
    "PAPER_DAMPING",
    "PAPER_DURATION",
    "PAPER_EIGENFREQUENCY",
    "PAPER_FRICTION",
    "PAPER_INITIAL_DISPLACEMENT",
    "PAPER_MAP_AMPLITUDE",
    "PAPER_MAP_FREQUENCY",
    "PAPER_MASS",
    "PAPER_OBJECTIVE_TIME",
    "PAPER_OPTIMAL_COUNT",
    "PAPER_PARTICLE_COUNT",
    "PAPER_PARTICLE_RADIUS",
    "PAPER_PRINTED_MASS",
    "PAPER_REPORTED",
    "PAPER_STIFFNESS",
    "PAPER_STRUCTURE",
    "PAPER_TIP_MASS",
    "REPORTED",
    "Reported",
    "Within",
    "near",
    "paper_beam",
]
