"""Every object a run needs pickles, and comes back the same.

Runs cross processes on the sweep engine (dask workers, ``pdamper map --model dem``) and the
settled-bed cache is keyed by the pickle of the particles, container and contact law
(:attr:`pdamper.dem.DEMEngine.settle_key`). So every restitution model, material, damper
(every fidelity of the registry) and settings object must pickle with the standard library's
pickle, unpickle equal and behave the same, and pickle to the same bytes whether or not it
has been evaluated (else the cache key of a curve would change with its first use).

The restitution models and fidelities are enumerated from the code (subclasses, registry):
a new one without a case here fails :func:`test_every_restitution_model_has_a_case` or
:func:`test_every_fidelity_has_a_case`.
"""

from __future__ import annotations

import pickle

import numpy as np
import pytest

from pdamper.contact.fit import fit_restitution
from pdamper.contact.restitution import (
    ConstantRestitution,
    ExponentialRestitution,
    LinearRestitution,
    MeasuredRestitution,
    ParametricRestitution,
    RestitutionCurve,
    ScaledRestitution,
    SmoothRestitution,
    TabulatedRestitution,
)
from pdamper.contact.thornton import ThorntonRestitution
from pdamper.materials import LIBRARY, MATERIALS, PVC, S235
from pdamper.models import DAMPER_MODELS
from pdamper.parameters import PAPER_DAMPER
from pdamper.parameters import vertical_dampers_paper as paper

V = np.array([0.0, 0.003, 0.05, 0.2, 0.7, 1.0, 1.8, 2.5, 19.0, 40.0])

MEASURED = MeasuredRestitution((0.2, 0.6, 1.8), (0.89, 0.86, 0.80), std=(0.01, 0.01, 0.02),
                               source="cor.csv")

#: One or more instances of every concrete curve class.
CURVES: dict[type, list[RestitutionCurve]] = {
    ConstantRestitution: [ConstantRestitution(0.6)],
    TabulatedRestitution: [TabulatedRestitution((0.0, 1.0, 2.0), (0.9, 0.7, 0.6))],
    MeasuredRestitution: [MEASURED, MeasuredRestitution((0.5,), (0.7,))],
    ExponentialRestitution: [paper.PAPER_COR_PP,
                             fit_restitution((0.1, 0.3, 0.6, 1.0, 1.5), (0.9, 0.75, 0.6, 0.52, 0.5),
                                             model="exponential").curve],
    LinearRestitution: [paper.PAPER_COR_PW, LinearRestitution(0.9, 0.0)],
    ThorntonRestitution: [ThorntonRestitution.from_materials(S235, PVC, 0.005),
                          ThorntonRestitution(0.05, name="a label")],
    ScaledRestitution: [MEASURED.scaled(1.2), paper.PAPER_COR_PP.scaled(0.5)],
}


#: The base classes of curves (no instances).
ABSTRACT = {SmoothRestitution, ParametricRestitution}


def _concrete_curve_classes() -> set[type]:
    found, todo = set(), [RestitutionCurve]
    while todo:
        for sub in todo.pop().__subclasses__():
            todo.append(sub)
            found.add(sub)
    return found - ABSTRACT


def roundtrip(obj):
    """``obj`` through pickle."""
    back = pickle.loads(pickle.dumps(obj, protocol=pickle.HIGHEST_PROTOCOL))
    assert type(back) is type(obj)
    return back


def test_every_restitution_model_has_a_case():
    import pdamper.contact.thornton  # noqa: F401 - registers its subclass

    missing = {c.__name__ for c in _concrete_curve_classes()} - {c.__name__ for c in CURVES}
    assert not missing, f"add pickling cases for {sorted(missing)}"


@pytest.mark.parametrize("curve", [c for cs in CURVES.values() for c in cs],
                         ids=lambda c: type(c).__name__)
def test_restitution_model_pickles(curve):
    fresh = pickle.dumps(curve)
    expected = curve(V)  # evaluating fills the curve's caches ...
    nodes = curve.tabulate()
    assert pickle.dumps(curve) == fresh  # ... which its pickle leaves out
    back = roundtrip(curve)
    assert back == curve
    np.testing.assert_array_equal(back(V), expected)
    for a, b in zip(back.tabulate(), nodes, strict=True):
        np.testing.assert_array_equal(a, b)
    assert back.describe() == curve.describe()


@pytest.mark.parametrize("name", sorted(MATERIALS))
def test_material_pickles(name):
    m = MATERIALS[name]
    assert roundtrip(m) == m
    entry = next(e for e in LIBRARY if e.material == m)
    assert roundtrip(entry) == entry


def _fields_map():
    from pdamper.analysis.fields import effective_field
    from pdamper.models import AnalyticalDamper

    return effective_field(AnalyticalDamper(PAPER_DAMPER), np.linspace(4.0, 8.0, 5),
                           np.linspace(0.005, 0.06, 6))


#: A damper with a measured table (the curve kind that did not pickle) and a model of each
#: fidelity; (model, frequency [Hz], amplitude [m]) at which its response is compared.
DAMPER = PAPER_DAMPER.with_count(4).with_restitution(paper.PAPER_COR_PP, MEASURED)
FIDELITIES = {
    "analytic": lambda: (DAMPER_MODELS["analytic"](DAMPER), 10.0, 0.032),
    "fields": lambda: (DAMPER_MODELS["fields"](PAPER_DAMPER, field=_fields_map()), 6.0, 0.03),
    "dem": lambda: (DAMPER_MODELS["dem"](DAMPER, integrator="verlet", cycles=2, skip_cycles=1,
                                         sample_rate=2000.0), 10.0, 0.01),
    "plastic": lambda: (DAMPER_MODELS["plastic"](DAMPER), 10.0, 0.032),
}


def test_every_fidelity_has_a_case():
    assert set(FIDELITIES) == set(DAMPER_MODELS)


def test_physical_damper_pickles():
    for d in (PAPER_DAMPER, paper.PAPER_DAMPER_CURVES, DAMPER):
        assert roundtrip(d) == d


@pytest.mark.parametrize("fidelity", sorted(FIDELITIES))
def test_damper_model_pickles_and_answers_the_same(fidelity):
    model, f, x = FIDELITIES[fidelity]()
    back = roundtrip(model)
    assert back.damper == model.damper
    a, b = model.response(f, x), back.response(f, x)
    assert np.isfinite(a.loss_factor).all()
    np.testing.assert_array_equal(b.loss_factor, a.loss_factor)
    np.testing.assert_array_equal(b.effective_mass_ratio, a.effective_mass_ratio)
    # and after a run (caches filled) it still pickles, to what it pickled before
    roundtrip(model)


def test_dem_settings_pickle_and_keep_the_settle_key():
    from dem_inputs import contact, container, lattice
    from pdamper.dem import DEMEngine, EngineSettings, HarmonicMotion, StructureMotion

    cp = contact(paper.PAPER_COR_PP, MEASURED, pairs={("S235", "PVC"): MEASURED.scaled(0.9)})
    assert roundtrip(cp) == cp
    box = container()
    assert roundtrip(box) == box
    ps = lattice(4)
    back = roundtrip(ps)
    np.testing.assert_array_equal(back.positions, ps.positions)
    for motion in (HarmonicMotion(0.01, 10.0), StructureMotion(1.5, 0.5, 1848.0, x0=-0.058)):
        assert roundtrip(motion) == motion
    engine = DEMEngine(ps, box, cp, HarmonicMotion(0.01, 10.0), EngineSettings(integrator="verlet"))
    key = engine.settle_key
    assert roundtrip(engine).settle_key == key
    assert engine.settle_key == key  # the key does not change with the curves' first use


def test_analysis_and_design_settings_pickle():
    from pdamper.analysis.stationarity import SteadyStateCriterion
    from pdamper.design.study import make_objective, parse_variable
    from pdamper.structure import SingleDOFStructure
    from pdamper.structure.beam import TimoshenkoBeam
    from pdamper.structure.modal import ModalStructure

    crit = SteadyStateCriterion()
    assert roundtrip(crit) == crit
    s = SingleDOFStructure(1.514, 0.55, 1848.0)
    assert roundtrip(s) == s
    m = ModalStructure.from_single_dof(s)
    assert roundtrip(m).equivalent_single_dof() == m.equivalent_single_dof()
    b = TimoshenkoBeam(length=0.68, width=0.08, height=0.006, youngs_modulus=200e9, elements=4)
    assert roundtrip(b) == b
    for spec in ("particles=16:64:16", "radius=2mm:5mm:4", "particle-material=S235,PVC"):
        v = parse_variable(spec)
        assert roundtrip(v) == v
    obj = make_objective("amplitude-at", 0.8, -0.058, s)
    assert roundtrip(obj) == obj


def test_cor_study_settings_pickle(tmp_path, monkeypatch):
    """A COR sensitivity variant with a table, and a fit with its covariance."""
    from pdamper.runs.cor_sensitivity import cor_variant

    (tmp_path / "cor.csv").write_text("velocity [m/s], cor [-]\n0.2, 0.89\n0.6, 0.86\n"
                                      "1.8, 0.80\n")
    monkeypatch.chdir(tmp_path)
    v = cor_variant("paper/cor.csv*1.2", PAPER_DAMPER)
    v.restitution_pw(V)  # evaluated: its interpolant cached
    assert roundtrip(v) == v
    fit = fit_restitution((0.1, 0.3, 0.6, 1.0, 1.5), (0.9, 0.75, 0.6, 0.52, 0.5),
                          std=(0.01,) * 5, model="exponential")
    back = roundtrip(fit)
    np.testing.assert_array_equal(back.curve(V), fit.curve(V))
    np.testing.assert_array_equal(back.covariance, fit.covariance)


def test_scenario_with_a_cor_table_pickles(tmp_path):
    from pdamper.io.scenario import load_scenario

    (tmp_path / "cor.csv").write_text("velocity [m/s], cor [-]\n0.2, 0.89\n0.6, 0.86\n"
                                      "1.8, 0.80\n")
    (tmp_path / "s.toml").write_text('[restitution]\nparticle_wall = { model = "table", '
                                     'file = "cor.csv" }\n')
    sc = load_scenario(tmp_path / "s.toml")
    back = roundtrip(sc)
    assert back == sc
    assert back.damper() == sc.damper()
    for name in DAMPER_MODELS:
        section = getattr(sc, name, None)
        if section is not None:
            assert roundtrip(section) == section


def test_design_evaluator_of_a_scenario_pickles_and_answers_the_same(tmp_path):
    """What ``pdamper optimize`` sends to its workers: the evaluator of a scenario with a COR
    table, its model built by the scenario (a bound method, no closure)."""
    import functools

    from pdamper.design.study import DesignEvaluator, make_objective
    from pdamper.io.scenario import load_scenario

    (tmp_path / "cor.csv").write_text("velocity [m/s], cor [-]\n0.2, 0.89\n1.8, 0.80\n")
    (tmp_path / "s.toml").write_text('[restitution]\nparticle_wall = { model = "table", '
                                     'file = "cor.csv" }\n')
    sc = load_scenario(tmp_path / "s.toml")
    obj = make_objective("amplitude-at", 0.8, -0.058, sc.structure_model())
    ev = DesignEvaluator(sc.structure_model(), sc.damper(), -0.058, obj,
                         functools.partial(sc.model, None))
    back = roundtrip(ev)
    design = {"particles": 48}
    assert back(design) == ev(design)
