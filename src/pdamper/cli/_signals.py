"""Signals of the command line: Ctrl-C, SIGTERM and SIGHUP end a command cleanly.

While a command runs, each of these signals raises :class:`~pdamper.errors.Interrupted` in
the main thread, so that every cleanup runs (the atomic writer removes its temporary
file, a staging directory disappears) and the command line ends with one line,
``interrupted``, and status ``128 + signal`` (130 for SIGINT, 143 for SIGTERM). A second
signal while the first unwinds is ignored for :data:`GRACE` seconds, so that the cleanup
finishes; after that, another one raises again. A signal that lands in a finalizer (where
Python prints an exception and goes on) is delivered again.

Every signal is recorded before its exception is raised, so that the command line answers
``interrupted`` even where a library turned the exception into one of its own: the
extension modules of matplotlib (pybind11) report any error of their initialisation as
``ImportError: initialization failed``, so that a Ctrl-C landing in ``import matplotlib``
(``cor --plot``) ended with that traceback and status 1.
"""

from __future__ import annotations

import contextlib
import os
import signal
import sys
import threading
import time
from collections.abc import Iterator

from pdamper.errors import Interrupted
from pdamper.files import DEFERRED_SIGNALS

#: Signals that stop a command (where the platform has them): those the atomic writer holds
#: back while it writes.
SIGNALS = DEFERRED_SIGNALS
#: Seconds during which a further signal leaves the cleanup of the first alone.
GRACE = 2.0


@contextlib.contextmanager
def raising_interrupts() -> Iterator[list[int]]:
    """While the block runs, :data:`SIGNALS` raise :class:`Interrupted` (main thread only;
    elsewhere the block runs with the handlers as they are).

    Yields the list of the signals received so far (their numbers, in order; filled in
    before the exception is raised), for the caller to tell an interrupt from what a
    library made of it.
    """
    received: list[int] = []
    if threading.current_thread() is not threading.main_thread():
        yield received
        return
    first: list[float] = []

    def handler(signum, _frame):
        received.append(signum)
        now = time.monotonic()
        if first and now - first[0] < GRACE:
            return
        first[:] = [now]
        raise Interrupted(signum)

    previous_hook = sys.unraisablehook

    def unraisable(info):
        # the signal landed in a finalizer (a generator closed by the garbage collector, a
        # __del__), where Python prints an exception and goes on: deliver it again, now
        # outside the finalizer
        if isinstance(info.exc_value, Interrupted):
            first.clear()
            again = threading.Timer(0.01, os.kill, (os.getpid(), info.exc_value.signum))
            again.daemon = True
            again.start()
            return
        previous_hook(info)

    previous = {s: signal.signal(s, handler) for s in SIGNALS}
    sys.unraisablehook = unraisable
    try:
        yield received
    finally:
        sys.unraisablehook = previous_hook
        for s, h in previous.items():
            signal.signal(s, h)
