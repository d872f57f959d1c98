"""pdamper's exceptions cross process boundaries (dask workers return them pickled)."""

from __future__ import annotations

import pickle

import pytest

from pdamper.errors import InputError, Interrupted, OutputError, SimulationError


@pytest.mark.parametrize("error", [InputError("particles.count", "must be in [0, 192], got 200"),
                                   OutputError("out", "cannot write m.nc: disk full"),
                                   SimulationError("NaN in the positions"), Interrupted(15)])
def test_errors_survive_pickling(error):
    back = pickle.loads(pickle.dumps(error))
    assert type(back) is type(error) and str(back) == str(error)
    for name in ("field", "message", "signum"):
        assert getattr(back, name, None) == getattr(error, name, None)
