"""Progress displays of the long commands (``optimize``, ``frf`` and ``simulate`` with the
DEM): a rich bar on standard error, never on standard output (a result, ``--json``, is
left as it is), and none with ``--quiet`` or when standard error is not a terminal (a
script's log gets no control characters)."""

from __future__ import annotations

import sys
from typing import Any, Literal


def showing() -> bool:
    """Whether a progress display is shown: stderr is a terminal and ``--quiet`` was not
    given."""
    from pdamper.cli._quiet import quiet

    try:
        return not quiet() and sys.stderr.isatty()
    except (AttributeError, ValueError):  # a closed or replaced stderr
        return False


class Bar:
    """A progress bar of ``what`` (``"designs"``) as a ``progress(done, total)`` callback;
    entered, it is the callback, or None when no display is shown (:func:`showing`).

    Counts that start again (the next batch of an optimiser's generation) add on: the bar
    shows every evaluation so far."""

    def __init__(self, what: str, force: bool | None = None) -> None:
        self.what = what
        self.show = showing() if force is None else force
        self._bar: Any = None
        self._task: Any = None
        self._offset = 0
        self._last = 0
        self._batches = 0

    def __enter__(self) -> Bar | None:
        if not self.show:
            return None
        from rich.console import Console
        from rich.progress import (
            BarColumn,
            MofNCompleteColumn,
            Progress,
            TextColumn,
            TimeElapsedColumn,
        )

        self._bar = Progress(TextColumn("{task.description}"), BarColumn(),
                             MofNCompleteColumn(), TimeElapsedColumn(),
                             console=Console(file=sys.stderr), transient=False)
        self._bar.__enter__()
        self._task = self._bar.add_task(self.what, total=None)
        return self

    def __call__(self, done: int, total: int, *_: Any) -> None:
        if done < self._last or (done == 1 and self._last >= 1):  # a new batch
            self._offset += self._last
            self._batches += 1
        self._last = done
        what = self.what + (f" (batch {self._batches + 1})" if self._batches else "")
        self._bar.update(self._task, completed=self._offset + done,
                         total=self._offset + total, description=what)

    def __exit__(self, *exc: Any) -> Literal[False]:
        if self._bar is not None:
            self._bar.__exit__(*exc)
        return False


class Spinner:
    """A spinner with ``what`` while a run without steps to count goes on (a coupled DEM
    run); nothing when no display is shown (:func:`showing`)."""

    def __init__(self, what: str, force: bool | None = None) -> None:
        self.what = what
        self.show = showing() if force is None else force
        self._status: Any = None

    def __enter__(self) -> Spinner:
        if self.show:
            from rich.console import Console

            self._status = Console(file=sys.stderr).status(self.what)
            self._status.__enter__()
        return self

    def __exit__(self, *exc: Any) -> Literal[False]:
        if self._status is not None:
            self._status.__exit__(*exc)
        return False


def frf_steps(total: int) -> Any:
    """A :class:`Bar` of the forced response's DEM steps (``total``: frequencies times
    sweeps), as the ``progress(frequency, info)`` callback of
    :func:`pdamper.coupling.frf.frequency_response`."""

    class _Steps(Bar):
        def __init__(self) -> None:
            super().__init__("DEM steps of the forced response")
            self.done = 0

        def step(self, f: float, info: dict) -> None:
            self.done += 1
            self._bar.update(self._task, completed=self.done, total=total,
                             description=f"DEM steps of the forced response ({f:.4g} Hz)")

    return _Steps()


__all__ = ["Bar", "Spinner", "frf_steps", "showing"]
