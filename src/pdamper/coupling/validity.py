"""Whether a Level III answer rests on damper answers outside the model's assumptions.

The analytical model checks its own assumptions at every (f, X) it answers
(:func:`pdamper.analysis.analytical.assumption_checks`: a collected bed, the clearance of
the real geometry, no scattering); a free decay of the pseudo-force coupling asks it at
each cycle's update (:class:`~pdamper.coupling.results.CycleUpdate`), a forced response at
each answer's stroke (:func:`pdamper.coupling.frf.assumption_record`). Models that report
no such check (``reports_assumptions`` false: the fields, the DEM) give None.
"""

from __future__ import annotations

from typing import Any

import numpy as np


def decay_assumptions(model: Any, res: Any, until: float | None = None) -> dict | None:
    """The :func:`~pdamper.analysis.analytical.assumption_summary` of the damper's updates
    of the free vibration ``res`` up to ``until`` [s] (default all), asked of ``model`` at
    each update's (frequency, amplitude); None where the model reports no check or no
    update was made (a damper without particles)."""
    from pdamper.analysis.analytical import assumption_summary

    if not getattr(model, "reports_assumptions", False) or model.damper.count == 0:
        return None  # (no particles: no damper answer to rest on)
    ups = [c for c in getattr(res, "cycles", ()) if until is None
           or c.time <= until * (1.0 + 1e-12)]
    ups = [c for c in ups if c.amplitude > 0 and np.isfinite(c.amplitude)]
    if not ups:
        return None
    diag = model.response(np.array([c.frequency for c in ups]),
                          np.array([c.amplitude for c in ups])).diagnostics
    return assumption_summary(diag["assumptions_hold"], diag["assumptions"])


def design_marks(summary: dict | None) -> dict:
    """A design's extras from a summary (:func:`decay_assumptions`,
    :func:`pdamper.coupling.frf.assumption_record`): ``assumptions_hold`` (bool) and
    ``assumptions`` (what failed at how many of the answers it rests on and the fidelity
    to use, "" where they hold); {} where the model reports no check."""
    if summary is None:
        return {}
    from pdamper.analysis.analytical import assumption_line

    line = assumption_line(summary, "answers")
    return {"assumptions_hold": not summary["flagged"], "assumptions": line or ""}
