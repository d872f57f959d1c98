"""Design limits: the mass of bed and container (``--max-mass``), response limits
(``--require``), the derived count variables ``bed-mass`` and ``fill``, on the user cases
(machine frame, bracket on a shaker)."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

from pdamper.design.study import (
    DesignCandidate,
    apply_design,
    lightest_within,
    make_limits,
    parse_limit,
    parse_variable,
)
from pdamper.errors import InputError
from pdamper.materials import get_material
from pdamper.parameters import PAPER_DAMPER

#: The machine frame's modes (the user case machine-frame/modes.csv) with the shapes at
#: the damper and the sensor, both the tip: the motor's column is a load point this study
#: does not use (the load here is the harmonic force of peak-frf at the damper's point).
FRAME_MODES = ("frequency [Hz], damping ratio [%], damper [kg^-0.5], observation [kg^-0.5]\n"
               "12.0, 1.0, 0.2582, 0.2582\n31.0, 0.8, -0.3162, -0.3162\n")
#: Aluminium box of the machine frame: 60 mm cube inside, 1.5 mm walls (problem.md).
FRAME_BOX, FRAME_WALL = 0.060, 0.0015
#: The bracket's box: 30 mm cube inside, 1 mm walls.
BRACKET_BOX, BRACKET_WALL = 0.030, 0.001
G0 = 9.80665


def box_mass(inner: float, wall: float) -> float:
    """A cube of aluminium walls: the outer cube minus the inner one [kg] (by hand, not by
    pdamper)."""
    rho = get_material("aluminium").density
    return rho * ((inner + 2 * wall) ** 3 - inner**3)


def _frame(tmp_path: Path) -> Path:
    """The machine frame's scenario (:data:`FRAME_MODES`)."""
    (tmp_path / "modes.csv").write_text(FRAME_MODES)
    text = f"""
title = "machine frame"
[container]
length = "60 mm"
width = "60 mm"
depth = "60 mm"
material = "aluminium"
mass = "{box_mass(FRAME_BOX, FRAME_WALL)} kg"
[particles]
material = "100Cr6"
radius = "4 mm"
count = 50
[structure]
modes = "modes.csv"
[optimization]
objective = "peak-frf"
frf_load = "10 N"
band = "10 Hz:14 Hz:7"
"""
    path = tmp_path / "frame.toml"
    path.write_text(text)
    return path


FRAME_VARY = ["--vary", "radius=3mm,6mm", "--vary", "particle-material=100Cr6,tungsten",
              "--vary", "bed-mass=0.2kg:0.45kg:3"]


def _run(cli, *args) -> dict:
    code, out, err = cli("optimize", *args, "--json")
    assert code == 0, err
    return json.loads(out)


@pytest.fixture(scope="module")
def frame_limited(tmp_path_factory):
    """The machine frame's study within 0.5 kg, run once with ``--plot`` and ``--json``
    (two tests read it: its JSON and its figure)."""
    import contextlib
    import io

    from pdamper.cli import main

    tmp = tmp_path_factory.mktemp("frame")
    png = tmp / "front.png"
    buf = io.StringIO()
    with contextlib.redirect_stdout(buf):
        code = main(["optimize", "--scenario", str(_frame(tmp)), *FRAME_VARY, "--max-mass",
                     "0.5kg", "--plot", str(png), "--json"])
    assert code == 0
    return json.loads(buf.getvalue()), png


def test_machine_frame_best_and_lightest_respect_the_mass_of_bed_and_box(cli, tmp_path,
                                                                         frame_limited):
    sc = _frame(tmp_path)
    box = box_mass(FRAME_BOX, FRAME_WALL)
    free = _run(cli, "--scenario", sc, *FRAME_VARY)
    study = frame_limited[0]
    # without the limit the best is the heaviest bed, 450 g with a box of 87.5 g: too heavy
    assert free["best"]["mass"] + box > 0.5
    for key in ("best", "lightest_within"):
        c = study[key]
        assert c["container_mass"] == pytest.approx(box, rel=1e-9)
        assert c["total_mass"] == pytest.approx(c["mass"] + box, rel=1e-12)
        assert c["total_mass"] <= 0.5 and c["feasible"]
        (row,) = c["limits"]
        assert row["quantity"] == "mass" and row["margin"] == pytest.approx(
            0.5 - c["total_mass"], abs=1e-12) and row["met"]
    # the study spans radius, material and bed mass (three count-deriving bed masses)
    names = {v["name"] for v in study["variables"]}
    assert names == {"radius", "particle_material", "bed_mass"}
    heavy = [c for c in study["candidates"] if c["bed_mass"] == pytest.approx(0.45)]
    assert len(heavy) == 4
    for c in heavy:  # every 450 g bed breaks 0.5 kg with its box: infeasible, the reason
        assert not c["feasible"] and c["status"] == "ok"
        assert "mass" in c["reason"] and "above the limit 500 g" in c["reason"]
        assert c["limits"][0]["margin"] == pytest.approx(0.5 - c["mass"] - box)
    # the front holds only designs within the limit
    assert study["front"] and all(c["total_mass"] <= 0.5 for c in study["front"])
    assert study["limits"] == [{"quantity": "mass", "op": "<=", "value": 0.5, "unit": "kg",
                                "text": "mass<=500g"}]
    assert study["within_limits"] == 8
    # lightest within 5 % of the best: recomputed by hand from the feasible candidates
    ok = [c for c in study["candidates"] if c["feasible"]]
    best = min(ok, key=lambda c: c["objective"])
    assert study["best"]["objective"] == best["objective"]
    near = [c for c in ok if c["objective"] <= 1.05 * best["objective"]]
    assert study["lightest_within"]["total_mass"] == min(c["total_mass"] for c in near)


def test_the_front_figure_marks_the_designs_outside_the_limits(tmp_path, frame_limited):
    from matplotlib.figure import Figure

    from pdamper.design.study import make_objective, optimize_design
    from pdamper.io.scenario import load_scenario
    from pdamper.plots import plot_design_front

    sc = load_scenario(_frame(tmp_path))
    structure = sc.structure_model()
    obj = make_objective("peak-frf", 0.8, -0.01, structure, band=sc.optimization.frf_band(),
                         frf_load="10 N")
    res = optimize_design(structure, sc.damper(), -0.01, FRAME_VARY[1::2],
                          objective="peak-frf", band=obj.band, frf_load="10 N",
                          max_mass=0.5)
    ax = plot_design_front(res, ax=Figure().subplots())
    lines = {ln.get_label(): ln for ln in ax.get_lines()}
    outside = lines["outside the limits (infeasible)"]
    assert len(outside.get_xdata()) == 4  # the four 450 g beds
    assert min(outside.get_xdata()) > 500.0  # drawn at their mass [g], beyond the limit
    assert lines["limit: mass <= 500 g"].get_xdata()[0] == pytest.approx(500.0)
    front = lines["Pareto front"]
    assert max(front.get_xdata()) <= 500.0
    # the landscape also draws them as outside
    from pdamper.plots import plot_design_landscape

    ax2 = plot_design_landscape(res, ax=Figure().subplots())
    assert "outside the limits (infeasible)" in {ln.get_label() for ln in ax2.get_lines()}
    # the command draws both panels with --plot
    png = frame_limited[1]
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def _bracket(tmp_path: Path) -> Path:
    """The bracket on the shaker: the 1-DOF M = 0.8 kg at 45 Hz, 0.5 % (problem.md), moved
    at its base by 0.5 g over the band around its resonance, both sweep directions."""
    m, f, zeta = 0.8, 45.0, 0.005
    k = m * (2 * math.pi * f) ** 2
    d = 2 * zeta * math.sqrt(k * m)
    text = f"""
title = "bracket on a shaker"
[container]
length = "30 mm"
width = "30 mm"
depth = "30 mm"
material = "aluminium"
mass = "{box_mass(BRACKET_BOX, BRACKET_WALL)} kg"
[particles]
material = "100Cr6"
radius = "1.5 mm"
count = 50
[structure]
mass = "{m} kg"
stiffness = "{k} N/m"
damping = "{d} kg/s"
[optimization]
objective = "peak-frf"
frf_load = "0.5 g"
band = "40 Hz:48 Hz:17"
"""
    path = tmp_path / "bracket.toml"
    path.write_text(text)
    return path


def test_bracket_no_design_within_80_g_meets_10_g_and_the_study_says_by_how_much(
        cli, tmp_path):
    sc = _bracket(tmp_path)
    code, out, err = cli("optimize", "--scenario", sc, "--vary", "bed-mass=0kg:0.064kg:3",
                         "--max-mass", "80g", "--require", "peak-acceleration<=10g",
                         "--json")
    assert code == 0, err
    study = json.loads(out)
    bare = next(c for c in study["candidates"] if c["particles"] == 0)
    # the bare board: 0.5 g times the transmissibility sqrt(1 + (2 zeta r)^2) /
    # |1 - r^2 + 2i zeta r| at the band's frequencies (45 Hz on it: about 1 / (2 zeta))
    f = np.linspace(40, 48, 17)
    r = f / 45.0
    tr = np.abs((1 + 2j * 0.005 * r) / (1 - r**2 + 2j * 0.005 * r))
    assert bare["peak_acceleration"] == pytest.approx(0.5 * G0 * tr.max(), rel=5e-3)
    assert bare["peak_acceleration_up"] == pytest.approx(bare["peak_acceleration_down"],
                                                         rel=5e-3)
    # none within 80 g meets 10 g with the analytical model: no best, and by how much
    assert study["best"] is None and study["within_limits"] == 0
    assert study["lightest_feasible"] is None
    assert "no evaluated design meets the limits" in study["not_applicable"]["best"]
    near = study["closest"]
    assert near["bed_mass"] == pytest.approx(0.064) and near["total_mass"] <= 0.08
    (mass_row, acc_row) = near["limits"]
    assert mass_row["met"] and not acc_row["met"]
    # the miss is the peak over both sweep directions against 10 g
    worst = max(near["peak_acceleration_up"], near["peak_acceleration_down"])
    assert acc_row["value"] == worst
    assert acc_row["margin"] == pytest.approx(10 * G0 - worst)
    assert acc_row["margin"] < 0
    # the text says it
    code, text, _ = cli("optimize", "--scenario", sc, "--vary", "bed-mass=0kg:0.064kg:3",
                        "--max-mass", "80g", "--require", "peak-acceleration<=10g")
    assert "best: none: no evaluated design meets the limits" in text
    assert f"misses by {(worst - 10 * G0) / G0:.4g} g" in text


def test_bracket_lightest_design_within_a_reachable_limit_is_the_first_of_the_front(
        cli, tmp_path):
    sc = _bracket(tmp_path)
    study = _run(cli, "--scenario", sc, "--vary", "bed-mass=0kg:0.064kg:3", "--max-mass",
                 "80g", "--require", "peak-acceleration<=35g")
    ok = [c for c in study["candidates"] if c["status"] == "ok"]
    meets = [c for c in ok if c["peak_acceleration_up"] <= 35 * G0
             and c["peak_acceleration_down"] <= 35 * G0 and c["total_mass"] <= 0.08]
    assert meets and len(meets) < len(ok)  # the bare board is out
    light = study["lightest_feasible"]
    assert light["total_mass"] == min(c["total_mass"] for c in meets)
    assert all(r["met"] for r in light["limits"])


def test_a_limit_on_a_quantity_the_objective_does_not_compute_is_refused(cli, tmp_path):
    code, _, err = cli("optimize", "--vary", "particles=0:32:32", "--require",
                       "peak-acceleration<=10g")
    assert code == 2
    assert err.startswith("error: optimization.require: ") and "amplitude-at" in err
    assert len(err.splitlines()) == 1


@pytest.mark.parametrize("text, quantity, op, value", [
    ("peak<=3mm", "peak", "<=", 0.003),
    ("peak-acceleration <= 10 g", "peak-acceleration", "<=", 10 * G0),
    ("rms-acceleration<3m/s^2", "rms-acceleration", "<=", 3.0),
    ("mean-damping>=2%", "mean-damping", ">=", 0.02),
    ("mass<=80 g", "mass", "<=", 0.08),
])
def test_parse_limit(text, quantity, op, value):
    lim = parse_limit(text)
    assert (lim.quantity, lim.op) == (quantity, op)
    assert lim.value == pytest.approx(value, rel=1e-12)


@pytest.mark.parametrize("text", ["peak=3mm", "peak<=3kg", "speed<=3m/s", "peak<=-1mm",
                                  "mean-damping>=x", "peak<=3"])
def test_bad_limits_are_one_line_errors(text):
    with pytest.raises(InputError) as info:
        parse_limit(text)
    assert info.value.field == "optimization.require"


def test_max_mass_is_declared_once_and_checked(cli):
    from pdamper.io.scenario import load_scenario
    from pdamper.io.scenario_reference import declaration_of

    d = declaration_of("optimization.max_mass")
    assert d.unit == "kg" and d.allowed == "> 0"
    assert load_scenario(None, {"optimization.max_mass": "500 g"}).optimization.max_mass \
        == pytest.approx(0.5)
    code, _, err = cli("optimize", "--max-mass", "-1kg")
    assert code == 2 and err.startswith("error: optimization.max_mass: must be in (0, inf]")
    code, _, err = cli("optimize", "--help")
    assert "--max-mass" in err + _ or code == 0


def test_bed_mass_and_fill_derive_the_count_for_each_radius_and_material():
    steel, tungsten = get_material("100Cr6"), get_material("tungsten")
    for material in (steel, tungsten):
        for r in (0.003, 0.005):
            d = apply_design(PAPER_DAMPER, {"bed_mass": 0.2, "radius": r,
                                            "particle_material": material.name})
            sphere = material.density * 4 / 3 * math.pi * r**3
            assert d.count == round(0.2 / sphere)
            assert abs(d.bed_mass - 0.2) <= sphere / 2
    d = apply_design(PAPER_DAMPER, {"fill": 0.5, "radius": 0.004})
    assert d.count == round(0.5 * d.max_count) and d.particle_radius == 0.004
    assert parse_variable("bed-mass=0.1kg:0.4kg:4").values == pytest.approx(
        (0.1, 0.2, 0.3, 0.4))
    assert parse_variable("fill=0.2:0.9:4").values == pytest.approx((0.2, 13 / 30, 2 / 3,
                                                                     0.9))
    with pytest.raises(InputError, match="optimization.vary.fill"):
        parse_variable("fill=0.2:1.5:3")
    with pytest.raises(InputError, match="at most one of particles, bed-mass and fill"):
        apply_design(PAPER_DAMPER, {"particles": 32, "bed_mass": 0.1})


def test_limits_choose_among_feasible_designs_only():
    lim = make_limits([], 0.3)

    def cand(mass, obj, violations=()):
        return DesignCandidate({}, 1, mass, obj, container_mass=0.1,
                               violations=violations)

    a, b, c = cand(0.1, 1.0), cand(0.25, 0.5, ("mass ...",)), cand(0.15, 0.98)
    assert lim[0].quantity == "mass" and lim[0].value == 0.3
    # b is best by objective but outside its limits: never on the front, never lightest
    assert lightest_within([a, b, c], c, 0.05) is a
    assert lightest_within([b], b, 0.05) is b  # (the best itself when none within)


def test_the_optimiser_finds_the_heaviest_bed_within_the_mass_limit():
    """A synthetic objective that rewards mass (minus the bed's mass): unlimited, the best
    is the heaviest bed; under max_mass the differential evolution must stay below the limit
    and get close to it."""
    from pdamper.design.study import make_objective, run_design_study
    from pdamper.parameters import PAPER_STRUCTURE

    damper = PAPER_DAMPER  # no container mass: the limit bounds the bed alone here

    def evaluate(design):
        return -apply_design(damper, design).bed_mass, {}

    obj = make_objective("amplitude-at", 0.8, -0.058, PAPER_STRUCTURE)
    var = [parse_variable("bed-mass=0.05kg:0.4kg")]
    free = run_design_study(evaluate, damper, var, obj, method="optimize",
                            max_evaluations=120, seed=1)
    limited = run_design_study(evaluate, damper, var, obj, method="optimize",
                               max_evaluations=120, seed=1, max_mass=0.2)
    assert free.best.mass > 0.35
    assert limited.best.total_mass <= 0.2
    assert limited.best.total_mass > 0.18  # the search moved up to the limit
    assert all(c.total_mass <= 0.2 for c in limited.front)
    assert any(not c.feasible for c in limited.candidates)  # it tried beyond and marked it


def test_a_scenario_refuses_a_limit_its_objective_does_not_compute():
    from pdamper.io.scenario import load_scenario

    with pytest.raises(InputError) as info:
        load_scenario(None, {"optimization.require": ["rms-acceleration<=1g"],
                             "optimization.objective": "peak-frf"})
    assert info.value.field == "optimization.require"
    assert "peak, rms" in info.value.message
    sc = load_scenario(None, {"optimization.require": ["peak<=3mm"],
                              "optimization.objective": "peak-frf"})
    assert sc.optimization.require == ["peak<=3mm"]
