"""File > Import > Point Cloud: the operators (a modal job with a progress
bar and Esc, and the file browser's), the menu entry and drag and drop.
What they run is importer.py's."""

import os

import bpy
from bpy_extras.io_utils import ImportHelper

from .importer import (FILE_EXTENSIONS, OUT_OF_CORE_THRESHOLD, ImportJob, OutOfCore, _core, end_modal_job,
                       import_point_cloud)


class _WindowProgress:
    """progress(done, total, stage) on the window manager's progress bar
    (the cursor counter; a no-op without a window)."""

    def __init__(self, wm):
        self.wm = wm
        self.total = None

    def __call__(self, done, total, stage):
        if self.total != total:
            if self.total is not None:
                self.wm.progress_end()
            self.wm.progress_begin(0, total)
            self.total = total
        self.wm.progress_update(done)

    def end(self):
        if self.total is not None:
            self.wm.progress_end()
            self.total = None


def _report_result(op, objects, recentre, warnings=(), notes=()):
    # A splat capture in Blender 5.3+ is a point cloud (its points), any other scan a mesh.
    points = sum(int(o.get("pointnpr_cache_points", len(o.data.vertices if o.type == 'MESH' else o.data.points)))
                 for o in objects)
    op.report({'INFO'}, "Imported %d points into %d object(s)" % (points, len(objects)))
    cached = [o for o in objects if "pointnpr_cache" in o]
    if cached:
        op.report({'INFO'}, "%d object(s) out of core: light proxies of %s" % (
            len(cached), ", ".join(str(o["pointnpr_cache"]) for o in cached)))
    for note in notes:
        op.report({'INFO'}, note)
    for warning in warnings:  # what the reader let pass (e.g. extra data after a PLY's last element)
        op.report({'WARNING'}, warning)
    if not recentre and objects:
        far = max(max(abs(c) for c in o.bound_box[i]) for o in objects for i in range(8))
        if far > 1.0e5:
            op.report({'WARNING'}, "Coordinates up to %.0f kept without recentring: "
                      "single-precision vertices lose detail at that magnitude" % far)


def _out_of_core(op):
    """The operator's out-of-core options (None when switched off)."""
    return OutOfCore(op.out_of_core_threshold, op.cache_folder) if op.out_of_core else None


def _import_errors():
    # pointnpr.Error: an out-of-core cache that cannot be written (disk full, no permission).
    return (getattr(_core(), "ReadError", ValueError), getattr(_core(), "Error", RuntimeError), OSError, ValueError,
            MemoryError)


class IMPORT_SCENE_OT_pointnpr_cloud_job(bpy.types.Operator):
    """Runs one import in the background of the UI: the file is read in a
    thread, meshes are created one per timer tick, the progress bar moves, and
    ESC cancels (leaving the scene as it was)"""
    bl_idname = "import_scene.pointnpr_cloud_job"
    bl_label = "Importing Point Cloud"
    bl_options = {'REGISTER', 'UNDO', 'INTERNAL'}

    filepath: bpy.props.StringProperty(subtype='FILE_PATH', options={'HIDDEN'})
    split_by_classification: bpy.props.BoolProperty(default=False, options={'HIDDEN'})
    split_by_scan: bpy.props.BoolProperty(default=True, options={'HIDDEN'})
    recentre: bpy.props.BoolProperty(default=True, options={'HIDDEN'})
    out_of_core: bpy.props.BoolProperty(default=True, options={'HIDDEN'})
    out_of_core_threshold: bpy.props.IntProperty(default=OUT_OF_CORE_THRESHOLD, options={'HIDDEN'})
    cache_folder: bpy.props.StringProperty(default="", options={'HIDDEN'})

    def invoke(self, context, event):
        self._job = ImportJob(context, self.filepath, self.split_by_classification, self.recentre,
                              _out_of_core(self), self.split_by_scan)
        self._progress = _WindowProgress(context.window_manager)
        self._job.start_reading_in_thread()
        self._timer = context.window_manager.event_timer_add(0.05, window=context.window)
        context.window_manager.modal_handler_add(self)
        if context.workspace is not None:
            context.workspace.status_text_set(
                "Importing %s (Esc to cancel)" % os.path.basename(self.filepath))
        return {'RUNNING_MODAL'}

    def _finish(self, context):
        end_modal_job(context, self._timer, self._progress)

    def modal(self, context, event):
        if event.type == 'ESC':
            self._finish(context)
            self._job.cancel_reading()
            self._job.cleanup()  # a read still running stops unseen
            self.report({'WARNING'}, "Import of %s cancelled" % os.path.basename(self.filepath))
            return {'CANCELLED'}
        if event.type != 'TIMER':
            return {'PASS_THROUGH'}
        try:
            complete = self._job.step()
        except _import_errors() as exc:
            self._finish(context)
            self._job.cleanup()
            self.report({'ERROR'}, "Cannot import %s: %s" % (os.path.basename(self.filepath), exc))
            return {'CANCELLED'}
        except BaseException:
            self._finish(context)
            self._job.cleanup()
            raise
        self._progress(self._job.steps_done, self._job.total_steps, self._job.stage)
        if not complete:
            return {'RUNNING_MODAL'}
        self._finish(context)
        _report_result(self, self._job.objects, self.recentre, self._job.warnings, self._job.notes)
        return {'FINISHED'}


class IMPORT_SCENE_OT_pointnpr_cloud(bpy.types.Operator, ImportHelper):
    """Import a point cloud (LAS, E57, PLY, PCD, XYZ) as vertex-only meshes"""
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
    split_by_scan: bpy.props.BoolProperty(
        name="One Object per Scan",
        description="E57 files with several scans: one object per scan, named after it, in the file's "
                    "collection (off: the scans merged into one object)",
        default=True)
    recentre: bpy.props.BoolProperty(
        name="Recentre",
        description="Subtract the rounded bounding box centre (kept as the object's "
                    "'pointnpr_origin' property) so that coordinates keep their precision",
        default=True)
    out_of_core: bpy.props.BoolProperty(
        name="Out-of-Core Cache",
        description="Scans above the threshold are written to an on-disk cache (next to the .blend, or in the "
                    "cache folder) and imported as a light proxy: renders stream the cache within a point budget",
        default=True)
    out_of_core_threshold: bpy.props.IntProperty(
        name="Threshold",
        description="Points above which a scan (or a class, when split) is imported out of core",
        default=OUT_OF_CORE_THRESHOLD, min=0)
    cache_folder: bpy.props.StringProperty(
        name="Cache Folder",
        description="Where out-of-core caches are written (empty: next to the .blend, or to the scan "
                    "while the .blend is unsaved)",
        default="", subtype='DIR_PATH')
    background: bpy.props.BoolProperty(
        name="Cancellable",
        description="With a window: read in the background with a progress bar; "
                    "Esc cancels and leaves the scene as it was",
        default=True, options={'HIDDEN', 'SKIP_SAVE'})

    def invoke(self, context, event):
        # A file dropped on the viewport (Blender 4.1+'s FileHandler below)
        # comes with its path: import it, no file browser.
        if self.properties.is_property_set("filepath"):
            return self.execute(context)
        return ImportHelper.invoke(self, context, event)

    def execute(self, context):
        if self.background and not bpy.app.background and context.window is not None:
            # Interactive: hand over to the modal job (progress bar, Esc),
            # which reports its own result.
            started = bpy.ops.import_scene.pointnpr_cloud_job(
                'INVOKE_DEFAULT', filepath=self.filepath,
                split_by_classification=self.split_by_classification, split_by_scan=self.split_by_scan,
                recentre=self.recentre, out_of_core=self.out_of_core, out_of_core_threshold=self.out_of_core_threshold,
                cache_folder=self.cache_folder)
            return {'FINISHED'} if started & {'RUNNING_MODAL', 'FINISHED'} else {'CANCELLED'}
        progress = _WindowProgress(context.window_manager)
        warnings, notes = [], []
        try:
            objects = import_point_cloud(context, self.filepath, self.split_by_classification,
                                         self.recentre, progress=progress, warnings=warnings,
                                         out_of_core=_out_of_core(self), split_by_scan=self.split_by_scan,
                                         notes=notes)
        except _import_errors() as exc:
            self.report({'ERROR'}, "Cannot import %s: %s" % (os.path.basename(self.filepath), exc))
            return {'CANCELLED'}
        finally:
            progress.end()
        _report_result(self, objects, self.recentre, warnings, notes)
        return {'FINISHED'}


def menu_func_import(self, context):
    self.layout.operator(IMPORT_SCENE_OT_pointnpr_cloud.bl_idname, text="Point Cloud (.las, .e57, .ply, .spz, .pcd, .xyz)")


# Drag and drop of scans into the 3D viewport (FileHandler: Blender 4.1+).
# .laz is listed even where the reader lacks it: the import then reports why.
DROP_EXTENSIONS = tuple(sorted(set(FILE_EXTENSIONS) | {"laz"}))
_file_handlers = []
if hasattr(bpy.types, "FileHandler"):
    class IO_FH_pointnpr_cloud(bpy.types.FileHandler):
        bl_idname = "IO_FH_pointnpr_cloud"
        bl_label = "PointNPR Point Cloud"
        bl_import_operator = "import_scene.pointnpr_cloud"
        bl_file_extensions = ";".join("." + e for e in DROP_EXTENSIONS)

        @classmethod
        def poll_drop(cls, context):
            return context.area is not None and context.area.type == 'VIEW_3D'

    _file_handlers.append(IO_FH_pointnpr_cloud)


def register():
    bpy.utils.register_class(IMPORT_SCENE_OT_pointnpr_cloud_job)
    bpy.utils.register_class(IMPORT_SCENE_OT_pointnpr_cloud)
    bpy.types.TOPBAR_MT_file_import.append(menu_func_import)
    for cls in _file_handlers:
        bpy.utils.register_class(cls)


def unregister():
    for cls in reversed(_file_handlers):
        bpy.utils.unregister_class(cls)
    bpy.types.TOPBAR_MT_file_import.remove(menu_func_import)
    bpy.utils.unregister_class(IMPORT_SCENE_OT_pointnpr_cloud)
    bpy.utils.unregister_class(IMPORT_SCENE_OT_pointnpr_cloud_job)
