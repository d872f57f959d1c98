"""Figures of the paper, from labelled results (Figs. 2, 4, 5, 7, 8, 9).

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
    plot_step_profile,
)
from pdamper.plots.level3 import (
    plot_damping_ratio_band,
    plot_design_front,
    plot_design_landscape,
    plot_mode_study,
    plot_model_damping_ratios,
    plot_model_trajectories,
    plot_phase_drift,
    plot_trajectory_band,
)
from pdamper.plots.restitution import (
    plot_cor_check,
    plot_cor_sensitivity,
    plot_material_table,
    plot_restitution_curves,
)

__all__ = [
    "plot_bed_trajectory",
    "plot_cor_check",
    "plot_cor_sensitivity",
    "plot_material_table",
    "plot_restitution_curves",
    "plot_damping_ratio",
    "plot_effective_mass_map",
    "plot_step_profile",
    "plot_field_difference",
    "plot_design_front",
    "plot_design_landscape",
    "plot_free_vibration",
    "plot_loss_factor_map",
    "plot_mode_map",
    "plot_mode_study",
    "plot_model_damping_ratios",
    "plot_model_trajectories",
    "plot_optimization",
    "plot_particle_snapshots",
    "plot_phase_drift",
    "plot_damping_ratio_band",
    "plot_trajectory_band",
]
