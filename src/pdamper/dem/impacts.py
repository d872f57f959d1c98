"""Single impacts simulated by the DEM: does the contact law give the COR it was asked for?

The paper calibrates the damping of its contact law from COR curves (Sects. 2-3). This
module runs the real engine (:class:`pdamper.dem.DEMEngine`, its public API only) on one
sphere hitting a wall, or two equal spheres hitting head-on, without gravity, and measures
the rebound: ``e = (separation speed after) / (approach speed before)``. ``pdamper cor``
shows it next to the target curve for a velocity grid (:func:`check_restitution`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from pdamper import resources
from pdamper.contact.law import ContactParameters
from pdamper.contact.restitution import RestitutionCurve
from pdamper.errors import InputError, SimulationError, check_range
from pdamper.materials import Material

#: Usual number of single impacts of a check (``pdamper cor``'s default grid).
USUAL_IMPACTS = 40
#: Simulated time after the approach, in elastic Hertz contact durations (the damped contact
#: lasts longer than the elastic one; the rebound is checked to have ended).
CONTACT_DURATIONS = 4.0


@dataclass(frozen=True)
class ImpactCheck:
    """Target COR and the COR of simulated single impacts on a velocity grid.

    Attributes
    ----------
    velocity
        Normal impact speeds [m/s].
    cor_target
        The curve's COR at those speeds [-].
    cor_simulated
        The rebound COR of the DEM contact law [-].
    sphere, partner
        Material names; ``sphere_sphere`` True for two equal spheres, False for a sphere
        on a wall of ``partner``.
    curve, damping_model, integrator
        What was simulated.
    """

    velocity: np.ndarray
    cor_target: np.ndarray
    cor_simulated: np.ndarray
    sphere: str
    partner: str
    sphere_sphere: bool
    radius: float
    curve: str
    damping_model: str
    integrator: str

    @property
    def deviation(self) -> np.ndarray:
        """Simulated minus target COR [-]."""
        return self.cor_simulated - self.cor_target

    @property
    def max_deviation(self) -> float:
        """Largest |simulated - target| over the grid [-]."""
        return float(np.max(np.abs(self.deviation)))

    @property
    def pair(self) -> str:
        return f"{self.sphere}:{self.partner}"

    def as_dict(self) -> dict:
        """JSON-ready record (keys ``velocity``, ``cor_target``, ``cor_simulated``,
        ``max_deviation`` and what was simulated)."""
        return {"velocity": self.velocity.tolist(), "cor_target": self.cor_target.tolist(),
                "cor_simulated": self.cor_simulated.tolist(), "max_deviation": self.max_deviation,
                "pair": self.pair,
                "contact": "sphere-sphere" if self.sphere_sphere else "sphere-wall",
                "radius": self.radius, "curve": self.curve, "damping_model": self.damping_model,
                "integrator": self.integrator,
                "units": {"velocity": "m/s", "radius": "m", "cor_target": "-",
                          "cor_simulated": "-", "max_deviation": "-"}}


def simulate_impact(velocity: float, curve: RestitutionCurve, sphere: Material,
                    partner: Material, radius: float, sphere_sphere: bool,
                    damping_model: str = "exact", integrator: str = "gear",
                    contact: ContactParameters | None = None) -> float:
    """Rebound COR of one normal impact at ``velocity`` [m/s] simulated by the DEM.

    A sphere of ``sphere`` material and ``radius`` [m] hits a resting wall of ``partner``
    material, or (``sphere_sphere``) two such spheres approach each other head-on at
    ``velocity / 2`` each; no gravity, no friction. The contact law is the DEM's, with
    ``curve`` for the pair and ``damping_model``; ``contact`` replaces the whole law.
    """
    from pdamper.contact.hertz import (
        contact_duration,
        effective_modulus,
        hertz_stiffness,
        max_overlap,
    )
    from pdamper.dem import Container, DEMEngine, EngineSettings, ParticleSet

    v = check_range("velocity", velocity, low=0.0, low_inclusive=False, unit="m/s")
    r = check_range("radius", radius, low=0.0, low_inclusive=False, unit="m")
    cp = contact or ContactParameters(curve, curve, 0.0, 0.0, damping_model=damping_model)
    m = 4.0 / 3.0 * math.pi * r**3 * sphere.density
    if sphere_sphere:
        m_star, r_star, e_star = 0.5 * m, 0.5 * r, effective_modulus(sphere, sphere)
    else:
        m_star, r_star, e_star = m, r, effective_modulus(sphere, partner)
    k = hertz_stiffness(e_star, r_star)
    gap = max_overlap(m_star, k, v)  # start one maximum overlap apart: contact soon
    t_c = contact_duration(m_star, k, v)
    box = (6.0 * r, 6.0 * r, 8.0 * r)
    if sphere_sphere:
        zc = 0.5 * box[2]
        pos = [[3 * r, 3 * r, zc - r - 0.5 * gap], [3 * r, 3 * r, zc + r + 0.5 * gap]]
        vel = [[0.0, 0.0, 0.5 * v], [0.0, 0.0, -0.5 * v]]
        wall = sphere
    else:
        pos = [[3 * r, 3 * r, r + gap]]
        vel = [[0.0, 0.0, -v]]
        wall = partner
    particles = ParticleSet(np.array(pos), r, sphere, velocities=np.array(vel))
    engine = DEMEngine(particles, Container(box, wall), cp, None,
                       EngineSettings(integrator=integrator, gravity=0.0, settle_time=0.0,
                                      reference_velocity=v))
    duration = gap / v + CONTACT_DURATIONS * t_c
    res = engine.run(duration, sample_rate=8.0 / duration)
    z = res.snapshot_positions[-1, :, 2]
    vz = res.snapshot_velocities[-1, :, 2]
    if sphere_sphere:
        separated, e = z[1] - z[0] > 2.0 * r, (vz[1] - vz[0]) / v
    else:
        separated, e = z[0] > r, vz[0] / v
    if not separated:
        raise SimulationError(f"the impact at {v:g} m/s had not ended after "
                              f"{CONTACT_DURATIONS:g} elastic contact durations")
    return float(e)


def impacts_cost(count: float, field: str = "velocity") -> resources.Cost:
    """What ``count`` simulated single impacts cost (:func:`pdamper.resources.count_cost`),
    judged from the count alone, before the speeds exist."""
    return resources.count_cost(count, "the COR check", "single impacts, each a DEM run",
                                bytes_each=4 * resources.BYTES_PER_VALUE,
                                seconds_each=resources.SECONDS_PER_IMPACT, field=field,
                                usual=USUAL_IMPACTS)


def check_restitution(velocity, curve: RestitutionCurve, sphere: Material, partner: Material,
                      radius: float, sphere_sphere: bool | None = None,
                      damping_model: str = "exact", integrator: str = "gear") -> ImpactCheck:
    """Simulated single impacts at every speed of ``velocity`` [m/s] against ``curve``.

    ``sphere_sphere`` defaults to ``sphere.name == partner.name``. The speeds are judged
    before the first run: their number by the hard limits of :mod:`pdamper.resources`
    (what no run can do), the fastest by the physics limits every DEM run obeys
    (:func:`pdamper.resources.check_impacts`).
    """
    v = np.atleast_1d(np.asarray(velocity, float))
    resources.require(impacts_cost(v.size), force=True)  # before any array of that size
    if v.ndim != 1 or v.size < 1 or np.any(~np.isfinite(v)) or np.any(v <= 0):
        raise InputError("velocity", "impact speeds must be finite and > 0 m/s")
    ss = sphere.name == partner.name if sphere_sphere is None else bool(sphere_sphere)
    r = check_range("radius", radius, low=0.0, low_inclusive=False, unit="m")
    resources.check_impacts([(r, sphere)], None if ss else partner, float(v.max()),
                            speed_field="velocity", radius_field="radius",
                            between_spheres=ss)
    sim = np.array([simulate_impact(x, curve, sphere, partner, radius, ss, damping_model,
                                    integrator) for x in v])
    return ImpactCheck(v, np.asarray(curve(v), float), sim, sphere.name, partner.name, ss,
                       float(radius), curve.describe(), damping_model, integrator)


__all__ = ["CONTACT_DURATIONS", "ImpactCheck", "check_restitution", "simulate_impact"]
