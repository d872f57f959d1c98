"""The container's mass at the damper point: 1-DOF and the mass-modified modal eigenproblem."""

import math

import numpy as np
import pytest

from pdamper.errors import InputError
from pdamper.structure import SingleDOFStructure
from pdamper.structure.modal import ModalStructure


def test_single_dof_added_mass_frequency():
    s = SingleDOFStructure(mass=1.514, damping=0.55, stiffness=1848.0)
    f0 = math.sqrt(1848.0 / 1.514) / (2 * math.pi)
    for mc in (0.08, 0.5, 5.0):
        assert s.with_added_mass(mc).natural_frequency == pytest.approx(
            f0 * math.sqrt(1.514 / (1.514 + mc)), rel=1e-6)
        m = ModalStructure.from_single_dof(s).with_added_mass(mc)
        assert m.natural_frequency == pytest.approx(f0 * math.sqrt(1.514 / (1.514 + mc)),
                                                    rel=1e-6)


def _machine_frame():
    # shared/user-cases/machine-frame/modes.csv
    return ModalStructure(np.array([12.0, 31.0]), np.array([0.01, 0.008]),
                          np.array([0.2582, -0.3162]), np.array([0.2582, -0.3162]),
                          np.array([0.2582, -0.3162]), participation=np.array([1.0, 0.5]))


@pytest.mark.parametrize("mc", [0.08, 0.5, 5.0])
def test_modal_added_mass_matches_numpy_eigen(mc):
    s = _machine_frame()
    w = 2 * np.pi * s.frequencies
    phi = s.damper_shape
    k = np.diag(w**2)
    m = np.eye(2) + mc * np.outer(phi, phi)
    lam, vec = np.linalg.eig(np.linalg.solve(m, k))
    order = np.argsort(lam.real)
    lam, vec = lam.real[order], vec.real[:, order]
    vec = vec / np.sqrt(np.einsum("ij,ik,kj->j", vec, m, vec))
    f_ref = np.sqrt(lam) / (2 * np.pi)
    phi_ref = vec.T @ phi
    new = s.with_added_mass(mc)
    np.testing.assert_allclose(new.frequencies, f_ref, rtol=1e-6)
    np.testing.assert_allclose(np.abs(new.damper_shape), np.abs(phi_ref), rtol=1e-6)
    np.testing.assert_allclose(np.abs(new.output_shape), np.abs(phi_ref), rtol=1e-6)
    # the added mass lowers both frequencies
    assert np.all(new.frequencies < s.frequencies)
    # each mode keeps the sign it had at the damper point
    assert np.array_equal(np.sign(new.damper_shape), np.sign(s.damper_shape))


def test_added_mass_zero_and_negative():
    s = _machine_frame()
    assert s.with_added_mass(0.0) is s
    with pytest.raises(InputError, match="damper.container_mass"):
        s.with_added_mass(-1.0)
    with pytest.raises(InputError, match="damper.container_mass"):
        SingleDOFStructure(1.0, 0.1, 100.0).with_added_mass(-0.1)


_MODES = ("frequency [Hz], damping ratio [%], damper [kg^-0.5], observation [kg^-0.5]\n"
          "12.0, 1.0, 0.2582, 0.2582\n31.0, 0.8, -0.3162, -0.3162\n")


def _scenario(tmp_path, structure: str, mass: float = 0.2):
    from pdamper.io.scenario import load_scenario

    (tmp_path / "modes.csv").write_text(_MODES)
    (tmp_path / "s.toml").write_text(f"[structure]\n{structure}\n[container]\nmass = {mass}\n")
    return load_scenario(tmp_path / "s.toml").structure_model()


def test_scenario_modes_file_adds_the_container_by_default(tmp_path):
    bare = _scenario(tmp_path, 'modes = "modes.csv"', 0.0)
    with_c = _scenario(tmp_path, 'modes = "modes.csv"', 0.2)
    ref = bare.with_added_mass(0.2)
    np.testing.assert_allclose(with_c.frequencies, ref.frequencies, rtol=1e-12)
    # mode 1 (15 kg at the tip) by about sqrt(15 / 15.2) to first order
    assert with_c.frequencies[0] < bare.frequencies[0] * math.sqrt(15.0 / 15.15)
    kept = _scenario(tmp_path, 'modes = "modes.csv"\nincludes_container_mass = true', 0.2)
    np.testing.assert_array_equal(kept.frequencies, bare.frequencies)


def test_scenario_single_dof_includes_the_container_by_default(tmp_path):
    from pdamper.parameters import PAPER_STRUCTURE

    s = _scenario(tmp_path, "", 0.2)
    assert s.mass == PAPER_STRUCTURE.mass
    added = _scenario(tmp_path, "includes_container_mass = false", 0.2)
    assert added.mass == pytest.approx(PAPER_STRUCTURE.mass + 0.2, rel=1e-12)


def test_added_mass_keeps_the_load_point():
    """The load point's shapes follow the new modes like the damper's (phi' = V^T phi)."""
    import numpy as np

    from pdamper.structure.modal import ModalStructure

    s = ModalStructure([12.0, 31.0], [0.01, 0.008], [0.2582, -0.3162], [0.2582, -0.3162],
                       load_shape=[0.15, 0.24])
    heavy = s.with_added_mass(0.2)
    # a static unit force at the load point deflects the damper's point by the flexibility
    # sum_i phi_d,i phi_L,i / w_i^2, which a mass cannot change (statics do not see it): it
    # holds only if the load shapes were carried into the new modes
    flex0 = np.sum(s.damper_shape * s._filled(s.load_shape) / s.angular_frequencies**2)
    flex1 = np.sum(heavy.damper_shape * heavy._filled(heavy.load_shape)
                   / heavy.angular_frequencies**2)
    np.testing.assert_allclose(flex1, flex0, rtol=1e-9)
    assert not np.allclose(heavy._filled(heavy.load_shape), heavy._filled(heavy.release_shape))
