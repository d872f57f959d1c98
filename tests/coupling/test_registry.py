"""The coupling table (pdamper.coupling.registry): one strategy per coupling, every dispatch
through it, the tables of earlier versions as its views, a new coupling as one class."""

import ast
from pathlib import Path

import pytest

import pdamper
from pdamper.coupling import COUPLINGS, MODAL_COUPLINGS, Release, Simulation
from pdamper.coupling.frf import HARMONIC_BALANCE, STEPPED_SINES, HarmonicLoad, frequency_response
from pdamper.coupling.loads import (
    LOAD_COSTS,
    LOAD_COUPLINGS,
    LOAD_STRUCTURES,
    LoadHistory,
    check_model,
    run_load,
)
from pdamper.coupling.registry import (
    LOAD_HISTORY,
    MODES,
    RELEASE,
    SINGLE_DOF,
    Coupling,
    coupling_of,
    register,
)
from pdamper.errors import InputError
from pdamper.models import DAMPER_MODELS, AnalyticalDamper
from pdamper.parameters import PAPER_DAMPER, PAPER_STRUCTURE
from pdamper.structure.modal import ModalStructure


def test_every_model_names_a_coupling_of_the_table():
    for name, cls in DAMPER_MODELS.items():
        assert cls.coupling in COUPLINGS, name
        assert COUPLINGS[cls.coupling].runs(RELEASE), name


def test_the_earlier_tables_are_views_of_the_table():
    """What each of the per-experiment tables held before the one table (their keys as
    they were written out), now read from the strategies' declarations."""
    assert set(COUPLINGS) == {"pseudo_force", "co_simulation", "plastic_bed"}
    assert set(MODAL_COUPLINGS) == {"pseudo_force", "co_simulation", "plastic_bed"}
    assert set(LOAD_COUPLINGS) == {"pseudo_force", "co_simulation", "plastic_bed"}
    assert set(LOAD_COSTS) == {"co_simulation"}
    assert set(LOAD_STRUCTURES) == {"co_simulation"}
    two = ModalStructure([5.0, 40.0], [0.01, 0.01], [0.8, 0.5])
    LOAD_STRUCTURES["co_simulation"](PAPER_STRUCTURE)  # ``f(structure)``, as before
    LOAD_STRUCTURES["co_simulation"](two)  # the DEM runs on N modes
    with pytest.raises(InputError) as e:
        LOAD_STRUCTURES["co_simulation"]("a beam")
    assert e.value.field == "structure"
    assert set(STEPPED_SINES) == {"pseudo_force", "co_simulation", "plastic_bed"}
    assert list(HARMONIC_BALANCE) == ["pseudo_force"]
    assert "pseudo_force" in HARMONIC_BALANCE and "co_simulation" not in HARMONIC_BALANCE


def test_the_entries_are_called_as_before():
    """``COUPLINGS[name](model, structure, duration, x0, sample_rate)`` is the release."""
    m = AnalyticalDamper(PAPER_DAMPER)
    a = COUPLINGS["pseudo_force"](m, PAPER_STRUCTURE, 0.5, -0.058, 2000.0)
    b = Simulation(PAPER_STRUCTURE, m, Release(-0.058, 0.5)).solve()
    assert (a.displacement == b.displacement).all()


class _Echo(Coupling):
    """A coupling of one class: a release on one DOF and load histories on any structure."""

    name = "echo_test"
    answers = {RELEASE: (SINGLE_DOF,), LOAD_HISTORY: (SINGLE_DOF, MODES)}

    def free_vibration(self, model, structure, duration, x0, sample_rate=2000.0):
        return ("release", duration, x0, sample_rate)

    def load(self, model, structure, load, sample_rate=2000.0, tail=0.0):
        return ("load", load.duration, sample_rate, tail)


class _EchoDamper(AnalyticalDamper):
    coupling = "echo_test"


@pytest.fixture
def echo():
    register(_Echo)
    yield _EchoDamper(PAPER_DAMPER)
    del COUPLINGS["echo_test"]


def test_a_new_coupling_is_one_class(echo):
    """Registered, every dispatch finds it and its declarations; nothing else changes."""
    assert Simulation(PAPER_STRUCTURE, echo, -0.058).run(1.5) == ("release", 1.5, -0.058,
                                                                  2000.0)
    h = LoadHistory([0.0, 1.0], [0.0, 1.0])
    assert run_load(echo, PAPER_STRUCTURE, h, 500.0, 0.2) == ("load", 1.0, 500.0, 0.2)
    assert "echo_test" in LOAD_COUPLINGS and "echo_test" not in LOAD_COSTS
    assert "echo_test" not in MODAL_COUPLINGS and "echo_test" not in STEPPED_SINES
    two = ModalStructure([5.0, 40.0], [0.01, 0.01], [0.8, 0.5])
    check_model(echo, two)  # load histories on N modes
    with pytest.raises(InputError, match="needs a single-DOF structure") as e:
        Simulation(two, echo, -0.058)  # the release on one DOF only
    assert e.value.field == "structure"
    with pytest.raises(InputError, match="has no stepped sine") as e:
        frequency_response(echo, PAPER_STRUCTURE, HarmonicLoad("force", 1.0), [5.0])
    assert e.value.field == "model"
    del COUPLINGS["echo_test"]
    with pytest.raises(InputError, match="is not one of") as e:
        Simulation(PAPER_STRUCTURE, echo, -0.058)
    assert e.value.field == "model"
    register(_Echo)  # for the fixture's clean-up


def test_a_coupling_without_a_name_is_refused():
    with pytest.raises(ValueError, match="no coupling name"):
        register(type("Nameless", (Coupling,), {}))
    with pytest.raises(InputError, match="is not one of"):
        coupling_of(object())


#: The modules of the table itself, where the coupling's name is the key.
_TABLE = {"coupling/registry.py", "coupling/strategies.py"}


def name_branches(source: str) -> list[int]:
    """Lines of ``source`` that branch on a coupling's name: ``x.coupling`` compared with a
    text or used as a key (``T[x.coupling]``), rather than the table asked."""
    lines = []
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.Compare):
            sides = [node.left, *node.comparators]
            if any(isinstance(s, ast.Attribute) and s.attr == "coupling" for s in sides) and \
                    any(isinstance(s, ast.Constant) and isinstance(s.value, str) or
                        isinstance(s, ast.Tuple | ast.List | ast.Set | ast.Dict)
                        for s in sides):
                lines.append(node.lineno)
        elif isinstance(node, ast.Subscript) and isinstance(node.slice, ast.Attribute) \
                and node.slice.attr == "coupling":
            lines.append(node.lineno)
    return lines


def test_nothing_outside_the_table_branches_on_a_coupling_name():
    root = Path(pdamper.__file__).parent
    bad = [f"{p.relative_to(root)}:{n}" for p in sorted(root.rglob("*.py"))
           if p.relative_to(root).as_posix() not in _TABLE
           for n in name_branches(p.read_text())]
    assert not bad, bad


def test_the_branch_finder_finds_branches():
    assert name_branches('if cls.coupling != "co_simulation":\n    pass\n') == [1]
    assert name_branches('f = TABLE[model.coupling]\n') == [1]
    assert name_branches('ok = m.coupling in ("a", "b")\n') == [1]
    assert not name_branches('s = coupling_of(model)\n')


def test_the_table_is_filled_whichever_module_is_imported_first():
    """The strategies register when the package is imported, so a module imported on its
    own (its package's ``__init__`` runs first) dispatches through a full table."""
    import subprocess
    import sys

    code = ("from pdamper.coupling.frf import STEPPED_SINES; "
            "from pdamper.coupling.loads import LOAD_COUPLINGS; "
            "print(sorted(STEPPED_SINES), sorted(LOAD_COUPLINGS))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True).stdout.strip()
    assert out == ("['co_simulation', 'plastic_bed', 'pseudo_force'] "
                   "['co_simulation', 'plastic_bed', 'pseudo_force']")
