"""Viewport frames rendered off Blender's UI thread.

Blender calls view_draw on its UI (main) thread for every redraw; a frame of
a large scan takes the core hundreds of milliseconds or more, which would
freeze navigation. So view_draw only syncs (Blender data can be read on the
main thread alone; the sync is cached), snapshots the camera and the scene
into a *request*, hands it to the one worker thread here and draws the
newest finished frame. The worker calls ``Renderer.render``, which releases
the GIL and runs on the core's own GL thread (cpp/gl/device.h), serialized
with F12 renders by the core's render mutex.

The rules that keep what is drawn honest:

- A request is one camera snapshot and one synced scene: no frame mixes two
  camera positions or two edits.
- Each session (one per viewport's engine instance) holds at most one
  pending request: a newer one replaces it (the replaced one never renders).
- Finished frames are published in request order: a frame older than the
  published one is dropped. A full-quality refinement whose view moved on
  before it finished is cancelled (``progress`` returns False between
  segments and tiles) and dropped: the moving view's reduced frames follow.
- Esc (``cancel()``), closing the viewport (``close()``, from the engine's
  ``__del__``) and unregistering (``shutdown()``) cancel pending work; a
  cancelled request's frame is never published.
- While the view moves, requests render at a reduced resolution (the scene's
  Navigation Resolution, with pixel-sized style parameters scaled by
  preview.py so the preview looks like the frame); once it has rested for
  the Refine Delay, at full resolution: each reduced request comes with the
  full one of its view, which the worker starts when it falls due unless a
  newer request replaced it. A main-thread timer tags the 3D views for
  redraw when a frame is ready.

Timings of PointNPR's main-thread callbacks are kept (``timing``) so the
longest block of Blender's UI thread can be measured.
"""

import atexit
import collections
import threading
import time
import traceback

import bpy

# Bounded logs for tests and diagnostics: (event, generation, detail...).
events = collections.deque(maxlen=4096)
# Per callback: [calls, total ms, max ms] of main-thread time spent here.
timing = {}
_POLL_S = 0.02          # timer period while frames are in flight
_HOLD_POLL_S = 0.01


def reset_timing():
    timing.clear()


class main_thread_timer:
    """Context manager adding the wall time of a main-thread callback to
    ``timing[name]``."""

    def __init__(self, name):
        self.name = name

    def __enter__(self):
        self.t0 = time.perf_counter()
        return self

    def __exit__(self, *_exc):
        ms = (time.perf_counter() - self.t0) * 1000.0
        entry = timing.setdefault(self.name, [0, 0.0, 0.0])
        entry[0] += 1
        entry[1] += ms
        entry[2] = max(entry[2], ms)
        return False


def longest_block_ms():
    return max((e[2] for e in timing.values()), default=0.0)


# Tests hold requests here to make "a frame is in flight" a state they can
# wait on instead of a timing: a function(request) -> True while that
# request must wait (cancelling it still works); None in normal use.
hold = None


class Request:
    """One frame to render: a camera snapshot, a synced scene, a size.
    ``scene`` is a pointnpr.Scene or a function the worker calls for it
    before rendering (the viewport builds new clouds there, off the UI
    thread)."""

    def __init__(self, renderer, scene, camera, width, height, scale, key, render_args):
        self.renderer = renderer
        self.scene = scene
        self.camera = camera
        self.width = width
        self.height = height
        self.scale = scale              # 1 = full quality; k = 1/k of the region's resolution
        self.key = key                  # what the frame shows (view, size, scene state)
        self.render_args = render_args  # time, composite, background, memory_budget_gb
        self.generation = 0
        self.cancelled = None           # reason, once cancelled

    @property
    def full(self):
        return self.scale == 1


class Frame:
    """A finished render: its pixels and what they show."""

    def __init__(self, request, color, render_ms, stats=None):
        self.generation = request.generation
        self.key = request.key
        self.scale = request.scale
        self.width, self.height = request.width, request.height
        self.color = color
        self.render_ms = render_ms
        self.stats = stats or {}  # the core's RenderResult.stats

    @property
    def full(self):
        return self.scale == 1


class Session:
    """The viewport state of one engine instance (one 3D view in Rendered
    shading), shared by the main thread and the worker under ``_lock``."""

    def __init__(self):
        self.pending = None
        self.running = None
        self.deferred = None      # the full frame due once the view has rested
        self.deferred_at = 0.0    # perf_counter time it is due
        self.published = None     # the newest finished Frame
        self.error = None         # the last render's error message, or None
        self.drawn_generation = -1
        self.closed = False
        # Main-thread only: what view_draw asked for last, and when the view last changed.
        self.requested = set()    # {(key, scale)} view_draw asked for last
        self.halted_key = None    # the view Esc stopped at: nothing renders until it changes
        self.synced = None        # the engine's _SyncedScene
        self.last_key = None
        self.last_change = 0.0
        with _lock:
            _sessions.append(self)

    # -- main thread ---------------------------------------------------------
    def submit(self, request, deferred=None, deferred_at=0.0):
        """Render ``request`` next; ``deferred`` (the full frame of the same
        view) once perf_counter() reaches ``deferred_at`` unless a newer
        request comes first. The worker starts it itself, so the refinement
        does not wait for Blender's event loop."""
        with _lock:
            if self.closed:
                return
            request.generation = _next_generation()
            for old in (self.pending, self.deferred):
                if old is not None:
                    self._drop(old, "replaced")
            self.deferred = None
            if deferred is not None:
                deferred.generation = _next_generation()
                self.deferred, self.deferred_at = deferred, deferred_at
                events.append(("deferred", deferred.generation, deferred.scale))
            running = self.running
            if running is not None and running.full and running.key != request.key:
                running.cancelled = running.cancelled or "superseded"
            self.pending = request
            events.append(("submitted", request.generation, request.scale))
            _wake.notify_all()
        _start_worker()
        ensure_polling()

    def cancel(self, reason="cancelled"):
        """Cancel pending and running work (Esc) and the refinement due; what
        was published stays, and nothing renders until the view changes."""
        self.halted_key = self.last_key
        with _lock:
            cancelled = False
            for waiting in (self.pending, self.deferred):
                if waiting is not None:
                    self._drop(waiting, reason)
                    cancelled = True
            self.pending = self.deferred = None
            if self.running is not None and self.running.cancelled is None:
                self.running.cancelled = reason
                cancelled = True
            return cancelled

    def close(self):
        """The viewport closed or the engine was freed: cancel everything."""
        self.cancel("closed")
        with _lock:
            self.closed = True
            self.published = None
            if self in _sessions:
                _sessions.remove(self)

    def busy(self):
        with _lock:
            return self.pending is not None or self.running is not None or self.deferred is not None

    def frame(self):
        with _lock:
            return self.published

    def needs_redraw(self):
        with _lock:
            return self.published is not None and self.published.generation != self.drawn_generation

    # -- worker --------------------------------------------------------------
    def _drop(self, request, reason):
        request.cancelled = request.cancelled or reason
        events.append(("dropped", request.generation, request.scale, reason))

    def _finish(self, request, color, render_ms, error=None, stats=None):
        with _lock:
            if self.running is request:
                self.running = None
            if request.cancelled is not None or self.closed:
                self._drop(request, request.cancelled or "closed")
                return
            if error is not None:
                self.error = error
                events.append(("failed", request.generation, request.scale, error))
                return
            if self.published is not None and self.published.generation > request.generation:
                self._drop(request, "older")
                return
            self.published = Frame(request, color, render_ms, stats)
            self.error = None
            events.append(("published", request.generation, request.scale, render_ms))


_lock = threading.Lock()
_wake = threading.Condition(_lock)
_sessions = []
_generation = [0]
_worker = [None]
_stopping = [False]


def _next_generation():
    _generation[0] += 1
    return _generation[0]


def sessions():
    with _lock:
        return list(_sessions)


def _take_request(now):
    """(session, request) of the oldest pending request of any session, else
    of a deferred one that is due, or None; and when the next deferred one
    falls due (under _lock)."""
    best, due = None, None
    for session in _sessions:
        if session.pending is not None and (best is None or session.pending.generation < best[1].generation):
            best = (session, session.pending)
    if best is None:
        for session in _sessions:
            if session.deferred is None:
                continue
            if session.deferred_at <= now and (best is None or session.deferred.generation < best[1].generation):
                best = (session, session.deferred)
            elif session.deferred_at > now:
                due = session.deferred_at if due is None else min(due, session.deferred_at)
    if best is not None:
        session, request = best
        if session.pending is request:
            session.pending = None
        else:
            session.deferred = None
        session.running = request
    return best, due


def _wait_while_held(request):
    while hold is not None and hold(request):
        if request.cancelled is not None or _stopping[0]:
            return False
        time.sleep(_HOLD_POLL_S)
    return request.cancelled is None


def _render(session, request):
    from .. import _self as pointnpr
    cancelled_error = pointnpr.RenderCancelled
    if not _wait_while_held(request):
        session._finish(request, None, 0.0)
        return
    t0 = time.perf_counter()
    try:
        scene = request.scene() if callable(request.scene) else request.scene
        if request.cancelled is not None:
            session._finish(request, None, 0.0)
            return
        result = request.renderer.render(
            scene, request.camera, request.width, request.height,
            progress=lambda _fraction, _what: request.cancelled is None and not _stopping[0],
            **request.render_args)
    except cancelled_error:
        session._finish(request, None, 0.0)
        return
    except Exception as exc:  # reported by view_draw, never raised into Blender
        traceback.print_exc()
        session._finish(request, None, 0.0, error=str(exc))
        return
    # A read-only view of the result's pixels, which it keeps alive: no copy here.
    session._finish(request, result.color, (time.perf_counter() - t0) * 1000.0, stats=dict(result.stats))


def _worker_main():
    while True:
        with _lock:
            taken = None
            while not _stopping[0]:
                now = time.perf_counter()
                taken, due = _take_request(now)
                if taken is not None:
                    break
                _wake.wait(None if due is None else max(due - now, 0.001))
            if taken is None:
                return
        _render(*taken)


def _start_worker():
    with _lock:
        if _worker[0] is not None and _worker[0].is_alive():
            return
        _stopping[0] = False
        thread = threading.Thread(target=_worker_main, name="PointNPR viewport", daemon=True)
        _worker[0] = thread
    thread.start()


def shutdown(timeout=5.0):
    """Cancel every session's work and stop the worker (add-on unregister)."""
    _stop_worker(timeout)
    if bpy.app.timers.is_registered(_poll):
        bpy.app.timers.unregister(_poll)


def _stop_worker(timeout):
    for session in sessions():
        session.close()
    with _lock:
        _stopping[0] = True
        _wake.notify_all()
        thread = _worker[0]
        _worker[0] = None
    if thread is not None and thread is not threading.current_thread():
        thread.join(timeout)


# Before the core's own exit handler (registered earlier, so run later)
# stops its GL thread: a frame in flight finishes or is cancelled first.
atexit.register(_stop_worker, 30.0)


# ---------------------------------------------------------------------------
# Main-thread polling: redraw the 3D views when a frame is ready.

def _tag_rendered_views():
    wm = getattr(bpy.context, "window_manager", None)
    for window in getattr(wm, "windows", ()):
        screen = window.screen
        for area in getattr(screen, "areas", ()):
            if area.type == 'VIEW_3D' and area.spaces.active.shading.type == 'RENDERED':
                area.tag_redraw()


def _poll():
    with main_thread_timer("timer"):
        try:
            active = sessions()
            if any(s.needs_redraw() for s in active):
                _tag_rendered_views()
            if any(s.busy() or s.needs_redraw() for s in active):
                return _POLL_S
        except Exception:
            traceback.print_exc()
    return None   # nothing in flight: the timer stops until the next request


def ensure_polling():
    if not bpy.app.timers.is_registered(_poll):
        bpy.app.timers.register(_poll, first_interval=_POLL_S)
