"""``pytest --cpu-durations=N``: the N tests of most CPU time, and the run's total.

Wall times (``--durations``) grow with whatever else runs on the machine; CPU seconds much
less, so this is the measure of the test loop's cost on a shared machine. A test's count
runs from its setup to its teardown and holds its process's CPU and that of the child
processes it waited for (``python -m pdamper`` children, a killed sweep); the workers of a
local cluster, which their nannies wait for, are not in it. Registered by tests/conftest.py.
"""

from __future__ import annotations

import os

import pytest

#: Where a test's count starts (on the item), and the counts the controller received.
_CPU_START = pytest.StashKey[float]()
_CPU_SPENT: dict[str, float] = {}


def pytest_addoption(parser):
    parser.addoption(
        "--cpu-durations", type=int, default=None, metavar="N",
        help="list the N tests of most CPU time (seconds of the test's process and of the "
             "child processes it waited for, setup to teardown) and the run's total: a "
             "measure that a loaded machine inflates far less than wall time (0: all)")


def cpu_seconds() -> float:
    """CPU seconds of this process and of its waited-for children, user and system
    (:func:`os.times`); a child's count arrives when it is waited for, and the workers of a
    local cluster, which a nanny process waits for, are not counted."""
    t = os.times()
    return t.user + t.system + t.children_user + t.children_system


@pytest.hookimpl(tryfirst=True)
def pytest_runtest_setup(item):
    if item.config.getoption("cpu_durations", None) is not None:
        item.stash[_CPU_START] = cpu_seconds()


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_makereport(item, call):
    outcome = yield
    start = item.stash.get(_CPU_START, None)
    if call.when == "teardown" and start is not None:
        # on the report, which pytest-xdist carries from its workers to the controller
        outcome.get_result().user_properties.append(("cpu_seconds", cpu_seconds() - start))



def pytest_runtest_logreport(report):
    if report.when == "teardown":
        for key, value in report.user_properties:
            if key == "cpu_seconds":
                _CPU_SPENT[report.nodeid] = value


def pytest_terminal_summary(terminalreporter, config):
    n = config.getoption("cpu_durations", None)
    if n is None or hasattr(config, "workerinput") or not _CPU_SPENT:
        return
    rows = sorted(_CPU_SPENT.items(), key=lambda kv: -kv[1])
    tr = terminalreporter
    tr.write_sep("=", f"CPU seconds of {len(rows)} tests: {sum(_CPU_SPENT.values()):.1f} s "
                      "(process and waited-for children, setup to teardown)")
    for nodeid, seconds in rows[:n] if n > 0 else rows:
        tr.write_line(f"{seconds:8.2f}s  {nodeid}")
