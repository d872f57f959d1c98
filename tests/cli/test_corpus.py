"""The hostile-input corpus (``tests/hostile_corpus.py``) as ordinary tests: every hostile input
gets its promised answer, in process, within a time bound."""

from __future__ import annotations

import os

import pytest

from answers import check_answer, memory_headroom, time_bound
from hostile_corpus import CASES, FILES, HEADROOM, OK, SCENARIOS

#: Seconds one invocation may take here (the slowest valid case runs a small map).
BOUND = 60.0


@pytest.fixture
def corpus_tmp(tmp_path):
    (tmp_path / "dir").mkdir()
    (tmp_path / "file").write_text("an earlier result\n")
    os.mkfifo(tmp_path / "fifo")
    for name, text in SCENARIOS.items():
        (tmp_path / f"{name}.toml").write_text(text, encoding="utf-8")
    for name, text in FILES.items():
        (tmp_path / name).write_text(text, encoding="utf-8")
    return tmp_path


def expand(arg: str, tmp) -> str:
    if arg.startswith("{scenario:"):
        return str(tmp / f"{arg[len('{scenario:'):-1]}.toml")
    return arg.replace("{tmp}", str(tmp))


@pytest.mark.parametrize(("args", "expected"), [c[1:] for c in CASES], ids=[c[0] for c in CASES])
def test_corpus_case(cli, corpus_tmp, args, expected, request):
    before = sorted(p.name for p in corpus_tmp.iterdir())
    with time_bound(BOUND), memory_headroom(HEADROOM.get(request.node.callspec.id)):
        code, out, err = cli(*[expand(a, corpus_tmp) for a in args])
    if isinstance(expected, OK):
        check_answer(code, out, err, ok=True)
    else:
        check_answer(code, out, err, field=expected.field)
        # refused before anything was written: the directory is as it was
        assert sorted(p.name for p in corpus_tmp.iterdir()) == before
    assert not [p for p in corpus_tmp.rglob("*") if p.name.endswith(".tmp")]
