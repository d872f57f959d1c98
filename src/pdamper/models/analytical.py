"""The analytical damper model (paper model 3): Eqs. (5)-(22)."""

from __future__ import annotations

import numpy as np

from pdamper.analysis.analytical import assumption_checks, bed_response
from pdamper.constants import STANDARD_GRAVITY
from pdamper.damper import ParticleDamper
from pdamper.errors import check_range
from pdamper.models.base import CONTACT_LAW_INPUTS, DamperModel, DamperResponse


class AnalyticalDamper(DamperModel):
    """Particle damper described by the analytical collect-and-collide formulas.

    Parameters
    ----------
    damper
        The physical damper; only its clearance and bed mass enter.
    gravity
        g [m/s^2], >= 0 (0: a structure in orbit, the collect-and-collide limit of
        Eqs. 19-21).

    Examples
    --------
    >>> from pdamper.parameters import PAPER_DAMPER
    >>> r = AnalyticalDamper(PAPER_DAMPER).response(10.0, 0.032)
    >>> round(float(r.loss_factor), 2)
    1.23
    """

    fidelity = "analytic"
    takes_gravity = True
    vectorised = True
    #: every response carries ``assumptions_hold`` / ``assumptions`` in its diagnostics
    reports_assumptions = True
    #: the bed is one perfectly plastic block (Eqs. 5-22): no friction, no rebound
    unused_inputs = {
        f: "the analytical bed is a perfectly plastic block (Eqs. 5-22): neither friction "
           "nor the coefficient of restitution enters it"
        for f in CONTACT_LAW_INPUTS}

    def __init__(self, damper: ParticleDamper, gravity: float = STANDARD_GRAVITY):
        super().__init__(damper)
        self.gravity = check_range("gravity", gravity, low=0.0, unit="m/s^2")

    def response(self, frequency, amplitude) -> DamperResponse:
        """Eqs. (5)-(22) at every (f [Hz], X [m]) point; ``details`` is the
        :class:`~pdamper.analysis.analytical.BedResponse`."""
        self.check_excitation(frequency, amplitude)
        d = self.damper
        r = bed_response(frequency, amplitude, d.clearance, d.bed_mass, self.gravity)
        return DamperResponse(frequency=r.frequency, amplitude=r.amplitude, mode=r.mode,
                              loss_factor=r.loss_factor,
                              dissipated_energy_per_cycle=r.dissipated_energy_per_cycle,
                              effective_mass_ratio=r.effective_mass_ratio, bed_mass=d.bed_mass,
                              details=r, stationary=np.ones(np.shape(r.mode), bool),
                              subharmonic_order=r.subharmonic_order,
                              diagnostics=self._assumptions(r))

    def _assumptions(self, r) -> dict:
        """``assumptions_hold`` (bool) and ``assumptions`` (the reasons, "" where they
        hold) per point (:func:`~pdamper.analysis.analytical.assumption_checks`)."""
        d = self.damper
        holds, why = assumption_checks(r, count=d.count, per_layer=d.per_layer,
                                       diameter=2.0 * d.particle_radius, length=d.length)
        return {"assumptions_hold": holds, "assumptions": why}
