"""File > Import > Point Cloud: vertex-only meshes from whatever pointnpr.read reads
(the operators: import_operators.py)."""

import os

import bpy
import numpy as np

from . import e57_import, splats, sync

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
FILE_EXTENSIONS = ("las", "laz", "e57", "ply", "spz", "pcd", "xyz", "pts", "txt", "csv", "asc")


def class_name(code):
    code = int(code)
    return "%s (%d)" % (ASPRS_CLASSES.get(code, "Class"), code)


def _core():
    from .. import _self as pointnpr
    return pointnpr


def rounded_centre(positions):
    """Bounding box centre rounded to whole units (the recentring offset)."""
    if positions.shape[0] == 0:
        return np.zeros(3)
    lo = positions.min(axis=0)
    hi = positions.max(axis=0)
    return np.round((lo + hi) * 0.5)


def local_positions(positions, origin, block=1 << 20):
    """float32 ``positions - origin`` (Blender's vertices), computed in double
    block by block: the same values as ``(positions - origin).astype(float32)``
    without a float64 copy of the whole array next to the reader's."""
    positions = np.asarray(positions)
    out = np.empty(positions.shape, dtype=np.float32)
    origin = np.asarray(origin, dtype=np.float64)
    for first in range(0, positions.shape[0], block):
        np.subtract(positions[first:first + block], origin, out=out[first:first + block], casting='same_kind')
    return out


def _as_uint8_colors(colors):
    colors = np.asarray(colors)
    if colors.dtype == np.uint16:
        colors = (colors >> 8).astype(np.uint8)
    elif colors.dtype.kind == 'f':
        colors = np.clip(np.rint(colors * 255.0), 0, 255).astype(np.uint8)
    return colors.astype(np.uint8, copy=False)


def add_color_attribute(data, colors):
    """The scan colour 'Col' (BYTE_COLOR, sRGB, POINT) of a mesh or point cloud."""
    colors = _as_uint8_colors(colors)
    # One float32 RGBA array, filled in place (no float temporaries per channel).
    rgba = np.ones((len(colors), 4), dtype=np.float32)
    channels = 4 if colors.shape[1] > 3 else 3
    np.divide(colors[:, :channels], np.float32(255.0), out=rgba[:, :channels], dtype=np.float32)
    holder = getattr(data, "color_attributes", None) or data.attributes
    attr = holder.new("Col", 'BYTE_COLOR', 'POINT')
    try:
        attr.data.foreach_set("color_srgb", rgba.reshape(-1))
    except (AttributeError, TypeError):
        rgba[:, :3] = sync.srgb_to_linear(rgba[:, :3])
        attr.data.foreach_set("color", rgba.reshape(-1))
    del rgba
    if hasattr(data, "color_attributes"):
        try:
            data.color_attributes.active_color = attr
        except Exception:
            pass


def create_point_mesh(name, positions, colors=None, intensity=None, classification=None):
    """A vertex-only mesh with 'Col' (BYTE_COLOR, sRGB), 'intensity' (FLOAT)
    and 'classification' (INT) point attributes."""
    n = positions.shape[0]
    mesh = bpy.data.meshes.new(name)
    mesh.vertices.add(n)
    # float32 in C order is what Blender stores: foreach_set reads it as it is.
    mesh.vertices.foreach_set("co", np.ascontiguousarray(positions, dtype=np.float32).reshape(-1))
    if colors is not None:
        add_color_attribute(mesh, colors)
    if intensity is not None:
        attr = mesh.attributes.new("intensity", 'FLOAT', 'POINT')
        attr.data.foreach_set("value", np.ascontiguousarray(intensity, dtype=np.float32))
    if classification is not None:
        attr = mesh.attributes.new("classification", 'INT', 'POINT')
        attr.data.foreach_set("value", np.ascontiguousarray(classification, dtype=np.int32))
    mesh.update()
    return mesh


class PointObjectJob:
    """Creates point objects step by step and can undo all of it: what an
    import or a segmentation made is removed on failure or cancel, so the
    scene is left exactly as it was."""

    def __init__(self):
        self.objects = []        # created, for the result
        self._created = []       # (collection of bpy.data, datablock) to remove on failure

    @staticmethod
    def pick(values, index):
        """The rows of an optional per-point array that belong to a group
        (index None: all of them)."""
        if values is None:
            return None
        values = np.asarray(values)
        return values if index is None else values[index]

    def track(self, blocks, block):
        """Records a datablock (e.g. a new collection) for cleanup()."""
        self._created.append((blocks, block))
        return block

    def add_point_object(self, name, collection, positions, colors=None, intensity=None, classification=None):
        mesh = self.track(bpy.data.meshes, create_point_mesh(name, positions, colors, intensity, classification))
        obj = self.track(bpy.data.objects, bpy.data.objects.new(name, mesh))
        collection.objects.link(obj)
        self.objects.append(obj)
        return obj

    def cleanup(self):
        """Removes everything this job created (after a failure or cancel)."""
        for blocks, block in reversed(self._created):
            try:
                blocks.remove(block)
            except (ReferenceError, RuntimeError):
                pass
        self._created = []
        self.objects = []
        for path in getattr(self, "caches_written", ()):
            for leftover in (path, path + ".partial"):
                try:
                    os.remove(leftover)
                except OSError:
                    pass
        self.caches_written = []


def end_modal_job(context, timer, progress):
    """Ends what a modal job operator started: its timer, the progress
    display and the status-bar hint (importer and segmenter alike)."""
    context.window_manager.event_timer_remove(timer)
    progress.end()
    if context.workspace is not None:
        context.workspace.status_text_set(None)


# Scans above this many points are imported out of core by default: their
# mesh, sync and GPU copies would take more than ~6 GB (issue 14: ~220 bytes
# a point in memory).
OUT_OF_CORE_THRESHOLD = 20_000_000
PROXY_POINTS = 200_000
CACHE_EXTENSION = ".pnprcache"


class OutOfCore:
    """Where and when an import writes an out-of-core cache (docs/io.md#scan-cache)."""

    def __init__(self, threshold=OUT_OF_CORE_THRESHOLD, folder="", proxy_points=PROXY_POINTS):
        self.threshold = int(threshold)
        self.folder = folder
        self.proxy_points = int(proxy_points)

    def wants(self, points):
        return points > self.threshold

    def cache_path(self, scan_path, object_name):
        """The chosen folder, else the .blend's, else the scan's."""
        folder = bpy.path.abspath(self.folder) if self.folder else ""
        if not folder:
            folder = os.path.dirname(bpy.data.filepath) if bpy.data.filepath else os.path.dirname(
                os.path.abspath(scan_path))
        os.makedirs(folder, exist_ok=True)
        safe = "".join(c if c.isalnum() or c in "-_." else "_" for c in object_name)
        return os.path.join(folder, safe + CACHE_EXTENSION)


class ImportCancelled(Exception):
    """The user cancelled the import (ESC); nothing was added to the scene."""


class ImportJob(PointObjectJob):
    """One import, in steps, so that progress can be shown and the user can
    cancel between them: reading (one C++ call, optionally in a thread: the
    reader releases the GIL), then one mesh per group (class). Everything is
    created unlinked and the root collection is linked into the scene only by
    the last step, so a failure or a cancel, followed by cleanup(), leaves
    the scene and bpy.data exactly as they were."""

    def __init__(self, context, filepath, split_by_classification=False, recentre=True, out_of_core=None,
                 split_by_scan=True):
        self.context = context
        self.filepath = filepath
        self.split = split_by_classification
        # E57: one object per scan (named after it) in the file's collection,
        # or all scans merged into one object.
        self.split_scans = split_by_scan
        self._scan_groups = False
        self._normals = None  # E57: the file's, or from the scans' row/column grids
        self._splats = None  # a splat capture's opacity, scales, rotations, SH (splats.py)
        self.recentre = recentre
        # OutOfCore options, or None: scans above its threshold become proxies of a cache.
        self.out_of_core = out_of_core
        self.caches_written = []  # removed again by cleanup()
        self.stem = os.path.splitext(os.path.basename(filepath))[0] or "Point Cloud"
        super().__init__()
        self._reading = None  # BackgroundCall of the reader
        self._streams = None  # streams(), once decided
        self._groups = None
        self._next_group = 0
        self.done = False
        self.warnings = []  # the reader's (metadata "warning")
        self.notes = []  # what the import report lists besides (E57: images, coordinate metadata)
        self._coordinate_metadata = ""
        self._sensor = None  # an organized frame's sensor, in the recentred frame

    # -- progress: steps done / total (total is known once the file is read)
    @property
    def total_steps(self):
        return 2 + (len(self._groups) if self._groups is not None else 1)

    @property
    def steps_done(self):
        if self._groups is None:  # the reader's own progress (LAZ: by chunk)
            return self._reading.fraction if self._reading is not None else 0
        return 1 + self._next_group + (1 if self.done else 0)

    @property
    def stage(self):
        if self._groups is None:
            return "reading %s" % os.path.basename(self.filepath)
        if self._next_group < len(self._groups):
            return "creating mesh %d of %d" % (self._next_group + 1, len(self._groups))
        return "adding to the scene" if not self.done else "done"

    def streams(self):
        """True when the scan goes to caches straight from the file, never
        held whole (a LAS/LAZ scan above the out-of-core threshold): its
        header gives the count before anything is read."""
        if self._streams is None:
            self._streams = False
            if self.out_of_core is not None and self.filepath.lower().endswith((".las", ".laz")):
                header = _core().read_header(self.filepath)
                self._streams = self.out_of_core.wants(int(header["point_count"]))
        return self._streams

    def _read(self, progress=None):
        """The file's points (PointData), or, when it streams, the list of
        caches written from it (pointnpr.write_scan_caches)."""
        core = _core()
        if not self.streams():
            if self.filepath.lower().endswith(".e57"):
                return e57_import.read_e57(core, self.filepath, progress=progress)
            return core.read(self.filepath, progress=progress)

        def path_for(code):
            name = self.stem if code < 0 else "%s %s" % (self.stem, class_name(code))
            path = self.out_of_core.cache_path(self.filepath, name)
            self.caches_written.append(path)
            return path

        return core.write_scan_caches(self.filepath, path_for, origin=None if self.recentre else [0.0, 0.0, 0.0],
                                      split_by_classification=self.split, progress=progress)

    def start_reading_in_thread(self):
        from .background import BackgroundCall

        self.streams()  # the header is read here: a bad one fails at once, on this thread
        self._reading = BackgroundCall(self._read, name="pointnpr-read")

    def cancel_reading(self):
        """Asks a read still running to stop at its next check (LAZ: the next
        chunk); does not wait for it."""
        if self._reading is not None and self._reading.progress is not None:
            self._reading.progress.cancel()

    @property
    def reading(self):
        return self._reading is not None and not self._reading.done

    def step(self):
        """Advances by one step; returns True when the import is complete.
        Raises what the reader raised (ReadError, OSError, ...)."""
        if self.done:
            return True
        if self._groups is None:
            if self._reading is not None:
                if not self._reading.done:
                    return False  # still reading
                data = self._reading.result()
                self._reading.forget_result()  # the reader's arrays go with _prepare's
            else:
                data = self._read()
            if self.streams():
                self._prepare_streamed(data)
            else:
                self._prepare(data)
            return False
        if self._next_group < len(self._groups):
            self._create_group(*self._groups[self._next_group])
            self._next_group += 1
            if self._next_group == len(self._groups):
                # Blender holds the points now: free the file's arrays before
                # the scene (and the first render) needs memory.
                self._local = self._colors = self._intensity = self._classification = self._normals = None
                self._splats = None
            return False
        # Last step: make it visible.
        parent = self.context.view_layer.active_layer_collection.collection \
            if self.context.view_layer is not None else self.context.scene.collection
        parent.children.link(self._root)
        self.done = True
        return True

    def _prepare(self, data):
        positions = np.asarray(data.positions, dtype=np.float64)
        if len(positions) == 0:
            # Nothing to add: an empty collection would be residue.
            raise ValueError("the file contains no points; nothing was imported")
        metadata = dict(data.metadata)
        sensor = metadata.get("sensor_origin")  # an organized frame's sensor: estimated normals face it
        warning = metadata.get("warning")
        if warning:
            self.warnings.append(str(warning))
        attrs = dict(data.attributes)
        # Only what the meshes get is kept; the reader's other columns and its
        # float64 positions are freed when this returns.
        self._colors = attrs.get("colors")
        self._intensity = attrs.get("intensity")
        classification = attrs.get("classification")
        self._classification = None if classification is None else np.asarray(classification)
        scan_index = attrs.get("scan_index")
        scan_names = str(metadata.get("scan_names", "")).split("\n")
        images = metadata.get("images2d")
        if images:  # E57 photos: listed, not (yet) used to colour the points
            self.notes.append("The file holds %d image(s), not imported: %s" % (
                int(metadata.get("images2d_count", 0)), str(images).replace("\n", "; ")))
        self._normals = attrs.get("normals") if metadata.get("format") == "e57" else None
        # A 3D Gaussian splat capture (3DGS PLY, SPZ): its parameters go on the object (splats.py).
        self._splats = [attrs[k] for k in ("opacity", "scales", "rotations", "sh")] \
            if metadata.get("gaussian_splats") else None
        self._splats_antialiased = bool(metadata.get("antialiased", 0))
        self._coordinate_metadata = str(metadata.get("coordinate_metadata", ""))
        if self._coordinate_metadata:  # E57: kept on the objects as 'pointnpr_coordinate_metadata'
            self.notes.append("Coordinate metadata: %s" % self._coordinate_metadata)
        del attrs, data
        self._origin = rounded_centre(positions) if self.recentre else np.zeros(3)
        self._local = local_positions(positions, self._origin)
        self._sensor = None if sensor is None else [float(v) for v in np.asarray(sensor, float) - self._origin]
        del positions
        self._cached = self.out_of_core is not None and self.out_of_core.wants(len(self._local))
        if self._cached and self._splats is not None:
            self.warnings.append("the out-of-core cache keeps the splats' centres and colours only: the "
                                 "gaussians mark cannot draw them (raise the Out-of-Core threshold)")
        self._root = self.track(bpy.data.collections, bpy.data.collections.new(self.stem))
        groups = []
        if self.split_scans and scan_index is not None:
            scan_index = np.asarray(scan_index)
            self._scan_groups = True
            for i in np.unique(scan_index):
                name = scan_names[i] if i < len(scan_names) and scan_names[i].strip() else \
                    "%s scan %d" % (self.stem, i)
                groups.append((name, np.nonzero(scan_index == i)[0]))
        elif self.split and self._classification is not None:
            for code in np.unique(self._classification):
                groups.append((class_name(code), np.nonzero(self._classification == code)[0]))
        else:
            groups.append((None, None))
        self._groups = groups

    def _prepare_streamed(self, caches):
        """Groups of a scan written to caches from the file: one per cache."""
        if not caches or sum(c["points"] for c in caches) == 0:
            raise ValueError("the file contains no points; nothing was imported")
        self._origin = np.asarray(caches[0]["origin"], dtype=np.float64)
        self._cached = True
        self._root = self.track(bpy.data.collections, bpy.data.collections.new(self.stem))
        self._groups = [(None if c["classification"] < 0 else class_name(c["classification"]), c)
                        for c in caches]

    def _create_group(self, label, index):
        if label is None:
            coll, name = self._root, self.stem
        elif self._scan_groups:  # E57 scans: side by side in the file's collection
            coll, name = self._root, label
        else:
            coll = self.track(bpy.data.collections, bpy.data.collections.new(label))
            self._root.children.link(coll)
            name = "%s %s" % (self.stem, label)
        pick = lambda values: self.pick(values, index)  # noqa: E731
        if isinstance(index, dict):  # streamed: the cache is written, add its proxy
            obj = self._add_proxy_object(name, coll, index["path"])
        elif self._cached:
            obj = self._add_cached_object(name, coll, pick(self._local), pick(self._colors),
                                          pick(self._intensity), pick(self._classification))
        elif self._splats is not None and splats.native_point_clouds():  # Blender 5.3+: its own splat type
            obj = splats.add_point_cloud_object(self, name, coll, pick(self._local), pick(self._colors),
                                                *(pick(values) for values in self._splats),
                                                antialiased=self._splats_antialiased)
        else:
            obj = self.add_point_object(name, coll, pick(self._local), pick(self._colors),
                                        pick(self._intensity), pick(self._classification))
            if self._splats is not None:
                splats.write(obj.data, *(pick(values) for values in self._splats), antialiased=self._splats_antialiased)
            normals = pick(self._normals)
            if normals is not None and not np.isnan(normals).any():
                # "N": the point normals the render takes instead of estimating them (sync.read_normals).
                attr = obj.data.attributes.new("N", 'FLOAT_VECTOR', 'POINT')
                attr.data.foreach_set("vector", np.ascontiguousarray(normals, np.float32).reshape(-1))
        obj["pointnpr_origin"] = [float(v) for v in self._origin]
        if self._sensor is not None:
            obj["pointnpr_sensor"] = self._sensor  # estimated normals face it (sync.cloud_for)
        if self._coordinate_metadata:
            obj["pointnpr_coordinate_metadata"] = self._coordinate_metadata

    def _add_cached_object(self, name, collection, local, colors, intensity, classification):
        """Writes the group's points to an out-of-core cache and adds an
        object whose mesh is a light proxy: a seeded subsample (the first
        points of every chunk's resolution queue) for the solid viewport,
        selection and transforms. The render streams the cache
        (sync.cloud_for reads the object's 'pointnpr_cache')."""
        core = _core()
        kwargs = {}
        if colors is not None:
            kwargs["colors"] = _as_uint8_colors(colors)
        if intensity is not None:
            kwargs["intensity"] = np.ascontiguousarray(intensity, dtype=np.float32)
        if classification is not None:
            kwargs["classification"] = np.ascontiguousarray(classification, dtype=np.uint8)
        # The coordinates a mesh would hold (float32 after recentring): the
        # cache renders what the same scan imported in memory renders.
        cloud = core.PointCloud(np.asarray(local, dtype=np.float32), **kwargs)
        path = self.out_of_core.cache_path(self.filepath, name)
        self.caches_written.append(path)
        core.write_scan_cache(path, cloud)
        del cloud  # the cache holds the points now
        cached = core.CachedCloud(path)
        # Point ids are the group's row numbers: the proxy picks its rows by them.
        proxy = np.asarray(cached.cloud(self.out_of_core.proxy_points).point_index)
        pick = lambda values: None if values is None else np.asarray(values)[proxy]  # noqa: E731
        obj = self.add_point_object(name, collection, local[proxy], pick(colors), pick(intensity),
                                    pick(classification))
        return self._reference_cache(obj, path, cached)

    def _add_proxy_object(self, name, collection, path):
        """The light proxy of a cache written straight from the file: the
        same seeded subsample, read back from the cache."""
        cached = _core().CachedCloud(path)
        proxy = cached.proxy(self.out_of_core.proxy_points)
        obj = self.add_point_object(name, collection, proxy["positions"], proxy.get("colors"),
                                    proxy.get("intensity"), proxy.get("classification"))
        return self._reference_cache(obj, path, cached)

    @staticmethod
    def _reference_cache(obj, path, cached):
        obj["pointnpr_cache"] = bpy.path.relpath(path) if bpy.data.filepath else path
        obj["pointnpr_cache_points"] = int(cached.num_points)
        lo, hi = cached.bounds
        obj["pointnpr_cache_bounds"] = [float(v) for v in lo + hi]
        return obj


def import_point_cloud(context, filepath, split_by_classification=False, recentre=True,
                       progress=None, cancelled=None, warnings=None, out_of_core=None, split_by_scan=True,
                       notes=None):
    """Read ``filepath`` and add it to the scene; returns the created objects.

    ``progress(done, total, stage)`` is called after each step and
    ``cancelled()`` is asked between steps (True: stop, raise ImportCancelled).
    On any failure (pointnpr.ReadError, OSError, ...) or cancel, the scene is
    left exactly as it was, and so it is for a file with no points (ValueError).
    What the reader let pass with a warning is appended to ``warnings``.
    ``out_of_core`` (an OutOfCore): groups above its threshold are written
    to caches and added as light proxies that reference them.
    ``split_by_scan`` (E57): one object per scan, named after the file's
    scan names, in the file's collection; False merges the scans. What the
    report lists besides (E57: its images, its coordinate metadata) is
    appended to ``notes``."""
    job = ImportJob(context, filepath, split_by_classification, recentre, out_of_core, split_by_scan)
    try:
        while True:
            if progress is not None:
                progress(job.steps_done, job.total_steps, job.stage)
            if cancelled is not None and cancelled():
                raise ImportCancelled("import of %s cancelled" % os.path.basename(filepath))
            if job.step():
                break
        if progress is not None:
            progress(job.steps_done, job.total_steps, job.stage)
    except BaseException:
        job.cleanup()
        raise
    if warnings is not None:
        warnings.extend(job.warnings)
    if notes is not None:
        notes.extend(job.notes)
    return job.objects
