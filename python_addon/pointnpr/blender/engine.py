"""The PointNPR render engine: final renders (F12, blender -b -f/-a) and
viewport renders (Rendered shading)."""

import time
import traceback

import bpy
import numpy as np

from . import nodes, sync, viewport_worker

ENGINE_ID = "POINTNPR"
SEGMENT_PASS = "Segment Index"

_renderer = [None]
# Counters for diagnostics and tests.
# viewport_renders counts the frames drawn (reduced and full).
stats = {"final_renders": 0, "viewport_renders": 0, "viewport_draws": 0, "slow_pass_writes": 0,
         "viewport_full_frames": 0, "viewport_reduced_frames": 0}


def _core():
    from .. import _self as pointnpr
    return pointnpr


def renderer():
    """The one pointnpr.Renderer of this Blender session (lazily created)."""
    if _renderer[0] is None:
        _renderer[0] = _core().Renderer()
    return _renderer[0]


def release():
    viewport_worker.shutdown()
    _renderer[0] = None
    sync.clear_cache()


# ---------------------------------------------------------------------------
# Helpers shared by final and viewport renders

def _matrix64(matrix):
    return np.array([list(row) for row in matrix], dtype=np.float64)


def render_size(scene):
    r = scene.render
    scale = r.resolution_percentage / 100.0
    return max(1, int(r.resolution_x * scale)), max(1, int(r.resolution_y * scale))


def scene_time(scene):
    r = scene.render
    fps = r.fps / (r.fps_base or 1.0)
    return (scene.frame_current + scene.frame_subframe) / fps


def scene_frame(scene):
    return scene.frame_current + scene.frame_subframe


def background(scene):
    if scene.render.film_transparent:
        return (0.0, 0.0, 0.0, 0.0)
    world = scene.world
    if world is None:
        return (0.0, 0.0, 0.0, 1.0)
    c = world.color
    return (float(c[0]), float(c[1]), float(c[2]), 1.0)


def _camera_world_matrix(cam_obj):
    m = _matrix64(cam_obj.matrix_world)
    # Blender normalises the camera's axes (scale does not zoom).
    for col in range(3):
        length = np.linalg.norm(m[:3, col])
        if length > 0:
            m[:3, col] /= length
    return m


def make_camera(depsgraph, cam_obj, width, height):
    """pointnpr.Camera for a camera object and a render size."""
    core = _core()
    if cam_obj is None:
        raise RuntimeError("The scene has no active camera")
    cam_obj = cam_obj.evaluated_get(depsgraph)
    scene = depsgraph.scene
    cam = cam_obj.data
    if cam_obj.type != 'CAMERA':
        raise RuntimeError("Active camera '%s' is not a camera object" % cam_obj.name)
    world_from_camera = _camera_world_matrix(cam_obj)
    r = scene.render
    if cam.type == 'PANO':
        raise RuntimeError("Panoramic cameras are not supported by PointNPR")
    common = dict(sensor_fit=cam.sensor_fit, shift_x=float(cam.shift_x), shift_y=float(cam.shift_y),
                  clip_start=float(cam.clip_start), clip_end=float(cam.clip_end),
                  width=int(width), height=int(height),
                  # Blender's ycor: the core scales the image height by it.
                  pixel_aspect=float(r.pixel_aspect_y) / float(r.pixel_aspect_x))
    try:
        if cam.type == 'ORTHO':
            return core.Camera.orthographic(world_from_camera, ortho_scale=float(cam.ortho_scale), **common)
        return core.Camera.perspective(world_from_camera, lens=float(cam.lens),
                                       sensor_width=float(cam.sensor_width),
                                       sensor_height=float(cam.sensor_height), **common)
    except core.ParameterError as e:
        # A NaN in its matrix, a scale of 0...: say which camera.
        raise core.ParameterError("camera '%s': %s" % (cam_obj.name, e)) from None


def _set_pass(render_pass, array):
    """Copy an (H, W[, C]) float image into a render pass (same row order)."""
    channels = render_pass.channels
    pixels = np.ascontiguousarray(array, dtype=np.float32).reshape(-1, channels)
    rect = render_pass.rect
    # bpy_prop_array.foreach_set takes the (pixels, channels) shape in 3.x;
    # try the flat layout too before the slow sequence assignment.
    for data in (pixels, pixels.reshape(-1)):
        try:
            rect.foreach_set(data)
            return
        except (AttributeError, TypeError, ValueError):
            continue
    stats["slow_pass_writes"] += 1
    render_pass.rect = pixels


def _find_pass(layer, name, view):
    found = layer.passes.find_by_name(name, view)
    if found is None:
        for p in layer.passes:
            if p.name == name:
                return p
    return found


def memory_budget_gb(scene):
    """Scene.pointnpr's memory budget (GB; 0 = the core's default)."""
    return float(getattr(getattr(scene, "pointnpr", None), "memory_budget_gb", 0.0))


def point_budget(scene, viewport=False):
    """Scene.pointnpr's point budget for final renders or the viewport (points; 0 = all)."""
    settings = getattr(scene, "pointnpr", None)
    name = "viewport_point_budget_millions" if viewport else "point_budget_millions"
    return int(round(float(getattr(settings, name, 0.0)) * 1e6))


def stats_line(synced, result):
    """The viewport header's line: segments, points, and what the point budget kept."""
    line = "PointNPR: %d segments, %s points" % (len(synced.segment_names), "{:,}".format(synced.num_points))
    if result is not None and "point_budget_level" in result.stats:
        line += " (%s drawn: point budget)" % "{:,}".format(int(result.stats["point_budget_points"]))
    return line


def do_render(scene_depsgraph, camera, width, height, progress=None, trust_cache=False, viewport=False):
    """Sync and render; returns (pointnpr render result, SyncResult)."""
    scene = scene_depsgraph.scene
    synced = sync.build_scene(scene_depsgraph, scene_frame(scene), trust_cache=trust_cache)
    composite = sync.scene_settings(scene)
    result = renderer().render(synced.scene, camera, width, height, time=scene_time(scene),
                               composite=composite, background=background(scene),
                               progress=progress, memory_budget_gb=memory_budget_gb(scene),
                               point_budget=point_budget(scene, viewport))
    return result, synced


# ---------------------------------------------------------------------------
# Viewport drawing

def _image_shader():
    import gpu
    for name in ('IMAGE', '2D_IMAGE'):
        try:
            return gpu.shader.from_builtin(name)
        except (ValueError, SystemError):
            continue
    raise RuntimeError("no builtin image shader")


class _ViewportImage:
    """An RGBA float texture drawn over the whole region."""

    def __init__(self, color):
        import gpu
        h, w = color.shape[:2]
        flat = np.ascontiguousarray(color, dtype=np.float32).reshape(-1)
        buf = gpu.types.Buffer('FLOAT', flat.size, flat)
        self.texture = gpu.types.GPUTexture((w, h), format='RGBA32F', data=buf)
        self.size = (w, h)

    def draw(self, w, h):
        """Over (0, 0)-(w, h): a reduced frame is stretched over the region."""
        from gpu_extras.batch import batch_for_shader
        shader = _image_shader()
        batch = batch_for_shader(shader, 'TRI_STRIP', {
            "pos": ((0, 0), (w, 0), (0, h), (w, h)),
            "texCoord": ((0, 0), (1, 0), (0, 1), (1, 1)),
        })
        shader.bind()
        shader.uniform_sampler("image", self.texture)
        batch.draw(shader)


# ---------------------------------------------------------------------------

class PointNPRRenderEngine(bpy.types.RenderEngine):
    bl_idname = ENGINE_ID
    bl_label = "PointNPR"
    bl_use_preview = False
    bl_use_postprocess = True

    # -- passes ------------------------------------------------------------
    def update_render_passes(self, scene=None, renderlayer=None):
        self.register_pass(scene, renderlayer, "Combined", 4, "RGBA", 'COLOR')
        if renderlayer is not None and renderlayer.use_pass_z:
            self.register_pass(scene, renderlayer, "Depth", 1, "Z", 'VALUE')
        self.register_pass(scene, renderlayer, SEGMENT_PASS, 1, "X", 'VALUE')

    # -- final render ------------------------------------------------------
    def render(self, depsgraph):
        try:
            self._render(depsgraph)
        except Exception as exc:  # never let an exception reach Blender
            cancelled = getattr(_core(), "RenderCancelled", None)
            if cancelled is not None and isinstance(exc, cancelled):
                return
            message = "PointNPR: %s" % (exc,)
            traceback.print_exc()
            try:
                self.report({'ERROR'}, message)
            except Exception:
                pass
            if hasattr(self, "error_set"):
                try:
                    self.error_set(message)
                except Exception:
                    pass

    def _render(self, depsgraph):
        scene = depsgraph.scene
        view_layer = depsgraph.view_layer
        width, height = render_size(scene)
        cam_obj = self.camera_override or scene.camera
        camera = make_camera(depsgraph, cam_obj, width, height)

        def progress(fraction, text):
            try:
                self.update_progress(min(max(float(fraction), 0.0), 1.0))
                self.update_stats("PointNPR", str(text))
            except Exception:
                pass
            return not self.test_break()

        self.update_stats("PointNPR", "Syncing scene")
        result, synced = do_render(depsgraph, camera, width, height, progress=progress)
        for warning in list(synced.warnings) + list(getattr(result, "warnings", ())):
            self.report({'WARNING'}, "PointNPR: %s" % warning)

        # Border render: Blender's result covers only the border rectangle
        # (same integer rounding as Blender's display rectangle).
        x0, y0, x1, y1 = 0, 0, width, height
        r = scene.render
        if r.use_border:
            x0, x1 = int(r.border_min_x * width), int(r.border_max_x * width)
            y0, y1 = int(r.border_min_y * height), int(r.border_max_y * height)
            if x1 <= x0 or y1 <= y0:
                return

        def crop(image):
            return image[y0:y1, x0:x1]

        rr = self.begin_result(0, 0, x1 - x0, y1 - y0, layer=view_layer.name)
        try:
            view = self.active_view_get() or ""
            layer = rr.layers[0]
            _set_pass(_find_pass(layer, "Combined", view), crop(result.color))
            if view_layer.use_pass_z:
                depth_pass = _find_pass(layer, "Depth", view)
                if depth_pass is not None:
                    _set_pass(depth_pass, crop(result.depth))
            seg_pass = _find_pass(layer, SEGMENT_PASS, view)
            if seg_pass is not None:
                _set_pass(seg_pass, crop(result.segment_index).astype(np.float32))
        finally:
            self.end_result(rr)
        self.update_progress(1.0)
        stats["final_renders"] += 1

    # -- viewport ----------------------------------------------------------
    # view_draw syncs on the main thread (only after an edit: a moving view
    # re-uses the synced scene), hands the frame to viewport_worker and
    # draws the newest finished one; every callback is timed there.
    def view_update(self, context, depsgraph):
        with viewport_worker.main_thread_timer("view_update"):
            self._view_update(depsgraph)

    def _view_update(self, depsgraph):
        try:
            first = not getattr(self, "_pointnpr_synced", False)
            for update in depsgraph.updates:
                id_ = update.id
                if isinstance(id_, bpy.types.Object) and update.is_updated_geometry:
                    sync.invalidate(id_.name)
                elif isinstance(id_, (bpy.types.Mesh,)) or \
                        (hasattr(bpy.types, "PointCloud") and isinstance(id_, bpy.types.PointCloud)):
                    sync.invalidate(id_.name)
                elif isinstance(id_, (bpy.types.Material, bpy.types.Image)):
                    sync.invalidate(id_.name)   # meshes coloured by it (blender/mesh_sync.py)
            if first:
                # Geometry may have changed while another engine was active
                # (what an F12 read and no edit reached since is kept).
                for obj in depsgraph.objects:
                    sync.revalidate(obj)
            self._pointnpr_synced = True
            self._pointnpr_dirty = True
        except Exception as exc:
            traceback.print_exc()
            self._pointnpr_error = str(exc)

    def view_draw(self, context, depsgraph):
        with viewport_worker.main_thread_timer("view_draw"):
            self._view_draw(context, depsgraph)

    def __del__(self):
        # The viewport closed or left Rendered shading: cancel its work.
        try:
            session = self.__dict__.get("_pointnpr_session")
        except ReferenceError:
            return
        if session is not None:
            session.close()

    def _session(self):
        session = getattr(self, "_pointnpr_session", None)
        if session is None:
            session = self._pointnpr_session = viewport_worker.Session()
        return session

    def _synced(self, depsgraph, session):
        """The synced scene (_SyncedScene), re-synced after an edit."""
        scene = depsgraph.scene
        state = (nodes.generation(), scene_frame(scene), tuple(background(scene)))
        synced = getattr(session, "synced", None)
        if synced is not None and synced.state == state and not getattr(self, "_pointnpr_dirty", True):
            return synced
        self._pointnpr_dirty = False
        try:
            session.synced = _SyncedScene(depsgraph, state)
            self.update_stats("", stats_line(session.synced.result, None))
        except Exception as exc:
            traceback.print_exc()
            session.synced = _SyncedScene(None, state, error=str(exc))
            self.update_stats("", "PointNPR error: %s" % exc)
        return session.synced

    def _view_draw(self, context, depsgraph):
        import gpu
        region = context.region
        rv3d = context.region_data
        scene = depsgraph.scene
        width, height = region.width, region.height
        if width < 1 or height < 1:
            return
        session = self._session()
        synced = self._synced(depsgraph, session)
        if synced.error is not None:
            self._pointnpr_error = synced.error
            self._pointnpr_image = None
            return
        view = _matrix64(rv3d.view_matrix)
        proj = _matrix64(rv3d.window_matrix)
        key = (width, height, view.tobytes(), proj.tobytes(), synced.serial)
        now = time.perf_counter()
        if key != session.last_key:
            session.last_key, session.last_change = key, now
        factor = navigation_factor(scene)
        delay = refine_delay(scene)
        resting = factor == 1 or now - session.last_change >= delay
        scale = 1 if resting else factor
        frame = session.frame()
        if (frame is None or frame.key != key or (resting and not frame.full)) and \
                (key, scale) not in session.requested and session.halted_key != key:
            camera = _core().Camera.from_matrices(view, proj)   # any size: its aspect is the matrices'

            def request(k):
                # Ceil: a reduced image covers the region (stretched by < 1 of its pixels).
                # The scene is made on the worker: building new clouds is its work.
                return viewport_worker.Request(renderer(), lambda: synced.scene_at(k), camera, -(-width // k),
                                               -(-height // k), k, key, synced.render_args_at(k))
            if scale == 1:
                session.requested = {(key, 1)}
                session.submit(request(1))
            else:
                # The full frame of this view follows when it has rested.
                session.requested = {(key, scale), (key, 1)}
                session.submit(request(scale), deferred=request(1), deferred_at=session.last_change + delay)
        if session.error is not None:
            self._pointnpr_error = session.error
            self.update_stats("", "PointNPR error: %s" % session.error)
        if frame is not None and frame.generation != session.drawn_generation:
            t0 = time.perf_counter()
            self._pointnpr_image = _ViewportImage(frame.color)
            stats["viewport_upload_ms"] = (time.perf_counter() - t0) * 1000.0
            stats["viewport_renders"] += 1
            stats["viewport_full_frames" if frame.full else "viewport_reduced_frames"] += 1
            session.drawn_generation = frame.generation
            viewport_worker.events.append(("drawn", frame.generation, frame.scale, frame.key == key))
            self._pointnpr_error = None
            self.update_stats("", stats_line(synced.result, frame))
        image = getattr(self, "_pointnpr_image", None)
        if image is None:
            return
        gpu.state.blend_set('ALPHA_PREMULT')
        self.bind_display_space_shader(scene)
        try:
            image.draw(width, height)
            stats["viewport_draws"] += 1
        finally:
            self.unbind_display_space_shader()
            gpu.state.blend_set('NONE')


def navigation_factor(scene):
    """1/k of the viewport's resolution while the view moves (Scene.pointnpr)."""
    value = getattr(getattr(scene, "pointnpr", None), "navigation_resolution", "1")
    return max(1, int(value))


def refine_delay(scene):
    """Seconds the view rests before the full-quality frame is rendered."""
    return float(getattr(getattr(scene, "pointnpr", None), "refine_delay", 0.5))


class _SyncedScene:
    """One sync of the scene and the core scenes made from it: the full one
    and, per navigation factor, one with scaled styles. The main thread
    reads Blender's data (only it may); the clouds not cached yet are built
    by scene_at() on the viewport's worker (sync.build_scene's defer)."""

    _serial = [0]

    def __init__(self, depsgraph, state, error=None):
        _SyncedScene._serial[0] += 1
        self.serial = _SyncedScene._serial[0]
        self.state = state
        self.error = error
        self.result = None
        self._scaled = {}
        if depsgraph is None:
            return
        scene = depsgraph.scene
        self.result = sync.build_scene(depsgraph, scene_frame(scene), trust_cache=True, defer=True)
        self.render_args = dict(time=scene_time(scene), composite=sync.scene_settings(scene),
                                background=background(scene), memory_budget_gb=memory_budget_gb(scene))
        self.point_budget = point_budget(scene, viewport=True)

    def render_args_at(self, scale):
        # A frame of 1/k the size keeps the full frame's points per pixel
        # with 1/k^2 of its budget: navigation frames stay light on any scan.
        budget = self.point_budget if scale == 1 or self.point_budget == 0 else \
            max(1, self.point_budget // (scale * scale))
        return dict(self.render_args, point_budget=budget)

    def scene_at(self, scale):
        """The core scene for frames of 1/scale the resolution (the worker's call)."""
        scene = self.result.finish()
        if scale == 1:
            return scene
        if scale not in self._scaled:
            from .. import preview
            self._scaled[scale] = preview.scaled_scene(self.result.segments, scale)
        return self._scaled[scale]


def register():
    bpy.utils.register_class(PointNPRRenderEngine)


def unregister():
    bpy.utils.unregister_class(PointNPRRenderEngine)
    release()
