"""The figure of a COR sensitivity study (:mod:`pdamper.runs.cor_sensitivity`): the
Level II loss factors per COR model and the Level III decays of DEM model 1.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.figure import Figure

    from pdamper.runs.cor_sensitivity import CORSensitivity


def sensitivity_figure(study: CORSensitivity, structure_envelope=None) -> Figure:
    """Figure of a study: Level II loss factors (left) and the Level III decays (right)."""
    from matplotlib.figure import Figure

    from pdamper import plots

    has3 = bool(study.runs)
    fig = Figure(figsize=(13 if has3 else 7, 4.8), layout="constrained")
    axes = fig.subplots(1, 2 if has3 else 1, squeeze=False).ravel()
    plots.plot_cor_sensitivity(study, ax=axes[0])
    axes[0].set_title("Level II, DEM: loss factor per COR model", fontsize="medium")
    if has3:
        ax = axes[1]
        for name, run in study.runs.items():
            t, a = run.peak_times, run.peak_amplitudes
            ax.plot(t, np.asarray(a) * 1e3, "o-", ms=3, lw=1, label=name)
        if study.analytical_run is not None:
            run = study.analytical_run
            ax.plot(run.peak_times, np.asarray(run.peak_amplitudes) * 1e3, "k-", lw=2,
                    alpha=0.4, label="analytical model (no COR)")
        ax.axvline(0.75, color="k", ls=":", lw=1)
        ax.axhline(19.0, color="k", ls="--", lw=1, label="experiment at 0.75 s (19 mm)")
        ax.set_xlabel("time t [s]")
        ax.set_ylabel("negative peak amplitude [mm]")
        ax.set_title("Level III, DEM model 1: decay from -58 mm", fontsize="medium")
        ax.grid(alpha=0.3)
        ax.legend(fontsize="x-small")
    return fig


__all__ = ["sensitivity_figure"]
