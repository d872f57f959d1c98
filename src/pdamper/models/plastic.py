"""The plastic-bed damper model: the analytical bed (paper Sect. 3.1) integrated event by
event as one perfectly plastic block (:mod:`pdamper.analysis.plastic_bed`).

Level II (``response``): the steady orbit of the block in a container moving as
``X sin(W t)`` (:func:`~pdamper.analysis.plastic_bed.harmonic_plastic_bed`): eta from the
impacts' losses (Eq. 3), m_eff from the block's first harmonic (Eq. 4), the motion mode from
the orbit's period and walls. Level III (the ``"plastic_bed"`` coupling of
:mod:`pdamper.coupling.plastic`): the block on the structure itself
(:class:`~pdamper.analysis.plastic_bed.PlasticBedSystem`), a damper force that follows any
container motion (free decays of N modes, load histories, shocks) instead of a loss factor
updated once per cycle.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from pdamper import resources
from pdamper.analysis.modes import MotionMode
from pdamper.analysis.plastic_bed import harmonic_plastic_bed
from pdamper.constants import STANDARD_GRAVITY
from pdamper.damper import ParticleDamper
from pdamper.errors import check_range
from pdamper.models.base import CONTACT_LAW_INPUTS, DamperModel, DamperResponse

#: Seconds one point of :func:`~pdamper.analysis.plastic_bed.harmonic_plastic_bed` takes
#: (measured: 10-15 ms on one core).
SECONDS_PER_POINT = 0.015
#: Seconds one integration step of the block on a structure takes (measured: 0.1-0.2 ms on
#: a busy core for one or two modes).
SECONDS_PER_STEP = 2e-4
#: Bytes per output sample of a run on a structure (the state, its rate, the bed).
BYTES_PER_SAMPLE = 200.0


def motion_modes(period, lid_impacts, impacts) -> np.ndarray:
    """Motion-mode codes (:class:`~pdamper.analysis.modes.MotionMode`) of the block's
    orbits: solid-like without impacts, scattering without a period up to
    :data:`~pdamper.analysis.plastic_bed.MAX_PERIOD_CYCLES`, double collect-and-collide
    where it hits the lid, single otherwise; harmonic for a period of one cycle,
    subharmonic for longer ones.

    >>> motion_modes([1, 2, 0, 1], [1.0, 0.0, 0.5, 0.0], [2.0, 0.5, 3.0, 0.0]).tolist()
    [3, 2, 5, 0]
    """
    p = np.asarray(period, int)
    lid = np.asarray(lid_impacts, float) > 0
    imp = np.asarray(impacts, float) > 0
    single = np.where(p == 1, int(MotionMode.SINGLE_CAC_HARMONIC),
                      int(MotionMode.SINGLE_CAC_SUBHARMONIC))
    double = np.where(p == 1, int(MotionMode.DOUBLE_CAC_HARMONIC),
                      int(MotionMode.DOUBLE_CAC_SUBHARMONIC))
    mode = np.where(lid, double, single)
    mode = np.where(p == 0, int(MotionMode.SCATTERING), mode)
    return np.where(imp, mode, int(MotionMode.SOLID))


class PlasticBedDamper(DamperModel):
    """The bed as one perfectly plastic block, integrated event by event.

    It keeps the analytical model's physics (collect-and-collide, Sect. 3.1) without its
    closed forms' assumptions on the trajectory: it answers at scattering cells, where a
    single impact falls after the next take-off, at zero gravity, and on a structure under
    any motion (a beating N-mode decay, a shock). Its limits are the block's: a bed of less
    than one layer rebounds with its COR instead of collecting (use ``dem`` there).

    Parameters
    ----------
    damper
        The physical damper; only its clearance and bed mass enter.
    gravity
        g [m/s^2], >= 0.

    Examples
    --------
    >>> from pdamper.parameters import PAPER_DAMPER
    >>> r = PlasticBedDamper(PAPER_DAMPER).response(10.0, 0.032)
    >>> round(float(r.loss_factor), 2), r.mode.item()
    (1.23, 3)
    """

    fidelity = "plastic"
    coupling = "plastic_bed"
    takes_gravity = True
    vectorised = True
    #: the block is perfectly plastic: no friction, no rebound
    unused_inputs = {
        f: "the plastic bed is one perfectly plastic block (collect-and-collide, Sect. 3.1): "
           "neither friction nor the coefficient of restitution enters it"
        for f in CONTACT_LAW_INPUTS}

    def __init__(self, damper: ParticleDamper, gravity: float = STANDARD_GRAVITY):
        super().__init__(damper)
        self.gravity = check_range("gravity", gravity, low=0.0, unit="m/s^2")

    def response(self, frequency, amplitude) -> DamperResponse:
        """The block's steady orbit at every (f [Hz], X [m]) point (about 12 ms a point);
        ``details`` is the :class:`~pdamper.analysis.plastic_bed.PlasticBedResponse`,
        ``diagnostics`` the orbit's period [cycles], impacts (all and with the lid) per
        cycle, airborne fraction, the complex power's eta (a check) and whether the
        block's assumption (a collected bed) holds."""
        self.check_excitation(frequency, amplitude)
        d = self.damper
        r = harmonic_plastic_bed(frequency, amplitude, d.clearance, d.bed_mass, self.gravity)
        mode = motion_modes(r.period_cycles, r.lid_impacts_per_cycle, r.impacts_per_cycle)
        order = np.where(r.period_cycles > 0, r.period_cycles - 1, -1)
        return DamperResponse(
            frequency=r.frequency, amplitude=r.amplitude, mode=mode,
            loss_factor=r.loss_factor,
            dissipated_energy_per_cycle=r.dissipated_energy_per_cycle,
            effective_mass_ratio=r.effective_mass_ratio, bed_mass=d.bed_mass, details=r,
            stationary=np.ones(np.shape(mode), bool), subharmonic_order=order,
            diagnostics={"period_cycles": r.period_cycles,
                         "impacts_per_cycle": r.impacts_per_cycle,
                         "lid_impacts_per_cycle": r.lid_impacts_per_cycle,
                         "airborne_fraction": r.airborne_fraction,
                         "loss_factor_complex_power": r.loss_factor_complex_power,
                         **self._assumptions(np.shape(mode))})

    def _assumptions(self, shape) -> dict:
        """``assumptions_hold`` and ``assumptions`` per point: the block needs a collected
        bed (at least one layer, two spheres)."""
        d = self.damper
        why = ""
        if d.count < max(d.per_layer, 2):
            why = (f"not a collected bed ({d.count} sphere(s), less than one layer of "
                   f"{d.per_layer}: they rebound with their COR); use dem")
        return {"assumptions_hold": np.full(shape, not why, bool),
                "assumptions": np.full(shape, why, object)}

    @classmethod
    def map_cost(cls, damper: ParticleDamper, frequency: tuple[float, float, int],
                 amplitude: tuple[float, float, int], points: float, settings=None, *,
                 gravity: float = STANDARD_GRAVITY, usual: tuple[float, float] = (10.0, 0.032),
                 axes: Sequence[tuple] = (),
                 damper_drivers: Sequence[tuple] = ()) -> resources.Cost:
        """About :data:`SECONDS_PER_POINT` a point of the grid."""
        return resources.Cost("the plastic bed's map", points * SECONDS_PER_POINT,
                              points * resources.ANALYTIC_BYTES_PER_POINT,
                              f"{points:.3g} grid points", tuple(axes))

    @classmethod
    def free_vibration_cost(cls, damper: ParticleDamper, duration: float, sample_rate: float,
                            natural_frequency: float, settings=None, *, x0: float = 0.0,
                            drivers: Sequence[tuple] = (),
                            damper_drivers: Sequence[tuple] = (),
                            count: int | None = None) -> resources.Cost:
        """One integration step per sample (:data:`SECONDS_PER_STEP`)."""
        samples = duration * sample_rate + 1
        return resources.Cost("the plastic bed's free vibration", samples * SECONDS_PER_STEP,
                              samples * BYTES_PER_SAMPLE, f"{samples:.3g} steps",
                              tuple(drivers))
