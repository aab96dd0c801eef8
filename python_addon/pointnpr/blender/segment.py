"""Split a point object into collections: by connected components
(CloudCompare's Label Connected Components), by colour region growing (PCL's
RegionGrowingRGB) or by an integer point attribute (LAS classification,
labels). One collection with one object per segment, under a collection
named after the object; the original object is hidden.

The labels come from the core in one call; the objects are then created
one per step, so that the progress bar moves and Esc cancels (leaving the
scene as it was). ``segment_object`` does the same synchronously for
scripts and tests.
"""
import bpy
import numpy as np

from . import sync
from .importer import PointObjectJob, class_name, end_modal_job

METHODS = (
    ('CONNECTED_COMPONENTS', "Connected Components",
     "Points in 26-connected occupied octree cells (CloudCompare's Label Connected Components)"),
    ('REGION_GROWING_RGB', "Colour Region Growing",
     "Regions of similar colour grown over nearest neighbours (PCL RegionGrowingRGB)"),
    ('ATTRIBUTE', "Integer Attribute",
     "One segment per value of an integer point attribute (classification: ASPRS class names)"),
)


class SegmentCancelled(Exception):
    pass


def _core():
    import pointnpr

    return pointnpr


def read_int_attribute(obj, name):
    attrs = getattr(obj.data, "attributes", None)
    attr = attrs.get(name) if attrs else None
    if attr is None or attr.domain != 'POINT' or attr.data_type not in {'INT', 'INT8', 'BOOLEAN'}:
        raise ValueError("object '%s' has no integer point attribute '%s'" % (obj.name, name))
    values = np.empty(len(attr.data), dtype=np.int32)
    attr.data.foreach_get("value", values)
    return values


def segment_labels(obj, method, octree_level=8, min_points=10, attribute="classification",
                   distance_threshold=0.05, point_color_threshold=6.0, region_color_threshold=5.0,
                   min_cluster_size=10, k=30):
    """(labels, names): int labels per point (-1: unassigned) and a name per
    label value, for ``obj``'s points."""
    core = _core()
    pos = sync.read_positions(obj).astype(np.float64)
    if method == 'CONNECTED_COMPONENTS':
        labels = core.connected_components(pos, level=octree_level, min_points=min_points)
        names = {int(v): "Component %d" % (v + 1) for v in np.unique(labels) if v >= 0}
        names[-1] = "Small components (< %d points)" % min_points
    elif method == 'REGION_GROWING_RGB':
        colors = sync.read_colors(obj)
        if colors is None:
            raise ValueError("object '%s' has no point colours to grow regions on" % obj.name)
        labels = core.region_growing_rgb(pos, colors, distance_threshold=distance_threshold,
                                         point_color_threshold=point_color_threshold,
                                         region_color_threshold=region_color_threshold,
                                         min_cluster_size=min_cluster_size, k=k)
        names = {int(v): "Region %d" % (v + 1) for v in np.unique(labels) if v >= 0}
        names[-1] = "Unassigned"
    elif method == 'ATTRIBUTE':
        values = read_int_attribute(obj, attribute)
        groups = core.split_by_attribute(values)
        labels = np.empty(len(values), dtype=np.int64)
        names = {}
        for i, (value, idx) in enumerate(groups.items()):
            labels[idx] = i
            names[i] = class_name(value) if attribute == "classification" else "%s %d" % (attribute, value)
    else:
        raise ValueError("unknown segmentation method %r" % method)
    return np.asarray(labels), names


class SegmentJob(PointObjectJob):
    """Creates one collection + object per segment, one per step()."""

    def __init__(self, context, obj, labels, names, max_segments=256):
        super().__init__()
        self.context = context
        self.source = obj
        order = [v for v in sorted(names) if v >= 0 and np.any(labels == v)]
        # Beyond max_segments, the smallest segments share one collection.
        sizes = {v: int(np.count_nonzero(labels == v)) for v in order}
        keep = sorted(order, key=lambda v: (-sizes[v], v))[:max_segments]
        rest = [v for v in order if v not in set(keep)]
        self._groups = [(names[v], np.nonzero(labels == v)[0]) for v in sorted(keep)]
        pooled = np.isin(labels, rest) | (labels < 0)
        if np.any(pooled):
            label = names.get(-1, "Other") if not rest else "Other segments"
            self._groups.append((label, np.nonzero(pooled)[0]))
        self._next = 0
        self._positions = sync.read_positions(obj)
        self._colors = sync.read_colors(obj)
        self._intensity = sync.read_intensity(obj)
        self._classification = sync.read_classification(obj)
        self._root = None

    @property
    def total_steps(self):
        return len(self._groups) + 1

    @property
    def steps_done(self):
        return self._next + (1 if self.done else 0)

    done = False

    def step(self):
        if self.done:
            return True
        if self._root is None:
            self._root = self.track(bpy.data.collections,
                                    bpy.data.collections.new("%s segments" % self.source.name))
        if self._next < len(self._groups):
            label, index = self._groups[self._next]
            self._create(label, index)
            self._next += 1
            return False
        parent = self.source.users_collection[0] if self.source.users_collection else self.context.scene.collection
        parent.children.link(self._root)
        layer = self.context.view_layer
        if layer is not None and layer.objects.get(self.source.name) is not None:
            self.source.hide_set(True)
        self.source.hide_render = True
        self.done = True
        return True

    def _create(self, label, index):
        coll = self.track(bpy.data.collections, bpy.data.collections.new(label))
        self._root.children.link(coll)
        name = "%s %s" % (self.source.name, label)
        pick = lambda values: self.pick(values, index)  # noqa: E731
        obj = self.add_point_object(name, coll, pick(self._positions), pick(self._colors),
                                    pick(self._intensity), pick(self._classification))
        obj.matrix_world = self.source.matrix_world.copy()
        if "pointnpr_origin" in self.source:
            obj["pointnpr_origin"] = list(self.source["pointnpr_origin"])


def segment_object(context, obj, method, progress=None, cancelled=None, max_segments=256, **params):
    """Splits ``obj``; returns the created objects. ``progress(done, total)``
    after each step, ``cancelled()`` between steps (True: raise
    SegmentCancelled with the scene left as it was)."""
    labels, names = segment_labels(obj, method, **params)
    job = SegmentJob(context, obj, labels, names, max_segments)
    try:
        while True:
            if progress is not None:
                progress(job.steps_done, job.total_steps)
            if cancelled is not None and cancelled():
                raise SegmentCancelled("segmentation of %s cancelled" % obj.name)
            if job.step():
                break
        if progress is not None:
            progress(job.steps_done, job.total_steps)
    except BaseException:
        job.cleanup()
        raise
    return job.objects


class _Progress:
    def __init__(self, wm):
        self.wm = wm
        self.total = None

    def __call__(self, done, total):
        if self.total is None:
            self.wm.progress_begin(0, total)
            self.total = total
        self.wm.progress_update(done)

    def end(self):
        if self.total is not None:
            self.wm.progress_end()
            self.total = None


def _point_object(context):
    obj = context.active_object
    return obj if obj is not None and obj.type == 'MESH' and len(obj.data.vertices) > 0 else None


class OBJECT_OT_pointnpr_segment(bpy.types.Operator):
    """Split the active point object into collections by connected components, colour regions or an integer attribute"""
    bl_idname = "object.pointnpr_segment"
    bl_label = "Segment Point Cloud"
    bl_options = {'REGISTER', 'UNDO'}

    method: bpy.props.EnumProperty(name="Method", items=METHODS, default='CONNECTED_COMPONENTS')
    octree_level: bpy.props.IntProperty(
        name="Octree Level", min=1, max=21, default=8,
        description="Cells of (1.01 x the largest bounding box extent) / 2^level, as CloudCompare")
    min_points: bpy.props.IntProperty(name="Min Points", min=1, default=10,
                                      description="Smaller components go to one 'small components' collection")
    attribute: bpy.props.StringProperty(name="Attribute", default="classification",
                                        description="Integer point attribute to split by")
    distance_threshold: bpy.props.FloatProperty(name="Distance", min=0.0, default=0.05, unit='LENGTH',
                                                description="Regions closer than this may merge")
    point_color_threshold: bpy.props.FloatProperty(name="Point Colour Threshold", min=0.0, default=6.0,
                                                   description="RGB distance (0-255) between neighbours")
    region_color_threshold: bpy.props.FloatProperty(name="Region Colour Threshold", min=0.0, default=5.0,
                                                    description="RGB distance between region means")
    min_cluster_size: bpy.props.IntProperty(name="Min Region Size", min=1, default=10)
    max_segments: bpy.props.IntProperty(name="Max Collections", min=1, max=4096, default=256,
                                        description="The smallest segments beyond this share one collection")

    @classmethod
    def poll(cls, context):
        return _point_object(context) is not None

    def _params(self):
        if self.method == 'CONNECTED_COMPONENTS':
            return dict(octree_level=self.octree_level, min_points=self.min_points)
        if self.method == 'REGION_GROWING_RGB':
            return dict(distance_threshold=self.distance_threshold,
                        point_color_threshold=self.point_color_threshold,
                        region_color_threshold=self.region_color_threshold,
                        min_cluster_size=self.min_cluster_size)
        return dict(attribute=self.attribute)

    def _start(self, context):
        obj = _point_object(context)
        labels, names = segment_labels(obj, self.method, **self._params())
        return SegmentJob(context, obj, labels, names, self.max_segments)

    def execute(self, context):
        progress = _Progress(context.window_manager)
        try:
            objects = segment_object(context, _point_object(context), self.method, progress=progress,
                                     max_segments=self.max_segments, **self._params())
        except (ValueError, _core().Error) as exc:
            self.report({'ERROR'}, str(exc))
            return {'CANCELLED'}
        finally:
            progress.end()
        self.report({'INFO'}, "Split into %d collection(s)" % len(objects))
        return {'FINISHED'}

    def invoke(self, context, event):
        if bpy.app.background or context.window is None:
            return self.execute(context)
        try:
            self._job = self._start(context)
        except (ValueError, _core().Error) as exc:
            self.report({'ERROR'}, str(exc))
            return {'CANCELLED'}
        self._progress = _Progress(context.window_manager)
        self._timer = context.window_manager.event_timer_add(0.02, window=context.window)
        context.window_manager.modal_handler_add(self)
        if context.workspace is not None:
            context.workspace.status_text_set("Segmenting %s (Esc to cancel)" % self._job.source.name)
        return {'RUNNING_MODAL'}

    def _finish(self, context):
        end_modal_job(context, self._timer, self._progress)

    def modal(self, context, event):
        if event.type == 'ESC':
            self._finish(context)
            self._job.cleanup()
            self.report({'WARNING'}, "Segmentation cancelled")
            return {'CANCELLED'}
        if event.type != 'TIMER':
            return {'PASS_THROUGH'}
        try:
            complete = self._job.step()
        except BaseException:
            self._finish(context)
            self._job.cleanup()
            raise
        self._progress(self._job.steps_done, self._job.total_steps)
        if not complete:
            return {'RUNNING_MODAL'}
        self._finish(context)
        self.report({'INFO'}, "Split into %d collection(s)" % len(self._job.objects))
        return {'FINISHED'}


def menu_func(self, context):
    self.layout.operator(OBJECT_OT_pointnpr_segment.bl_idname)


def register():
    bpy.utils.register_class(OBJECT_OT_pointnpr_segment)
    bpy.types.VIEW3D_MT_object.append(menu_func)


def unregister():
    bpy.types.VIEW3D_MT_object.remove(menu_func)
    bpy.utils.unregister_class(OBJECT_OT_pointnpr_segment)
