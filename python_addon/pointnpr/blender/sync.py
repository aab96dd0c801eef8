"""Blender scene -> pointnpr.Scene.

Segments are collections. Every visible object with points belongs to the
segment of (the first scene collection among) its users_collection; objects
directly in the scene collection form a segment named after it. Segment
order is the depth-first (pre-order) order of the collection hierarchy;
objects within a segment are sorted by name.

Point clouds are cached per object at module level, so geometry is uploaded
once and reused across frames and viewport redraws.
"""

import threading
import zlib

import bpy
import numpy as np

from . import edits, mesh_sync, nodes, splats


_COLOR_TYPES = {'BYTE_COLOR', 'FLOAT_COLOR'}


def _core():
    from .. import _self as pointnpr
    return pointnpr


# ---------------------------------------------------------------------------
# Collections, segments and styles

def collection_order(scene):
    """[(collection, style tree or None)] in depth-first pre-order, starting
    with the scene collection; styles inherited from the parent where a
    collection has none, then the scene's default style."""
    scene = getattr(scene, "original", scene)
    default = getattr(scene, "pointnpr_default_style", None)
    if not nodes.is_style_tree(default):
        default = None
    order = []
    seen = set()

    def visit(coll, inherited):
        if coll.name in seen and coll is not scene.collection:
            return
        seen.add(coll.name)
        own = getattr(coll, "pointnpr_style", None)
        style = own if nodes.is_style_tree(own) else inherited
        order.append((coll, style))
        for child in coll.children:
            visit(child, style)

    visit(scene.collection, default)
    return order


def resolve_style(scene, collection):
    """The style tree a collection renders with (own, inherited, scene default) or None."""
    for coll, style in collection_order(scene):
        if coll == collection or coll.name == getattr(collection, "name", None):
            return style
    return None


def source_attributes(core_style):
    """The per-point attributes (names as pointnpr.PointCloud's keywords) the
    host reads for ``core_style`` (a pointnpr.Style), as a tuple in a fixed
    order: what the core's ``Style.source_attributes`` lists, and a splat
    capture's parameters for the gaussians mark (splats.py)."""
    return tuple(sorted(set(core_style.source_attributes) | ({splats.SOURCE} if splats.wanted(core_style) else set())))


# color_source 'auto' draws the first of these an object has (the core's
# AutoColor), so the later ones need not be read where an earlier one is.
AUTO_COLOR_SOURCES = ("colors", "intensity", "classification")


def fallback_attributes(core_style):
    """Of AUTO_COLOR_SOURCES, those ``core_style`` reads only for 'auto'
    colour (no other use of them): cloud_for skips each where the object has
    one before it, e.g. a LiDAR scan's intensity and classification when it
    has colours (8 bytes a point in the core, more while reading)."""
    names = set(core_style.attributes)
    if "auto_color" not in names:
        return ()
    return tuple(a for a in AUTO_COLOR_SOURCES if a not in names)


# ---------------------------------------------------------------------------
# Geometry -> numpy

def has_points(obj):
    data = getattr(obj, "data", None)
    if obj.type == 'MESH':
        return data is not None and len(data.vertices) > 0
    if obj.type == 'POINTCLOUD' and data is not None:
        if hasattr(data, "points"):
            return len(data.points) > 0
        attr = data.attributes.get("position")
        return attr is not None and len(attr.data) > 0
    return False


def read_positions(obj):
    data = obj.data
    if obj.type == 'MESH':
        n = len(data.vertices)
        co = np.empty(n * 3, dtype=np.float32)
        data.vertices.foreach_get("co", co)
    elif hasattr(data, "points"):
        n = len(data.points)
        co = np.empty(n * 3, dtype=np.float32)
        data.points.foreach_get("co", co)
    else:  # point cloud without the legacy 'points' collection
        attr = data.attributes["position"]
        n = len(attr.data)
        co = np.empty(n * 3, dtype=np.float32)
        attr.data.foreach_get("vector", co)
    return co.reshape(n, 3)


def _point_attributes(data):
    return getattr(data, "attributes", None) or ()


def _first_color_attribute(data):
    colors = getattr(data, "color_attributes", None)
    candidates = colors if colors is not None else _point_attributes(data)
    for attr in candidates:
        if attr.data_type in _COLOR_TYPES and attr.domain in ('POINT', 'CORNER') and not attr.name.startswith("."):
            return attr
    return None


def srgb_to_linear(x):
    x = np.clip(x, 0.0, 1.0)
    return np.where(x <= 0.04045, x / 12.92, np.power((x + 0.055) / 1.055, 2.4))


def read_colors(obj):
    """(N,3) uint8 display sRGB from the first point colour attribute, or None."""
    attr = _first_color_attribute(obj.data)
    if attr is None:
        return None
    rgb = mesh_sync.srgb_values(attr)[:, :3]  # a view: converted in place below
    if attr.domain == 'CORNER':
        # Face-corner colours (a mesh drawn as points): each vertex the mean
        # of its corners'.
        loops = obj.data.loops
        vertex = np.empty(len(loops), dtype=np.int64)
        loops.foreach_get("vertex_index", vertex)
        count = np.bincount(vertex, minlength=len(obj.data.vertices)).astype(np.float64)
        mean = np.ones((len(obj.data.vertices), 3))
        for k in range(3):
            total = np.bincount(vertex, weights=rgb[:, k], minlength=len(obj.data.vertices))
            mean[:, k] = np.where(count > 0, total / np.maximum(count, 1.0), 1.0)
        rgb = mean
    # In place: no float temporaries the size of the cloud besides ``values``.
    rgb *= 255.0
    np.rint(rgb, out=rgb)
    np.clip(rgb, 0, 255, out=rgb)
    return rgb.astype(np.uint8)


def _read_point_values(obj, name, data_types, dtype):
    """The values of the point-domain attribute ``name`` of one of
    ``data_types``, as ``dtype``, or None."""
    attrs = _point_attributes(obj.data)
    attr = attrs.get(name) if attrs else None
    if attr is None or attr.domain != 'POINT' or attr.data_type not in data_types:
        return None
    values = np.empty(len(attr.data), dtype=dtype)
    attr.data.foreach_get("value", values)
    return values


def read_intensity(obj):
    return _read_point_values(obj, "intensity", {'FLOAT'}, np.float32)


def read_classification(obj):
    values = _read_point_values(obj, "classification", {'INT', 'INT8'}, np.int32)
    return None if values is None else np.clip(values, 0, 255, out=values).astype(np.uint8)


def read_point_index(obj):
    """Stable point ids from an integer point attribute named "point_index",
    or None (the core then numbers the points in order)."""
    values = _read_point_values(obj, "point_index", {'INT'}, np.int32)
    # The same bits as astype(uint32), without a copy.
    return None if values is None else values.view(np.uint32)


def read_normals(obj):
    """(N,3) float32 normals from a float-vector point attribute named
    "normal" or "N", only for point clouds and meshes without faces (a
    mesh's own "normal" would be its shading normals); None otherwise: the
    core then estimates normals itself. Nothing is made up here."""
    data = obj.data
    if obj.type == 'MESH' and len(getattr(data, "polygons", ())) > 0:
        return None
    attrs = _point_attributes(data)
    if not attrs:
        return None
    for name in ("normal", "N"):
        attr = attrs.get(name)
        if attr is not None and attr.domain == 'POINT' and attr.data_type == 'FLOAT_VECTOR':
            values = np.empty(len(attr.data) * 3, dtype=np.float32)
            attr.data.foreach_get("vector", values)
            return values.reshape(-1, 3)
    return None


_READERS = {
    "colors": read_colors,
    "intensity": read_intensity,
    "classification": read_classification,
    "point_index": read_point_index,
    "normals": read_normals,
    splats.SOURCE: splats.read,
}

# Attributes read per object, for tests and diagnostics:
# [(object name, attribute name)] of the reads since the last clear.
read_log = []


# ---------------------------------------------------------------------------
# Cloud cache

class _CacheEntry:
    __slots__ = ("pending", "data_name", "read_at", "signature")

    def __init__(self, pending, data_name, read_at, signature):
        self.pending = pending      # the PendingCloud read (its cloud once resolved)
        self.data_name = data_name
        self.read_at = read_at      # edits.now() before the object was read
        self.signature = signature  # unedited_signature() then, or None: never trusted unread

    def key(self):
        return self.pending.key()

    def get(self, defer):
        """The PointCloud, or with ``defer`` the PendingCloud where it is not built yet."""
        return self.pending.built() or (self.pending if defer else self.pending.resolve())

    @property
    def cloud(self):
        return self.pending.resolve()


_cloud_cache = {}   # cloud_key() -> _CacheEntry
# reads: objects whose geometry was read; hits: clouds reused; trusted: of
# those, reused without reading the object (no edit since it was read).
_stats = {"uploads": 0, "hits": 0, "trusted": 0, "reads": 0}


def cache_stats():
    return dict(_stats, objects=len(_cloud_cache))


def clear_cache():
    mesh_sync.clear_cache()
    _cloud_cache.clear()
    _scan_caches.clear()
    _stats.update(uploads=0, hits=0, trusted=0, reads=0)
    del read_log[:]


def invalidate(name):
    """Forget the clouds of object ``name`` (its mesh and any point cloud its
    modifiers make) or of objects using data ``name``."""
    mesh_sync.invalidate(name)
    for key in [k for k, e in _cloud_cache.items() if k[1] == name or e.data_name == name]:
        del _cloud_cache[key]


def revalidate(obj):
    """Forget the clouds of evaluated object ``obj`` unless they may be
    trusted unread (a plain object no edit reached since, the same
    signature: see cloud_for): what the viewport calls when it starts, for
    geometry edited while another engine was active."""
    plain = is_plain(obj)
    for key in [k for k in _cloud_cache if k[1] == obj.name]:
        entry = _cloud_cache[key]
        if not (plain and key[0] == obj.type and key[4] is None and entry.signature is not None and
                entry.signature == unedited_signature(obj, key[2]) and
                edits.unchanged_since(entry.read_at, (obj.name, entry.data_name))):
            del _cloud_cache[key]
    mesh_sync.invalidate(obj.name)


def prune_cache(used=None):
    """Drop the clouds of objects that no longer exist (frees their GPU
    memory) and, with ``used`` (the cache keys a scene build used), the
    clouds of those objects made for another set of attributes (their style
    changed)."""
    names = set(bpy.data.objects.keys())
    used = set(used or ())
    mesh_sync.prune_cache({k[1:] for k in used if k[0] == "TRIANGLES"}, names, {k[1] for k in used})
    modes = {}   # (type, name) -> the evaluation modes of its clouds the build used
    for k in used:
        if k[0] != "TRIANGLES":
            modes.setdefault(k[:2], set()).add(k[4])

    def stale(k):
        used_modes = modes.get(k[:2])
        if used_modes is None or k in used:
            return False
        # The same evaluation for other attributes, or a cloud of the object
        # read before it gained (None: had no) modifiers or the reverse; the
        # other depsgraph's cloud of a modified object stays.
        return k[4] in used_modes or k[4] is None or None in used_modes

    for key in [k for k in _cloud_cache if k[1] not in names or stale(k)]:
        del _cloud_cache[key]


_scan_caches = {}   # absolute path -> (mtime_ns, size, pointnpr.CachedCloud)


def cache_path_of(obj):
    """The out-of-core cache an imported proxy references (its 'pointnpr_cache'), or None."""
    get = getattr(obj, "get", None)
    path = get("pointnpr_cache") if get is not None else None
    return bpy.path.abspath(str(path)) if path else None


def cached_cloud_for(obj, path):
    """The pointnpr.CachedCloud of a proxy object, opened once per file
    version (reopened when the file changes). A missing or damaged cache
    raises pointnpr.ReadError naming the object: the render reports it."""
    import os

    core = _core()
    try:
        st = os.stat(path)
        stamp = (st.st_mtime_ns, st.st_size)
        entry = _scan_caches.get(path)
        if entry is None or entry[:2] != stamp:
            _scan_caches.pop(path, None)
            entry = stamp + (core.CachedCloud(path),)
            _scan_caches[path] = entry
    except (OSError, core.ReadError) as exc:
        raise core.ReadError("object '%s' renders the out-of-core cache %s, which cannot be used: %s "
                             "(import the scan again)" % (obj.name, path, getattr(exc, "reason", exc))) from None
    return entry[2]


def cloud_for(obj, attributes, trust_cache=False, fallbacks=(), mode=None, defer=False):
    """The pointnpr.PointCloud of evaluated object ``obj``
    with the source attributes the style needs (a tuple of names, see
    source_attributes(); a single name or None is accepted too). Only those
    attributes are read from the object, and of ``fallbacks`` (see
    fallback_attributes()) only the first the object has. ``mode`` is the
    depsgraph's evaluation mode ('VIEWPORT', 'RENDER'): an object whose
    modifiers may evaluate differently in each keeps a cloud per mode.

    A cached cloud is reused without reading the object again
    - with ``trust_cache`` (viewport, where depsgraph updates invalidate
      entries), or
    - where the object is plain data (is_plain()) and no edit reached it
      since it was read (blender/edits.py) and its unedited_signature() is
      the same: a repeated F12 of a large scan reads nothing.
    Otherwise the geometry is read and a CRC32 of the coordinates and
    attribute bytes decides whether the cached cloud still holds.

    With ``defer`` (the viewport's main thread) a cloud not cached yet is
    returned as a PendingCloud: what was read, built later by resolve()."""
    if attributes is None:
        attributes = ()
    elif isinstance(attributes, str):
        attributes = (attributes,)
    attributes = tuple(sorted(set(attributes)))
    fallbacks = tuple(a for a in AUTO_COLOR_SOURCES if a in fallbacks and a in attributes)
    name = obj.name
    plain = is_plain(obj)
    # Geometry-nodes output appears as an instance named like its object
    # but of another type: the type is part of the key. Two styles asking
    # for different attributes of one object keep one cloud each.
    cache_key = cloud_key(obj, attributes, fallbacks, mode)
    entry = _cloud_cache.get(cache_key)
    if trust_cache and entry is not None:
        _stats["hits"] += 1
        return entry.get(defer)
    data_name = getattr(obj.data, "name", None)
    signature = unedited_signature(obj, attributes) if plain else None
    if entry is not None and signature is not None and entry.signature == signature and \
            edits.unchanged_since(entry.read_at, (name, data_name)):
        _stats["hits"] += 1
        _stats["trusted"] += 1
        return entry.get(defer)
    read_at = edits.now()
    # A plain object's evaluated points are its original data: on the main
    # thread (nothing edits it meanwhile) they are read from there, which
    # spares the copy Blender 3.4 makes of an evaluated mesh's vertices on
    # their first access (0.3 s and 12 B a point at 10M points).
    source = obj.original if plain and threading.current_thread() is threading.main_thread() else obj
    values = {}
    # 'auto' colour's sources first, in its order: once one is found the
    # fallbacks after it are not read.
    colour_found = False
    for attribute in sorted(attributes, key=_read_order):
        reader = _READERS.get(attribute)
        if reader is None:
            continue   # an attribute this add-on cannot read: the core's to handle
        if attribute in fallbacks and colour_found:
            continue
        read_log.append((name, attribute))
        value = reader(source)
        if value is not None:
            values[attribute] = value
            colour_found = colour_found or attribute in AUTO_COLOR_SOURCES
    # The positions last: the colours' float temporaries are gone by then.
    _stats["reads"] += 1
    positions = read_positions(source)  # float32, as Blender stores them
    sensor = source.sensor if isinstance(source, _InstanceCopy) else _sensor_of(source)
    if sensor is not None:
        values["sensor"] = sensor
    pending = PendingCloud(positions, values)
    if defer and entry is None:
        # Nothing to compare with: the CRC and the cloud are the worker's.
        _cloud_cache[cache_key] = _CacheEntry(pending, data_name, read_at, signature)
        _stats["uploads"] += 1
        return pending
    if entry is not None and entry.key() == pending.key():
        _stats["hits"] += 1
        entry.read_at, entry.signature = read_at, signature
        return entry.get(defer)
    entry = _cloud_cache[cache_key] = _CacheEntry(pending, data_name, read_at, signature)
    _stats["uploads"] += 1
    return entry.get(defer)


class PendingCloud:
    """What was read of an object for its pointnpr.PointCloud, built by
    resolve(): in the viewport on its worker thread, where the core's
    constructor (the Morton sort, about 60 % of a 10M-point scan's first
    sync) and the CRC run without the GIL, so Blender's UI thread only
    reads. Resolved once, by whichever thread asks first."""

    def __init__(self, positions, values):
        self.num_points = len(positions)
        self._arrays = (positions, values)
        self._key = None
        self._cloud = None
        self._lock = threading.Lock()

    def key(self):
        """(attribute names, point count, CRC32 of the bytes read): what the cache compares."""
        with self._lock:
            if self._key is None:
                positions, values = self._arrays
                crc = 0
                for value in values.values():   # in read order, then the positions
                    # zlib reads the arrays' own memory (tobytes() would copy them).
                    for part in (value.values() if isinstance(value, dict) else (value,)):
                        crc = zlib.crc32(np.ascontiguousarray(part), crc)
                self._key = (tuple(sorted(values)), len(positions), zlib.crc32(positions, crc))
            return self._key

    def built(self):
        """The pointnpr.PointCloud if it was built, else None."""
        return self._cloud

    def resolve(self):
        """The pointnpr.PointCloud (built on the first call)."""
        self.key()
        with self._lock:
            if self._cloud is None:
                positions, values = self._arrays
                # The core reads float32 positions as they are (in double,
                # point by point); the object's matrix is composed with them
                # in double per chunk.
                splat = values.pop(splats.SOURCE, None) or {}  # its keywords, spelled out
                self._cloud = _core().PointCloud(positions, **values, **splat)
                self._arrays = None
            return self._cloud


def _sensor_of(obj):
    """Where a depth frame's sensor stood, in the object's frame (the
    importer's 'pointnpr_sensor'), or None."""
    sensor = getattr(obj, "original", obj).get("pointnpr_sensor")
    return tuple(float(v) for v in sensor) if sensor is not None and len(sensor) == 3 else None


def resolved(cloud):
    """``cloud`` built: a PendingCloud's PointCloud, anything else as it is."""
    return cloud.resolve() if isinstance(cloud, PendingCloud) else cloud


def is_plain(obj):
    """True for an object whose evaluated points are its own data as stored:
    in Object Mode (edit and sculpt modes keep their changes outside the
    mesh until they are flushed), without modifiers or particle systems
    (evaluated per frame and per viewport / render: geometry nodes, hooks,
    render-only levels), shape keys or animated data, and not an instance.
    Only such an object's cloud is trusted without reading it (cloud_for):
    nothing but an edit can change it, and every edit is seen (edits.py)."""
    original = getattr(obj, "original", None)
    if original is None or isinstance(obj, _InstanceCopy):
        return False
    if getattr(original, "mode", 'OBJECT') != 'OBJECT':
        return False
    if len(getattr(original, "modifiers", ())) or len(getattr(original, "particle_systems", ())):
        return False
    data = getattr(original, "data", None)
    if data is None or getattr(data, "is_editmode", False) or getattr(data, "shape_keys", None) is not None:
        return False
    animation = getattr(data, "animation_data", None)
    return animation is None or (animation.action is None and len(animation.drivers) == 0)


# Points sampled by unedited_signature(): enough to see a script that
# rewrote the whole cloud with foreach_set and no update (Blender's own
# viewport does not see that either), about 2 ms.
_SIGNATURE_SAMPLES = 1024

# Where Blender shares mesh arrays between the original and its evaluated
# copies (implicit sharing, Blender 3.6+), the first access through its API
# to a layer that an evaluation shares copies the whole layer, however few
# points are read: 0.34 s for the positions of 10.2M points in 4.5, paid
# again on every F12 (its depsgraph shares them anew). Above this many
# points the sample is left out there; the edit tracking still decides.
_SAMPLE_COPY_LIMIT = 1_000_000


def _sampling_copies_layers():
    return bpy.app.version >= (3, 6, 0)


def unedited_signature(obj, attributes):
    """What must be the same for a plain object's cloud to be trusted
    unread: its data-block (address and name), point count and bounds (the
    evaluated object's, computed by its evaluation) and, on the main thread,
    a strided sample of its positions and of the attributes read — a safety
    net under the edit tracking, not a proof (an untracked change of a
    single point between the samples is not seen).

    The sample is read from the original data, which a plain object's
    evaluated points are: the first access to an evaluated mesh's vertices
    copies them in Blender 3.4 (0.3 s at 10M points). Off the main thread
    (an F12 in Blender's UI renders on its own, while the UI may edit the
    original) the sample is left out, and so it is for clouds above
    _SAMPLE_COPY_LIMIT points where reading it would copy whole layers."""
    data = obj.data
    original = getattr(getattr(obj, "original", obj), "data", None)
    if obj.type == 'MESH':
        n = len(data.vertices)
    elif hasattr(data, "points"):
        n = len(data.points)
    else:
        n = len(data.attributes["position"].data)
    bounds = tuple(tuple(corner) for corner in getattr(obj, "bound_box", ()))
    sample = None
    if original is not None and threading.current_thread() is threading.main_thread() and \
            not (n > _SAMPLE_COPY_LIMIT and _sampling_copies_layers()):
        sample = hash(tuple(_sample(obj.type, original, n, attributes)))
    return (original.as_pointer() if original is not None else 0, getattr(data, "name", None), n, bounds, sample)


def _sample(obj_type, data, n, attributes):
    """Values of every (n / _SIGNATURE_SAMPLES)-th point of ``data``."""
    if obj_type == 'MESH':
        points, field = data.vertices, "co"
    elif hasattr(data, "points"):
        points, field = data.points, "co"
    else:
        points, field = data.attributes["position"].data, "vector"
    if len(points) != n:
        return [("count", len(points))]
    samples = sorted(set(np.linspace(0, n - 1, min(n, _SIGNATURE_SAMPLES)).astype(np.int64).tolist())) if n else []
    values = [tuple(getattr(points[i], field)) for i in samples]
    attrs = _point_attributes(data)
    for attribute in attributes:
        if attribute == "colors":
            attr = _first_color_attribute(data)
        else:
            found = (attrs.get(name) for name in _SAMPLED_ATTRIBUTES.get(attribute, ())) if attrs else ()
            attr = next((a for a in found if a is not None), None)
        if attr is None:
            values.append((attribute, None))
            continue
        field = mesh_sync.VALUE_FIELDS.get(attr.data_type, "value")
        items = attr.data
        values.append((attribute, attr.name, attr.data_type, attr.domain, len(items)))
        if len(items) == n:
            values.extend(_value_tuple(getattr(items[i], field)) for i in samples)
    return values


# The point attributes each reader reads (see _READERS).
_SAMPLED_ATTRIBUTES = {"intensity": ("intensity",), "classification": ("classification",),
                       "point_index": ("point_index",), "normals": ("normal", "N"),
                       splats.SOURCE: ("opacity", "radiance:base")}


def _value_tuple(value):
    return tuple(value) if hasattr(value, "__len__") else value


def _read_order(attribute):
    """'auto' colour's sources first, in its order, then the others by name."""
    if attribute in AUTO_COLOR_SOURCES:
        return (0, AUTO_COLOR_SOURCES.index(attribute), "")
    return (1, 0, attribute)


def cloud_key(obj, attributes, fallbacks=(), mode=None):
    """The cloud cache's key of ``obj`` read for ``attributes`` (sorted) and
    ``fallbacks``, in evaluation ``mode`` (None for a plain object: the same
    points in the viewport and in renders)."""
    return (obj.type, obj.name, attributes, fallbacks, None if mode is None or is_plain(obj) else mode)


# ---------------------------------------------------------------------------
# Scene building

class SyncResult:
    def __init__(self):
        self.scene = None         # the pointnpr.Scene, once finish() made it
        self.segment_names = []   # index = segment index in the render
        self.segments = []        # (name, pointnpr.Style, instances), as given to Scene.add_segment
        self.warnings = []
        self.num_objects = 0
        self.num_points = 0
        self._lock = threading.Lock()

    def finish(self):
        """The pointnpr.Scene, with every PendingCloud of the segments built
        (the viewport's worker calls it; build_scene does without defer)."""
        with self._lock:
            if self.scene is None:
                segments = [(name, style, [(resolved(c), matrix, obj_name) for c, matrix, obj_name in instances])
                            for name, style, instances in self.segments]
                scene = _core().Scene()
                for name, style, instances in segments:
                    scene.add_segment(name, style, instances)
                self.segments, self.scene = segments, scene
            return self.scene


def _matrix64(matrix):
    return np.array([list(row) for row in matrix], dtype=np.float64)


def _owner_collection(obj, order_index):
    """The first of the object's users_collection that is part of the scene."""
    original = getattr(obj, "original", obj)
    for coll in original.users_collection:
        idx = order_index.get(coll.name)
        if idx is not None:
            return idx
    return None


def visible_instances(depsgraph):
    """[(evaluated object, world matrix 4x4 float64, segment-owner object)]"""
    out = []
    for inst in depsgraph.object_instances:
        # For instances (collection instances, geometry-nodes output such
        # as a PointCloud made from a mesh) 'object' is the instanced
        # evaluated object and 'parent' the object that instances it.
        obj = inst.object
        owner = inst.parent if inst.is_instance and inst.parent is not None else obj
        if obj is None or obj.type not in {'MESH', 'POINTCLOUD'}:
            continue
        if obj.type == 'MESH' and getattr(obj, "mode", 'OBJECT') == 'EDIT':
            obj = _EditModeCopy(obj)
        elif not has_points(obj):
            continue
        elif inst.is_instance:
            obj = _InstanceCopy(obj)
        if not has_points(obj):
            continue
        out.append((obj, _matrix64(inst.matrix_world), owner))
    return out


class _InstanceCopy:
    """What the sync reads of an instanced object (geometry-nodes output),
    taken while the iterator is on it: the object is a temporary the next
    step reuses (garbage afterwards in Blender 4.5+); its data stays."""
    __slots__ = ("name", "type", "data", "material_slots", "sensor")

    def __init__(self, obj):
        self.name, self.type, self.data = obj.name, obj.type, obj.data
        self.sensor = None  # an instance's points are not one sensor's frame
        # Mesh surfaces read their materials through the slots.
        self.material_slots = [_MaterialSlot(slot.material) for slot in getattr(obj, "material_slots", ())]


class _EditModeCopy(_InstanceCopy):
    """An object in Edit Mode: its evaluated mesh wraps the edit mesh and
    has no vertex arrays (no vertices through the API); to_mesh() makes the
    mesh of what is being edited (owned by the evaluated object, freed with
    it). Never trusted unread (sync.is_plain)."""
    __slots__ = ()

    def __init__(self, obj):
        super().__init__(obj)
        self.data = obj.to_mesh()
        self.sensor = _sensor_of(obj)


class _MaterialSlot:
    __slots__ = ("material",)

    def __init__(self, material):
        self.material = material


def scene_sun_direction(depsgraph):
    """World-space unit direction toward the scene's sun lamp (the first
    visible one by name), or None. A sun shines along its local -Z."""
    suns = []
    for inst in depsgraph.object_instances:
        obj = inst.object
        if obj is not None and obj.type == 'LIGHT' and getattr(obj.data, "type", None) == 'SUN':
            suns.append((obj.name, np.array(inst.matrix_world, dtype=np.float64)[:3, 2]))
    if not suns:
        return None
    _name, z = min(suns, key=lambda s: s[0])
    length = np.linalg.norm(z)
    return z / length if length > 0 else None


def _apply_scene_sun(desc, depsgraph, warnings, tree):
    """A style where the mark or the Mesh Surface has light_space
    scene_sun takes its light direction (world azimuth and elevation) from
    the scene's sun lamp, for both (one switch per style: scans and meshes
    lit alike)."""
    surface = desc.get("surface") or {}
    if "scene_sun" not in (desc["mark"][1].get("light_space"), surface.get("light_space")):
        return
    sun = scene_sun_direction(depsgraph)
    if sun is None:
        warnings.append("style '%s' takes its light from the scene's sun lamp, but the scene has none: its own "
                        "light direction is used" % getattr(tree, "name", "default"))
        return
    light = {"light_space": "scene_sun",
             "light_azimuth": float(np.degrees(np.arctan2(sun[1], sun[0]))),
             "light_elevation": float(np.degrees(np.arcsin(np.clip(sun[2], -1.0, 1.0))))}
    if "light_space" in desc["mark"][1]:
        desc["mark"] = (desc["mark"][0], dict(desc["mark"][1], **light))
    desc["surface"] = dict(surface, **light)


def build_scene(depsgraph, frame, trust_cache=False, defer=False):
    """SyncResult with a pointnpr.Scene of the depsgraph's visible point objects
    and styles evaluated at ``frame``. With ``defer`` (the viewport) the
    objects are read but clouds not cached yet are not built: the result's
    scene is None until its finish(), which the caller runs off Blender's
    main thread."""
    result = SyncResult()
    scene = depsgraph.scene
    order = collection_order(scene)
    order_index = {coll.name: i for i, (coll, _style) in enumerate(order)}
    members = {}   # order index -> [(obj, matrix)]
    for obj, matrix, owner in visible_instances(depsgraph):
        idx = _owner_collection(owner, order_index)
        if idx is None:
            idx = 0
        members.setdefault(idx, []).append((obj, matrix))

    style_cache = {}
    used_keys = set()
    for idx in sorted(members):
        coll, tree = order[idx]
        key = tree.name if tree is not None else None
        if key not in style_cache:
            desc = nodes.read_style(tree, frame)
            result.warnings.extend(desc["warnings"])
            _apply_scene_sun(desc, depsgraph, result.warnings, tree)
            core_style = nodes.make_core_style(desc)
            style_cache[key] = (core_style, source_attributes(core_style), fallback_attributes(core_style))
        style, attributes, fallbacks = style_cache[key]
        # Objects with faces go as meshes unless the style draws their
        # vertices (meshes = points: read as clouds, as before meshes were).
        as_meshes = style.surface["meshes"] != "points"
        mesh_attributes = tuple(sorted(style.mesh_source_attributes))
        instances = []
        for obj, matrix in sorted(members[idx], key=lambda m: m[0].name):
            if as_meshes and mesh_sync.has_faces(obj):
                mesh = mesh_sync.mesh_for(obj, mesh_attributes, trust_cache=trust_cache)
                used_keys.add(("TRIANGLES", obj.name, getattr(obj.data, "name", ""), mesh_attributes))
                instances.append((mesh, matrix, obj.name))
                result.num_objects += 1
                continue
            cache_path = cache_path_of(obj)
            if cache_path is not None:
                # An out-of-core scan: the render streams its cache, not the proxy's vertices.
                cloud = cached_cloud_for(obj, cache_path)
            else:
                cloud = cloud_for(obj, attributes, trust_cache=trust_cache, fallbacks=fallbacks, mode=depsgraph.mode,
                                  defer=defer)
                used_keys.add(cloud_key(obj, attributes, fallbacks, depsgraph.mode))
            # Named for the core's warnings: it reports each cause once per
            # frame (missing colours, non-finite points) with the objects.
            instances.append((cloud, matrix, obj.name))
            result.num_objects += 1
            result.num_points += cloud.num_points
        result.segments.append((coll.name, style, instances))
        result.segment_names.append(coll.name)
    prune_cache(used_keys)
    if not defer:
        result.finish()
    return result


def scene_settings(scene):
    """Composite settings dict from Scene.pointnpr (the rasterizer is a
    parameter of the Points mark now, not a scene setting)."""
    settings = getattr(scene, "pointnpr", None)
    if settings is None:
        return {}
    composite = {}
    for param, pid in getattr(settings, "pointnpr_params", ()):
        value = getattr(settings, pid)
        if param["type"] == "color":
            value = tuple(value)
        composite[param["name"]] = value
    return composite
