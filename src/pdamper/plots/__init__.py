"""Figures of the paper, from labelled results.

Every function takes ``ax=None`` (a new figure is made when None), returns the Axes and
never shows or saves. matplotlib is imported here only.
"""

from pdamper.plots.figures import (
    plot_bed_trajectory,
    plot_damping_ratio,
    plot_effective_mass_map,
    plot_field_difference,
    plot_free_vibration,
    plot_loss_factor_map,
    plot_mode_map,
    plot_optimization,
    plot_particle_snapshots,
)

__all__ = [
    "plot_bed_trajectory",
    "plot_damping_ratio",
    "plot_effective_mass_map",
    "plot_field_difference",
    "plot_free_vibration",
    "plot_loss_factor_map",
    "plot_mode_map",
    "plot_optimization",
    "plot_particle_snapshots",
]
