"""pdamper.runs.maps: the cached maps of ``pdamper paper`` and ``pdamper map``."""

import numpy as np

import pdamper._version
from pdamper.io.scenario import Scenario
from pdamper.runs.maps import map_context, run_map


def test_a_cached_map_is_reused_only_by_the_code_that_made_it(tmp_path, monkeypatch):
    """The cache key holds the digest of the computing source beside the version (which
    changes only at releases): a map made by other code is recomputed, never reused."""
    out = tmp_path / "m.nc"
    grid = {"frequency": np.array([5.0, 10.0]), "amplitude": np.array([0.01, 0.03])}
    sc = Scenario()
    first = run_map(sc, "analytic", out=out, cache=True, **grid)
    assert not first.cached and first.dataset.attrs["pdamper_source"] == \
        pdamper._version.source_digest()
    assert run_map(sc, "analytic", out=out, cache=True, **grid).cached
    monkeypatch.setattr(pdamper._version, "source_digest", lambda: "0" * 16)
    assert map_context(sc, "analytic")["pdamper_source"] == "0" * 16
    again = run_map(sc, "analytic", out=out, cache=True, **grid)
    assert not again.cached and again.dataset.attrs["pdamper_source"] == "0" * 16


def test_the_source_digest_follows_the_computing_code_only(tmp_path):
    """A change of a computing module changes the digest; figures and command-line
    formatting (``plots``, ``cli``) do not change a number, so they do not."""
    from pdamper._version import tree_digest

    for sub in ("dem", "plots", "cli"):
        (tmp_path / sub).mkdir()
        (tmp_path / sub / "a.py").write_text("x = 1\n")
    base = tree_digest(tmp_path)
    (tmp_path / "plots" / "a.py").write_text("x = 2\n")
    (tmp_path / "cli" / "b.py").write_text("y = 1\n")
    assert tree_digest(tmp_path) == base
    (tmp_path / "dem" / "a.py").write_text("x = 2\n")
    assert tree_digest(tmp_path) != base
