"""pdamper: design particle dampers for vertically vibrating structures.

The package follows the three levels of the design toolchain of the reference paper
("Systematic design of particle dampers for transient vertical vibrations"):

- Level I, single impacts: :mod:`pdamper.materials`, :mod:`pdamper.contact`.
- Level II, one damper under harmonic excitation: :mod:`pdamper.dem`,
  :mod:`pdamper.analysis`.
- Level III, damper on a structure: :mod:`pdamper.structure`, :mod:`pdamper.coupling`,
  :mod:`pdamper.design`.

Heavy modules (numba kernels, xarray, matplotlib) are imported where used, so that
``import pdamper`` stays fast. Installed read-only, pdamper points numba's cache at a
writable per-user directory, and drops cached kernels whose sources (or the helpers they
inline from other files) changed (:mod:`pdamper._numba_cache`).
"""

from pdamper import _numba_cache
from pdamper._version import __version__
from pdamper.errors import InputError, PdamperError, SimulationError

# before any module of pdamper imports numba: a read-only installation caches elsewhere,
# and kernels cached from older sources are dropped
_numba_cache.configure()
_numba_cache.refresh()

__all__ = ["__version__", "InputError", "PdamperError", "SimulationError"]
