"""Level III: damper design by optimisation (paper Sect. 4.2.2).

:func:`optimize_particle_count` is the paper's one-variable study; :func:`optimize_design`
varies several design variables (:mod:`pdamper.design.study`), evaluating designs in
parallel through :func:`pdamper.design.parallel.evaluate_parallel`.
"""

from pdamper.design.optimize import Candidate, OptimizationResult, optimize_particle_count
from pdamper.design.parallel import Outcome, evaluate_parallel
from pdamper.design.study import (
    DEFAULT_TOLERANCE,
    OBJECTIVES,
    VARIABLES,
    DesignCandidate,
    DesignStudyResult,
    DesignVariable,
    Objective,
    lightest_within,
    make_objective,
    optimize_design,
    pareto_front,
    parse_tolerance,
    parse_variable,
    run_design_study,
)

__all__ = ["Candidate", "DEFAULT_TOLERANCE", "DesignCandidate", "DesignStudyResult",
           "DesignVariable", "OBJECTIVES", "Objective", "OptimizationResult", "Outcome",
           "VARIABLES", "evaluate_parallel", "lightest_within", "make_objective",
           "optimize_design", "optimize_particle_count", "pareto_front", "parse_tolerance",
           "parse_variable", "run_design_study"]
