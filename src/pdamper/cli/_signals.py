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

A signal sent to the process may be delivered to any of its threads (dask runs several);
Python then runs the handler only when the main thread next executes Python code, and a
main thread waiting on a lock (dask's ``sync`` waits 10 s at a time) heard of the Ctrl-C
only when its wait ended: 1-2 s while a local cluster started. :func:`_relaying` hands
every such signal to the main thread, whose wait it interrupts.
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
#: Seconds within which a signal relayed to the main thread reports itself (see
#: :func:`_relaying`).
ECHO = 0.5


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
            again = threading.Timer(0.01, os.kill, (os.getpid(), info.exc_value.signum))
            again.daemon = True
            again.start()
            # only now: a copy of the signal (see _relaying) arriving while the timer
            # starts finds the grace period running and leaves this hook alone
            first.clear()
            return
        previous_hook(info)

    previous = {s: signal.signal(s, handler) for s in SIGNALS}
    sys.unraisablehook = unraisable
    try:
        with _relaying():
            yield received
    finally:
        sys.unraisablehook = previous_hook
        for s, h in previous.items():
            signal.signal(s, h)


@contextlib.contextmanager
def _relaying() -> Iterator[None]:
    """While the block runs, every signal of :data:`SIGNALS`, whichever thread the system
    delivered it to, is sent again to the main thread (``pthread_kill``), so that a wait
    there is interrupted and the handler runs at once.

    Python's C-level handler writes each signal's number to the wakeup descriptor
    (``signal.set_wakeup_fd``) in whichever thread received it; a thread reads them and
    relays. The relayed copy writes its number too: that echo is not relayed again. A
    copy that reaches the main thread beside the original one runs the handler within
    its grace period, where it does nothing. Where the platform lacks ``pthread_kill``,
    the block runs without relaying.
    """
    if not hasattr(signal, "pthread_kill"):  # pragma: no cover - not POSIX
        yield
        return
    main = threading.main_thread().ident
    assert main is not None  # the main thread has started: it runs this
    wanted = {int(s) for s in SIGNALS}
    read_end, write_end = os.pipe()
    os.set_blocking(write_end, False)
    try:
        previous_fd = signal.set_wakeup_fd(write_end, warn_on_full_buffer=False)
    except (ValueError, OSError):  # pragma: no cover - not the main thread
        os.close(read_end)
        os.close(write_end)
        yield
        return
    echo_until: dict[int, float] = {}  # a relayed copy's own number, expected until then

    def relay() -> None:
        while True:
            try:
                data = os.read(read_end, 64)
            except OSError:
                return
            if not data:  # the write end was closed: the block is over
                return
            for signum in data:
                if signum not in wanted:
                    continue
                if time.monotonic() < echo_until.pop(signum, 0.0):
                    continue  # the relayed copy itself (none comes where the main thread
                    # had the signal pending still: the expectation then lapses)
                echo_until[signum] = time.monotonic() + ECHO
                with contextlib.suppress(OSError, ValueError):  # the main thread is gone
                    signal.pthread_kill(main, signum)

    relayer = threading.Thread(target=relay, name="pdamper-signal-relay", daemon=True)
    relayer.start()
    try:
        yield
    finally:
        signal.set_wakeup_fd(previous_fd)
        os.close(write_end)
        relayer.join(1.0)
        os.close(read_end)
