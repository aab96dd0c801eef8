"""PointNPR: non-photorealistic rendering of 3D scans.

Importable in plain Python (scripts, tests, farms) and as a Blender add-on.
The Blender part loads only when ``bpy`` is importable.
"""
import atexit as _atexit
import os as _os
import sys as _sys

# The package itself, for its submodules: `from .. import _self as pointnpr`
# works under whatever name the package was imported (a legacy add-on zip
# unpacked under another folder name, bl_ext.<repository>.<id>), where
# `import pointnpr` would find another copy or nothing.
_self = _sys.modules[__name__]

from . import _pointnpr
from ._pointnpr import (  # noqa: F401  (the public API)
    Camera,
    Cancelled,
    Error,
    GLError,
    ParameterError,
    PointCloud,
    Progress,
    RenderCancelled,
    Renderer,
    RenderResult,
    Scene,
    Style,
    TriangleMesh,
    gl_info,
    load_image,
    save_image,
    schemas,
)
from ._pointnpr import (  # noqa: F401  (geometry: cpp/geometry, docs/geometry.md)
    computed_attributes,
    connected_components,
    curvature,
    estimate_normals,
    feature_degree,
    grid_normals,
    knn,
    line_fit,
    feature_chains,
    local_resolution,
    radius_search,
    region_growing_rgb,
    remove_outliers,
    split_by_attribute,
)

try:  # the readers are bound by cpp/python/bind_io.cpp
    from ._pointnpr import PointData, ReadError, read, read_e57_scans, read_header, write  # noqa: F401
    from ._pointnpr import SCAN_CACHE_VERSION, CachedCloud, write_scan_cache, write_scan_caches  # noqa: F401  (docs/io.md#scan-cache)
except ImportError:  # pragma: no cover - only while the readers are absent
    pass

bl_info = {
    "name": "PointNPR",
    "author": "PointNPR developers",
    "version": (0, 1, 0),
    "blender": (3, 4, 0),
    "location": "Render Properties > Render Engine > PointNPR; File > Import > Point Cloud",
    "description": "Non-photorealistic, segment-based rendering of point clouds",
    "category": "Render",
}

# Shaders are installed next to the compiled module.
_pointnpr.set_shader_dir(_os.path.join(_os.path.dirname(_os.path.abspath(__file__)), "shaders"))
_atexit.register(_pointnpr.shutdown)


def schema(schema_id, kind=None):
    """The parameter schema of one mark, filter or stage (see schemas()),
    by its id or a former one (``former_ids``: the pencil_hatching filter
    was ``hatching``, the hatching mark's id, so ``kind`` ('mark', 'filter'
    or 'stage') tells them apart). Without ``kind`` the first match wins:
    current ids first, marks first."""
    matching = [s for s in schemas() if kind in (None, s["kind"])]
    for s in matching:
        if s["id"] == schema_id:
            return s
    for s in matching:
        if schema_id in s.get("former_ids", ()):
            return s
    raise KeyError(f"no {kind or 'schema'} named {schema_id!r}")


def look_at(eye, target, up=(0.0, 0.0, 1.0)):
    """World-from-camera matrix (4x4, float64) of a camera at ``eye`` looking
    at ``target`` with ``up`` roughly up, for ``Camera.perspective``."""
    import numpy as np

    eye, target, up = (np.asarray(v, float) for v in (eye, target, up))
    forward = target - eye
    forward /= np.linalg.norm(forward)
    side = np.cross(forward, up)
    side /= np.linalg.norm(side)
    m = np.eye(4)
    m[:3, 0], m[:3, 1], m[:3, 2], m[:3, 3] = side, np.cross(side, forward), -forward, eye
    return m


def _bundled(folder):
    here = _os.path.join(_os.path.dirname(_os.path.abspath(__file__)), folder)
    names = sorted(f for f in _os.listdir(here) if f.endswith(".png")) if _os.path.isdir(here) else []
    return {_os.path.splitext(f)[0]: _os.path.join(here, f) for f in names}


def paper_textures():
    """Paper height maps shipped with the add-on, {name: path}, for the
    watercolor filter's ``paper`` (made by scripts/make_textures.py)."""
    return _bundled("papers")


def look_up_tables():
    """Colour look-up tables (Hald CLUT images) shipped with the add-on,
    {name: path}, for color_grade's ``lut``; ``identity`` is the one to edit
    in an image editor to make your own."""
    return _bundled("luts")


try:
    import bpy as _bpy  # noqa: F401

    _IN_BLENDER = True
except ImportError:
    _IN_BLENDER = False


def register():
    """Blender add-on entry point."""
    from . import blender

    blender.register()


def unregister():
    from . import blender

    blender.unregister()
