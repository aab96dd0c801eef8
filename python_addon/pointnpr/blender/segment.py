"""Split a point object into collections: by connected components
(CloudCompare's Label Connected Components), by colour region growing (PCL's
RegionGrowingRGB) or by an integer point attribute (LAS classification,
labels). One collection with one object per segment, under a collection
named after the object; the original object is hidden.

The labels come from one core call on a worker thread (the UI stays alive,
the progress bar follows the core's progress, Esc stops the core within
milliseconds); the objects are then created one per step. A cancel at any
point leaves the scene as it was. ``segment_object`` does the same for
scripts and tests, without a window.
"""
import bpy
import numpy as np

from . import sync
from .background import BackgroundCall
from .importer import PointObjectJob, class_name, end_modal_job

# Share of the progress bar for the labelling; object creation has the rest.
LABELLING_SHARE = 0.5

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
    from .. import _self as pointnpr

    return pointnpr


def read_int_attribute(obj, name):
    attrs = getattr(obj.data, "attributes", None)
    attr = attrs.get(name) if attrs else None
    if attr is None or attr.domain != 'POINT' or attr.data_type not in {'INT', 'INT8', 'BOOLEAN'}:
        raise ValueError("object '%s' has no integer point attribute '%s'" % (obj.name, name))
    values = np.empty(len(attr.data), dtype=np.int32)
    attr.data.foreach_get("value", values)
    return values


class Labelling:
    """One segmentation's core call: the inputs are read from Blender when
    it is made (main thread); ``compute`` touches no Blender data, so it can
    run on a worker thread."""

    def __init__(self, obj, method, octree_level=8, min_points=10, attribute="classification",
                 distance_threshold=0.05, point_color_threshold=6.0, region_color_threshold=5.0,
                 min_cluster_size=10, k=30):
        if sync.cache_path_of(obj) is not None:
            # Its vertices are a subsample: split, it would lose the scan (docs/io.md#scan-cache).
            raise ValueError("object '%s' is the proxy of an out-of-core scan: segment it by importing with "
                             "Split by Classification (one cache per class)" % obj.name)
        self.method = method
        self.min_points = min_points
        self.attribute = attribute
        if method == 'CONNECTED_COMPONENTS':
            self.positions = sync.read_positions(obj).astype(np.float64)
            self.kwargs = dict(level=octree_level, min_points=min_points)
        elif method == 'REGION_GROWING_RGB':
            self.positions = sync.read_positions(obj).astype(np.float64)
            self.colors = sync.read_colors(obj)
            if self.colors is None:
                raise ValueError("object '%s' has no point colours to grow regions on" % obj.name)
            self.kwargs = dict(distance_threshold=distance_threshold, point_color_threshold=point_color_threshold,
                               region_color_threshold=region_color_threshold, min_cluster_size=min_cluster_size,
                               k=k)
        elif method == 'ATTRIBUTE':
            self.values = read_int_attribute(obj, attribute)
        else:
            raise ValueError("unknown segmentation method %r" % method)

    def compute(self, progress=None):
        """(labels, names): int labels per point (-1: unassigned) and a name
        per label value. Raises pointnpr.Cancelled once ``progress`` is
        cancelled."""
        core = _core()
        if self.method == 'CONNECTED_COMPONENTS':
            labels = core.connected_components(self.positions, progress=progress, **self.kwargs)
            names = {int(v): "Component %d" % (v + 1) for v in np.unique(labels) if v >= 0}
            names[-1] = "Small components (< %d points)" % self.min_points
        elif self.method == 'REGION_GROWING_RGB':
            labels = core.region_growing_rgb(self.positions, self.colors, progress=progress, **self.kwargs)
            names = {int(v): "Region %d" % (v + 1) for v in np.unique(labels) if v >= 0}
            names[-1] = "Unassigned"
        else:
            groups = core.split_by_attribute(self.values)
            labels = np.empty(len(self.values), dtype=np.int64)
            names = {}
            for i, (value, idx) in enumerate(groups.items()):
                labels[idx] = i
                names[i] = class_name(value) if self.attribute == "classification" else \
                    "%s %d" % (self.attribute, value)
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

    @property
    def fraction(self):
        """Of the whole segmentation, the labelling being done."""
        return LABELLING_SHARE + (1.0 - LABELLING_SHARE) * self.steps_done / self.total_steps

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
        for key in ("pointnpr_origin", "pointnpr_sensor"):  # the parts share the scan's frame and sensor
            if key in self.source:
                obj[key] = list(self.source[key])


def segment_object(context, obj, method, progress=None, cancelled=None, max_segments=256, **params):
    """Splits ``obj``; returns the created objects. ``progress(fraction,
    stage)`` as the work goes on (stage: "labelling", then "creating");
    ``cancelled()`` is asked every few milliseconds while the core labels
    (True: the core call is stopped) and between the objects created; on
    True, SegmentCancelled is raised with the scene left as it was."""
    call = BackgroundCall(Labelling(obj, method, **params).compute, name="pointnpr-segment")
    while not call.wait(0.005):
        if progress is not None:
            progress(LABELLING_SHARE * call.fraction, "labelling")
        if cancelled is not None and cancelled():
            call.cancel()
            raise SegmentCancelled("segmentation of %s cancelled while labelling" % obj.name)
    labels, names = call.result()
    job = SegmentJob(context, obj, labels, names, max_segments)
    try:
        while True:
            if progress is not None:
                progress(job.fraction, "creating")
            if cancelled is not None and cancelled():
                raise SegmentCancelled("segmentation of %s cancelled" % obj.name)
            if job.step():
                break
        if progress is not None:
            progress(job.fraction, "creating")
    except BaseException:
        job.cleanup()
        raise
    return job.objects


class _Progress:
    """The window manager's progress bar, from 0 to 1."""

    def __init__(self, wm):
        self.wm = wm
        self.started = False

    def __call__(self, fraction, stage=None):
        if not self.started:
            self.wm.progress_begin(0.0, 1.0)
            self.started = True
        self.wm.progress_update(min(max(fraction, 0.0), 1.0))

    def end(self):
        if self.started:
            self.wm.progress_end()
            self.started = False


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
        obj = _point_object(context)
        try:
            labelling = Labelling(obj, self.method, **self._params())
        except (ValueError, _core().Error) as exc:
            self.report({'ERROR'}, str(exc))
            return {'CANCELLED'}
        self._source = obj
        self._call = BackgroundCall(labelling.compute, name="pointnpr-segment")
        self._job = None
        self._progress = _Progress(context.window_manager)
        self._timer = context.window_manager.event_timer_add(0.02, window=context.window)
        context.window_manager.modal_handler_add(self)
        if context.workspace is not None:
            context.workspace.status_text_set("Segmenting %s (Esc to cancel)" % obj.name)
        return {'RUNNING_MODAL'}

    def _finish(self, context):
        end_modal_job(context, self._timer, self._progress)

    def modal(self, context, event):
        if event.type == 'ESC':
            self._finish(context)
            if self._job is None:
                self._call.cancel()  # the core stops at its next check
                self.report({'WARNING'}, "Segmentation cancelled while labelling (%d %% done)"
                            % round(100 * self._call.fraction))
            else:
                self._job.cleanup()
                self.report({'WARNING'}, "Segmentation cancelled")
            return {'CANCELLED'}
        if event.type != 'TIMER':
            return {'PASS_THROUGH'}
        try:
            if self._job is None:
                if not self._call.done:
                    self._progress(LABELLING_SHARE * self._call.fraction)
                    return {'RUNNING_MODAL'}
                labels, names = self._call.result()
                self._job = SegmentJob(context, self._source, labels, names, self.max_segments)
                return {'RUNNING_MODAL'}
            complete = self._job.step()
        except (ValueError, _core().Error) as exc:
            self._finish(context)
            if self._job is not None:
                self._job.cleanup()
            self.report({'ERROR'}, str(exc))
            return {'CANCELLED'}
        except BaseException:
            self._finish(context)
            if self._job is not None:
                self._job.cleanup()
            raise
        self._progress(self._job.fraction)
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
    from . import background

    background.cancel_all()  # a labelling still running must not outlive the add-on
    bpy.types.VIEW3D_MT_object.remove(menu_func)
    bpy.utils.unregister_class(OBJECT_OT_pointnpr_segment)
