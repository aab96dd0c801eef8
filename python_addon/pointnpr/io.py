"""Helpers around the point cloud readers bound in ``_pointnpr``.

``pointnpr.read(path)`` returns a ``PointData``; ``to_cloud(data)`` (also
available as ``data.to_cloud()``) turns it into the renderer's ``PointCloud``.
"""
import numpy as _np

from . import _pointnpr

__all__ = ["read", "to_cloud", "ReadError", "PointData", "RENDERED_ATTRIBUTES"]

read = _pointnpr.read
ReadError = _pointnpr.ReadError
PointData = _pointnpr.PointData

# Attributes of a PointData that PointCloud takes, with the dtype it wants.
RENDERED_ATTRIBUTES = {
    "colors": _np.uint8,
    "intensity": _np.float32,
    "classification": _np.uint8,
}


def to_cloud(data):
    """PointCloud (pointnpr.PointCloud) from a PointData: positions plus the
    colors, intensity and classification the file has (others are dropped)."""
    kwargs = {}
    attrs = data.attributes
    for name, dtype in RENDERED_ATTRIBUTES.items():
        values = attrs.get(name)
        if values is not None:
            kwargs[name] = _np.ascontiguousarray(values, dtype=dtype)
    return _pointnpr.PointCloud(_np.ascontiguousarray(data.positions, dtype=_np.float64), **kwargs)
