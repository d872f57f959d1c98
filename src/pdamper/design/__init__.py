"""Level III: damper design by optimisation (paper Sect. 4.2.2)."""

from pdamper.design.optimize import Candidate, OptimizationResult, optimize_particle_count

__all__ = ["Candidate", "OptimizationResult", "optimize_particle_count"]
