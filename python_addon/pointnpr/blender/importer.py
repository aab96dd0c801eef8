"""File > Import > Point Cloud: vertex-only meshes from whatever pointnpr.read reads."""

import os

import bpy
import numpy as np
from bpy_extras.io_utils import ImportHelper

from . import sync

# ASPRS LAS 1.4 standard point classes.
ASPRS_CLASSES = {
    0: "Never Classified",
    1: "Unclassified",
    2: "Ground",
    3: "Low Vegetation",
    4: "Medium Vegetation",
    5: "High Vegetation",
    6: "Building",
    7: "Low Point (Noise)",
    8: "Model Key-point",
    9: "Water",
    10: "Rail",
    11: "Road Surface",
    12: "Overlap",
    13: "Wire Guard",
    14: "Wire Conductor",
    15: "Transmission Tower",
    16: "Wire Connector",
    17: "Bridge Deck",
    18: "High Noise",
}

# What pointnpr.read accepts (its ReadError lists them for unknown extensions).
FILE_EXTENSIONS = ("las", "ply", "pcd", "xyz", "pts", "txt", "csv")


def class_name(code):
    code = int(code)
    return "%s (%d)" % (ASPRS_CLASSES.get(code, "Class"), code)


def _core():
    import pointnpr
    return pointnpr


def rounded_centre(positions):
    """Bounding box centre rounded to whole units (the recentring offset)."""
    if positions.shape[0] == 0:
        return np.zeros(3)
    lo = positions.min(axis=0)
    hi = positions.max(axis=0)
    return np.round((lo + hi) * 0.5)


def _as_uint8_colors(colors):
    colors = np.asarray(colors)
    if colors.dtype == np.uint16:
        colors = (colors >> 8).astype(np.uint8)
    elif colors.dtype.kind == 'f':
        colors = np.clip(np.rint(colors * 255.0), 0, 255).astype(np.uint8)
    return colors.astype(np.uint8, copy=False)


def create_point_mesh(name, positions, colors=None, intensity=None, classification=None):
    """A vertex-only mesh with 'Col' (BYTE_COLOR, sRGB), 'intensity' (FLOAT)
    and 'classification' (INT) point attributes."""
    n = positions.shape[0]
    mesh = bpy.data.meshes.new(name)
    mesh.vertices.add(n)
    mesh.vertices.foreach_set("co", np.ascontiguousarray(positions, dtype=np.float32).reshape(-1))
    if colors is not None:
        colors = _as_uint8_colors(colors)
        rgba = np.ones((n, 4), dtype=np.float32)
        rgba[:, :3] = colors[:, :3].astype(np.float32) / 255.0
        if colors.shape[1] > 3:
            rgba[:, 3] = colors[:, 3].astype(np.float32) / 255.0
        holder = getattr(mesh, "color_attributes", None) or mesh.attributes
        attr = holder.new("Col", 'BYTE_COLOR', 'POINT')
        try:
            attr.data.foreach_set("color_srgb", rgba.reshape(-1))
        except (AttributeError, TypeError):
            lin = rgba.copy()
            lin[:, :3] = sync.srgb_to_linear(rgba[:, :3])
            attr.data.foreach_set("color", lin.reshape(-1))
        if hasattr(mesh, "color_attributes"):
            try:
                mesh.color_attributes.active_color = attr
            except Exception:
                pass
    if intensity is not None:
        attr = mesh.attributes.new("intensity", 'FLOAT', 'POINT')
        attr.data.foreach_set("value", np.ascontiguousarray(intensity, dtype=np.float32))
    if classification is not None:
        attr = mesh.attributes.new("classification", 'INT', 'POINT')
        attr.data.foreach_set("value", np.ascontiguousarray(classification, dtype=np.int32))
    mesh.update()
    return mesh


def import_point_cloud(context, filepath, split_by_classification=False, recentre=True):
    """Read ``filepath`` and add it to the scene. Raises pointnpr.ReadError
    (or OSError) before anything is created when the file cannot be read.
    Returns the list of created objects."""
    data = _core().read(filepath)
    positions = np.asarray(data.positions, dtype=np.float64)
    attrs = dict(data.attributes)
    colors = attrs.get("colors")
    intensity = attrs.get("intensity")
    classification = attrs.get("classification")
    origin = rounded_centre(positions) if recentre else np.zeros(3)
    local = positions - origin

    stem = os.path.splitext(os.path.basename(filepath))[0] or "Point Cloud"
    parent = context.view_layer.active_layer_collection.collection \
        if context.view_layer is not None else context.scene.collection
    root = bpy.data.collections.new(stem)
    parent.children.link(root)

    groups = []
    if split_by_classification and classification is not None:
        classification = np.asarray(classification)
        for code in np.unique(classification):
            groups.append((class_name(code), np.nonzero(classification == code)[0]))
    else:
        groups.append((None, None))

    created = []
    for label, index in groups:
        def pick(values):
            if values is None:
                return None
            values = np.asarray(values)
            return values if index is None else values[index]
        if label is None:
            coll = root
            name = stem
        else:
            coll = bpy.data.collections.new(label)
            root.children.link(coll)
            name = "%s %s" % (stem, label)
        mesh = create_point_mesh(name, pick(local), pick(colors), pick(intensity), pick(classification))
        obj = bpy.data.objects.new(name, mesh)
        obj["pointnpr_origin"] = [float(v) for v in origin]
        coll.objects.link(obj)
        created.append(obj)
    return created


class IMPORT_SCENE_OT_pointnpr_cloud(bpy.types.Operator, ImportHelper):
    """Import a point cloud (LAS, PLY, PCD, XYZ) as vertex-only meshes"""
    bl_idname = "import_scene.pointnpr_cloud"
    bl_label = "Import Point Cloud"
    bl_options = {'REGISTER', 'UNDO'}

    filename_ext = ".las"
    filter_glob: bpy.props.StringProperty(
        default=";".join("*." + e for e in FILE_EXTENSIONS), options={'HIDDEN'}, maxlen=255)
    split_by_classification: bpy.props.BoolProperty(
        name="Split by Classification",
        description="One collection (and object) per LAS class, named after the ASPRS classes",
        default=False)
    recentre: bpy.props.BoolProperty(
        name="Recentre",
        description="Subtract the rounded bounding box centre (kept as the object's "
                    "'pointnpr_origin' property) so that coordinates keep their precision",
        default=True)

    def execute(self, context):
        core = _core()
        read_error = getattr(core, "ReadError", ValueError)
        try:
            objects = import_point_cloud(context, self.filepath, self.split_by_classification,
                                         self.recentre)
        except (read_error, OSError, ValueError) as exc:
            self.report({'ERROR'}, "Cannot import %s: %s" % (os.path.basename(self.filepath), exc))
            return {'CANCELLED'}
        points = sum(len(o.data.vertices) for o in objects)
        self.report({'INFO'}, "Imported %d points into %d object(s)" % (points, len(objects)))
        if not self.recentre and objects:
            far = max(max(abs(c) for c in o.bound_box[i]) for o in objects for i in range(8))
            if far > 1.0e5:
                self.report({'WARNING'}, "Coordinates up to %.0f kept without recentring: "
                            "single-precision vertices lose detail at that magnitude" % far)
        return {'FINISHED'}


def menu_func_import(self, context):
    self.layout.operator(IMPORT_SCENE_OT_pointnpr_cloud.bl_idname, text="Point Cloud (.las, .ply, .pcd, .xyz)")


def register():
    bpy.utils.register_class(IMPORT_SCENE_OT_pointnpr_cloud)
    bpy.types.TOPBAR_MT_file_import.append(menu_func_import)


def unregister():
    bpy.types.TOPBAR_MT_file_import.remove(menu_func_import)
    bpy.utils.unregister_class(IMPORT_SCENE_OT_pointnpr_cloud)
