"""Motion modes of a simulated particle bed, from its recorded motion (paper Sect. 3, Figs. 3-4).

The paper classifies its DEM runs by eye ("animations and velocity fields"); the analytical
model classifies by the impacts of an inelastic block (:mod:`pdamper.analysis.analytical`).
:func:`classify_motion` decides from what every DEM run records: the height of the bed's
centre of mass in the container and the vertical force of the particles on the container,
over an averaging window of whole cycles. The features, in the order of the decision:

``lift``
    Range of the bed's height in the container over the window [m]. Below
    ``LIFT_THRESHOLD`` x the particle radius the bed never takes off: **solid-like**.
``period`` and ``periodicity_residual``
    The smallest ``p`` in 1..4 cycles with ``RMS(y(t) - y(t - p T)) <= PERIODIC_TOLERANCE``
    x the range of ``y``, ``y`` the height of the bed. No such ``p``: the bed does not move
    repetitively: **scattering** (the paper: "the particle system begins to scatter and no
    regular motion is seen anymore").
``contact_fraction``
    Share of the window in which the bed presses on a wall (``|F_z| > CONTACT_FORCE`` x
    ``m_bed g``). A collect-and-collide bed collects at every impact over many particle
    collisions and adopts the wall's velocity: it presses on a wall for 17-50 % of a cycle
    in the benchmark runs; a bed that rebounds elastically touches the walls only during
    short impacts (1-3 %). Periodic, with less than ``MIN_CONTACT`` cycles of wall contact
    per period (``contact_fraction x period``): **rattling**, a mode the paper does not name
    (the locked columns of the constant-COR lattice bed bounce between bottom and lid, eta
    up to 2.6 > 4/pi, docs/fields.md).
``lid_contacts_per_cycle``
    Separate episodes of the force pushing the lid up (``F_z > LID_FORCE`` x ``m_bed g``)
    while the bed is in the upper half of its travel (episodes less than 1/8 cycle apart
    count as one impact of the bed). At least one every second period:
    **double** collect-and-collide, else **single**.
``period`` again
    ``p = 1``: harmonic; ``p > 1``: subharmonic of order ``n_s = p - 1`` (one bottom impact
    every ``p`` cycles, Eqs. 12 and 18).

The inputs are plain arrays (:class:`BedSignals`), so synthetic trajectories test every
branch; :meth:`BedSignals.from_dem` takes them from a :class:`pdamper.dem.DEMResult`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from pdamper.analysis.modes import MotionMode
from pdamper.analysis.stationarity import whole_cycles
from pdamper.constants import STANDARD_GRAVITY
from pdamper.errors import InputError

#: Take-off: the bed's height in the container varies by more than this x particle radius.
LIFT_THRESHOLD = 0.1
#: Repetitive: RMS difference of the bed height one period apart <= this x its range. The
#: repetitive DEM beds of the benchmark stay below 0.067, the irregular ones above 0.10.
PERIODIC_TOLERANCE = 0.08
#: Longest period tested [cycles].
MAX_PERIOD = 4
#: Bed on a wall: |F_z| above this x m_bed g.
CONTACT_FORCE = 0.2
#: Collect-and-collide beds press on a wall at least this long per period [cycles].
MIN_CONTACT = 0.1
#: Lid impact: F_z above this x m_bed g with the bed in the upper half of its travel.
LID_FORCE = 0.5


@dataclass(frozen=True)
class BedSignals:
    """What the classifier reads, sampled with a whole number of samples per cycle.

    Attributes
    ----------
    time : (n,) [s]
        From the start of the excitation (t = 0 at the start of cycle 1).
    height : (n,) [m]
        Height of the bed's centre of mass above the container bottom.
    force_z : (n,) [N]
        Vertical force of the particles on the container (negative: pressing on the
        bottom; positive: pushing the lid up).
    frequency : float [Hz]
    bed_mass : float [kg]
    particle_radius : float [m]
    container_height : float [m]
        Inner height of the container (the bottom-to-lid distance).
    gravity : float [m/s^2]
    """

    time: np.ndarray
    height: np.ndarray
    force_z: np.ndarray
    frequency: float
    bed_mass: float
    particle_radius: float
    container_height: float
    gravity: float = STANDARD_GRAVITY

    @classmethod
    def from_dem(cls, result) -> BedSignals:
        """The signals of a harmonic :class:`pdamper.dem.DEMResult`."""
        if result.frequency is None:
            raise InputError("motion", "mode classification needs a harmonic excitation")
        box = result.attrs.get("box_m")
        if box is None:
            raise InputError("result", "the DEM result does not record its box (attrs['box_m'])")
        return cls(time=np.asarray(result.time),
                   height=np.asarray(result.center_of_mass[:, 2] - result.container_position),
                   force_z=np.asarray(result.force[:, 2]), frequency=float(result.frequency),
                   bed_mass=float(result.bed_mass),
                   particle_radius=float(np.max(result.radius)),
                   container_height=float(box[2]),
                   gravity=float(result.attrs.get("gravity_m_s2", STANDARD_GRAVITY)))


@dataclass(frozen=True)
class ModeClassification:
    """Motion mode of a run and the features it was decided from (module docstring).

    Attributes
    ----------
    mode
        The :class:`MotionMode`.
    subharmonic_order
        ``n_s = period - 1`` for collect-and-collide and rattling beds, -1 otherwise.
    period
        Repetition period in cycles (0: not repetitive or solid-like).
    periodicity_residual
        Relative residual of the best period tested [-].
    lift
        Range of the bed's height over the window [m].
    contact_fraction, lid_contacts_per_cycle
        See the module docstring [-].
    first_cycle, last_cycle
        The window, 1-based inclusive.
    reason
        One line: why this mode.
    """

    mode: MotionMode
    subharmonic_order: int
    period: int
    periodicity_residual: float
    lift: float
    contact_fraction: float
    lid_contacts_per_cycle: float
    first_cycle: int
    last_cycle: int
    reason: str


def _episodes(mask: np.ndarray, min_gap: int) -> int:
    """Number of runs of True in ``mask``, runs closer than ``min_gap`` samples merged (the
    spheres of one bed reach a wall one after another)."""
    idx = np.flatnonzero(np.asarray(mask, bool))
    if idx.size == 0:
        return 0
    return 1 + int(np.count_nonzero(np.diff(idx) > min_gap))


def classify_motion(signals: BedSignals, first_cycle: int | None = None,
                    last_cycle: int | None = None) -> ModeClassification:
    """Classify the bed's motion over cycles ``first_cycle..last_cycle`` (1-based,
    inclusive; default: the last ``min(12, all but 2)`` cycles).

    Examples
    --------
    A bed resting on the bottom of a container shaken below 1 g:

    >>> import numpy as np
    >>> t = np.linspace(0, 1, 401)
    >>> s = BedSignals(t, np.full(t.size, 0.01), -0.13 * 9.81 * (1 + 0.5 * np.sin(8 * np.pi * t)),
    ...                4.0, 0.13, 0.005, 0.12)
    >>> classify_motion(s).mode.label
    'solid'
    """
    t = np.asarray(signals.time, float)
    y_abs = np.asarray(signals.height, float)
    fz = np.asarray(signals.force_z, float)
    f = float(signals.frequency)
    if not (t.shape == y_abs.shape == fz.shape) or t.size < 8:
        raise InputError("signals", "time, height and force_z need equal lengths (>= 8)")
    n = whole_cycles(t, f)
    if n < 1:
        raise InputError("signals", "need at least one whole cycle")
    last = n if last_cycle is None else int(last_cycle)
    first = max(1, last - min(12, max(n - 2, 1)) + 1) if first_cycle is None else int(first_cycle)
    if not 1 <= first <= last <= n:
        raise InputError("cycles", f"window {first}-{last} outside the {n} recorded cycles")
    spc = int(round((t.size - 1) / (t[-1] - t[0]) / f))  # samples per cycle
    i0 = int(round((first - 1) * spc))
    i1 = int(round(last * spc)) + 1
    y = y_abs[i0:i1]
    fw = fz[i0:i1]
    ncyc = last - first + 1
    weight = signals.bed_mass * signals.gravity
    lift = float(y.max() - y.min())
    contact = float(np.mean(np.abs(fw) > CONTACT_FORCE * weight))

    def done(mode, order, period, res, lid, why):
        return ModeClassification(mode, order, period, res, lift, contact, lid, first, last,
                                  why)

    if lift <= LIFT_THRESHOLD * signals.particle_radius:
        return done(MotionMode.SOLID, -1, 0, math.nan, 0.0,
                    f"the bed's height varies by {lift * 1e3:.3g} mm <= "
                    f"{LIFT_THRESHOLD:g} r: no take-off")
    travel = max(signals.container_height - 2.0 * float(y.min()), 1e-12)
    upper = (y - y.min()) / travel > 0.5
    lid = _episodes((fw > LID_FORCE * weight) & upper, max(1, spc // 8)) / ncyc
    rng = max(lift, 1e-12)
    residuals = []
    for p in range(1, min(MAX_PERIOD, ncyc - 1) + 1):
        a = y[p * spc:]
        b = y[:-p * spc]
        residuals.append(float(np.sqrt(np.mean((a - b) ** 2))) / rng)
    period = next((p for p, r in enumerate(residuals, 1) if r <= PERIODIC_TOLERANCE), 0)
    best = min(residuals) if residuals else math.nan
    if period == 0:
        return done(MotionMode.SCATTERING, -1, 0, best, lid,
                    f"no repetition within {len(residuals)} cycles (best residual {best:.2f} > "
                    f"{PERIODIC_TOLERANCE:g})")
    res = residuals[period - 1]
    if contact * period < MIN_CONTACT:
        return done(MotionMode.RATTLING, period - 1, period, res, lid,
                    f"repeats every {period} cycle(s) but presses on a wall only "
                    f"{contact * period:.2g} cycles per period: elastic rebounds, not collected")
    double = lid * period >= 0.5
    if period == 1:
        mode = MotionMode.DOUBLE_CAC_HARMONIC if double else MotionMode.SINGLE_CAC_HARMONIC
    else:
        mode = MotionMode.DOUBLE_CAC_SUBHARMONIC if double else MotionMode.SINGLE_CAC_SUBHARMONIC
    return done(mode, period - 1, period, res, lid,
                f"repeats every {period} cycle(s), {lid:.2g} lid impacts per cycle, on a wall "
                f"{contact * period:.2g} cycles per period")
