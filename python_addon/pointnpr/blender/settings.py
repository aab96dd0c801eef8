"""Scene and collection properties.

Scene.pointnpr holds the composite settings, generated from
``pointnpr.schema("composite")``. Its ``rasterizer`` is a legacy setting:
the rasterizer is now a parameter of each Points mark node; files saved
before that keep the value here, and versioning.py copies it into the Points
nodes that replace their Rasterize nodes. It is no longer drawn nor used for
rendering.
Collection.pointnpr_style and Scene.pointnpr_default_style point to styles.
"""

import bpy

from . import nodes

RASTERIZERS = (
    ("compute", "Compute", "Splats rasterized by compute shaders with 64-bit atomics"),
    ("gl_points", "GL Points", "Splats drawn as OpenGL points"),
)

NAVIGATION_RESOLUTIONS = (
    ("1", "Full", "Render every viewport frame at full resolution"),
    ("2", "1/2", "Half the viewport's resolution while the view moves"),
    ("4", "1/4", "A quarter of the viewport's resolution while the view moves"),
    ("8", "1/8", "An eighth of the viewport's resolution while the view moves"),
)

_classes = []


def _reserved_group_names():
    names = set(dir(bpy.types.PropertyGroup))
    names.update(p.identifier for p in bpy.types.PropertyGroup.bl_rna.properties)
    names.update(("rasterizer", "memory_budget_gb", "point_budget_millions", "viewport_point_budget_millions",
                  "navigation_resolution", "refine_delay"))
    return names


def build_settings_class(schema):
    reserved = _reserved_group_names()
    annotations = {}
    params = []
    for param in schema.get("params", ()):
        pid = nodes.property_identifier(param["name"], reserved)
        annotations[pid] = nodes.make_property(param, update=nodes.on_property_update)
        params.append((dict(param), pid))
    annotations["rasterizer"] = bpy.props.EnumProperty(
        name="Rasterizer (legacy)", items=RASTERIZERS, default="compute",
        description="Scene-wide rasterizer of files saved before the mark stage; now the "
                    "Points mark node's Rasterizer")
    # A render setting, not a style's: the renderer's memory budget.
    annotations["memory_budget_gb"] = bpy.props.FloatProperty(
        name="Memory Budget", default=2.0, min=0.125, max=4096.0, step=25, precision=2,
        description="GL memory a frame may take, in GB: larger frames (posters, prints) are drawn "
                    "in tiles, the same pixels as drawn whole")
    # Level of detail (the resolution queue): most points a frame draws.
    annotations["point_budget_millions"] = bpy.props.FloatProperty(
        name="Point Budget", default=0.0, min=0.0, max=100000.0, step=10, precision=1, unit='NONE',
        description="Most points a final render draws, in millions (0: every point). Over it, every "
                    "visible chunk draws the start of its fixed random order, with one density on "
                    "screen: near chunks keep more, far ones fewer")
    annotations["viewport_point_budget_millions"] = bpy.props.FloatProperty(
        name="Viewport Point Budget", default=3.0, min=0.0, max=100000.0, step=10, precision=1,
        description="Most points the viewport draws, in millions (0: every point): keeps large "
                    "scans interactive; F12 uses Point Budget")
    # Viewport settings (blender/viewport_worker.py), not a style's either.
    annotations["navigation_resolution"] = bpy.props.EnumProperty(
        name="Navigation Resolution", items=NAVIGATION_RESOLUTIONS, default="4",
        description="Viewport resolution while the view moves (pixel sizes of the styles scaled to match); "
                    "the full frame follows once the view rests")
    annotations["refine_delay"] = bpy.props.FloatProperty(
        name="Refine Delay", default=0.5, min=0.0, max=10.0, step=10, precision=2, subtype='TIME_ABSOLUTE',
        unit='TIME_ABSOLUTE',
        description="Seconds the viewport's view must rest before the full-resolution frame is rendered")
    return type("PointNPRSceneSettings", (bpy.types.PropertyGroup,), {
        "__annotations__": annotations,
        "__doc__": schema.get("doc", "PointNPR scene settings"),
        "pointnpr_params": tuple(params),
    })


def register():
    from .. import _self as pointnpr
    cls = build_settings_class(pointnpr.schema("composite"))
    bpy.utils.register_class(cls)
    _classes.append(cls)
    bpy.types.Scene.pointnpr = bpy.props.PointerProperty(type=cls, name="PointNPR")
    bpy.types.Scene.pointnpr_default_style = bpy.props.PointerProperty(
        type=bpy.types.NodeTree, name="Default Style", poll=nodes.poll_style_tree,
        update=nodes.on_property_update,
        description="Style of collections that have none and inherit none")
    bpy.types.Collection.pointnpr_style = bpy.props.PointerProperty(
        type=bpy.types.NodeTree, name="Style", poll=nodes.poll_style_tree,
        update=nodes.on_property_update,
        description="PointNPR style of this collection's points (empty: inherit the parent's)")


def unregister():
    del bpy.types.Collection.pointnpr_style
    del bpy.types.Scene.pointnpr_default_style
    del bpy.types.Scene.pointnpr
    for cls in reversed(_classes):
        bpy.utils.unregister_class(cls)
    _classes.clear()
