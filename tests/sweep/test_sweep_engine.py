"""The sweep engine (:mod:`pdamper.sweep`) in this process: stored points, retries, status,
keys; the dask runs are in test_resume.py."""

from __future__ import annotations

import json
import math
from functools import partial

import numpy as np
import pytest
from sweep_points import calls, point, points, value_of

from pdamper.errors import InputError
from pdamper.sweep import PointStore, point_key, run_sweep


def same(a: dict, b: dict) -> bool:
    return a.keys() == b.keys() and all(
        (isinstance(a[k], float) and math.isnan(a[k]) and math.isnan(b[k])) or a[k] == b[k]
        for k in a)


def test_values_are_those_of_the_function_and_stored_one_file_per_point(tmp_path):
    r = run_sweep(point, points(6), store=tmp_path / "s", serial=True)
    assert [p.index for p in r.points] == list(range(6))
    assert all(same(p.values, value_of(p.params)) for p in r.points)
    files = sorted((tmp_path / "s").iterdir())
    assert len(files) == 6 and all(f.suffix == ".json" for f in files)  # no temp files left
    rec = json.loads(files[0].read_text())
    assert {"key", "index", "params", "status", "values", "error", "attempts",
            "pdamper_version"} <= set(rec)
    assert r.computed == 6 and r.reused == 0 and r.failed == 0
    assert r.values("y") == pytest.approx([value_of(p)["y"] for p in points(6)])


def test_a_second_run_computes_only_the_missing_points(tmp_path):
    log = str(tmp_path / "calls")
    store = tmp_path / "s"
    ref = run_sweep(point, points(8), serial=True)
    run_sweep(partial(point, log=log), points(8)[:5], store=store, serial=True)
    (next(store.iterdir())).unlink()  # and one stored point lost
    assert len(calls(log)) == 5
    r = run_sweep(partial(point, log=log), points(8), store=store, serial=True)
    assert r.computed == 4 and r.reused == 4
    assert len(calls(log)) == 9 and sorted(set(calls(log))) == list(range(8))
    for a, b in zip(r.points, ref.points, strict=True):
        assert same(a.values, b.values) and a.status == b.status


def test_a_failed_point_is_retried_then_recorded_and_never_ends_the_sweep(tmp_path):
    log = str(tmp_path / "calls")
    r = run_sweep(partial(point, log=log, fail_at=(2,)), points(4), store=tmp_path / "s",
                  retries=2, serial=True)
    assert calls(log).count(2) == 3  # first attempt + 2 retries
    p = r.points[2]
    assert p.status == "failed" and p.attempts == 3 and p.values == {}
    assert p.error == "ValueError: point 2 cannot be computed"
    assert r.status_codes().tolist() == [0, 0, 1, 0]
    assert math.isnan(r.values("y")[2]) and r.failed == 1
    # the failure is stored: a rerun keeps it unless asked to retry it
    r2 = run_sweep(partial(point, log=log), points(4), store=tmp_path / "s", serial=True)
    assert r2.points[2].status == "failed" and r2.computed == 0
    r3 = run_sweep(partial(point, log=log), points(4), store=tmp_path / "s", serial=True,
                   retry_failed=True)
    assert r3.points[2].ok and r3.computed == 1 and r3.failed == 0


def test_retry_if_skips_deterministic_failures(tmp_path):
    log = str(tmp_path / "calls")
    r = run_sweep(partial(point, log=log, fail_at=(1,)), points(2), retries=3, serial=True,
                  retry_if=lambda exc: not isinstance(exc, ValueError))
    assert calls(log).count(1) == 1 and r.points[1].attempts == 1


def test_keys_change_with_context_and_params_not_with_side_channels():
    p = {"i": 0, "x": 1.0}
    k = point_key(point, {"v": 1}, p)
    assert k == point_key(partial(point, log="elsewhere"), {"v": 1}, dict(p))
    assert k != point_key(point, {"v": 2}, p)
    assert k != point_key(point, {"v": 1}, {"i": 0, "x": 1.5})
    assert k != point_key(value_of, {"v": 1}, p)
    assert point_key(point, None, {"x": np.float64(1.0), "i": np.int64(0)}) == \
        point_key(point, None, {"i": 0, "x": 1.0})


def test_changed_context_recomputes_and_progress_reports_every_point(tmp_path):
    seen = []
    run_sweep(point, points(3), store=tmp_path / "s", context={"v": 1}, serial=True)
    r = run_sweep(point, points(3), store=tmp_path / "s", context={"v": 2}, serial=True,
                  progress=lambda done, total, pr: seen.append((done, total, pr.index)))
    assert r.computed == 3 and sorted(i for *_, i in seen) == [0, 1, 2]
    assert [d for d, *_ in seen] == [1, 2, 3] and {t for _, t, _ in seen} == {3}
    assert len(PointStore(tmp_path / "s")) == 6  # the old records stay, unused


def test_bad_inputs():
    with pytest.raises(InputError, match="retries"):
        run_sweep(point, points(1), retries=-1, serial=True)
    with pytest.raises(InputError, match="sweep"):
        run_sweep(point, [{"i": 0, "x": object()}], serial=True)
    r = run_sweep(lambda p: 3, points(1), serial=True)
    assert r.points[0].error.startswith("TypeError: the point function must return a dict")
