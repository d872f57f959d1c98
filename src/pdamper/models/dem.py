"""The DEM damper model (the paper's model 1, Sects. 3 and 4.1).

Level II: :meth:`DEMDamper.response` runs the DEM under harmonic container motion and
applies the complex power method (Eqs. 1-4); the runs travel in the response's ``details``.
Level III: the ``"co_simulation"`` strategy of :mod:`pdamper.coupling` integrates the
structure together with the particles through :meth:`DEMDamper.engine`.
"""

from __future__ import annotations

import logging

import numpy as np

from pdamper.contact.law import DEFAULT_MIN_IMPACT_VELOCITY, ContactParameters
from pdamper.damper import ParticleDamper
from pdamper.dem.model import DEFAULT_SAFETY, INTEGRATORS
from pdamper.errors import InputError, check_range
from pdamper.models.base import DamperModel, DamperResponse

logger = logging.getLogger(__name__)

#: Motion-mode code of DEM responses: the DEM does not classify modes (yet).
UNCLASSIFIED = -1

#: Cycles simulated and cycles left out of the complex power: the paper's procedure
#: (Sect. 3.1.2: eight cycles, the first two cut off).
DEFAULT_CYCLES = 8
DEFAULT_SKIP_CYCLES = 2
#: Samples per second of the force and container series of a Level II run [Hz].
DEFAULT_SAMPLE_RATE = 4000.0

#: Initial packings: the paper's square-lattice layers, or random (seeded).
PACKINGS = ("lattice", "random")


def _whole(field: str, value, low: int) -> int:
    try:
        ok = not isinstance(value, bool) and int(value) == value and value >= low
    except (TypeError, ValueError, OverflowError):
        ok = False
    if not ok:
        raise InputError(field, f"must be a whole number >= {low}, got {value!r}")
    return int(value)


class DEMDamper(DamperModel):
    """Particle damper simulated by the discrete element method.

    Parameters
    ----------
    damper
        Container, spheres and materials; its ``friction`` and COR curves
        (``restitution_pp``, ``restitution_pw``) set the contact law.
    integrator
        ``"gear"`` (variable step, the paper's) or ``"verlet"``.
    cycles, skip_cycles
        Level II: cycles simulated, and cycles left out of the complex power.
    packing, seed
        ``"lattice"`` (the paper's 4 x 4 layers) or ``"random"`` (uses ``seed``).
    sample_rate
        Samples per second of the force and container time series [Hz].
    snapshot_rate
        Particle snapshots per second [Hz] (None: first and last only).
    damping_model
        ``"exact"``, ``"gonthier"`` or ``"tsuji"``: the damping law of the normal force.
    min_impact_velocity
        Floor of the onset speed that sets the damping of the exact and Gonthier laws
        [m/s] (default 0.01; see docs/dem.md on rattling columns).
    safety
        Time step / Hertz contact time (see :class:`pdamper.dem.DEMEngine`) [-].
    options
        Further keyword arguments of :class:`pdamper.dem.DEMEngine` (``safety``, ...).

    Examples
    --------
    >>> from pdamper.parameters import PAPER_DAMPER
    >>> DEMDamper(PAPER_DAMPER, integrator="verlet", cycles=3, skip_cycles=1)
    DEMDamper(count=32, integrator='verlet', packing='lattice')
    """

    fidelity = "dem"
    coupling = "co_simulation"

    def __init__(self, damper: ParticleDamper, integrator: str = "gear",
                 cycles: int = DEFAULT_CYCLES, skip_cycles: int = DEFAULT_SKIP_CYCLES,
                 packing: str = "lattice", seed: int = 0,
                 sample_rate: float = DEFAULT_SAMPLE_RATE, snapshot_rate: float | None = None,
                 damping_model: str = "exact", safety: float = DEFAULT_SAFETY,
                 min_impact_velocity: float = DEFAULT_MIN_IMPACT_VELOCITY, **options):
        super().__init__(damper)
        if integrator not in INTEGRATORS:
            raise InputError("dem.integrator", f"must be one of {', '.join(INTEGRATORS)}, "
                             f"got {integrator!r}")
        if packing not in PACKINGS:
            raise InputError("dem.packing", f"must be one of {', '.join(PACKINGS)}, "
                             f"got {packing!r}")
        self.cycles = _whole("dem.cycles", cycles, 1)
        self.skip_cycles = _whole("dem.skip_cycles", skip_cycles, 0)
        if self.skip_cycles >= self.cycles:
            raise InputError("dem.skip_cycles", f"must be in [0, {self.cycles - 1}] for "
                             f"{self.cycles} cycles, got {self.skip_cycles}")
        self.seed = _whole("dem.seed", seed, 0)
        self.integrator = integrator
        self.packing = packing
        self.sample_rate = check_range("dem.sample_rate", sample_rate, low=0.0,
                                       low_inclusive=False, unit="Hz")
        self.snapshot_rate = (None if snapshot_rate is None else
                              check_range("dem.snapshot_rate", snapshot_rate, low=0.0,
                                          low_inclusive=False, unit="Hz"))
        for name in ("friction", "restitution_pp", "restitution_pw"):
            if getattr(damper, name) is None:
                raise InputError(f"particles.{name}", "the DEM needs the friction coefficient "
                                 "and the COR curves of the damper (ParticleDamper.friction, "
                                 ".restitution_pp, .restitution_pw)")
        try:
            self.contact = ContactParameters(restitution_pp=damper.restitution_pp,
                                             restitution_pw=damper.restitution_pw,
                                             friction_pp=damper.friction,
                                             friction_pw=damper.friction,
                                             damping_model=damping_model,
                                             min_impact_velocity=min_impact_velocity)
        except InputError as exc:  # name the field as the [dem] section does
            raise InputError(f"dem.{exc.field}", exc.message) from None
        self.safety = check_range("dem.safety", safety, low=0.0, high=1.0, low_inclusive=False)
        self.options = options

    @property
    def damping_model(self) -> str:
        """The COR-damping relation of the contact law."""
        return self.contact.damping_model

    # ------------------------------------------------------------------ set-up
    def engine(self, motion):
        """The :class:`pdamper.dem.DEMEngine` of this damper under ``motion``."""
        from pdamper.dem import Container, DEMEngine, ParticleSet

        d = self.damper
        if d.count < 1:
            raise InputError("particles.count", "the DEM model needs at least 1 particle")
        if self.packing == "lattice":
            particles = ParticleSet.lattice(d.count, d.box, d.particle_radius,
                                            d.particle_material)
        else:
            particles = ParticleSet.random(d.count, d.box, d.particle_radius,
                                           d.particle_material, seed=self.seed)
        return DEMEngine(particles, Container(d.box, d.wall_material, d.container_mass),
                         self.contact, motion, integrator=self.integrator, seed=self.seed,
                         safety=self.safety, **self.options)

    # ------------------------------------------------------------------ Level II
    def run(self, frequency: float, amplitude: float):
        """One DEM run of ``cycles`` cycles at f [Hz], X [m]: the
        :class:`~pdamper.dem.DEMResult`."""
        from pdamper.dem import HarmonicMotion

        f = check_range("frequency", frequency, low=0.0, low_inclusive=False, unit="Hz")
        x = check_range("amplitude", amplitude, low=0.0, low_inclusive=False, unit="m")
        return self.engine(HarmonicMotion(amplitude=x, frequency=f)).run(
            self.cycles / f, sample_rate=self.sample_rate, snapshot_rate=self.snapshot_rate)

    def response(self, frequency, amplitude) -> DamperResponse:
        """Run the DEM at every (f, X) point and apply Eqs. (1)-(4) over the cycles after
        ``skip_cycles``.

        Motion modes are not classified (code ``UNCLASSIFIED``); ``details`` holds the
        :class:`~pdamper.dem.DEMResult` of every point.
        """
        f, x = np.broadcast_arrays(np.asarray(frequency, float), np.asarray(amplitude, float))
        eta = np.empty(f.shape)
        e_tilde = np.empty(f.shape)
        ratio = np.empty(f.shape)
        runs = np.empty(f.shape, dtype=object)
        for idx in np.ndindex(f.shape):
            res = self.run(f[idx], x[idx])
            cp = res.complex_power(self.skip_cycles)
            eta[idx], e_tilde[idx], ratio[idx] = (cp.loss_factor, cp.dissipated_energy_per_cycle,
                                                  cp.effective_mass_ratio)
            runs[idx] = res
            logger.info("DEM f=%.3g Hz X=%.3g m: eta=%.3f (%d steps, %.2f s)", f[idx], x[idx],
                        cp.loss_factor, res.steps, res.wall_seconds)
        return DamperResponse(frequency=f, amplitude=x, mode=np.full(f.shape, UNCLASSIFIED),
                              loss_factor=eta, dissipated_energy_per_cycle=e_tilde,
                              effective_mass_ratio=ratio, bed_mass=self.bed_mass, details=runs)

    def __repr__(self) -> str:
        return (f"DEMDamper(count={self.damper.count}, integrator={self.integrator!r}, "
                f"packing={self.packing!r})")
