"""What every scenario must satisfy whichever command reads it, checked on load: every
section builds, and nothing in it lacks a physical meaning (:mod:`pdamper.resources`).

Cheap by design (no DEM run, no numba, no grid built): what a run *costs* is judged apart,
for the runs a command makes (:mod:`pdamper.runs.resources`).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from pdamper import resources
from pdamper.errors import InputError
from pdamper.io.grids import parse_axis
from pdamper.parameters import vertical_dampers_paper as paper

if TYPE_CHECKING:  # pragma: no cover
    from pdamper.damper import ParticleDamper
    from pdamper.io.scenario import Scenario

#: Usual (f [Hz], X [m]) of a Level II run: the paper's benchmark point; of the two, the
#: one further above its usual value is named when a motion is too fast.
USUAL_EXCITATION = paper.BENCHMARK_EXCITATION


def validate(sc: Scenario) -> None:
    """Build what every section describes and check its physics (cheaply: no DEM run, no
    numba, no grid), so that its errors surface at load time whichever command reads the
    scenario."""
    damper = sc.damper()
    sc.structure_model()
    sc.map_ranges()
    parse_axis(sc.map.dem_frequency, "Hz", "map.dem_frequency")
    parse_axis(sc.map.dem_amplitude, "m", "map.dem_amplitude")
    counts = sc.map_particles()
    if counts is not None and counts.max() > damper.max_count:
        raise InputError("map.particles", f"counts must be in [1, {damper.max_count}] (n_max of "
                         f"this container), got {counts.max()}")
    sc.optimization.sizes()  # checked, not built: a range's size is judged by its run
    sc.map_model("dem", damper)
    sc.model(None, damper)
    check_physics(sc, damper)


def check_physics(sc: Scenario, damper: ParticleDamper | None = None) -> None:
    """Refuse what has no physical meaning in any model (:mod:`pdamper.resources`):
    spheres too small, strokes too long, impacts too fast, excitations faster than a
    contact, in ``[particles]``, ``[excitation]``, ``[structure]`` and ``[map]``."""
    d = sc.damper() if damper is None else damper
    resources.check_particles(d)
    g = sc.excitation.gravity
    resources.check_motion(d, sc.excitation.frequency, sc.excitation.amplitude,
                           usual=USUAL_EXCITATION, gravity=g)
    resources.check_release(d, sc.structure_model().natural_frequency,
                            sc.structure.initial_displacement, gravity=g)
    (f0, f1, _), (x0, x1, _) = sc.map_ranges()
    resources.check_grid(d, (f0, f1), (x0, x1), usual=USUAL_EXCITATION, gravity=g)
