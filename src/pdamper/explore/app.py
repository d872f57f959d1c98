"""The page of ``pdamper explore``: widgets for :class:`~pdamper.explore.design.Inputs`,
Bokeh figures for its views, a DEM check that runs beside the page (docs/explore.md).

Every number the page shows comes from :mod:`pdamper.explore.design`, which the command
line shares: the peak lines are ``pdamper frf``'s, verbatim. A slider's move redraws the
quick views (bare FRF, Level II map, mass) at once and the forced response when it is
solved, in a worker thread, so that the page keeps answering; the DEM check runs in a
separate process (a dask ``LocalCluster`` of one worker, as the maps use) and adds its
point to the map when it arrives.
"""

from __future__ import annotations

import asyncio
import dataclasses
import signal
import time
from concurrent.futures import Future, ThreadPoolExecutor
from pathlib import Path
from typing import Any

import numpy as np
import panel as pn
from bokeh.models import ColumnDataSource, LinearColorMapper
from bokeh.models.annotations import ColorBar
from bokeh.plotting import figure

from pdamper.errors import PdamperError
from pdamper.explore import design
from pdamper.explore.design import CONTROLS, LOADS, Inputs

#: One thread solves forced responses: a newer design's result replaces an older one's.
_SOLVER = ThreadPoolExecutor(max_workers=1, thread_name_prefix="pdamper-frf")
#: Seconds between the DEM check's progress updates on the page.
POLL = 0.5

_MODE_NAMES = ["solid-like", "single CaC", "single CaC subh.", "double CaC",
               "double CaC subh.", "scattering", "rattling"]
#: A colour per motion mode on the map (code -> colour; -1, none: grey).
_MODE_COLOURS = {0: "#7f7f7f", 1: "#2ca02c", 2: "#98df8a", 3: "#1f77b4", 4: "#aec7e8",
                 5: "#ff7f0e", 6: "#9467bd"}


def _mode_name(code: int) -> str:
    return _MODE_NAMES[int(code)] if 0 <= int(code) < len(_MODE_NAMES) else "none"


def _dem_point(inputs: Inputs, frequency: float, stroke: float) -> dict[str, Any]:
    """One DEM point of the design (runs in the check's worker process)."""
    from pdamper.explore.design import scenario_of

    t0 = time.perf_counter()
    sc = scenario_of(dataclasses.replace(inputs, model=None))
    model = sc.model("dem", sc.damper())
    r = model.response(frequency, stroke)
    return {"frequency": frequency, "stroke": stroke,
            "loss_factor": float(np.ravel(r.loss_factor)[0]),
            "effective_mass_ratio": float(np.ravel(r.effective_mass_ratio)[0]),
            "mode": int(np.ravel(r.mode)[0]), "seconds": time.perf_counter() - t0}


class DEMChecks:
    """The DEM checks of one server: a one-worker dask cluster started at the first check,
    results cached per (design, point)."""

    def __init__(self) -> None:
        self._client: Any = None
        self.cache: dict[tuple, dict[str, Any]] = {}

    def submit(self, inputs: Inputs, frequency: float, stroke: float) -> Future | Any:
        key = (inputs, round(frequency, 9), round(stroke, 12))
        if key in self.cache:
            done: Future = Future()
            done.set_result(self.cache[key])
            return done
        if self._client is None:
            from dask.distributed import Client, LocalCluster

            cluster = LocalCluster(n_workers=1, threads_per_worker=1, processes=True,
                                   dashboard_address=None)
            self._client = Client(cluster)
        fut = self._client.submit(_dem_point, inputs, frequency, stroke, pure=False)
        fut.add_done_callback(lambda f: self.cache.setdefault(key, f.result())
                              if f.status == "finished" else None)
        return fut

    def close(self) -> None:
        if self._client is not None:
            cluster = self._client.cluster
            self._client.close()
            cluster.close()
            self._client = None


class Page:
    """One browser session's page."""

    def __init__(self, base: Inputs, checks: DEMChecks, out_dir: Path,
                 mass_limit: float | None = None):
        self.inputs = base
        self.checks = checks
        self.out_dir = out_dir
        self.generation = 0
        sc = design.scenario_of(base)
        self.widgets: dict[str, Any] = {}
        self.rows: dict[str, Any] = {}
        self._controls(sc)
        if "particles.count" in self.widgets:
            self.widgets["particles.count"].end = max(int(sc.damper().max_count),
                                                      self.widgets["particles.count"].value)
        self._bed_widgets(base, sc.damper())
        mats = design.materials()
        self.particle_material = pn.widgets.Select(
            label="particle material", options=mats, value=_name(sc.particles.material, mats))
        self.container_material = pn.widgets.Select(
            label="container material", options=mats, value=_name(sc.container.material, mats))
        self.particle_material.param.watch(self._on_value("particles.material"), "value")
        self.container_material.param.watch(self._on_value("container.material"), "value")
        kind = base.load_kind
        self.load_kind = pn.widgets.RadioButtonGroup(label="load", options=list(LOADS),
                                                     value=kind)
        unit, _, lo, hi = LOADS[kind]
        self.load = pn.widgets.FloatSlider(label=f"load amplitude [{unit}]", start=lo, end=hi,
                                           step=0.1, value=base.load_amplitude,
                                           css_classes=["ctl-load"])
        self.frequency = pn.widgets.TextInput(label="frequencies (start:stop:count)",
                                              value=base.frequency,
                                              placeholder="default: every mode, resolved")
        self.sweep = pn.widgets.Select(label="sweep", options=["both", "up", "down"],
                                       value=base.sweep)
        self.load.label = f"load amplitude [{LOADS[kind][0]}]"
        fidelities = ["analytic"] + (["fields"] if base.fields is not None else [])
        self.fidelity = pn.widgets.Select(label="fidelity", options=fidelities,
                                          value=base.model if base.model in fidelities
                                          else "analytic")
        self.mass_limit = pn.widgets.FloatInput(label="mass limit [g] (0: none)", start=0,
                                                value=0 if mass_limit is None
                                                else mass_limit * 1e3)
        for chooser in (self.load_kind, self.frequency, self.sweep, self.fidelity):
            chooser.param.watch(self._on_load, "value")
        self.load.param.watch(self._on_load, "value_throttled")
        self.mass_limit.param.watch(lambda _e: self._schedule(), "value")

        self.message = pn.pane.Alert("", alert_type="danger", visible=False,
                                     css_classes=["message"])
        self.status = pn.pane.Markdown("", css_classes=["status"])
        self.peaks = pn.pane.Markdown("", css_classes=["peaks"])
        self.mass = pn.pane.Markdown("", css_classes=["mass"])
        self.notes = pn.pane.Markdown("", css_classes=["notes"])
        self.offer = pn.pane.Alert("", alert_type="warning", visible=False,
                                   css_classes=["offer"])
        self.dem_text = pn.pane.Markdown("", css_classes=["dem"])
        self.time_text = pn.pane.Str("", css_classes=["time-lines"])
        self.saved = pn.pane.Markdown("", css_classes=["saved"])
        self.save_path = pn.widgets.TextInput(label="scenario file",
                                              value=str(out_dir / "explored.toml"))
        self.save_button = pn.widgets.Button(label="Save scenario", color="primary",
                                             css_classes=["save"])
        self.report_button = pn.widgets.Button(label="Report", css_classes=["report"])
        self.dem_button = pn.widgets.Button(label="DEM check", color="warning",
                                            css_classes=["demcheck"])
        self.save_button.on_click(self._on_save)
        self.report_button.on_click(self._report)
        self.dem_button.on_click(self._dem)
        self._figures()
        self.dem_points: list[dict[str, Any]] = []
        self.response: design.Response | None = None
        self._queued: list[Future] = []
        self._answered = 0  # the generation whose full answer is drawn
        self._redrawn = ""
        self._drawn_for: Inputs | None = None  # the design whose forced response is drawn

    def _bed_widgets(self, base: Inputs, damper0: Any) -> None:
        """The bed's mass instead of the count: the count derived from it for the radius
        and material set (pdamper optimize's bed-mass variable)."""
        self.count_from = pn.widgets.RadioButtonGroup(
            label="bed given by", options=["count", "bed mass"],
            value="count" if base.bed_mass is None else "bed mass", css_classes=["count-from"])
        self.bed_mass = pn.widgets.FloatSlider(
            label="bed mass [g]", start=0.0,
            end=max(1000.0, round(damper0.max_count * damper0.particle_mass * 1e3)),
            step=1.0, value=float(base.bed_mass if base.bed_mass is not None
                                  else round(damper0.bed_mass * 1e3)),
            disabled=base.bed_mass is None, sizing_mode="stretch_width",
            css_classes=["ctl-bed-mass"])
        self.count_from.param.watch(self._on_bed_mass, "value")
        self.bed_mass.param.watch(self._on_bed_mass, "value_throttled")

    def _controls(self, sc: Any) -> None:
        """A slider per control, with its declaration (key, allowed range) in a tooltip."""
        start = design.values_of(sc)
        for c in CONTROLS:
            if c.key.startswith("structure.") and sc.structure.modes is not None \
                    and c.key not in design.WITH_MODES:
                continue  # a modes file: the structure is the file's, not the sliders'
            value = start.get(c.key, c.low)
            decl = c.declaration()
            unit = "" if c.unit == "1" else f" [{c.unit}]"
            tip = f"{decl.doc} Scenario key {c.key}; allowed {decl.allowed or 'any'}."
            cls = pn.widgets.IntSlider if c.integer else pn.widgets.FloatSlider
            lo, hi = design.span(c, value)
            w = cls(label=f"{c.label}{unit}", start=lo, end=hi, step=c.step,
                    value=int(value) if c.integer else value,
                    sizing_mode="stretch_width",
                    css_classes=[f"ctl-{c.key.replace('.', '-')}"])
            w.param.watch(self._on_value(c.key), "value_throttled")
            self.widgets[c.key] = w
            self.rows[c.key] = pn.Row(w, pn.widgets.TooltipIcon(value=tip),
                                      sizing_mode="stretch_width")

    # ---- layout ---------------------------------------------------------------------------
    def layout(self, start: bool = True) -> pn.template.BaseTemplate:
        """The page: inputs in the sidebar, views in the main area; ``start``: its views
        computed when the session loads."""
        row = self.rows.get
        side = pn.Column(
            "### Damper", self.count_from, row("particles.count"), self.bed_mass,
            row("particles.radius"),
            self.particle_material, row("container.length"), row("container.width"),
            row("container.depth"), self.container_material, row("container.mass"),
            row("particles.friction"),
            "### Structure and load",
            *[w for k, w in self.rows.items() if k.startswith("structure.")],
            self.load_kind, self.load, self.frequency, self.sweep, self.fidelity,
            self.mass_limit, sizing_mode="stretch_width")
        side.objects = [o for o in side.objects if o is not None]
        main = pn.Column(
            self.message, self.status,
            # the time view on its own tab, drawn when opened (the page loads faster)
            pn.Tabs(("forced response and Level II map", pn.Row(self.frf_fig, self.map_fig)),
                    ("in time (pdamper simulate)", pn.Column(self.time_fig, self.time_text)),
                    dynamic=True),
            self.peaks, self.mass, self.offer, self.notes,
            pn.Row(self.dem_button, self.dem_text),
            pn.Row(self.save_path, self.save_button, self.report_button), self.saved)
        tpl = pn.template.BootstrapTemplate(title="pdamper explore", sidebar=[side],
                                            main=[main])
        if start:
            pn.state.onload(self._start)
        return tpl

    def _figures(self) -> None:
        # sources named, so that a browser test finds what the page drew
        self.frf_src = {n: ColumnDataSource(data={"f": [], "x": []}, name=f"frf-{n}")
                        for n in ("bare", "up", "down")}
        self.hb_src = {n: ColumnDataSource(data={"f": [], "x": []}, name=f"hb-{n}")
                       for n in ("s", "u", "e")}
        p = figure(title="forced response at the output point", height=470, width=560,
                   x_axis_label="frequency [Hz]", y_axis_label="amplitude [mm]",
                   tools="pan,wheel_zoom,box_zoom,reset,save")
        p.line("f", "x", source=self.frf_src["bare"], color="gray", line_dash="dashed",
               legend_label="without damper")
        p.line("f", "x", source=self.frf_src["up"], color="#1f77b4", line_width=2,
               legend_label="sweep up")
        p.line("f", "x", source=self.frf_src["down"], color="#d62728", line_width=2,
               line_dash="dotdash", legend_label="sweep down")
        p.scatter("f", "x", source=self.hb_src["s"], color="black", size=4,
                  legend_label="harmonic balance, stable")
        p.scatter("f", "x", source=self.hb_src["u"], color="orange", size=4, marker="x",
                  legend_label="harmonic balance, unstable")
        p.scatter("f", "x", source=self.hb_src["e"], color="purple", size=4,
                  marker="triangle", legend_label="harmonic balance, edge")
        self.frf_fail_src = ColumnDataSource(data={"f": [], "x": [], "why": []},
                                             name="frf-fails")
        p.scatter("f", "x", source=self.frf_fail_src, color="red", size=9, marker="x",
                  line_width=2, legend_label="analytical assumptions fail")
        p.legend.click_policy = "hide"
        p.legend.label_text_font_size = "8pt"
        p.legend.ncols = 2  # below the curves, which it would hide
        p.add_layout(p.legend[0], "below")
        self.frf_fig = pn.pane.Bokeh(p)
        self.map_src = ColumnDataSource(data={"image": [np.zeros((2, 2))], "x": [0], "y": [0],
                                              "dw": [1], "dh": [1]})
        self.path_src = ColumnDataSource(data={"f": [], "x": []})
        self.dem_src = ColumnDataSource(data={"f": [], "x": [], "eta": [], "label": []})
        self.mapper = LinearColorMapper(palette="Viridis256", low=0, high=1)
        m = figure(title="damper loss factor (Level II), motion modes and operating path",
                   height=470,
                   width=520, x_axis_label="frequency [Hz]",
                   y_axis_label="container stroke [mm]", tools="pan,wheel_zoom,reset,save")
        m.image("image", x="x", y="y", dw="dw", dh="dh", source=self.map_src,
                color_mapper=self.mapper)  # type: ignore[call-arg]  # bokeh's stubs lag
        m.line("f", "x", source=self.path_src, color="white", line_width=2,
               legend_label="operating path (sweep up)")
        # the motion mode of every cell, a colour per mode (hover: eta, mode, assumptions)
        self.cell_src = ColumnDataSource(data={"f": [], "x": [], "eta": [], "mode": [],
                                               "colour": [], "why": []}, name="map-cells")
        cells = m.scatter("f", "x", source=self.cell_src, size=5, color="colour",
                          line_color="black", line_width=0.3, legend_field="mode")
        self.fail_src = ColumnDataSource(data={"f": [], "x": []}, name="map-fails")
        m.scatter("f", "x", source=self.fail_src, size=8, marker="x", color="red",
                  line_width=1.5, legend_label="analytical assumptions fail")
        m.scatter("f", "x", source=self.dem_src, size=12, marker="star", color="red",
                  line_color="white", legend_label="DEM check")
        from bokeh.models import HoverTool

        m.add_tools(HoverTool(renderers=[cells], tooltips=[
            ("f", "@f{0.00} Hz"), ("stroke", "@x{0.000} mm"), ("eta", "@eta{0.000}"),
            ("mode", "@mode"), ("assumptions", "@why")]))
        m.legend.click_policy = "hide"
        # below the map, in columns: the modes' dots would hide the map inside it
        m.legend.ncols = 3
        m.add_layout(m.legend[0], "below")
        m.add_layout(ColorBar(color_mapper=self.mapper, title="eta"), "right")
        self.time_src = ColumnDataSource(data={"t": [], "x": []}, name="time")
        t = figure(title="in time: pdamper simulate of this design", height=260, width=1080,
                   x_axis_label="time [s]", y_axis_label="displacement [mm]",
                   tools="pan,wheel_zoom,box_zoom,reset,save")
        t.line("t", "x", source=self.time_src, color="#1f77b4")
        self.time_plot = t
        self.time_fig = pn.pane.Bokeh(t)
        m.legend.label_text_font_size = "8pt"
        self.map_fig = pn.pane.Bokeh(m)

    # ---- events ---------------------------------------------------------------------------
    def _on_value(self, key: str):
        def changed(event) -> None:
            self.inputs = self.inputs.with_value(key, event.new)
            self._schedule()
        return changed

    def _on_bed_mass(self, _event=None) -> None:
        by_mass = self.count_from.value == "bed mass"
        self.bed_mass.disabled = not by_mass
        if "particles.count" in self.widgets:
            self.widgets["particles.count"].disabled = by_mass
        self.inputs = dataclasses.replace(
            self.inputs, bed_mass=float(self.bed_mass.value or 0.0) if by_mass else None)
        if not by_mass and "particles.count" in self.widgets:
            self.inputs = self.inputs.with_value("particles.count",
                                                 self.widgets["particles.count"].value)
        self._schedule()

    def _on_load(self, _event=None) -> None:
        kind = self.load_kind.value
        if kind != self.inputs.load_kind:
            unit, _, lo, hi = LOADS[kind]
            self.load.label = f"load amplitude [{unit}]"
            self.load.start, self.load.end = lo, hi
            self.load.value = min(max(float(self.load.value or lo), lo), hi)
        model = self.fidelity.value
        self.inputs = dataclasses.replace(
            self.inputs, load_kind=kind, load_amplitude=float(self.load.value or 0.0),
            frequency=(self.frequency.value or "").strip(), sweep=self.sweep.value, model=model)
        self._schedule()

    def _start(self) -> None:
        self._schedule()

    def _fail(self, exc: Exception) -> None:
        self.message.object = f"error: {exc}"
        self.message.visible = True
        self.status.object = ""

    def _schedule(self) -> None:
        """Quick views now; the forced response in the solver thread (the page answers
        meanwhile): where the grid is large a preview first, the forced response on a
        coarser grid of the same band (:func:`~pdamper.explore.design.preview`), then the
        full grid's, then the time view.
        A newer design supersedes an older one: its results are not drawn and its work not
        yet started is dropped."""
        self.generation += 1
        gen = self.generation
        t0 = time.perf_counter()
        for queued in self._queued:  # an older design's work not started: dropped
            queued.cancel()
        try:
            self.quick = design.quick(self.inputs)
        except (PdamperError, ValueError) as exc:
            self._fail(exc)
            return
        self.message.visible = False
        if self.inputs.bed_mass is not None and "particles.count" in self.widgets:
            w = self.widgets["particles.count"]
            n = int(design.with_derived_count(self.inputs).overrides()["particles.count"])
            w.end = max(w.end, n)
            w.value = n  # shown, not sent: the count follows the bed mass
        doc = pn.state.curdoc

        def redraw() -> None:
            self._draw_quick()
            self._redrawn = f"views redrawn in {(time.perf_counter() - t0) * 1e3:.0f} ms"
            self.status.object = f"{self._redrawn}; solving the forced response ..."
        # Bokeh sources change under the document's lock: on the next tick of its loop
        (doc.add_next_tick_callback(redraw) if doc is not None else redraw())
        inputs = self.inputs
        # a first answer at the resolution a curve needs, then the full grid's, then the
        # time view: each drawn when it arrives, if the design is still the page's
        jobs = [(design.response, self._solved), (design.time_response, self._timed)]
        # a large grid's preview, unless only the time view's inputs changed (the forced
        # response drawn is this design's)
        if design.preview_grid(self.quick.frequency.size) is not None \
                and design.forced_inputs(inputs) != self._drawn_for:
            jobs.insert(0, (design.preview, self._previewed))
        self._queued = []
        for solve, draw in jobs:
            fut = _SOLVER.submit(solve, inputs)
            self._queued.append(fut)

            def arrived(f: Future, draw=draw) -> None:
                if doc is not None and not f.cancelled():
                    doc.add_next_tick_callback(lambda: draw(gen, f, t0))
            fut.add_done_callback(arrived)

    def _previewed(self, gen: int, fut: Future, t0: float) -> None:
        """The preview's curves, until the full grid's answer replaces them (its peak lines
        are said in the status, with the grid they are for; the peak lines shown below
        the views are only ever the full answer's)."""
        if gen != self.generation or self._answered == gen:
            return
        try:
            res = fut.result()
        except (PdamperError, ValueError):
            return  # the full answer says why
        if res is None:
            return
        self._draw_response(res)
        n = res.frf.frequency.size
        # the design's peak lines are the full grid's (pdamper frf's for the view)
        self.peaks.object = f"*the peak lines of all {res.of} frequencies: solving ...*"
        said = (f"`pdamper frf --frequency {res.grid}`: " if res.grid else "") + \
            "; ".join(res.peak_lines)
        self.status.object = (
            f"{self._redrawn}; first answer at {n} of the {res.of} frequencies after "
            f"{time.perf_counter() - t0:.2f} s ({said}); solving all {res.of} ...")

    def _timed(self, gen: int, fut: Future, _t0: float = 0.0) -> None:
        """The time view (free decay or load response) when it is computed."""
        if gen != self.generation:
            return
        try:
            self._draw_time(fut.result())
        except (PdamperError, ValueError) as exc:
            self.time_text.object = f"error: {exc}"

    def _draw_time(self, r: design.TimeResponse) -> None:
        self.time_src.data = {"t": r.time, "x": r.displacement * 1e3}
        title = ("free decay: released from the structure's initial displacement "
                 "(pdamper simulate)" if r.kind == "release"
                 else "response to the scenario's [load] history (pdamper simulate)")
        self.time_plot.title.text = title  # type: ignore[union-attr]  # figure() made a Title
        self.time_text.object = "\n".join(r.lines)

    def _solved(self, gen: int, fut: Future, t0: float) -> None:
        if gen != self.generation:
            return  # a newer design is being solved
        try:
            res = fut.result()
        except (PdamperError, ValueError) as exc:
            self._fail(exc)
            return
        self.response = res
        self._answered = gen
        self._drawn_for = design.forced_inputs(self.inputs)
        self._draw_response(res)
        self.status.object = (f"forced response solved ({res.seconds:.2f} s; page answered "
                              f"after {(time.perf_counter() - t0):.2f} s)")

    # ---- drawing --------------------------------------------------------------------------
    def _draw_quick(self) -> None:
        q = self.quick
        self.frf_src["bare"].data = {"f": q.frequency, "x": q.bare * 1e3}
        eta = np.where(np.isfinite(q.map_loss_factor), q.map_loss_factor, np.nan)
        f0, f1 = float(q.map_frequency[0]), float(q.map_frequency[-1])
        x0, x1 = float(q.map_stroke[0]) * 1e3, float(q.map_stroke[-1]) * 1e3
        # the map's strokes are log-spaced: drawn against their index scaled to mm
        lin = np.linspace(x0, x1, eta.shape[0])
        img = np.array([np.interp(lin, q.map_stroke * 1e3, eta[:, j])
                        for j in range(eta.shape[1])]).T
        self.map_src.data = {"image": [img], "x": [f0], "y": [x0], "dw": [max(f1 - f0, 1e-9)],
                             "dh": [max(x1 - x0, 1e-9)]}
        finite = eta[np.isfinite(eta)]
        self.mapper.high = float(max(finite.max(), 1e-3)) if finite.size else 1.0
        F, X = np.meshgrid(q.map_frequency, q.map_stroke * 1e3)
        codes = q.map_mode.ravel()
        why = ([""] * codes.size if q.map_reasons is None
               else [str(r) or "hold" for r in np.ravel(q.map_reasons)])
        self.cell_src.data = {"f": F.ravel(), "x": X.ravel(), "eta": eta.ravel(),
                              "mode": [_mode_name(c) for c in codes],
                              "colour": [_MODE_COLOURS.get(int(c), "#bbbbbb") for c in codes],
                              "why": why}
        # marked: the cells failing on their own (a design-wide reason is said once)
        common = design.design_wide(q.map_reasons, None if self.response is None
                                    else self.response.reasons)
        own = (np.zeros(codes.shape, bool) if q.map_reasons is None
               else np.ravel(design.marked(q.map_reasons, common)))
        self.fail_src.data = {"f": F.ravel()[own], "x": X.ravel()[own]}
        self._offer()
        limit = self.mass_limit.value
        self.mass.object = "**mass** " + design.mass_text(q, None if not limit
                                                           else limit * 1e-3)
        notes = [f"- {k}: not used by the {self.fidelity.value} fidelity ({why})"
                 for k, why in q.unused.items()]
        self.notes.object = "\n".join(notes)

    def _draw_response(self, res: design.Response) -> None:
        r = res.frf
        for name in ("up", "down"):
            c = r.sweeps.get(name)
            self.frf_src[name].data = ({"f": r.frequency, "x": c.amplitude * 1e3} if c is not None
                                       else {"f": [], "x": []})
        hb = r.harmonic_balance
        for code in ("s", "u", "e"):
            fs, xs = [], []
            if hb is not None and hb.branch is not None:
                for i, f in enumerate(r.frequency):
                    for a, b in zip(hb.amplitude[i], hb.branch[i], strict=True):
                        if b and b[0] == code:
                            fs.append(float(f))
                            xs.append(float(a) * 1e3)
            self.hb_src[code].data = {"f": fs, "x": xs}
        path = r.sweeps.get("up") or next(iter(r.sweeps.values()), None)
        self.path_src.data = ({"f": r.frequency, "x": path.stroke * 1e3} if path is not None
                              else {"f": [], "x": []})
        self.peaks.object = "\n".join(f"- `{line}`" for line in res.peak_lines)
        common = design.design_wide(self.quick.map_reasons if getattr(self, "quick", None)
                                    else None, res.reasons)
        bad = (np.zeros(r.frequency.size, bool) if res.reasons is None
               else design.marked(res.reasons, common))
        x_path = (path.amplitude * 1e3 if path is not None else np.full(r.frequency.size,
                                                                         np.nan))
        self.frf_fail_src.data = {"f": r.frequency[bad], "x": x_path[bad],
                                  "why": [str(w) for w in np.asarray(res.reasons)[bad]]
                                  if res.reasons is not None else []}
        self._offer()

    def _offer(self) -> None:
        """The fields fidelity offered where the analytical model's assumptions fail."""
        q = getattr(self, "quick", None)
        if q is None:
            return
        text = design.fields_offer(q, self.response, self.fidelity.value)
        self.offer.object = text
        self.offer.visible = bool(text)

    # ---- DEM check, save, report ----------------------------------------------------------
    def _dem(self, _event=None) -> None:
        if self.response is None:
            self.dem_text.object = "the forced response is not solved yet"
            return
        r = self.response.frf
        c = r.sweeps.get("up") or next(iter(r.sweeps.values()))
        k = int(np.argmax(c.amplitude))
        f, x = float(r.frequency[k]), float(c.stroke[k])
        try:
            fut = self.checks.submit(self.inputs, f, x)
        except Exception as exc:  # noqa: BLE001 - the page says why, in one line
            self.dem_text.object = f"DEM check could not start: {exc}"
            return
        t0 = time.perf_counter()
        self.dem_text.object = f"DEM check at {f:g} Hz, stroke {x * 1e3:.2f} mm: running ..."
        analytic = float(np.ravel(self.inputs_model_response(f, x))[0])

        def poll() -> None:
            if not fut.done():
                self.dem_text.object = (f"DEM check at {f:g} Hz, stroke {x * 1e3:.2f} mm: "
                                        f"running, {time.perf_counter() - t0:.0f} s")
                return
            cb.stop()
            try:
                p = fut.result()
            except Exception as exc:  # noqa: BLE001
                self.dem_text.object = f"DEM check failed: {exc}"
                return
            self.dem_points.append(p)
            self.dem_src.stream({"f": [p["frequency"]], "x": [p["stroke"] * 1e3],
                                 "eta": [p["loss_factor"]], "label": ["DEM"]})
            self.dem_text.object = (
                f"DEM at {p['frequency']:g} Hz, stroke {p['stroke'] * 1e3:.2f} mm: "
                f"eta {p['loss_factor']:.3g} (this fidelity {analytic:.3g}), "
                f"{_MODE_NAMES[p['mode']] if 0 <= p['mode'] < len(_MODE_NAMES) else 'unclassified'}"
                f"; {p['seconds']:.1f} s")
        cb = pn.state.add_periodic_callback(poll, period=int(POLL * 1000))

    def inputs_model_response(self, f: float, x: float) -> np.ndarray:
        sc = design.scenario_of(self.inputs)
        return sc.model(self.inputs.model, sc.damper()).response(f, x).loss_factor

    def _on_save(self, _event=None) -> None:
        self._save()

    def _save(self) -> Path | None:
        try:
            path = design.save_scenario(self.inputs, Path(self.save_path.value or
                                                          "explored.toml").expanduser())
        except (PdamperError, ValueError, OSError) as exc:
            self._fail(exc)
            return None
        self.saved.object = (f"saved `{path}`; the forced response of this view: "
                             f"`{self.inputs.command(path)}`")
        return path

    async def _report(self, _event=None) -> None:
        import sys

        path = self._save()
        if path is None:
            return
        out = path.with_suffix("")
        out = out.with_name(out.name + "-report")
        self.saved.object += f"\n\nreport running: `pdamper report --scenario {path} --out {out}`"
        proc = await asyncio.create_subprocess_exec(
            sys.executable, "-m", "pdamper", "report", "--scenario", str(path), "--out",
            str(out), stdout=asyncio.subprocess.PIPE, stderr=asyncio.subprocess.PIPE)
        _, err = await proc.communicate()
        if proc.returncode == 0:
            self.saved.object += f"\n\nreport written: `{out / 'report.html'}`"
        else:
            self.saved.object += f"\n\nreport failed: {err.decode().strip().splitlines()[-1:]}"


def _name(material: Any, names: list[str]) -> str:
    name = material if isinstance(material, str) else getattr(material, "name", "")
    return name if name in names else names[0]


def warm(base: Inputs, checks: DEMChecks, out_dir: Path,
         mass_limit: float | None = None) -> None:
    """The first session's set-up, done before the server says it is ready: a page built
    once into a document of its own (Bokeh's models made for the first time cost about a
    second) and the base design's quick views into their cache, so that the first browser
    to connect gets its page at once. (Its forced response is solved when a page asks:
    solved here, its lines would be on the page before a user's first change of the
    frequencies had reached the server.) A design the scenario refuses is said on the
    page, not here."""
    from bokeh.document import Document

    try:
        Page(base, checks, out_dir, mass_limit).layout(start=False).server_doc(Document())
        design.quick(base)
    except Exception:  # noqa: BLE001 - the page itself shows what is wrong
        pass


def serve(base: Inputs, *, port: int, show: bool, out_dir: Path,
          mass_limit: float | None = None) -> None:
    """Serve the page on 127.0.0.1:``port`` until interrupted (Ctrl-C: the command line's
    ``interrupted``, status 130)."""
    checks = DEMChecks()

    def page() -> Any:
        return Page(base, checks, out_dir, mass_limit).layout()

    warm(base, checks, out_dir, mass_limit)

    server = pn.serve({"/": page}, address="127.0.0.1", port=port, show=False, start=False,
                      websocket_origin=[f"127.0.0.1:{port}", f"localhost:{port}"],
                      title="pdamper explore")
    url = f"http://127.0.0.1:{server.port}/"
    # the address is printed once the loop runs with the signal handlers below in place
    server.io_loop.add_callback(
        lambda: print(f"pdamper explore: serving {url} (Ctrl-C stops)", flush=True))
    if show:
        import webbrowser

        server.io_loop.add_callback(lambda: webbrowser.open(url))
    received: list[int] = []

    def stop(signum: int, _frame: Any) -> None:
        # the server's loop ends first, then the command line reports the signal
        # (`interrupted`, 128 + signal) as every command does
        received.append(signum)
        server.io_loop.add_callback_from_signal(server.io_loop.stop)

    previous = {s: signal.signal(s, stop) for s in (signal.SIGINT, signal.SIGTERM)}
    try:
        server.start()
        server.io_loop.start()
    finally:
        for s, handler in previous.items():
            signal.signal(s, handler)
        server.stop()
        checks.close()
    if received:
        from pdamper.errors import Interrupted

        raise Interrupted(received[0])
