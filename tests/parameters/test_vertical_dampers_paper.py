"""The paper's parameter set: derived values against the paper's text (NOTES on the
structure's printed constants) and the semantics of the reported-number tolerances."""

from __future__ import annotations

import math

import pytest

from pdamper.analysis.modes import MotionMode
from pdamper.parameters import vertical_dampers_paper as paper


def test_structure_mass_reproduces_the_measured_eigenfrequency():
    """M = K / (2 pi f0)^2 = 1.514 kg gives f0 = 5.56 Hz; the printed 1.139 kg gives 6.41 Hz."""
    assert paper.PAPER_MASS == pytest.approx(1.514, abs=0.001)
    assert paper.PAPER_STRUCTURE.natural_frequency == pytest.approx(5.56, abs=1e-9)
    printed = math.sqrt(paper.PAPER_STIFFNESS / paper.PAPER_PRINTED_MASS) / (2 * math.pi)
    assert printed == pytest.approx(6.41, abs=0.01)


def test_benchmark_damper_numbers_of_the_paper():
    """n_max = 192, h = 100 mm, X_opt = 31.8 mm ("32 mm"), 32 spheres 132 g ("131 g"),
    64 spheres 265 g (Sects. 3.1.1, 4.2.1, 4.2.2)."""
    d = paper.PAPER_DAMPER
    assert d.max_count == 192 and d.per_layer == paper.PAPER_COUNT_STEP
    assert d.clearance == pytest.approx(0.100)
    assert d.optimal_stroke * 1e3 == pytest.approx(31.8, abs=0.05)
    assert d.bed_mass == pytest.approx(0.131, abs=0.002)
    assert d.with_count(paper.PAPER_OPTIMAL_COUNT).bed_mass == pytest.approx(0.265, abs=0.001)
    assert d.friction == 0.1


def test_fig4_example_points_cover_every_mode_the_paper_names():
    from pdamper.analysis.modes import PAPER_MODES

    assert {m for _, _, m, _ in paper.FIG4_EXAMPLES} == set(PAPER_MODES)
    assert set(MotionMode) - set(PAPER_MODES) == {MotionMode.RATTLING}


def test_reported_keys_are_unique_and_ordered_as_the_table():
    keys = [r.key for r in paper.PAPER_REPORTED]
    assert len(keys) == len(set(keys)) == 40
    assert keys[:6] == [f"fig4_{c}" for *_, c in paper.FIG4_EXAMPLES]


def test_tolerance_semantics():
    w = paper.Within(1.0, 2.0, low_open=True)
    assert not w(1.0) and w(1.0 + 1e-12) and w(2.0) and not w(2.0 + 1e-12)
    assert paper.near(64, 16, closed=True)(48) and not paper.near(64, 16)(48)
    r = paper.REPORTED["double_cac_harmonic_eta"]
    assert r.agrees((0.26, 1.25)) and not r.agrees((0.1, 1.25)) and not r.agrees((0.3, 1.3))
    assert paper.REPORTED["fig4_3ii"].agrees(MotionMode.DOUBLE_CAC_SUBHARMONIC)
    assert not paper.REPORTED["fig4_3ii"].agrees(MotionMode.SCATTERING)
    assert paper.REPORTED["dem_mode_agreement"].agrees(0.3) is None  # no number to compare
    assert paper.REPORTED["amplitude_32_0p75s"].agrees(0.019 * 1.29)
    assert not paper.REPORTED["amplitude_32_0p75s"].agrees(0.019 * 1.31)
