"""Ctrl-C through casadi/IPOPT: an interrupt that a solve swallowed is raised again.

casadi runs Python's SIGINT handler inside IPOPT's callbacks, catches the resulting
``KeyboardInterrupt`` and ends the solve with a status (``NonIpopt_Exception_Thrown`` or
``User_Requested_Stop``) or, on some paths, a ``RuntimeError`` that mentions it. The
caller would then go on as if nothing happened. :func:`guard` wraps one solve: it notes a
SIGINT whose handler raised ``KeyboardInterrupt`` during the solve, and after the solve
raises ``KeyboardInterrupt`` again (:func:`check` does the same from a solve's statistics).
"""

from __future__ import annotations

import _thread
import importlib
import os
import signal
import sys
import threading
import time
from collections.abc import Iterator
from contextlib import contextmanager
from types import FrameType
from typing import Any, NoReturn

#: IPOPT return statuses that mean the solve was stopped by a user interrupt
INTERRUPT_STATUSES = frozenset({"User_Requested_Stop"})


def is_interrupt_error(exc: BaseException) -> bool:
    """Whether ``exc`` (a casadi ``RuntimeError``) wraps a ``KeyboardInterrupt``."""
    text = str(exc).lower()
    return "keyboardinterrupt" in text or "interrupt" in text


def check(stats: dict[str, Any]) -> None:
    """Raise ``KeyboardInterrupt`` if a solve's ``stats()`` say a user stopped it."""
    if stats.get("return_status") in INTERRUPT_STATUSES:
        raise KeyboardInterrupt


#: the C module under ``signal`` (no typing stub): its calls run no Python code
_signal: Any = importlib.import_module("_signal")
_SIGINT = int(signal.SIGINT)


def _set_sigint(handler: Any) -> None:
    """Install ``handler`` for SIGINT by the C call alone.

    ``signal.signal`` wraps that call in Python code (enum conversions), where a SIGINT's
    handler can raise half-way; in CI an interrupt casadi had left set failed there as
    ``SystemError: <class 'int'> returned a result with an exception set``, and guard's
    flag stayed installed (see :func:`_raise_interrupt`).
    """
    _signal.signal(_SIGINT, handler)


def _restore_sigint(handler: Any) -> bool:
    """Install ``handler`` for SIGINT whatever arrives meanwhile; whether SIGINT raised.

    A ``KeyboardInterrupt`` raised around the call (by the handler being replaced, or by
    ``handler`` itself once installed) is noted and the call made again: the handler is
    ``handler`` when this returns, and the caller raises the interrupt.
    """
    interrupted = False
    while True:
        try:
            _set_sigint(handler)
            return interrupted
        except KeyboardInterrupt:
            interrupted = True


class _Flag:
    """A SIGINT handler around the current one that notes the interrupts it raised."""

    def __init__(self, prior: Any) -> None:
        self.prior = prior
        self.raised = False

    def __call__(self, signum: int, frame: Any) -> None:
        try:
            self.prior(signum, frame)
        except KeyboardInterrupt:
            self.raised = True
            raise


def _raise_interrupt() -> NoReturn:
    """Raise ``KeyboardInterrupt``, also where casadi left one set as the current error.

    casadi runs Python code (its numpy conversions) from C++: a ``KeyboardInterrupt``
    raised there is caught in C++ but stays set, and the next call that checks turns it
    into ``SystemError: <class 'KeyboardInterrupt'> returned a result with an exception
    set`` (3 of 150 interrupted loops of solves). That error clears it; raised again, the
    interrupt is itself.
    """
    try:
        raise KeyboardInterrupt
    except SystemError:
        pass
    raise KeyboardInterrupt from None


@contextmanager
def guard() -> Iterator[None]:
    """Run a casadi solve; an interrupt it swallowed is raised after it.

    Raises:
        KeyboardInterrupt: SIGINT arrived during the block (and its handler raised
            ``KeyboardInterrupt``), whatever the block then did (casadi may swallow it and
            return None, or fail with another error), or casadi raised a ``RuntimeError``
            about an interrupt.
    """
    flag = None
    try:
        try:
            if threading.current_thread() is threading.main_thread():
                prior = _signal.getsignal(_SIGINT)
                if callable(prior):
                    flag = _Flag(prior)
                    _set_sigint(flag)
            yield
        finally:  # _restore_sigint absorbs a SIGINT meanwhile: the block's error stays
            # (a SystemError from an interrupt casadi left set leaves it with the handler
            # already set, and is an error after a SIGINT: the interrupt, below)
            if flag is not None and _restore_sigint(flag.prior):
                flag.raised = True
    except Exception as exc:
        if (flag is not None and flag.raised) or (isinstance(exc, RuntimeError)
                                                  and is_interrupt_error(exc)):
            _raise_interrupt()
        raise
    if flag is not None and flag.raised:
        _raise_interrupt()


#: text of the warning casadi prints (to ``sys.stderr``) when it catches an interrupt
CASADI_WARNING = 'WARNING("KeyboardInterruptException")'


class _Filtered:
    """A text stream that drops casadi's interrupt warning line.

    casadi writes a message in pieces (``"CasADi - "``, ``"2026"``, ``"-"``, ...,
    ``' WARNING("'``, ``"KeyboardInterruptException"``, ...): a line that starts with
    ``"CasADi - "`` is held until its newline, then dropped or passed on whole.
    """

    def __init__(self, stream: Any) -> None:
        self._stream = stream
        self._held = ""

    def write(self, text: str) -> int:
        if not self._held and not text.startswith("CasADi - "):
            return self._stream.write(text)
        self._held += text
        if "\n" in self._held:
            line, _, rest = self._held.partition("\n")
            self._held = ""
            if CASADI_WARNING not in line:
                self._stream.write(line + "\n")
            if rest:
                self.write(rest)
        return len(text)

    def close_held(self) -> None:
        """Pass on a held, unfinished line."""
        if self._held:
            self._stream.write(self._held)
            self._held = ""

    def __getattr__(self, name: str) -> Any:
        return getattr(self._stream, name)


@contextmanager
def quiet_casadi_warning() -> Iterator[None]:
    """Drop casadi's "KeyboardInterruptException" warning from ``sys.stderr`` in the block.

    The interrupt itself is raised again by :func:`guard`; the command line reports it in
    one line of its own.
    """
    real = sys.stderr
    sys.stderr = filtered = _Filtered(real)
    try:
        yield
    finally:
        filtered.close_held()
        sys.stderr = real


class _Watch:
    """Whether a SIGINT arrived while a command ran (see :func:`watch`)."""

    received = False


_WATCH = _Watch()

#: modules whose functions Python calls from C and whose exceptions it drops with an
#: "Exception ignored in ..." message (weakref callbacks: WeakKeyDictionary's ``remove``)
_CALLBACK_FILES = ("weakref.py", "_weakrefset.py")


def in_ignored_callback(frame: FrameType | None) -> bool:
    """Whether ``frame`` runs inside a callback whose exceptions Python ignores.

    A weakref callback or a ``__del__`` (run by the garbage collector at any moment): a
    ``KeyboardInterrupt`` raised there is printed as "Exception ignored in ..." and lost.
    """
    while frame is not None:
        code = frame.f_code
        if code.co_name == "__del__" or code.co_filename.endswith(_CALLBACK_FILES):
            return True
        frame = frame.f_back
    return False


class _Redeliver:
    """A daemon thread that signals the main thread again a millisecond after it is asked.

    The SIGINT handler asks it when the interrupt landed inside a callback (where raising
    would lose it): the handler then runs again once the callback has returned.
    """

    def __init__(self) -> None:
        self.wanted = threading.Event()
        self.thread: threading.Thread | None = None

    def request(self) -> None:
        if self.thread is None:
            self.thread = threading.Thread(target=self._run, name="scara_opt-sigint",
                                           daemon=True)
            self.thread.start()
        self.wanted.set()

    def _run(self) -> None:
        while True:
            self.wanted.wait()
            self.wanted.clear()
            time.sleep(1e-3)
            _thread.interrupt_main(signal.SIGINT)  # nothing if the handler is gone by now


_REDELIVER = _Redeliver()


def _note_sigint(signum: int, frame: FrameType | None) -> None:
    _WATCH.received = True
    if in_ignored_callback(frame):  # raised there, it would be printed and lost
        _REDELIVER.request()
        return
    raise KeyboardInterrupt


@contextmanager
def watch() -> Iterator[_Watch]:
    """Note every SIGINT of a whole command (then raise ``KeyboardInterrupt`` as Python does).

    Some libraries catch the ``KeyboardInterrupt`` and go on, or fail with another error
    (trimesh's import guards turn it into a ``TypeError``): an error that leaves the block
    after a SIGINT is raised as the ``KeyboardInterrupt`` it was, and the command line asks
    :func:`raise_if_received` before it commits its files. Notes only in the main thread
    with Python's default handler.
    """
    _WATCH.received = False
    main = threading.current_thread() is threading.main_thread()
    prior = _signal.getsignal(_SIGINT) if main else None
    install = prior is signal.default_int_handler
    late = False  # a SIGINT while the prior handler was put back
    try:
        try:
            if install:
                _set_sigint(_note_sigint)
            yield _WATCH
        finally:  # _restore_sigint absorbs a SIGINT meanwhile: the block's error stays
            late = install and _restore_sigint(prior)
            _WATCH.received = _WATCH.received or late
    except Exception:
        if _WATCH.received:  # a library turned the interrupt into another error
            _raise_interrupt()
        raise
    if late:
        _raise_interrupt()


def exit_now(code: int) -> NoReturn:
    """End the process with ``code`` now: stdout and stderr flushed, Python's teardown skipped.

    After a command has finished, Python's teardown (joining threads, atexit handlers, the
    garbage collector, then its signal handlers reset) is where a Ctrl-C printed "Exception
    ignored ..." or a traceback, or killed the process by SIGINT with no message. The
    command line's work is done and its files are written by then: Ctrl-C is ignored from
    here, and the process ends at once with the command's exit code.
    """
    while True:
        try:
            if threading.current_thread() is threading.main_thread():
                _set_sigint(_signal.SIG_IGN)  # the int: _signal refuses the enum
            for stream in (sys.stdout, sys.stderr):
                try:
                    stream.flush()
                except (OSError, ValueError, AttributeError):  # a closed pipe (`| head`)
                    pass
            os._exit(code)
        except KeyboardInterrupt:  # arrived before SIG_IGN took over: once more
            continue


def raise_if_received() -> None:
    """Raise ``KeyboardInterrupt`` if :func:`watch` saw a SIGINT (that someone swallowed)."""
    if _WATCH.received:
        raise KeyboardInterrupt
