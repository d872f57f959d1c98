"""The DEM damper model (the paper's model 1, Sect. 4.1).

Level II: :meth:`DEMDamper.response` runs the DEM under harmonic container motion and
applies the complex power method (Eqs. 1-4). Level III: :meth:`DEMDamper.free_vibration`
integrates the 1-DOF structure together with the particles, the container being the
end-effector (no pseudo force, no per-cycle update).
"""

from __future__ import annotations

import logging

import numpy as np

from pdamper.analysis.fields import DamperResponse
from pdamper.coupling.base import DamperModel
from pdamper.coupling.decrement import negative_peaks
from pdamper.coupling.free_vibration import FreeVibrationResult
from pdamper.damper import ParticleDamper
from pdamper.errors import InputError, check_range

logger = logging.getLogger(__name__)

#: Motion-mode code of DEM responses: the DEM does not classify modes.
UNCLASSIFIED = -1


class DEMDamper(DamperModel):
    """Particle damper simulated by the discrete element method.

    Parameters
    ----------
    damper
        Container, spheres and materials; its ``friction`` sets mu of every contact.
    contact
        :class:`pdamper.dem.ContactParameters` (COR curves, damping model); default:
        constant COR 0.6 (sphere-sphere) and 0.85 (sphere-wall) with the damper's friction.
    integrator
        ``"gear"`` (variable step, the paper's) or ``"verlet"``.
    cycles, skip_cycles
        Level II: cycles simulated, and cycles left out of the complex power (paper: 8, 2).
    packing, seed
        ``"lattice"`` (the paper's 4 x 4 layers) or ``"random"`` (uses ``seed``).
    sample_rate
        Samples per second of the force and container time series [Hz].
    options
        Further keyword arguments of :class:`pdamper.dem.DEMSimulation` (``safety``, ...).
    """

    fidelity = "dem"

    def __init__(self, damper: ParticleDamper, contact=None, integrator: str = "gear",
                 cycles: int = 8, skip_cycles: int = 2, packing: str = "lattice", seed: int = 0,
                 sample_rate: float = 4000.0, **options):
        super().__init__(damper)
        if packing not in ("lattice", "random"):
            raise InputError("packing", f"must be 'lattice' or 'random', got {packing!r}")
        if int(cycles) != cycles or cycles < 1:
            raise InputError("cycles", f"must be a whole number >= 1, got {cycles}")
        if int(skip_cycles) != skip_cycles or not 0 <= skip_cycles < cycles:
            raise InputError("skip_cycles", f"must be in [0, {cycles - 1}], got {skip_cycles}")
        self.contact = contact
        self.integrator = integrator
        self.cycles, self.skip_cycles = int(cycles), int(skip_cycles)
        self.packing, self.seed = packing, seed
        self.sample_rate = check_range("sample_rate", sample_rate, low=0.0, low_inclusive=False,
                                       unit="Hz")
        self.options = options
        self.last_results: list = []

    # ------------------------------------------------------------------ set-up
    def simulation(self, motion):
        """The :class:`pdamper.dem.DEMSimulation` of this damper under ``motion``."""
        from pdamper.dem import ContactParameters, Container, DEMSimulation, ParticleSet

        d = self.damper
        if d.count < 1:
            raise InputError("particles.count", "the DEM model needs at least 1 particle")
        box = (d.width, d.depth, d.length)
        if self.packing == "lattice":
            particles = ParticleSet.lattice(d.count, box, d.particle_radius, d.particle_material)
        else:
            particles = ParticleSet.random(d.count, box, d.particle_radius, d.particle_material,
                                           seed=self.seed)
        contact = self.contact or ContactParameters(friction_pp=d.friction, friction_pw=d.friction)
        return DEMSimulation(particles, Container(box, d.wall_material, d.container_mass),
                             contact, motion, integrator=self.integrator, seed=self.seed,
                             **self.options)

    # ------------------------------------------------------------------ Level II
    def response(self, frequency, amplitude) -> DamperResponse:
        """Run the DEM at every (f, X) point and apply Eqs. (1)-(4).

        Motion modes are not classified (code ``UNCLASSIFIED``); the runs are kept in
        ``last_results``.
        """
        from pdamper.dem import HarmonicMotion

        f, x = np.broadcast_arrays(np.asarray(frequency, float), np.asarray(amplitude, float))
        eta = np.empty(f.shape)
        e_tilde = np.empty(f.shape)
        ratio = np.empty(f.shape)
        self.last_results = []
        for idx in np.ndindex(f.shape):
            fi = check_range("frequency", f[idx], low=0.0, low_inclusive=False, unit="Hz")
            xi = check_range("amplitude", x[idx], low=0.0, low_inclusive=False, unit="m")
            res = self.simulation(HarmonicMotion(amplitude=xi, frequency=fi)).run(
                self.cycles / fi, sample_rate=self.sample_rate)
            cp = res.complex_power(self.skip_cycles)
            eta[idx], e_tilde[idx], ratio[idx] = (cp.loss_factor, cp.dissipated_energy_per_cycle,
                                                  cp.effective_mass_ratio)
            self.last_results.append(res)
            logger.info("DEM f=%.3g Hz X=%.3g m: eta=%.3f (%d steps, %.2f s)", fi, xi,
                        cp.loss_factor, res.steps, res.wall_seconds)
        return DamperResponse(frequency=f, amplitude=x, mode=np.full(f.shape, UNCLASSIFIED),
                              loss_factor=eta, dissipated_energy_per_cycle=e_tilde,
                              effective_mass_ratio=ratio, bed_mass=self.bed_mass)

    # ------------------------------------------------------------------ Level III
    def free_vibration(self, structure, duration, initial_displacement, sample_rate=2000.0):
        """Structure and particles integrated together (model 1), released from rest.

        The particles' weight shifts the static equilibrium by ``-m_bed g / K``; peak
        amplitudes are measured from that equilibrium.
        """
        from pdamper.dem import StructureMotion

        check_range("simulation.duration", duration, low=0.0, low_inclusive=False, unit="s")
        if not initial_displacement < 0:
            raise InputError("structure.initial_displacement",
                             f"must be < 0 m (released from a minimum), got {initial_displacement:g} m")
        motion = StructureMotion(mass=structure.mass, damping=structure.damping,
                                 stiffness=structure.stiffness, x0=initial_displacement)
        sim = self.simulation(motion)
        res = sim.run(duration, sample_rate=sample_rate)
        self.last_results = [res]
        x_eq = -self.bed_mass * sim.gravity / structure.stiffness
        t, x = res.time, res.container_position
        tp, ap = negative_peaks(t, x - x_eq)
        keep = tp > 0.5 / structure.natural_frequency  # the release is the first peak
        peak_t = np.concatenate([[0.0], tp[keep]])
        peak_a = np.concatenate([[abs(initial_displacement - x_eq)], ap[keep]])
        return FreeVibrationResult(
            time=t, displacement=x, peak_times=peak_t, peak_amplitudes=peak_a, model="dem",
            inputs={"duration": duration, "initial_displacement": initial_displacement,
                    "sample_rate": sample_rate, "integrator": self.integrator,
                    "seed": self.seed, "steps": res.steps, "wall_seconds": res.wall_seconds,
                    "static_equilibrium": x_eq,
                    "energy_balance_error": res.energy_balance_error()})

    def __repr__(self) -> str:
        return (f"DEMDamper(count={self.damper.count}, integrator={self.integrator!r}, "
                f"packing={self.packing!r})")


