"""Design studies over several variables (extends paper Sect. 4.2.2): specifications, the
whole landscape with infeasible designs, the known optimum of a synthetic objective by
brute force and by scipy, parallel evaluation on dask."""

from __future__ import annotations

import json
import math

import pytest

from pdamper.design import (
    DesignVariable,
    evaluate_parallel,
    make_objective,
    optimize_design,
    parse_variable,
    run_design_study,
)
from pdamper.design.study import settling_time
from pdamper.errors import InputError
from pdamper.parameters import PAPER_DAMPER, PAPER_STRUCTURE


def test_variable_specifications():
    assert parse_variable("particles=16:176:16").values == tuple(range(16, 177, 16))
    assert parse_variable("particles=0,32,64").values == (0, 32, 64)
    r = parse_variable("radius=3mm:6mm:4")
    assert r.values == pytest.approx((0.003, 0.004, 0.005, 0.006)) and r.bounds == (0.003, 0.006)
    assert parse_variable("container-length=100mm:140mm:3").name == "container_length"
    assert parse_variable("particle-material=S235,PVC").values == ("S235", "PVC")
    assert parse_variable("radius=3mm:6mm").values is None


@pytest.mark.parametrize(("spec", "pattern"), [
    ("particles=16:96:6", "not a multiple of the step 6"),
    ("particles=16:8:8", "start:stop:step"),
    ("colour=red", "unknown design variable 'colour'"),
    ("particle-material=S235,unobtainium", "unknown material 'unobtainium'"),
    ("radius=-3mm:6mm:4", "radius"),
    ("radius=3 blorps", "unknown unit"),
    ("radius", "expected 'name=values'"),
    ("particle-material=,", "empty material name"),          # a list of no material
    ("particle-material=S235,,PVC", "empty material name"),
    ("particle-material=S235,", "empty material name"),
])
def test_bad_specifications(spec, pattern):
    with pytest.raises(InputError, match=pattern):
        parse_variable(spec)


def _synthetic(design):
    """A bowl with its minimum at 80 spheres of 4.5 mm radius (objective 0)."""
    return ((design["particles"] - 80) / 16) ** 2 + ((design["radius"] - 0.0045) / 0.001) ** 2, {}


OBJ = make_objective("amplitude-at", 0.8, -0.058, PAPER_STRUCTURE)


def test_grid_over_two_variables_returns_every_candidate_and_the_known_optimum():
    """Brute force over 11 counts x 7 radii = 77 designs: all in the landscape, in grid
    order, with every design variable; the infeasible ones (more spheres than fit with
    r = 5.5 or 6 mm) reported, not dropped; the best is the bowl's minimum."""
    v = [parse_variable("particles=16:176:16"), parse_variable("radius=3mm:6mm:7")]
    res = run_design_study(_synthetic, PAPER_DAMPER, v, OBJ)
    assert res.method == "grid" and len(res.candidates) == 77
    assert [(c.particles, c.design["radius"]) for c in res.candidates] == [
        (n, r) for n in v[0].values for r in v[1].values]
    infeasible = [c for c in res.candidates if c.status == "infeasible"]
    assert infeasible and all(c.objective is None and "particles.count" in c.reason
                              for c in infeasible)
    assert {round(c.design["radius"], 4) for c in infeasible} <= {0.0055, 0.006}
    assert res.best.particles == 80 and res.best.design["radius"] == pytest.approx(0.0045)
    d = res.as_dict()
    assert {"particles", "mass", "objective", "radius", "container_length",
            "particle_material", "feasible", "status"} <= set(d["candidates"][0])
    assert d["infeasible"] == len(infeasible) and d["evaluations"] == 77


def test_optimiser_on_a_continuous_variable_finds_the_known_optimum():
    """scipy's differential evolution over the count (integer lattice) and a continuous
    radius interval: the optimum (80, 4.5 mm) within the resolution, every evaluation in
    the landscape, reproducible with its seed."""
    v = [parse_variable("particles=16:176:16"), parse_variable("radius=3mm:6mm")]
    res = run_design_study(_synthetic, PAPER_DAMPER, v, OBJ, max_evaluations=400, seed=3)
    assert res.method == "optimize" and res.seed == 3
    assert res.best.particles == 80
    assert res.best.design["radius"] == pytest.approx(0.0045, abs=1e-4)
    assert len(res.candidates) > 50
    again = run_design_study(_synthetic, PAPER_DAMPER, v, OBJ, max_evaluations=400, seed=3)
    assert [c.design for c in again.candidates] == [c.design for c in res.candidates]


def test_auto_switches_to_the_optimiser_for_large_grids():
    v = [parse_variable("particles=0:176:16"), parse_variable("radius=3mm:6mm:50")]
    res = run_design_study(_synthetic, PAPER_DAMPER, v, OBJ, max_grid=100,
                           max_evaluations=120)
    assert res.method == "optimize"
    with pytest.raises(InputError, match="is an interval"):
        run_design_study(_synthetic, PAPER_DAMPER, [parse_variable("radius=3mm:6mm")], OBJ,
                         method="grid")


def test_failed_evaluations_are_recorded():
    def flaky(design):
        if design["particles"] == 48:
            raise RuntimeError("solver blew up")
        return float(design["particles"]), {}

    res = run_design_study(flaky, PAPER_DAMPER, [parse_variable("particles=16:64:16")], OBJ)
    bad = [c for c in res.candidates if c.status == "failed"]
    assert len(bad) == 1 and bad[0].reason == "RuntimeError: solver blew up"
    assert res.best.particles == 16


def _square(design):
    x = design["x"]
    if x == 3:
        raise ValueError("three is bad")
    return x * x


def test_evaluate_parallel_on_dask_keeps_order_and_captures_errors():
    """Two dask worker processes (the sweep engine of the maps): the outcomes come back in
    order, the failing point as an error, the others as values; the same as in-process."""
    pytest.importorskip("dask.distributed")
    items = [{"x": k} for k in range(6)]
    par = evaluate_parallel(_square, items, workers=2)
    ser = evaluate_parallel(_square, items)
    assert [o.value for o in par] == [o.value for o in ser] == [0, 1, 4, None, 16, 25]
    assert par[3].error == ser[3].error == "ValueError: three is bad"
    with pytest.raises(InputError, match="optimization.workers"):
        evaluate_parallel(_square, items, workers=-1)


def test_real_study_on_dask_equals_in_process():
    """The paper's structure and model 3 over two variables, once on two dask workers."""
    pytest.importorskip("dask.distributed")
    specs = ["particles=32:64:32", "radius=4mm:5mm:2"]
    a = optimize_design(PAPER_STRUCTURE, PAPER_DAMPER, -0.058, specs, workers=2)
    b = optimize_design(PAPER_STRUCTURE, PAPER_DAMPER, -0.058, specs)
    assert [c.objective for c in a.candidates] == [c.objective for c in b.candidates]
    assert len(a.candidates) == 4


def test_objectives_on_the_paper_case():
    """amplitude-at equals the paper study's objective; settling-time and mean-damping rank
    more spheres (up to 64) as better, as the amplitude does (Sect. 4.2.2)."""
    from pdamper.design import optimize_particle_count

    counts = "particles=0:64:32"
    amp = optimize_design(PAPER_STRUCTURE, PAPER_DAMPER, -0.058, [counts])
    ref = optimize_particle_count(PAPER_STRUCTURE, PAPER_DAMPER, -0.058, 0.8,
                                  counts=[0, 32, 64])
    assert [c.objective for c in amp.candidates] == [c.objective for c in ref.candidates]
    settle = optimize_design(PAPER_STRUCTURE, PAPER_DAMPER, -0.058, [counts],
                             objective="settling-time")
    t = [c.objective for c in settle.candidates]
    assert t[0] == pytest.approx(2.0) and settle.candidates[0].extra == {"settled": False}
    assert t[2] < t[1] < t[0] and settle.best.particles == 64
    assert settle.objective.threshold == pytest.approx(0.0145)
    damp = optimize_design(PAPER_STRUCTURE, PAPER_DAMPER, -0.058, [counts],
                           objective="mean-damping")
    z = [c.objective for c in damp.candidates]
    assert damp.objective.sense == "max" and damp.best.particles == 64
    assert z[0] == pytest.approx(PAPER_STRUCTURE.damping_ratio, rel=1e-6) and z[1] > 5 * z[0]


def test_settling_time_interpolates_the_envelope():
    """The exponential envelope through (0, 40 mm) and (1 s, 10 mm) reaches 20 mm at 0.5 s."""
    assert settling_time([0.0, 1.0], [0.04, 0.01], 0.02) == pytest.approx(0.5)
    assert settling_time([0.0, 1.0], [0.04, 0.03], 0.02) is None
    assert math.isclose(settling_time([0.0, 1.0], [0.01, 0.005], 0.02), 0.0)


def test_optimize_cli_default_is_the_papers_study_and_vary_adds_variables(cli, tmp_path):
    code, out, err = cli("optimize", "--json")
    assert code == 0, err
    d = json.loads(out)
    assert [c["particles"] for c in d["candidates"]] == list(range(0, 192, 16))
    assert {"particles", "mass", "objective"} <= set(d["best"])
    assert d["method"] == "grid" and d["objective_name"] == "amplitude-at"
    png = tmp_path / "land.png"
    code, out, err = cli("optimize", "--vary", "particles=96:176:80", "--vary",
                         "radius=5mm:6mm:2", "--objective", "amplitude-at", "--at", "0.8s",
                         "--plot", png, "--json")
    assert code == 0, err
    d = json.loads(out)
    assert len(d["candidates"]) == 4
    c = {(c["particles"], round(c["radius"], 4)): c for c in d["candidates"]}
    assert c[(176, 0.006)]["feasible"] is False and c[(176, 0.006)]["objective"] is None
    assert c[(96, 0.005)]["feasible"] is True
    assert png.read_bytes()[:4] == b"\x89PNG"
    code, _, err = cli("optimize", "--vary", "particles=16:96:6")
    assert code == 2 and err.startswith("error: optimization.vary") and err.count("\n") == 1


def test_scenario_optimization_keys(tmp_path):
    from pdamper.io.scenario import load_scenario

    p = tmp_path / "s.toml"
    p.write_text('[optimization]\nvary = ["particles=16:64:16", "radius=4mm:5mm:2"]\n'
                 'objective = "settling-time"\nthreshold = "12 mm"\nworkers = 0\n')
    sc = load_scenario(p)
    assert [v.name for v in sc.optimization.variables()] == ["particles", "radius"]
    assert sc.optimization.threshold == pytest.approx(0.012)
    p.write_text('[optimization]\nvary = ["radius=4mm:5mm:0"]\n')
    with pytest.raises(InputError, match="optimization.vary"):
        load_scenario(p)
    p.write_text('[optimization]\nobjective = "fastest"\n')
    with pytest.raises(InputError, match="optimization.objective"):
        load_scenario(p)
    assert isinstance(DesignVariable("particles", (1,)).size, int)


def test_particle_material_is_a_design_variable():
    """Materials by name (pdamper.materials): PVC spheres weigh 1400/7900 of steel ones, so
    the same 32 spheres damp less (Sect. 3.2: dissipation linear in the bed mass)."""
    res = optimize_design(PAPER_STRUCTURE, PAPER_DAMPER, -0.058, ["particle-material=S235,PVC"])
    steel, pvc = res.candidates
    assert (steel.design["particle_material"], pvc.design["particle_material"]) == ("S235",
                                                                                    "PVC")
    assert pvc.mass == pytest.approx(steel.mass * 1400 / 7900)
    assert res.best is steel and pvc.objective > 1.2 * steel.objective


def test_a_variable_without_values_is_refused():
    """A study over an empty list would evaluate nothing and end with no best design."""
    for values, bounds in (((), None), (None, None)):
        with pytest.raises(InputError, match="^optimization.vary: 'particles': no values"):
            DesignVariable("particles", values, bounds)


# -- counts judged before they are built; ranges judged by the physics limits up front
def test_a_variables_count_is_judged_before_its_values_are_built():
    """``particles=0:1000000000:1`` used to build a tuple of 10^9 counts (out of memory);
    ``radius=1mm:3mm:100000000`` hung."""
    from answers import memory_headroom
    from pdamper.design.study import variable_size
    from pdamper.io.scenario import load_scenario
    from pdamper.runs.resources import check_runs

    with memory_headroom(2**30):
        assert variable_size("particles=0:1000000000:1") == ("particles", 1000000001)
        assert variable_size("radius=1mm:3mm:100000000") == ("radius", 100000000)
        with pytest.raises(InputError) as info:  # the API: what no machine holds
            parse_variable("particles=0:1000000000:1")
        assert info.value.field == "optimization.vary.particles"
        with pytest.raises(InputError) as info:
            optimize_design(PAPER_STRUCTURE, PAPER_DAMPER, -0.058, ["particles=0:1000000000:1"])
        assert info.value.field == "optimization.vary.particles"
        # the scenario: read by any command without building, judged for the study
        spec = {"optimization.vary": ["radius=1mm:3mm:100000000"]}
        load_scenario(None, spec)
        with pytest.raises(InputError) as info:
            check_runs(load_scenario(None, spec), ("optimization",))
        assert info.value.field == "optimization.vary.radius" and "--force" in info.value.message
        check_runs(load_scenario(None, spec), ("optimization",), force=True)  # judged, not built


def test_a_range_outside_the_physical_limits_is_refused_before_any_run():
    """``radius=1nm:3mm:4`` used to evaluate a 1 nm sphere as a feasible design."""
    from pdamper.models import AnalyticalDamper

    runs = []

    class Counted(AnalyticalDamper):
        def response(self, frequency, amplitude):
            runs.append(self.damper.particle_radius)
            return super().response(frequency, amplitude)

    with pytest.raises(InputError) as info:
        optimize_design(PAPER_STRUCTURE, PAPER_DAMPER, -0.058, ["radius=1nm:3mm:4"],
                        model=Counted)
    assert info.value.field == "optimization.vary.radius"
    assert "0.1 mm" in info.value.message and "\n" not in str(info.value)
    assert runs == []  # no design ran


def test_a_candidate_outside_the_physical_limits_is_infeasible_with_the_reason():
    """A combination of in-range values outside the limits (found by the optimiser, say)
    stays in the landscape, infeasible, with the reason; it is never evaluated."""
    evaluated = []

    class Evaluate:
        def __call__(self, design):
            evaluated.append(design)
            return float(design["particles"]), {}

        def check(self, design):
            if design.get("particles") == 32 and design.get("radius", 0.005) < 0.005:
                raise InputError("structure.initial_displacement", "too fast together")

    obj = make_objective("amplitude-at", 0.8, -0.058, PAPER_STRUCTURE)
    res = run_design_study(Evaluate(), PAPER_DAMPER, [parse_variable("particles=16,32"),
                                                      parse_variable("radius=4mm,5mm")], obj)
    bad = [c for c in res.candidates if c.status == "infeasible"]
    assert [(c.design["particles"], c.design["radius"]) for c in bad] == [(32, 0.004)]
    assert "too fast together" in bad[0].reason
    assert {"particles": 32, "radius": 0.004} not in evaluated and len(evaluated) == 3
