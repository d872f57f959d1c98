"""The user's structure from the scenario and the command line: ``[structure] modes`` (a
CSV of modes, :mod:`pdamper.io.modes`) and ``[structure] beam`` (the Timoshenko beam)."""

from __future__ import annotations

import json

import numpy as np
import pytest

from pdamper.errors import InputError
from pdamper.io.modes import read_modes
from pdamper.io.scenario import load_scenario
from pdamper.parameters import PAPER_STRUCTURE

HEADER = "frequency [Hz], damping ratio [1], damper [kg^-0.5]"


def _paper_mode_csv(path):
    """The paper's 1-DOF (Eq. 23) as one mass-normalised mode, written to full precision."""
    s = PAPER_STRUCTURE
    path.write_text(f"# the paper's 1-DOF as one mode\n{HEADER}\n"
                    f"{s.natural_frequency!r}, {s.damping_ratio!r}, {float(1 / np.sqrt(s.mass))!r}\n")
    return path


def _close(a, b, rtol=1e-12):
    a, b = np.asarray(a, float), np.asarray(b, float)
    assert a.shape == b.shape
    np.testing.assert_allclose(a, b, rtol=rtol, atol=1e-15)


def test_reader_units_order_and_observation_point(tmp_path):
    p = tmp_path / "modes.csv"
    p.write_text("frequency [1/min]; damping ratio [%]; damper [kg^-0.5]; tip [kg^-0.5]\n"
                 "2760; 1; -0.9; 0.3\n"
                 "330; 0.5; 0.8; 0.7\n")
    s = read_modes(p)
    _close(s.frequencies, [5.5, 46.0])          # sorted; 1/min -> Hz
    _close(s.damping_ratios, [0.005, 0.01])     # % -> 1
    _close(s.damper_shape, [0.8, -0.9])
    _close(s.output_shape, [0.7, 0.3])
    _close(s.release_shape, [0.8, -0.9])        # released at the damper's point
    assert not s.coincident


@pytest.mark.parametrize("text, where", [
    ("5, 0.01, 0.8\n", "row 1: no header"),
    ("frequency, damping ratio [1], damper [kg^-0.5]\n5, 0.01, 0.8\n",
     "row 1, column 'frequency': no unit"),
    ("frequency [Hz], damping ratio [wibble], damper [kg^-0.5]\n5, 0.01, 0.8\n",
     "row 1, column 'damping ratio [wibble]': unknown unit"),
    ("frequency [Hz], damping ratio [m], damper [kg^-0.5]\n5, 0.01, 0.8\n",
     "row 1, column 'damping ratio [m]': unit 'm' is not a frequency"),
    ("frequency [Hz], damper [kg^-0.5]\n5, 0.8\n", "row 1: no damping ratio column"),
    ("frequency [Hz], damping ratio [1]\n5, 0.01\n", "row 1: no mode-shape column"),
    (f"{HEADER}, b [kg^-0.5], c [kg^-0.5]\n5, 0.01, 0.8, 1, 1\n",
     "row 1, column 'c [kg^-0.5]': at most two mode-shape columns"),
    (f"{HEADER}\n", "row 1: no modes"),
    (f"{HEADER}\n5, 0.01, 0.8\n6, 0.01\n", "row 3: 2 values, the header has 3 columns"),
    (f"{HEADER}\n5, 0.01, 0.8\n6, x, 1\n",
     "row 3, column 'damping ratio [1]': not a number: 'x'"),
    (f"{HEADER}\n5, 0.01, nan\n", "row 2, column 'damper [kg^-0.5]': nan is not a finite"),
    (f"{HEADER}\n# comment\n0, 0.01, 0.8\n",
     "row 3, column 'frequency [Hz]': the frequency must be > 0"),
    (f"{HEADER}\n5, -0.01, 0.8\n",
     "row 2, column 'damping ratio [1]': the damping ratio must be >= 0"),
    (f"{HEADER}\n5, 0.01, 0\n6, 0.01, 0\n",
     "row 3, column 'damper [kg^-0.5]': the damper's point does not move in any mode"),
])
def test_bad_modes_files_get_one_line_errors_naming_file_row_and_column(tmp_path, text, where):
    p = tmp_path / "modes.csv"
    p.write_text(text)
    with pytest.raises(InputError) as info:
        read_modes(p)
    assert info.value.field == "structure.modes"
    msg = str(info.value)
    assert "\n" not in msg
    assert f"{p}, {where}" in msg, msg


def test_missing_and_binary_modes_files(tmp_path):
    with pytest.raises(InputError, match="file not found"):
        read_modes(tmp_path / "none.csv")
    (tmp_path / "b.csv").write_bytes(b"\xff\xfe\x00\x81")
    with pytest.raises(InputError, match="not UTF-8"):
        read_modes(tmp_path / "b.csv")


def test_modes_path_is_relative_to_the_scenario_file(tmp_path):
    sub = tmp_path / "case"
    sub.mkdir()
    _paper_mode_csv(sub / "modes.csv")
    (sub / "s.toml").write_text('[structure]\nmodes = "modes.csv"\n')
    s = load_scenario(sub / "s.toml").structure_model()
    assert s.modes == 1
    _close(s.equivalent_single_dof().mass, PAPER_STRUCTURE.mass)


def test_one_mode_equal_to_the_1dof_gives_identical_simulate(tmp_path, cli):
    csv = _paper_mode_csv(tmp_path / "modes.csv")
    args = ("simulate", "--duration", "1.5s", "--json")
    code, out, err = cli(*args)
    assert code == 0, err
    ref = json.loads(out)
    code, out, err = cli(*args, "--modes", csv)
    assert code == 0, err
    got = json.loads(out)
    (tmp_path / "s.toml").write_text(f'[structure]\nmodes = "{csv}"\n')
    code, out, err = cli(*args, "--scenario", tmp_path / "s.toml")
    assert code == 0, err
    for run in (got, json.loads(out)):
        assert run["inputs"]["structure"]["modes"] == str(csv)
        assert len(run["peaks"]) == len(ref["peaks"]) >= 5
        for key in ("time", "amplitude"):
            _close([p[key] for p in run["peaks"]], [p[key] for p in ref["peaks"]])
        _close(run["final_amplitude"], ref["final_amplitude"])
        _close(run["effective_frequency"], ref["effective_frequency"])
        for key in ("effective_mass", "damping", "loss_factor", "amplitude"):
            _close([c[key] for c in run["cycles"]], [c[key] for c in ref["cycles"]])


def test_one_mode_equal_to_the_1dof_gives_identical_optimize(tmp_path, cli):
    csv = _paper_mode_csv(tmp_path / "modes.csv")
    args = ("optimize", "--step", 48, "--json")
    code, out, err = cli(*args)
    assert code == 0, err
    ref = json.loads(out)
    code, out, err = cli(*args, "--modes", csv)
    assert code == 0, err
    got = json.loads(out)
    # the design and its marks exactly; what the run measured (the objective, the
    # response's harmonic deviation) to rounding, as the modal path sums in another order
    measured = ("objective", "harmonic_deviation")
    best = {k: v for k, v in got["best"].items() if k not in measured}
    assert best == {k: v for k, v in ref["best"].items() if k not in measured}
    for k in measured:
        _close(got["best"][k], ref["best"][k])
    assert len(got["candidates"]) == len(ref["candidates"]) >= 3
    _close([c["objective"] for c in got["candidates"]],
           [c["objective"] for c in ref["candidates"]])


def test_beam_from_the_scenario_gives_the_python_api_results(tmp_path, cli):
    from pdamper.coupling import Simulation
    from pdamper.models import AnalyticalDamper
    from pdamper.parameters import PAPER_DAMPER, PAPER_INITIAL_DISPLACEMENT
    from pdamper.structure.beam import TimoshenkoBeam, TipMass
    from pdamper.structure.modal import ModalStructure

    # length in bare SI: "700 mm" parses to 0.7000000000000001 m, which moves the higher
    # modes' shapes by ~1e-9 (the eigenvectors' conditioning), not the mapping under test
    (tmp_path / "s.toml").write_text(
        '[structure]\nbeam = { length = 0.7, width = "80 mm", height = "6 mm", '
        'youngs_modulus = "210 GPa", poisson_ratio = 0.29, density = "7800 kg/m^3", '
        'elements = 40, tip_mass = "1.3 kg", modes = 3, damper_position = "650 mm", '
        'observation_position = "700 mm", damping_ratio = [0.005, 0.01, 0.02] }\n')
    beam = TimoshenkoBeam(length=0.7, width=0.08, height=0.006, youngs_modulus=210e9,
                          poisson_ratio=0.29, density=7800.0, elements=40)
    api = ModalStructure.from_beam(beam, TipMass(1.3), 3, damper_position=0.65,
                                   output_position=0.7, release_position=0.65,
                                   damping_ratio=[0.005, 0.01, 0.02])
    built = load_scenario(tmp_path / "s.toml").structure_model()
    for key in ("frequencies", "damping_ratios", "damper_shape", "output_shape",
                "release_shape"):
        _close(getattr(built, key), getattr(api, key))
    assert built.modes == 3 and not built.coincident
    ref = Simulation(api, AnalyticalDamper(PAPER_DAMPER), PAPER_INITIAL_DISPLACEMENT).run(
        1.0, 2000.0)
    code, out, err = cli("simulate", "--duration", "1s", "--json", "--scenario",
                         tmp_path / "s.toml")
    assert code == 0, err
    got = json.loads(out)
    assert len(got["peaks"]) == len(ref.peak_times) >= 4
    _close([p["time"] for p in got["peaks"]], ref.peak_times)
    _close([p["amplitude"] for p in got["peaks"]], ref.peak_amplitudes)
    _close(got["final_amplitude"], ref.final_amplitude)
    # and it differs from the default 1-DOF: the scenario's beam was used
    code, out, err = cli("simulate", "--duration", "1s", "--json")
    assert abs(json.loads(out)["peaks"][1]["time"] - got["peaks"][1]["time"]) > 1e-3


def test_default_beam_is_the_paper_beam():
    from pdamper.parameters.vertical_dampers_paper import paper_beam
    from pdamper.structure.modal import ModalStructure

    built = load_scenario(None, {"structure.beam": {}}).structure_model()
    beam, tip = paper_beam()
    api = ModalStructure.from_beam(beam, tip, 1,
                                   damping_ratio=PAPER_STRUCTURE.damping_ratio)
    _close(built.frequencies, api.frequencies)
    _close(built.damper_shape, api.damper_shape)


@pytest.mark.parametrize("structure, field, text", [
    ({"modes": "m.csv", "beam": {}}, "structure", "not both"),
    ({"modes": "m.csv", "stiffness": "1000 N/m"}, "structure", "leave out stiffness"),
    ({"beam": {}, "mass": "1 kg"}, "structure", "leave out mass"),
    ({"modes": "none.csv"}, "structure.modes", "file not found"),
    ({"beam": {"damper_position": "900 mm"}}, "structure.beam.damper_position",
     "beam's length"),
    ({"beam": {"modes": 2, "damping_ratio": [0.1]}}, "structure.beam.damping_ratio",
     "one per mode"),
    ({"beam": {"material": "S235", "density": "7000 kg/m^3"}}, "structure.beam", "not both"),
    ({"beam": {"modez": 2}}, "structure.beam.modez", "unknown key"),
    ({"beam": {"modes": 0}}, "structure.beam.modes", "greater than or equal to 1"),
    ({"beam": {"elements": 5, "modes": 40}}, "structure.beam.modes", "<= 10"),
    ({"beam": {"elements": 100000}}, "structure.beam.elements", "1000"),
    ({"beam": {"height": "-6 mm"}}, "structure.beam.height", "greater than 0"),
])
def test_bad_structure_keys_get_one_line_errors(tmp_path, structure, field, text):
    (tmp_path / "m.csv").write_text(f"{HEADER}\n5, 0.01, 0.8\n")
    structure = {k: (str(tmp_path / v) if k == "modes" else v) for k, v in structure.items()}
    with pytest.raises(InputError) as info:
        load_scenario(None, {f"structure.{k}": v for k, v in structure.items()})
    assert info.value.field == field, str(info.value)
    assert text in info.value.message and "\n" not in str(info.value)


def test_bad_modes_file_on_the_command_line(tmp_path, cli):
    p = tmp_path / "modes.csv"
    p.write_text(f"{HEADER}\n5, 0.01, abc\n")
    code, out, err = cli("simulate", "--modes", p)
    assert code != 0 and out == ""
    assert f"structure.modes: {p}, row 2, column 'damper [kg^-0.5]': not a number" in err


def test_example_scenario_beam_entry_is_valid(tmp_path):
    """The commented ``beam`` entry of ``pdamper example-scenario``, uncommented in place of
    the 1-DOF keys, loads: the paper's beam with three modes."""
    from pdamper.io.scenario import EXAMPLE_SCENARIO

    lines = []
    for line in EXAMPLE_SCENARIO.splitlines():
        if line.startswith(("stiffness =", "damping =")):
            continue
        lines.append(line[2:] if line.startswith("# beam = {") else line)
    (tmp_path / "s.toml").write_text("\n".join(lines) + "\n")
    s = load_scenario(tmp_path / "s.toml").structure_model()
    assert s.modes == 3
    assert 5.5 < s.frequencies[0] < 6.5   # the paper's first bending mode (docs/beam.md)


def test_a_beam_with_all_three_constants_is_built_from_them():
    from pdamper.io.scenario import BeamSpec
    from pdamper.io.structure import beam_structure

    steel = beam_structure(BeamSpec(modes=1, elements=10))
    soft = beam_structure(BeamSpec(modes=1, elements=10, youngs_modulus=70e9,
                                   poisson_ratio=0.33, density=2700.0))
    assert soft.frequencies[0] != steel.frequencies[0]


def test_a_beam_with_some_of_its_constants_is_refused():
    from pdamper.errors import InputError
    from pdamper.io.scenario import BeamSpec
    from pdamper.io.structure import beam_structure

    with pytest.raises(InputError) as e:
        beam_structure(BeamSpec(youngs_modulus=70e9, density=2700.0))
    assert e.value.field == "structure.beam.poisson_ratio"
