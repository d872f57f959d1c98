"""Typed settings, each declared once: type, unit, default, constraint and docstring.

A setting is a field of a frozen :class:`Settings` model declared with :func:`setting`; the
declaration is the one place of its constraint (checked by one validator of the base class,
with the messages of :func:`pdamper.errors.check_range`), its unit (SI inside; the scenario
and the command line parse quantities with this unit at the edges) and its description
(the docstring of the field, the scenario reference and the command line's help).

The declaration machinery (:func:`setting`, :class:`Settings`, :func:`declaration`,
:func:`check_setting`) is :mod:`pdamper.settings`, re-exported here.

- :class:`EngineSettings`: the DEM engine and its integrators (:class:`pdamper.dem.DEMEngine`).
- The Level II settings of the DEM damper (run plan, steady-state criterion, accuracy target)
  are in :mod:`pdamper.models.settings`; the scenario's ``[dem]`` section and the ``dem``
  command derive from them.

Settings objects list their values (:meth:`Settings.get_params`) and are copied with
changes (:meth:`Settings.clone`), as scikit-learn's estimators are.
"""

from __future__ import annotations

from pdamper.constants import STANDARD_GRAVITY
from pdamper.dem.inputs import (
    DEFAULT_GEAR_TOLERANCE,
    DEFAULT_GEAR_VELOCITY_SCALE,
    DEFAULT_SAFETY,
    INTEGRATORS,
)

# the declaration machinery is level 0 (the damper, level 1, declares its quantities with
# it too); re-exported for the settings of the DEM and their users
from pdamper.settings import (  # noqa: F401
    KINDS,
    Settings,
    allowed,
    check_setting,
    declaration,
    redeclare,
    setting,
)

#: ``integrator="auto"`` runs Gear and hands over to velocity Verlet while Gear's mean step
#: over a judgement window of the excitation is below AUTO_COST_RATIO x the step Verlet would
#: take. At 1 the rule needs no cost model: Verlet then takes fewer steps, and each is
#: cheaper (a variable Gear step costs 1.6-2.4 Verlet steps: 2.4 at 32 spheres, 1.6 at 176,
#: where the force evaluation dominates). Gear's step falls below Verlet's where its
#: stability limit holds it, whatever its tolerance: a jammed bed (the full container,
#: 0.16 us against Verlet's 0.39 us). A ratio of 2.4 handed a Level III run of 176 spheres
#: (impacts and flights alternating within each structure period) to Verlet for 0.7 of its
#: 2 s and made it 14-80 % slower than Gear. Both integrators meet the verification table
#: of docs/verification.md.
AUTO_COST_RATIO = 1.0
#: Gear tolerance of a Level II run of the DEM damper from the lattice, throughout (no
#: transient tolerance), where ``gear_tolerance`` is left at its default (None). The lattice
#: is one deterministic start whose ordered state the independent codes keep (LIGGGHTS 3.8
#: from the same jittered lattice, docs/agreement.md "How the lattice is integrated"); at 1e-3 in the
#: first cycles pdamper left it (10 Hz / 32 mm, Tsuji law: eta 1.100, m_eff/m_bed 1.110
#: against LIGGGHTS' 0.949 / 1.922). 1e-6 held it at 32 mm but not with Tsuji's law at
#: 80 mm (5 Hz: 0.534 at 1e-6, 0.448 at 1e-8, 0.344 at 1e-9 and 0.343 at 1e-10; velocity
#: Verlet 0.338 / 0.350 at safety 0.005 / 0.02, LIGGGHTS 0.354), nor 128 spheres at 5 Hz /
#: 32 mm (0.626 at 1e-6; 0.395 / 0.395 / 0.395 at 1e-8 / 1e-9 / 1e-10, Verlet 0.394). At
#: 1e-9 the 32 spheres' 12-point grid (5-20 Hz x 10-80 mm, two jitters, Tsuji's law) agrees
#: with 1e-10 within 0.3 % at 11 points (2 % at 15 Hz / 80 mm) and takes 0.6-1.6x the steps
#: of 1e-6 (the kept order is a block in free flight; the 128 spheres 1.4-3.2x). Random beds
#: keep DEFAULT_GEAR_TOLERANCE and the transient tolerance (their realisation spread covers
#: what it changes).
LATTICE_GEAR_TOLERANCE = 1e-9
#: Starts the tolerance rule knows: the DEM damper's lattice, and every other start.
STARTS = ("lattice", "random", "given")


def gear_tolerance_for(value: float | None, start: str = "given") -> float:
    """The Gear tolerance a run uses: ``value`` where the settings give one, else by the
    ``start`` (the declaration of ``EngineSettings.gear_tolerance``):
    :data:`LATTICE_GEAR_TOLERANCE` (1e-9) for ``"lattice"``,
    :data:`~pdamper.dem.inputs.DEFAULT_GEAR_TOLERANCE` (1e-5) otherwise.

    >>> gear_tolerance_for(None, "lattice"), gear_tolerance_for(None, "random")
    (1e-09, 1e-05)
    >>> gear_tolerance_for(1e-6, "lattice")
    1e-06
    """
    if value is not None:
        return float(value)
    return LATTICE_GEAR_TOLERANCE if start == "lattice" else DEFAULT_GEAR_TOLERANCE


class EngineSettings(Settings):
    """Settings of the DEM engine (paper Sect. 3): integrator, step control, settling and
    stops (:class:`pdamper.dem.DEMEngine`). SI units."""

    integrator: str = setting(
        "verlet", "``verlet`` (fixed-step velocity Verlet), ``gear`` (variable-step "
        "fifth-order Gear predictor-corrector, the paper's) or ``auto`` (Gear, handing the "
        "excitation over to Verlet where Gear's steps fall below ``auto_cost_ratio`` x "
        "Verlet's).", choices=INTEGRATORS)
    safety: float = setting(
        DEFAULT_SAFETY, "Time step / Hertz contact duration at the reference speed (the "
        "Gear integrator's step at a contact onset).", low=0.0, high=1.0,
        low_inclusive=False)
    gravity: float = setting(STANDARD_GRAVITY, "g, acting along -z.", unit="m/s^2", low=0.0)
    gear_tolerance: float | None = setting(
        None, "Error tolerance of the Gear step control (:func:`gear_tolerance_for`).",
        low=0.0, low_inclusive=False, kind="number",
        none="by the start: 1e-9 for a Level II run of the DEM damper from the lattice "
        "(LATTICE_GEAR_TOLERANCE), 1e-5 otherwise (DEFAULT_GEAR_TOLERANCE, random beds)")
    gear_velocity_scale: float = setting(
        DEFAULT_GEAR_VELOCITY_SCALE, "Velocity scale of the Gear step control.", unit="m/s",
        low=0.0, low_inclusive=False)
    gear_adaptive: bool = setting(True, "False keeps the Gear step fixed (convergence "
                                  "studies).")
    max_step: float = setting(1e-4, "Upper bound of the Gear step.", unit="s", low=0.0,
                              low_inclusive=False)
    skin: float | None = setting(None, "Verlet-list skin.", unit="m", low=0.0,
                                 low_inclusive=False, kind="number",
                                 none="0.2 x the smallest radius")
    settle_time: float | None = setting(
        None, "Settling under gravity in the resting container before the excitation (0: "
        "none).", unit="s", low=0.0, kind="number",
        none="the free fall over the container height + 0.05 s (a Level II run of the DEM "
        "damper: + 1 s)")
    settle_rest_speed: float | None = setting(
        None, "The settling ends once the bed's root-mean-square speed (its translational "
        "kinetic energy as a speed, sqrt(2 E_kin / m_bed)) has stayed below this for "
        "``settle_rest_time``; ``settle_time`` is then the longest settling.",
        unit="m/s", low=0.0, low_inclusive=False, kind="number",
        none="never: the settling lasts settle_time")
    settle_rest_time: float = setting(
        0.05, "How long the bed's rms speed must stay below ``settle_rest_speed`` (checked every "
        "SETTLE_CHECK_INTERVAL, 5 ms of bed time) before the settling ends.", unit="s",
        low=0.0, low_inclusive=False)
    max_overlap: float | None = setting(
        None, "Overlap / radius at which the run stops (large overlaps are a regime of fast "
        "impacts, reported as ``max_overlap_ratio`` and warned about above "
        "``OVERLAP_WARNING_LIMIT``).", low=0.0, high=1.0,
        low_inclusive=False, kind="number",
        none="never: large overlaps are reported as max_overlap_ratio and warned about")
    reference_velocity: float | None = setting(
        None, "Impact speed at which the contact duration is evaluated.", unit="m/s",
        low=0.0, low_inclusive=False, kind="number",
        none="from the excitation and the free fall over the container height")
    gear_contact_bound: bool = setting(
        False, "Bound the Gear step by the time to the next contact (never below 6 x the "
        "Verlet step). Off by default: in a dense bed some pair is always about to touch, "
        "and the bound doubled the steps at unchanged accuracy; the error control with "
        "rejection resolves onsets (docs/dem.md).")
    seed: int | None = setting(None, "Recorded in the results (the engine itself is "
                               "deterministic).", low=0, kind="whole", none="none recorded")
    auto_cost_ratio: float = setting(
        AUTO_COST_RATIO, "``integrator = auto`` hands over to Verlet when Gear's mean step falls below "
        "this times Verlet's (inf: at the first judgement, 0: never).", low=0.0,
        infinite=True)
    gear_free_flight: bool = setting(
        True, "Take the spheres that cannot touch anything before a horizon out of the Gear "
        "step (their free flight is an exact parabola): the same physics at a lower cost "
        "per step where few spheres are in contact (pdamper.dem.kernels.flights).")
    transient_cycles: int = setting(
        0, "The first cycles of a harmonic excitation (the start from rest, which the "
        "averaged window of a Level II run skips) that run at ``gear_transient_tolerance`` "
        "instead of ``gear_tolerance``: the averaged window sees only the motion after "
        "them, which for a chaotic bed starts another realisation (docs/fields.md, "
        "section 1).", low=0)
    gear_transient_tolerance: float | None = setting(
        None, "Gear tolerance of the first ``transient_cycles`` cycles.", low=0.0,
        low_inclusive=False, kind="number", none="gear_tolerance")
