"""A core call on a worker thread, for operators that must keep Blender's
UI alive: the core releases the GIL while it works, reports to a
``pointnpr.Progress`` (read for the progress bar) and stops with
``pointnpr.Cancelled`` once that is cancelled (Esc). Calls still running
when the add-on is disabled are cancelled (``cancel_all``)."""
import threading

_running = set()


class BackgroundCall:
    """``fn(*args, progress=..., **kwargs)`` on a thread (without the
    ``progress`` keyword when ``watch`` is False, for calls that take none)."""

    def __init__(self, fn, *args, name="pointnpr", watch=True, **kwargs):
        from .. import _self as pointnpr

        self.progress = pointnpr.Progress() if watch else None
        if watch:
            kwargs["progress"] = self.progress
        self._outcome = None
        self._thread = threading.Thread(target=self._run, args=(fn, args, kwargs), name=name, daemon=True)
        _running.add(self)
        self._thread.start()

    def _run(self, fn, args, kwargs):
        try:
            self._outcome = (True, fn(*args, **kwargs))
        except BaseException as exc:  # handed to the thread that asks for result()
            self._outcome = (False, exc)
        finally:
            _running.discard(self)

    @property
    def done(self):
        return self._outcome is not None

    @property
    def fraction(self):
        """Work done in [0, 1] as the core reports it (0 for unwatched calls)."""
        return self.progress.fraction if self.progress is not None else 0.0

    def wait(self, timeout):
        """True once the call has ended (waits at most ``timeout`` seconds)."""
        self._thread.join(timeout)
        return self.done

    def result(self):
        """The call's value, or what it raised (pointnpr.Cancelled after a cancel)."""
        self._thread.join()
        ok, value = self._outcome
        if not ok:
            raise value
        return value

    def forget_result(self):
        """Drops the reference to a value already taken with result(), so that
        its memory (a whole scan) can go while this call is still referenced."""
        if self._outcome is not None and self._outcome[0]:
            self._outcome = (True, None)

    def cancel(self):
        """Asks the core to stop and waits until it has (at its next check:
        milliseconds). Unwatched calls run to their end."""
        if self.progress is not None:
            self.progress.cancel()
        self._thread.join()


def running():
    """The calls still running."""
    return list(_running)


def cancel_all():
    for call in list(_running):
        call.cancel()
