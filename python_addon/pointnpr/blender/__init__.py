"""PointNPR inside Blender: render engine, styles as node trees, importer.

``pointnpr.register()`` / ``pointnpr.unregister()`` forward here.
unregister() undoes everything register() did, so the add-on can be
enabled and disabled repeatedly in one session.
"""

from . import edits, engine, import_operators, importer, nodes, segment, settings, sync, ui, versioning

# Order matters: node classes before the properties that point to trees,
# the engine before the panels that name it; versioning last (it migrates
# the open file's legacy nodes, which needs all of them).
_modules = (edits, nodes, settings, engine, ui, import_operators, segment, versioning)
_registered = []


def register():
    if _registered:
        return
    try:
        for module in _modules:
            module.register()
            _registered.append(module)
    except Exception:
        unregister()
        raise


def unregister():
    while _registered:
        module = _registered.pop()
        module.unregister()


def is_registered():
    return bool(_registered)


__all__ = ("edits", "engine", "import_operators", "importer", "nodes", "segment", "settings", "sync", "ui", "versioning", "register",
           "unregister")
