"""Level I: materials of particles and container walls.

:class:`Material` holds the elastic constants the Hertz contact needs (E, nu), the density
and, where known, the yield strength (for Thornton's elastic-plastic COR model,
:mod:`pdamper.contact.thornton`). The library (:mod:`pdamper.materials.library`) holds the
paper's two materials (Fig. 2-left: :data:`S235` spheres, :data:`PVC` walls) and the
materials particle dampers commonly use, every number with its source (``docs/materials.md``).
:func:`get_material` looks them up by name or alias, case- and punctuation-insensitively.
"""

from __future__ import annotations

from pdamper.materials.base import Material
from pdamper.materials.library import (
    LIBRARY,
    MATERIALS,
    PVC,
    REFERENCES,
    S235,
    LibraryEntry,
    get_material,
    known_names,
)

__all__ = ["Material", "S235", "PVC", "MATERIALS", "LIBRARY", "REFERENCES", "LibraryEntry",
           "get_material", "known_names"]
