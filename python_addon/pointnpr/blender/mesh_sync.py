"""Blender meshes with faces -> pointnpr.TriangleMesh (issue 15).

The evaluated mesh (modifiers and Geometry Nodes applied, as the depsgraph
hands it over; instances come with their own matrices) is triangulated by
Blender's loop triangles. Only what the style reads is read
(Style.mesh_source_attributes): the material's base colour, the first
colour attribute (per vertex or per face corner), the active UV map and the
image of an Image Texture node feeding the Principled BSDF's Base Color.

Meshes are cached per object like clouds (sync.cloud_for): keyed on the
object, the attributes read and a CRC32 of the bytes; in the viewport
(trust_cache) a cached mesh is reused without reading the object again
until a depsgraph update invalidates it.
"""

import zlib

import bpy

import numpy as np


_COLOR_TYPES = {'BYTE_COLOR', 'FLOAT_COLOR'}
# Where an attribute's items hold their value, by data type (QUATERNION's and
# the scalars': "value"); FLOAT4 is Blender 5.3's splat "radiance:base".
VALUE_FIELDS = {'BYTE_COLOR': "color", 'FLOAT_COLOR': "color", 'FLOAT_VECTOR': "vector", 'FLOAT4': "vector"}


def _core():
    from .. import _self as pointnpr
    return pointnpr


def has_faces(obj):
    data = getattr(obj, "data", None)
    return obj.type == 'MESH' and data is not None and len(data.polygons) > 0


def linear_to_srgb(x):
    x = np.clip(np.asarray(x, dtype=np.float64), 0.0, 1.0)
    return np.where(x <= 0.0031308, x * 12.92, 1.055 * np.power(x, 1.0 / 2.4) - 0.055)


# ---------------------------------------------------------------------------
# Materials

def _principled(material):
    """The Principled BSDF feeding the material's output, or None."""
    if material is None or material.node_tree is None:
        return None
    # Blender 5.0 always uses a material's nodes (use_nodes is deprecated).
    if bpy.app.version < (5, 0, 0) and not material.use_nodes:
        return None
    tree = material.node_tree
    outputs = [n for n in tree.nodes if n.type == 'OUTPUT_MATERIAL']
    for out in sorted(outputs, key=lambda n: not getattr(n, "is_active_output", False)):
        surface = out.inputs.get("Surface")
        for link in (surface.links if surface is not None else ()):
            if link.from_node.type == 'BSDF_PRINCIPLED':
                return link.from_node
    return next((n for n in tree.nodes if n.type == 'BSDF_PRINCIPLED'), None)


def material_base_color(material):
    """(r, g, b, a) display sRGB of a material's base colour (the Principled
    BSDF's Base Color, else the viewport colour), or None."""
    if material is None:
        return None
    node = _principled(material)
    if node is not None:
        rgba = tuple(node.inputs["Base Color"].default_value)
    else:
        rgba = tuple(material.diffuse_color)
    rgb = linear_to_srgb(rgba[:3])   # Blender's colours are scene-linear
    return (float(rgb[0]), float(rgb[1]), float(rgb[2]), 1.0)


def material_image(material):
    """The image of an Image Texture node linked to the Principled BSDF's
    Base Color, or None."""
    node = _principled(material)
    if node is None:
        return None
    for link in node.inputs["Base Color"].links:
        src = link.from_node
        if src.type == 'TEX_IMAGE' and src.image is not None and src.image.size[0] > 0:
            return src.image
    return None


def image_rgba(image):
    """(H, W, 4) uint8 display sRGB pixels of a Blender image, bottom row first."""
    w, h = image.size
    px = np.empty(w * h * 4, dtype=np.float32)
    image.pixels.foreach_get(px)
    px = px.reshape(h, w, 4)
    if image.is_float:   # float buffers hold scene-linear values
        px[..., :3] = linear_to_srgb(px[..., :3])
    return np.clip(np.rint(px * 255.0), 0, 255).astype(np.uint8)


def _materials(obj):
    return [slot.material for slot in getattr(obj, "material_slots", ())]


# ---------------------------------------------------------------------------
# Geometry

def _triangles(mesh):
    if hasattr(mesh, "calc_loop_triangles"):
        mesh.calc_loop_triangles()
    tris = mesh.loop_triangles
    n = len(tris)
    verts = np.empty(n * 3, dtype=np.int32)
    loops = np.empty(n * 3, dtype=np.int32)
    mats = np.empty(n, dtype=np.int32)
    tris.foreach_get("vertices", verts)
    tris.foreach_get("loops", loops)
    tris.foreach_get("material_index", mats)
    return verts.reshape(n, 3), loops, mats


def _color_attribute(mesh):
    colors = getattr(mesh, "color_attributes", None)
    candidates = colors if colors is not None else getattr(mesh, "attributes", ())
    active = getattr(colors, "active_color", None) if colors is not None else None
    ordered = ([active] if active is not None else []) + list(candidates)
    for attr in ordered:
        if attr.data_type in _COLOR_TYPES and attr.domain in ('POINT', 'CORNER') and not attr.name.startswith("."):
            return attr
    return None


def srgb_values(attr):
    """(N, 4) float32 display sRGB of the colour attribute ``attr`` (meshes
    and point clouds alike): its 'color_srgb', or on a Blender without it
    its scene-linear 'color' converted."""
    n = len(attr.data)
    values = np.empty(n * 4, dtype=np.float32)
    try:
        attr.data.foreach_get("color_srgb", values)
    except (AttributeError, TypeError):
        attr.data.foreach_get("color", values)
        values[:] = linear_to_srgb(values)
    return values.reshape(n, 4)


def _read_colors(mesh, loops):
    """(N, 4) uint8 display sRGB and 'vertex' / 'corner', or (None, None)."""
    attr = _color_attribute(mesh)
    if attr is None:
        return None, None
    values = srgb_values(attr)
    if attr.domain == 'CORNER':
        values = values[loops]
    rgba = np.clip(np.rint(values * 255.0), 0, 255).astype(np.uint8)
    return rgba, ('corner' if attr.domain == 'CORNER' else 'vertex')


def _read_uvs(mesh, loops):
    layer = mesh.uv_layers.active if len(mesh.uv_layers) else None
    if layer is None:
        return None
    uv = np.empty(len(layer.data) * 2, dtype=np.float32)
    layer.data.foreach_get("uv", uv)
    return uv.reshape(-1, 2)[loops]


def read_mesh(obj, attributes, log=None):
    """Keyword arguments of pointnpr.TriangleMesh for evaluated object ``obj``
    with the ``attributes`` (names of Style.mesh_source_attributes)."""
    mesh = obj.data
    n = len(mesh.vertices)
    co = np.empty(n * 3, dtype=np.float32)
    mesh.vertices.foreach_get("co", co)
    tri, loops, mat_index = _triangles(mesh)
    kwargs = {"positions": co.reshape(n, 3).astype(np.float64), "triangles": tri}
    materials = _materials(obj)
    first = next((m for m in materials if m is not None), None)

    def logged(name):
        if log is not None:
            log.append((obj.name, name))

    if "base_color" in attributes and first is not None:
        logged("base_color")
        kwargs["base_color"] = material_base_color(first)
    if "colors" in attributes:
        logged("colors")
        rgba, domain = _read_colors(mesh, loops)
        if rgba is None and len([m for m in materials if m is not None]) > 1:
            # Several materials and no colour attribute: each triangle in
            # its material's base colour (per corner).
            table = np.array([(material_base_color(m) or (0.8, 0.8, 0.8, 1.0)) for m in materials], np.float64)
            per_tri = table[np.clip(mat_index, 0, len(table) - 1)]
            rgba, domain = np.clip(np.rint(np.repeat(per_tri, 3, axis=0) * 255.0), 0, 255).astype(np.uint8), 'corner'
        if rgba is not None:
            kwargs["colors"], kwargs["color_domain"] = rgba, domain
    if "texture" in attributes and first is not None:
        image = material_image(first)
        uvs = _read_uvs(mesh, loops) if image is not None else None
        if image is not None and uvs is not None:
            logged("texture")
            kwargs["texture"] = image_rgba(image)
            kwargs["uvs"], kwargs["uv_domain"] = uvs, 'corner'
    return kwargs


# ---------------------------------------------------------------------------
# Cache

class _Entry:
    __slots__ = ("key", "mesh", "data_name", "materials")

    def __init__(self, key, mesh, data_name, materials):
        self.key = key
        self.mesh = mesh
        self.data_name = data_name
        self.materials = materials


_mesh_cache = {}   # (object name, mesh data name, attributes) -> _Entry
_stats = {"uploads": 0, "hits": 0}
read_log = []      # [(object name, what)] read since the last clear


def cache_stats():
    return dict(_stats, objects=len(_mesh_cache))


def clear_cache():
    _mesh_cache.clear()
    _stats["uploads"] = _stats["hits"] = 0
    del read_log[:]


def invalidate(name):
    """Forget the meshes of object ``name``, of objects using data ``name``
    or a material or image named ``name``."""
    for key in [k for k, e in _mesh_cache.items()
                if k[0] == name or e.data_name == name or name in e.materials]:
        del _mesh_cache[key]


def prune_cache(used, names, synced=()):
    """Drop the meshes of objects that are gone (``names``: those that
    exist), of objects read for another set of attributes, and of objects
    the last build drew otherwise (``synced``: every object name it used,
    e.g. now as a cloud of vertices)."""
    used_objects = {k[:2] for k in used}
    synced = set(synced)
    for key in [k for k in _mesh_cache if k[0] not in names or (k[:2] in used_objects and k not in used) or
                (k[0] in synced and k[:2] not in used_objects)]:
        del _mesh_cache[key]


def mesh_for(obj, attributes, trust_cache=False):
    """The pointnpr.TriangleMesh of evaluated object ``obj`` with the mesh
    source attributes the style reads."""
    attributes = tuple(sorted(set(attributes or ())))
    # Geometry-nodes instances share their object's name but not its data.
    cache_key = (obj.name, getattr(obj.data, "name", ""), attributes)
    entry = _mesh_cache.get(cache_key)
    if trust_cache and entry is not None:
        _stats["hits"] += 1
        return entry.mesh
    kwargs = read_mesh(obj, attributes, read_log)
    crc = 0
    for name in sorted(kwargs):
        value = kwargs[name]
        crc = zlib.crc32(np.asarray(value).tobytes() if not isinstance(value, str) else value.encode(), crc)
    key = (tuple(sorted(kwargs)), crc)
    if entry is not None and entry.key == key:
        _stats["hits"] += 1
        return entry.mesh
    mesh = _core().TriangleMesh(**kwargs)
    used = set()
    for m in _materials(obj):
        if m is not None:
            used.add(m.name)
            image = material_image(m)
            if image is not None:
                used.add(image.name)
    _mesh_cache[cache_key] = _Entry(key, mesh, getattr(obj.data, "name", None), used)
    _stats["uploads"] += 1
    return mesh
