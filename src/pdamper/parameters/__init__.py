"""Parameter sets named after the publications they come from (PyBaMM's habit).

:mod:`pdamper.parameters.vertical_dampers_paper` holds every number of the reference paper:
the benchmark damper and structure, the Level II grid, the Fig. 4 example points, and the
numbers it reports with the tolerance each comparison uses.
"""

from pdamper.parameters.vertical_dampers_paper import (
    PAPER_DAMPER,
    PAPER_INITIAL_DISPLACEMENT,
    PAPER_REPORTED,
    PAPER_STRUCTURE,
    paper_beam,
)

__all__ = ["PAPER_DAMPER", "PAPER_STRUCTURE", "PAPER_INITIAL_DISPLACEMENT", "PAPER_REPORTED",
           "paper_beam"]
