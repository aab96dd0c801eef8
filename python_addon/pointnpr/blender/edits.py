"""Which objects' geometry was edited since a point cloud was read from them.

An F12 used to read every cached object's vertices and colours again and
checksum them to find them unchanged (1.4 s of a 3.1 s F12 at 10.2M points,
issue 14). Blender says what it re-evaluates: every edit that reaches the
evaluated geometry (an operator, a property, ``mesh.update()`` after
``foreach_set``, edit-mode changes, a modifier's input moving) is a
geometry update of the view layer's depsgraph, and the render operator
evaluates that depsgraph before it renders (measured in Blender 3.4, bpy
4.2 and 5.0: tests/blender/test_sync_trust.py). So persistent handlers
keep a clock of edits here:

- ``depsgraph_update_post``: an object with a geometry update (or any
  update outside Object Mode, or a change of mode), and any update of a
  mesh or point cloud data-block, is stamped with the clock's next tick;
- ``load_post``, ``undo_post``, ``redo_post``: everything read before is
  stale (undo swaps data-blocks without per-object updates).

sync.cloud_for takes ``now()`` before it reads an object and trusts the
cloud later only while ``unchanged_since(that tick, names)``: an edit made
while it was reading (an F12 renders on its own thread) stamps a later
tick, so that cloud is read again next time.
"""

import bpy
from bpy.app.handlers import persistent

_clock = [0]
_stamps = {}     # ID name -> the tick of its last edit
_epoch = [0]     # the tick of the last file load, undo or redo
_modes = {}      # object name -> its mode at its last update
_GEOMETRY_DATA = tuple(getattr(bpy.types, name) for name in ("Mesh", "PointCloud", "Curves")
                       if hasattr(bpy.types, name))


def now():
    """The tick a read that starts now records."""
    return _clock[0]


def tracking():
    """True while the handlers are installed (the add-on is registered):
    without them nothing may be trusted."""
    return _on_depsgraph_update in bpy.app.handlers.depsgraph_update_post


def unchanged_since(tick, names):
    """True if no ID of ``names`` was edited, and no file loaded or undo
    made, after ``tick`` (a value of now())."""
    if not tracking() or _epoch[0] > tick:
        return False
    return all(_stamps.get(name, 0) <= tick for name in names if name)


def mark_edited(name):
    """Record an edit of the ID named ``name`` (the handlers' own entry; tests use it too)."""
    _clock[0] += 1
    _stamps[name] = _clock[0]


def forget_all():
    """Everything read so far is stale."""
    _clock[0] += 1
    _epoch[0] = _clock[0]
    _stamps.clear()
    _modes.clear()


@persistent
def _on_depsgraph_update(_scene, depsgraph=None):
    for update in getattr(depsgraph, "updates", ()):
        id_ = update.id
        if isinstance(id_, bpy.types.Object):
            # Transforms are not part of a cloud (the matrix is read every
            # frame), nor are shading updates in Object Mode (Blender 4.x
            # sends them to every object when any data-block is removed).
            # Sculpt and paint strokes are shading updates: in those modes
            # everything counts, and so does leaving them.
            mode = getattr(id_, "mode", 'OBJECT')
            left = _modes.get(id_.name, mode) != mode
            _modes[id_.name] = mode
            if update.is_updated_geometry or mode != 'OBJECT' or left:
                mark_edited(id_.name)
        elif isinstance(id_, _GEOMETRY_DATA):
            mark_edited(id_.name)


@persistent
def _on_reset(*_args):
    forget_all()


_HANDLERS = (("depsgraph_update_post", _on_depsgraph_update), ("load_post", _on_reset),
             ("undo_post", _on_reset), ("redo_post", _on_reset))


def register():
    for name, handler in _HANDLERS:
        handlers = getattr(bpy.app.handlers, name)
        if handler not in handlers:
            handlers.append(handler)
    # Edits made before the handlers existed were not seen.
    forget_all()


def unregister():
    for name, handler in _HANDLERS:
        handlers = getattr(bpy.app.handlers, name)
        while handler in handlers:
            handlers.remove(handler)
    forget_all()
