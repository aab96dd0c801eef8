"""Styles for a preview drawn at a fraction of the frame's resolution.

A viewport that renders at 1/4 of its size while the view moves and then
stretches the image over the region would show 6 px splats as 24 px ones
and outlines four times as thick. Every parameter whose unit is a pixel
("px" in its schema) is therefore divided by the factor, so the preview is
the full frame, smaller: the same look in fewer pixels. Values are clamped
to the parameter's range, and integer parameters are rounded half up but
kept at 1 or more where they were (an outline thinner than a preview pixel
is drawn one preview pixel wide rather than vanishing).
"""

import math

from . import _pointnpr

_PIXEL_UNIT = "px"


def _pixel_params(kind, schema_id):
    """{name: (type, min)} of a schema's parameters measured in pixels."""
    for s in _pointnpr.schemas():
        if s["id"] == schema_id and s["kind"] == kind:
            return {p["name"]: (p["type"], p.get("min")) for p in s["params"] if p.get("unit") == _PIXEL_UNIT}
    return {}


def scaled_params(params, kind, schema_id, factor):
    """A copy of ``params`` (a schema's values) with its pixel-sized values
    divided by ``factor`` (>= 1)."""
    pixel = _pixel_params(kind, schema_id)
    out = dict(params)
    for name, (ptype, lowest) in pixel.items():
        if name not in out:
            continue
        value = out[name] / float(factor)
        if ptype == "int":
            value = int(math.floor(value + 0.5)) if value >= 1 or value == 0 else 1
        if lowest is not None:
            value = max(value, lowest)
        out[name] = value
    return out


def scaled_style(style, factor):
    """``style`` (a pointnpr.Style) with every pixel-sized parameter of its
    mark, filters, depth inpainting and mesh surface divided by ``factor``."""
    if factor == 1:
        return style
    mark_id, mark_params = style.mark
    return _pointnpr.Style(
        mark=(mark_id, scaled_params(mark_params, "mark", mark_id, factor)),
        filters=[(fid, scaled_params(p, "filter", fid, factor)) for fid, p in style.filters],
        inpaint=scaled_params(style.inpaint, "stage", "inpaint", factor),
        surface=scaled_params(style.surface, "mark", "mesh_surface", factor))


def scaled_scene(segments, factor):
    """A pointnpr.Scene of ``segments`` ([(name, Style, instances)], as
    given to Scene.add_segment) with scaled styles; the clouds and meshes
    are the same objects (nothing is copied or uploaded again)."""
    scene = _pointnpr.Scene()
    scaled = {}
    for name, style, instances in segments:
        if id(style) not in scaled:
            scaled[id(style)] = (style, scaled_style(style, factor))
        scene.add_segment(name, scaled[id(style)][1], instances)
    return scene
