"""What every ``pdamper`` invocation must answer, shared by the corpus and the
fuzz suite: exit 0 with finite JSON, or exit 2 with exactly one line on stderr that names a
field (``error: <field>: <what is wrong and what is allowed>``); never a traceback, never a
hang (:func:`time_bound`).
"""

from __future__ import annotations

import contextlib
import json
import math
import re
import signal

#: ``error: <field>: ...``: a dotted scenario field (``particles.material.poisson_ratio``),
#: an output (``out``, ``vtk``, ``stdout``) or a command-line option (``--particles``).
ERROR_LINE = re.compile(r"^error: (?P<field>--?[a-z][a-z0-9-]*|[a-z_][a-z0-9_]*"
                        r"(\.[a-z_][a-z0-9_]*)*): \S")


class Hang(AssertionError):
    """An invocation did not answer within its time bound (an assertion, so that
    hypothesis reports and shrinks the example)."""


@contextlib.contextmanager
def time_bound(seconds: float):
    """Raise :class:`Hang` in the main thread if the block runs longer than ``seconds``."""

    def alarm(_signum, _frame):
        raise Hang(f"no answer within {seconds:g} s")

    old = signal.signal(signal.SIGALRM, alarm)
    signal.setitimer(signal.ITIMER_REAL, seconds)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, old)


def _finite(o) -> bool:
    if isinstance(o, float):
        return math.isfinite(o)
    if isinstance(o, dict):
        return all(_finite(v) for v in o.values())
    if isinstance(o, list):
        return all(_finite(v) for v in o)
    return True


def check_answer(code: int, out: str, err: str, field: str | None = None,
                 ok: bool | None = None) -> str | None:
    """Assert that ``(code, out, err)`` is a proper answer; returns the field of an error.

    ``field``: the error must name this field (prefix match on dotted components);
    ``ok``: True requires success, False requires an error.
    """
    assert "Traceback" not in err, err
    if code == 0:
        assert ok is not False and field is None, f"expected an error, got success: {out[:200]}"
        text = out.strip()
        if text.startswith("{"):
            data = json.loads(text)
            assert _finite(data), "non-finite number in the JSON"
        return None
    assert code == 2, f"exit status {code} (expected 0 or 2): {err!r}"
    assert ok is not True, f"expected success, got {err!r}"
    lines = err.splitlines()
    assert len(lines) == 1 and err.endswith("\n"), f"expected one line on stderr, got {err!r}"
    m = ERROR_LINE.match(lines[0])
    assert m, f"the error line names no field: {lines[0]!r}"
    assert out == "", f"an error printed to stdout too: {out[:200]!r}"
    if field is not None:
        got = m["field"]
        assert got == field or got.startswith(field + "."), (
            f"expected the field {field!r}, got {lines[0]!r}")
    return m["field"]


@contextlib.contextmanager
def memory_headroom(nbytes: float | None):
    """Let the block map at most ``nbytes`` of address space beyond what the process holds
    (the soft ``RLIMIT_AS``, restored after): an input whose refusal regressed into building
    what it implies fails with MemoryError at once instead of taking the machine's memory.
    Does nothing for None or where the limit cannot be set."""
    import resource

    if nbytes is None:
        yield
        return
    try:
        with open("/proc/self/status") as fh:
            held = next(int(line.split()[1]) * 1024 for line in fh if line.startswith("VmSize:"))
        old = resource.getrlimit(resource.RLIMIT_AS)
    except (OSError, StopIteration, ValueError, AttributeError):
        yield
        return
    cap = held + int(nbytes)
    if old[1] != resource.RLIM_INFINITY:
        cap = min(cap, old[1])
    resource.setrlimit(resource.RLIMIT_AS, (cap, old[1]))
    try:
        yield
    finally:
        resource.setrlimit(resource.RLIMIT_AS, old)


def refused(fn, field: str, *words: str):
    """``fn()`` raises an :class:`~pdamper.errors.InputError` of one line naming ``field``
    whose message holds every one of ``words``; returns the error."""
    import pytest

    from pdamper.errors import InputError

    with pytest.raises(InputError) as info:
        fn()
    assert info.value.field == field, str(info.value)
    for w in words:
        assert w in info.value.message, str(info.value)
    assert "\n" not in str(info.value)
    return info.value
