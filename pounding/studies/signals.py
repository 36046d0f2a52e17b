"""Stopping a study on SIGINT and SIGTERM without losing a stop request or a stored run."""

from __future__ import annotations

import contextlib
import signal
import sys
from collections.abc import Iterator
from typing import Any


class StudyInterrupted(KeyboardInterrupt):
    """A study stopped by SIGINT or SIGTERM; the runs finished before it are stored."""

    def __init__(self, signum: int = signal.SIGINT) -> None:
        super().__init__(signal.Signals(signum).name)
        self.signum = signum


# The signal that asked the running study to stop. The handler also raises, but a KeyboardInterrupt
# raised while a callback runs can be swallowed (5 of 22 SIGINT trials ran on to exit 0): the loops
# check this after every run and before every pool restart, so a stop request is never lost.
# "defer" is set while a run is being stored: the stop then waits for the check that follows.
_STOP: dict[str, int] = {}


@contextlib.contextmanager
def _stop_deferred() -> Iterator[None]:
    # a stop between a run's file and its log line left the two disagreeing (1 trial in 72)
    _STOP["defer"] = 1
    try:
        yield
    finally:
        del _STOP["defer"]


def _check_stop() -> None:
    if "signum" in _STOP:
        raise StudyInterrupted(_STOP["signum"])


@contextlib.contextmanager
def stop_on_signals() -> Iterator[None]:
    """Make SIGINT and SIGTERM stop a study run inside this block with :class:`StudyInterrupted`
    (its ``signum`` says which; exit status 128 + signum by convention), however the signal meets
    the loop. Only the main thread can install signal handlers: elsewhere this does nothing."""
    import threading

    if threading.current_thread() is not threading.main_thread():
        yield
        return

    def handler(signum: int, frame: Any) -> None:
        if "signum" not in _STOP:  # a second signal must not break off stopping the workers
            _STOP["signum"] = signum
            if "defer" not in _STOP:  # else raised by the check that follows every stored run
                raise StudyInterrupted(signum)

    hook = sys.unraisablehook

    def unraisable(info: Any) -> None:
        # the handler's raise landed in a callback Python cannot propagate from (a weakref callback
        # of importlib's module locks, a __del__): CPython prints it as "Exception ignored" with a
        # traceback; the stop is recorded in _STOP and honoured by the checks, so that is noise
        if not isinstance(info.exc_value, StudyInterrupted):
            hook(info)

    _STOP.pop("signum", None)
    previous = {s: signal.signal(s, handler) for s in (signal.SIGINT, signal.SIGTERM)}
    sys.unraisablehook = unraisable
    try:
        yield
    finally:
        for s, h in previous.items():
            signal.signal(s, h)
        sys.unraisablehook = hook
        _STOP.pop("signum", None)
