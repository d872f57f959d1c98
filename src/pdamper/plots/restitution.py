"""Plots of Level I: COR curves (paper Fig. 2-right), the material table (Fig. 2-left), the
calibration check of single impacts (``pdamper cor``) and the COR sensitivity study.

Every function takes ``ax=None`` (a new figure when None), returns the Axes, and never
shows or saves.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping

import numpy as np

from pdamper.plots.figures import _axes


def _items(curves) -> list:
    return list(curves.items()) if isinstance(curves, Mapping) else list(curves)


def plot_restitution_curves(curves, ax=None, velocity: tuple[float, float] = (0.0, 2.0),
                            styles: Iterable[str] | None = None, points=None):
    """COR over impact speed (Fig. 2-right).

    Parameters
    ----------
    curves
        ``{label: RestitutionCurve}`` or ``[(label, curve), ...]``.
    velocity
        Speed range [m/s].
    styles
        Matplotlib line styles, one per curve (default: solid).
    points
        Optional ``{label: (v, e)}`` of measured or simulated points, drawn as markers.
    """
    ax = _axes(ax)
    v = np.linspace(velocity[0], velocity[1], 400)
    styles = list(styles) if styles is not None else []
    for i, (label, curve) in enumerate(_items(curves)):
        ls = styles[i] if i < len(styles) else "-"
        ax.plot(v, curve(v), ls, lw=1.8, label=label)
    for label, (pv, pe) in (points or {}).items():
        ax.plot(pv, pe, "o", ms=4, mfc="none", label=label)
    ax.set_xlabel("impact velocity v [m/s]")
    ax.set_ylabel("coefficient of restitution e [-]")
    ax.set_xlim(velocity)
    ax.set_ylim(0.0, 1.05)
    ax.grid(alpha=0.3)
    ax.legend(fontsize="x-small", loc="lower left")
    return ax


def plot_material_table(materials, ax=None, friction: float | None = None, notes=None):
    """The material data as a table (Fig. 2-left).

    Parameters
    ----------
    materials
        ``{column label: Material}`` (e.g. ``{"sphere": S235, "wall": PVC}``).
    friction
        mu of every contact [-] (a row if given).
    notes
        Optional ``{row label: [text per column]}`` added at the bottom.
    """
    ax = _axes(ax)
    items = _items(materials)
    rows = [("material", [m.name for _, m in items]),
            ("E [GPa]", [f"{m.youngs_modulus / 1e9:.4g}" for _, m in items]),
            ("nu [-]", [f"{m.poisson_ratio:g}" for _, m in items]),
            ("rho [kg/m^3]", [f"{m.density:g}" for _, m in items]),
            ("yield [MPa]", ["-" if m.yield_strength is None else f"{m.yield_strength / 1e6:.4g}"
                             for _, m in items])]
    if friction is not None:
        rows.append(("mu [-]", [f"{friction:g} (all contacts)"] * len(items)))
    rows += list((notes or {}).items())
    table = ax.table(cellText=[r[1] for r in rows], rowLabels=[r[0] for r in rows],
                     colLabels=[label for label, _ in items], loc="center", cellLoc="center")
    table.auto_set_font_size(False)
    table.set_fontsize(8)
    table.scale(1.0, 1.4)
    ax.axis("off")
    return ax


def plot_cor_check(check, ax=None, curve=None):
    """Target COR and simulated single impacts (``pdamper cor``).

    Parameters
    ----------
    check
        :class:`pdamper.dem.impacts.ImpactCheck`.
    curve
        The target curve, drawn densely if given (else through the grid points).
    """
    ax = _axes(ax)
    v = check.velocity
    if curve is not None:
        vv = np.linspace(0.0, float(v.max()) * 1.02, 400)
        ax.plot(vv, curve(vv), "-", lw=1.8, color="C0", label=f"target: {check.curve}")
    else:
        ax.plot(v, check.cor_target, "-", lw=1.8, color="C0", label=f"target: {check.curve}")
    ax.plot(v, check.cor_simulated, "o", ms=4, mfc="none", color="C3",
            label=f"DEM single impacts ({check.damping_model}, {check.integrator}); "
                  f"max |dev| = {check.max_deviation:.1e}")
    kind = "sphere-sphere" if check.sphere_sphere else "sphere-wall"
    ax.set_title(f"{check.pair} ({kind}, r = {check.radius * 1e3:g} mm)", fontsize="medium")
    ax.set_xlabel("impact velocity v [m/s]")
    ax.set_ylabel("coefficient of restitution e [-]")
    ax.set_ylim(0.0, 1.05)
    ax.grid(alpha=0.3)
    ax.legend(fontsize="x-small", loc="lower left")
    return ax


def plot_cor_sensitivity(study, ax=None, quantity: str = "loss_factor"):
    """Level II results of a COR sensitivity study: ``quantity`` per COR variant (bars
    grouped by excitation point).

    Parameters
    ----------
    study
        :class:`pdamper.runs.cor_sensitivity.CORSensitivity`.
    """
    ax = _axes(ax)
    ds = study.level2
    variants = [str(x) for x in ds["variant"].values]
    points = list(range(ds.sizes["point"]))
    width = 0.8 / max(len(variants), 1)
    for i, name in enumerate(variants):
        y = ds[quantity].sel(variant=name).values
        bars = ax.bar(np.array(points) + (i - (len(variants) - 1) / 2) * width, y, width,
                      color=f"C{i}")
        ax.bar([np.nan], [np.nan], color=f"C{i}", label=name)  # unhatched legend entry
        if "stationary" in ds:
            for bar, ok in zip(bars, ds["stationary"].sel(variant=name).values, strict=True):
                if not ok:  # a transient: the two halves of the window differ
                    bar.set_hatch("///")
                    bar.set_edgecolor("white")
    if quantity == "loss_factor" and "loss_factor_analytical" in ds:
        ax.plot(points, ds["loss_factor_analytical"].values, "kD", ms=6,
                label="analytical block model (no COR)")
    labels = [f"{f:g} Hz / {x * 1e3:g} mm" for f, x in zip(ds["frequency"].values,
                                                             ds["amplitude"].values, strict=True)]
    ax.set_xticks(points, labels, fontsize="small")
    if quantity == "loss_factor":
        ax.axhline(4.0 / np.pi, color="k", ls="--", lw=1, label="4/pi (collect-and-collide)")
        ax.set_ylabel("effective loss factor eta [-]")
    else:
        ax.set_ylabel(f"{quantity} [{ds[quantity].attrs.get('units', '-')}]")
    if "stationary" in ds and not bool(ds["stationary"].all()):
        ax.bar([np.nan], [np.nan], color="0.6", hatch="///", edgecolor="white",
               label="hatched: transient (window halves differ)")
    top = np.nanmax(ds[quantity].values)
    ax.set_ylim(0.0, 1.45 * max(top, 4.0 / np.pi if quantity == "loss_factor" else top))
    ax.legend(fontsize="x-small", ncols=2, loc="upper left")
    ax.grid(alpha=0.3, axis="y")
    return ax


__all__ = ["plot_cor_check", "plot_cor_sensitivity", "plot_material_table",
           "plot_restitution_curves"]
