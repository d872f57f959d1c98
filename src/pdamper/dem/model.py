"""Former name of :mod:`pdamper.dem.inputs` (the inputs of a DEM run), kept so that code
importing ``pdamper.dem.model`` keeps working: this module *is* :mod:`pdamper.dem.inputs`
(the same module object, so classes, constants and warning filters agree)."""

import sys

from pdamper.dem import inputs as _inputs

sys.modules[__name__] = _inputs
