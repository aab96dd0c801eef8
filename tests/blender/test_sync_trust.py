"""F12 trusts a cached cloud without reading the object again only while no
edit reached it (blender/edits.py, sync.cloud_for; issue 14): a repeated
F12 reads no geometry, and after every kind of edit the next F12 renders
the new geometry — the same bytes as a render from an empty cache."""
import os

import bpy
import numpy as np
import pytest

import helpers
from pointnpr.blender import edits, sync

N_SIDE = 24   # 24 x 24 points of 4 colours across a 6 x 6 area


def _scan_scene():
    scene = helpers.reset_scene()
    cam = helpers.add_camera(location=(0.0, 0.0, 10.0), ortho=True)
    cam.data.ortho_scale = 8.0
    coll = helpers.new_collection("Scan")
    pts = helpers.grid_points(3.0, 6.0 / (N_SIDE - 1), 0.0)
    colors = np.zeros((len(pts), 3))
    colors[:, 0] = pts[:, 0] > 0
    colors[:, 1] = pts[:, 1] > 0
    colors[:, 2] = 0.5
    obj = helpers.add_points("Scan", coll, pts, colors=colors)
    tree = helpers.constant_style("Colours", helpers.RED, point_size=4.0)
    tree.nodes["Points"].color_source = "rgb"
    coll.pointnpr_style = tree
    return scene, obj


def _f12(tmp_path, name):
    return helpers.render_pixels(tmp_path, name + ".png")[1]


def _fresh(tmp_path, name):
    """The same frame from an empty cache: every object read anew."""
    sync.clear_cache()
    return _f12(tmp_path, name)


def _positions(obj):
    co = np.empty(len(obj.data.vertices) * 3, dtype=np.float32)
    obj.data.vertices.foreach_get("co", co)
    return co.reshape(-1, 3)


def _shift_half(obj, update=True):
    co = _positions(obj)
    co[co[:, 0] > 0, 0] += 0.7
    obj.data.vertices.foreach_set("co", co.ravel())
    if update:
        obj.data.update()


def _shift_all(obj):
    co = _positions(obj)
    co[:, 0] += 0.7
    obj.data.vertices.foreach_set("co", co.ravel())   # no update(): the signature sees it


def _recolour(obj, update=True):
    attr = obj.data.color_attributes["Col"]
    rgba = np.empty(len(attr.data) * 4, dtype=np.float32)
    attr.data.foreach_get("color_srgb", rgba)
    rgba = rgba.reshape(-1, 4)
    rgba[:, :3] = rgba[:, [2, 0, 1]]
    attr.data.foreach_set("color_srgb", rgba.ravel())
    if update:
        obj.data.update()


def _edit_mode_translate(obj, leave=False):
    bpy.context.view_layer.objects.active = obj
    obj.select_set(True)
    bpy.ops.object.mode_set(mode='EDIT')
    bpy.ops.mesh.select_all(action='SELECT')
    assert bpy.ops.transform.translate(value=(0.7, 0.0, 0.0)) == {'FINISHED'}
    if leave:
        bpy.ops.object.mode_set(mode='OBJECT')


def _displace(obj, strength=0.7):
    mod = obj.modifiers.new("Shift", 'DISPLACE')
    mod.direction = 'X'
    mod.mid_level = 0.0
    mod.strength = strength
    return mod


def _change_modifier(obj):
    obj.modifiers["Shift"].strength = 1.4


def _animated_modifier(obj):
    mod = _displace(obj, 0.0)
    mod.keyframe_insert("strength", frame=1)
    mod.strength = 2.0
    mod.keyframe_insert("strength", frame=10)


def _animated_shape_key(obj):
    obj.shape_key_add(name="Basis")
    key = obj.shape_key_add(name="Shifted")
    co = _positions(obj)
    co[:, 0] += 1.5
    key.data.foreach_set("co", co.ravel())
    key.value = 0.0
    key.keyframe_insert("value", frame=1)
    key.value = 1.0
    key.keyframe_insert("value", frame=10)


# (name, set-up before the first F12 or None, the edit)
EDITS = [
    ("vertices moved by foreach_set and mesh.update()", None, _shift_half),
    ("every vertex moved by foreach_set, no update()", None, _shift_all),
    ("colour attribute set by foreach_set and mesh.update()", None, _recolour),
    ("every colour set by foreach_set, no update()", None, lambda obj: _recolour(obj, update=False)),
    ("vertices moved by an operator, still in edit mode", None, _edit_mode_translate),
    ("vertices moved by an operator, back in object mode", None, lambda obj: _edit_mode_translate(obj, True)),
    ("a modifier added", None, _displace),
    ("a modifier's setting changed", _displace, _change_modifier),
    ("frame change of an animated modifier", _animated_modifier, lambda obj: bpy.context.scene.frame_set(5)),
    ("frame change of an animated shape key", _animated_shape_key, lambda obj: bpy.context.scene.frame_set(5)),
]


def test_a_second_f12_without_edits_reads_no_geometry(tmp_path):
    _scan_scene()
    sync.clear_cache()
    first = _f12(tmp_path, "first")
    stats = sync.cache_stats()
    assert stats["reads"] == 1 and stats["uploads"] == 1
    reads = list(sync.read_log)
    assert ("Scan", "colors") in reads
    second = _f12(tmp_path, "second")
    stats = sync.cache_stats()
    assert (stats["reads"], stats["uploads"], stats["trusted"]) == (1, 1, 1)
    assert sync.read_log == reads    # nothing read: neither the colours nor the vertices
    assert second == first
    # A transform is not an edit of the cloud: still nothing read, and the picture moves.
    bpy.data.objects["Scan"].location.x += 0.5
    moved = _f12(tmp_path, "moved")
    assert sync.cache_stats()["reads"] == 1 and moved != first


def test_a_large_cloud_is_not_sampled_where_sampling_would_copy_its_layers(tmp_path, monkeypatch):
    """Where Blender shares arrays (3.6+), reading a sample of a cloud above
    _SAMPLE_COPY_LIMIT would copy its whole layers on every F12: it is left
    out and the edit tracking alone decides; below the limit, and in Blender
    versions that copy nothing, the sample is read."""
    _scene, obj = _scan_scene()
    sampled = []
    real_sample = sync._sample
    monkeypatch.setattr(sync, "_sample", lambda *a: sampled.append(a[2]) or real_sample(*a))
    sync.clear_cache()
    first = _f12(tmp_path, "first")
    assert sampled, "a small cloud is sampled"
    monkeypatch.setattr(sync, "_SAMPLE_COPY_LIMIT", N_SIDE * N_SIDE - 1)   # this cloud is "large" now
    del sampled[:]
    sync.clear_cache()
    assert _f12(tmp_path, "large") == first
    assert bool(sampled) == (bpy.app.version < (3, 6, 0))
    assert sync.cache_stats()["reads"] == 1
    assert _f12(tmp_path, "again") == first and sync.cache_stats()["trusted"] == 1
    _shift_half(obj)   # an edit with update(): still seen without the sample
    assert _f12(tmp_path, "edited") != first and sync.cache_stats()["reads"] == 2


@pytest.mark.parametrize("name,setup,edit", EDITS, ids=[e[0] for e in EDITS])
def test_the_f12_after_an_edit_renders_the_new_geometry(tmp_path, name, setup, edit):
    _scene, obj = _scan_scene()
    if setup is not None:
        setup(obj)
    sync.clear_cache()
    _f12(tmp_path, "warm")
    before = _f12(tmp_path, "before")   # the second F12: from the cache
    reads = sync.cache_stats()["reads"]
    edit(obj)
    after = _f12(tmp_path, "after")
    assert sync.cache_stats()["reads"] == reads + 1, "the edited object was not read again"
    assert after != before, "the edit did not change the picture: the test shows nothing"
    try:
        assert after == _fresh(tmp_path, "fresh"), "stale geometry rendered after: " + name
    finally:
        if obj.mode != 'OBJECT':
            bpy.ops.object.mode_set(mode='OBJECT')


def test_an_edit_during_a_read_is_not_trusted_later(tmp_path, monkeypatch):
    # The F12 renders on its own thread in Blender's UI: an edit the
    # handlers see while the object is being read stamps a later tick, so
    # the cloud read then is read again next time.
    _scene, obj = _scan_scene()
    sync.clear_cache()
    read = sync.read_positions

    def edited_while_reading(o):
        edits.mark_edited("Scan")
        return read(o)

    monkeypatch.setattr(sync, "read_positions", edited_while_reading)
    _f12(tmp_path, "first")
    monkeypatch.setattr(sync, "read_positions", read)
    _f12(tmp_path, "second")
    assert sync.cache_stats()["reads"] == 2 and sync.cache_stats()["trusted"] == 0
    _f12(tmp_path, "third")
    assert sync.cache_stats()["reads"] == 2 and sync.cache_stats()["trusted"] == 1


def test_a_render_only_modifier_keeps_a_cloud_per_evaluation_mode(tmp_path):
    _scene, obj = _scan_scene()
    sync.clear_cache()
    plain = _f12(tmp_path, "plain")
    mod = _displace(obj)
    mod.show_viewport = False   # the F12 evaluates it, the viewport does not
    viewport = sync.build_scene(bpy.context.evaluated_depsgraph_get(), 1.0, trust_cache=True)
    first = _f12(tmp_path, "first")
    assert first != plain
    modes = sorted(k[4] for k in sync._cloud_cache)
    assert modes == ["RENDER", "VIEWPORT"]
    viewport_cloud = viewport.segments[0][2][0][0]
    # Neither evaluation throws the other's cloud away.
    again = sync.build_scene(bpy.context.evaluated_depsgraph_get(), 1.0, trust_cache=True)
    assert again.segments[0][2][0][0] is viewport_cloud
    assert _f12(tmp_path, "second") == first == _fresh(tmp_path, "fresh")


def test_without_the_handlers_nothing_is_trusted(tmp_path):
    _scan_scene()
    sync.clear_cache()
    edits.unregister()
    try:
        _f12(tmp_path, "first")
        _f12(tmp_path, "second")
        assert sync.cache_stats()["reads"] == 2 and sync.cache_stats()["trusted"] == 0
    finally:
        edits.register()


# Undo needs a window (ed.undo's poll): a second Blender under Xvfb renders,
# edits, renders, undoes and renders again.
UNDO_SCRIPT = r"""
import os, sys, bpy
import numpy as np
sys.path.insert(0, os.environ["POINTNPR_BUILD_DIR"])
sys.path.insert(0, os.environ["TESTS"])
import pointnpr
pointnpr.register()
import helpers
from pointnpr.blender import sync

def f12(name):
    path = os.path.join(os.environ["OUT"], name + ".png")
    bpy.context.scene.render.filepath = path
    bpy.ops.render.render(write_still=True)
    return open(path, "rb").read()

def run():
    try:
        win = bpy.context.window_manager.windows[0]
        with bpy.context.temp_override(window=win, area=win.screen.areas[0]):
            helpers.reset_scene()
            obj = helpers.add_points("Scan", bpy.context.scene.collection, helpers.grid_points(3.0, 0.25, 0.0))
            helpers.add_camera(ortho=True)
            bpy.ops.ed.undo_push(message="scan")
            before = f12("before")
            reads = sync.cache_stats()["reads"]
            co = np.empty(len(obj.data.vertices) * 3, dtype=np.float32)
            obj.data.vertices.foreach_get("co", co)
            co = co.reshape(-1, 3)
            co[co[:, 0] > 0, 0] += 1.0
            obj.data.vertices.foreach_set("co", co.ravel())
            obj.data.update()
            bpy.ops.ed.undo_push(message="moved")
            moved = f12("moved")
            bpy.ops.ed.undo()
            undone = f12("undone")
            sync.clear_cache()
            fresh = f12("fresh")
            print("RESULT", moved != before, undone == before, undone == fresh,
                  sync.cache_stats()["reads"] - reads, flush=True)
    finally:
        os._exit(0)

bpy.app.timers.register(run, first_interval=0.5)
"""


@pytest.mark.window
def test_the_f12_after_an_undo_renders_the_undone_geometry(tmp_path):
    script = tmp_path / "undo.py"
    script.write_text(UNDO_SCRIPT)
    proc = helpers.run_blender_in_window(script, env={"OUT": str(tmp_path), "TESTS": os.path.dirname(__file__)})
    out = proc.stdout
    assert proc.returncode == 0, out[-3000:] + proc.stderr[-3000:]
    # Moved, then undone: the picture of before the edit, as from an empty cache.
    assert "RESULT True True True" in out, out[-3000:] + proc.stderr[-3000:]


def test_the_viewport_starting_keeps_what_an_f12_read_unless_it_was_edited(tmp_path):
    # engine.view_update's first call revalidates every object: geometry may
    # have changed while another engine was active, but what no edit reached
    # is kept (no second read of a large scan on entering Rendered shading).
    _scene, obj = _scan_scene()
    sync.clear_cache()
    _f12(tmp_path, "f12")
    cloud = next(iter(sync._cloud_cache.values())).cloud
    depsgraph = bpy.context.evaluated_depsgraph_get()
    sync.revalidate(obj.evaluated_get(depsgraph))
    synced = sync.build_scene(depsgraph, 1.0, trust_cache=True)
    assert synced.segments[0][2][0][0] is cloud and sync.cache_stats()["reads"] == 1
    _shift_half(obj)
    depsgraph = bpy.context.evaluated_depsgraph_get()
    sync.revalidate(obj.evaluated_get(depsgraph))
    assert not sync._cloud_cache
    synced = sync.build_scene(depsgraph, 1.0, trust_cache=True)
    assert synced.segments[0][2][0][0] is not cloud and sync.cache_stats()["reads"] == 2
