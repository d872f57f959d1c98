"""Parameter sets named after the publications they come from."""

from pdamper.parameters.vertical_dampers_paper import (
    PAPER_DAMPER,
    PAPER_INITIAL_DISPLACEMENT,
    PAPER_STRUCTURE,
)

__all__ = ["PAPER_DAMPER", "PAPER_STRUCTURE", "PAPER_INITIAL_DISPLACEMENT"]
