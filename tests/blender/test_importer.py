import os
import struct

import bpy
import numpy as np
import pointnpr
import pytest
from pointnpr.blender import import_operators, importer

import helpers

SAMPLE_LAS = os.path.join(helpers.IO_DATA, "sample_c.las")          # colours + classes
CLASSIFIED_LAS = os.path.join(helpers.IO_DATA, "laspy_nebraska_classified.las")
PLY = os.path.join(helpers.IO_DATA, "tinyply_elephant.ply")


def las_header_point_count(path):
    with open(path, "rb") as f:
        header = f.read(375)
    assert header[:4] == b"LASF"
    legacy = struct.unpack_from("<I", header, 107)[0]
    if legacy == 0 and len(header) >= 255:
        return struct.unpack_from("<Q", header, 247)[0]
    return legacy


def ply_vertex_count(path):
    with open(path, "rb") as f:
        for line in f:
            if line.startswith(b"element vertex"):
                return int(line.split()[2])
            if line.startswith(b"end_header"):
                break
    raise AssertionError("no vertex element")


def _scene_snapshot():
    return (sorted(o.name for o in bpy.data.objects), sorted(m.name for m in bpy.data.meshes),
            sorted(c.name for c in bpy.data.collections),
            sorted(c.name for c in bpy.context.scene.collection.children))


def _attribute(mesh, name, prop, dtype, width=1):
    attr = mesh.attributes[name]
    values = np.empty(len(attr.data) * width, dtype=dtype)
    attr.data.foreach_get(prop, values)
    return values if width == 1 else values.reshape(-1, width)


def test_import_las_with_attributes(scene):
    assert bpy.ops.import_scene.pointnpr_cloud(filepath=SAMPLE_LAS) == {'FINISHED'}
    data = pointnpr.read(SAMPLE_LAS)
    objs = [o for o in bpy.data.objects if o.type == 'MESH']
    assert len(objs) == 1
    obj = objs[0]
    mesh = obj.data
    assert len(mesh.vertices) == las_header_point_count(SAMPLE_LAS) == data.positions.shape[0]
    assert len(mesh.polygons) == 0 and len(mesh.edges) == 0
    # Collection named after the file, in the scene.
    assert obj.users_collection[0].name == "sample_c"
    # Recentred: local + origin == georeferenced coordinates.
    origin = np.array(obj["pointnpr_origin"], dtype=np.float64)
    assert np.all(origin == np.round(origin))
    lo, hi = data.positions.min(axis=0), data.positions.max(axis=0)
    assert np.allclose(origin, np.round((lo + hi) / 2))
    co = np.empty(len(mesh.vertices) * 3, dtype=np.float32)
    mesh.vertices.foreach_get("co", co)
    assert np.abs(co.reshape(-1, 3) + origin - data.positions).max() < 1e-3
    # Colour: BYTE_COLOR point attribute 'Col', sRGB bytes preserved.
    col = mesh.attributes["Col"]
    assert col.data_type == 'BYTE_COLOR' and col.domain == 'POINT'
    srgb = _attribute(mesh, "Col", "color_srgb", np.float32, 4)
    assert np.array_equal(np.rint(srgb[:, :3] * 255).astype(np.uint8), data.attributes["colors"])
    inten = mesh.attributes["intensity"]
    assert inten.data_type == 'FLOAT' and inten.domain == 'POINT'
    assert np.allclose(_attribute(mesh, "intensity", "value", np.float32), data.attributes["intensity"])
    cls = mesh.attributes["classification"]
    assert cls.data_type == 'INT' and cls.domain == 'POINT'
    assert np.array_equal(_attribute(mesh, "classification", "value", np.int32),
                          data.attributes["classification"].astype(np.int32))


def test_local_positions_in_blocks_are_the_whole_arrays_values_in_order():
    rng = np.random.default_rng(3)
    positions = rng.random((10_007, 3)) * [300.0, 200.0, 40.0] + [6.5e5, 6.6e6, 100.0]
    origin = importer.rounded_centre(positions)
    whole = (positions - origin).astype(np.float32)
    for block in (1, 1000, 4096, 10_007, 1 << 20):   # blocks that do and do not divide N
        local = importer.local_positions(positions, origin, block=block)
        assert local.dtype == np.float32 and local.flags.c_contiguous
        assert np.array_equal(local, whole), block


def test_imported_vertices_are_the_files_points_in_order_as_float32(scene):
    assert bpy.ops.import_scene.pointnpr_cloud(filepath=CLASSIFIED_LAS) == {'FINISHED'}
    data = pointnpr.read(CLASSIFIED_LAS)
    obj = next(o for o in bpy.data.objects if o.type == 'MESH')
    co = np.empty(len(obj.data.vertices) * 3, dtype=np.float32)
    obj.data.vertices.foreach_get("co", co)
    origin = np.array(obj["pointnpr_origin"], dtype=np.float64)
    assert np.array_equal(co.reshape(-1, 3), (data.positions - origin).astype(np.float32))


def test_import_without_recentre(scene):
    bpy.ops.import_scene.pointnpr_cloud(filepath=SAMPLE_LAS, recentre=False)
    obj = next(o for o in bpy.data.objects if o.type == 'MESH')
    assert list(obj["pointnpr_origin"]) == [0.0, 0.0, 0.0]


def test_split_by_classification(scene):
    data = pointnpr.read(CLASSIFIED_LAS)
    codes, counts = np.unique(data.attributes["classification"], return_counts=True)
    assert bpy.ops.import_scene.pointnpr_cloud(
        filepath=CLASSIFIED_LAS, split_by_classification=True) == {'FINISHED'}
    root = bpy.data.collections["laspy_nebraska_classified"]
    names = [c.name for c in root.children]
    assert names == [importer.class_name(c) for c in codes]
    assert "Ground (2)" in names and "High Vegetation (5)" in names and "Building (6)" in names
    total = 0
    for code, count in zip(codes, counts):
        coll = bpy.data.collections[importer.class_name(code)]
        assert len(coll.objects) == 1
        mesh = coll.objects[0].data
        assert len(mesh.vertices) == count
        assert set(_attribute(mesh, "classification", "value", np.int32)) == {int(code)}
        total += len(mesh.vertices)
    assert total == las_header_point_count(CLASSIFIED_LAS)


def test_import_ply(scene):
    assert bpy.ops.import_scene.pointnpr_cloud(filepath=PLY) == {'FINISHED'}
    obj = next(o for o in bpy.data.objects if o.type == 'MESH')
    assert len(obj.data.vertices) == ply_vertex_count(PLY)


def test_a_depth_frames_sensor_reaches_the_rendered_cloud(scene):
    """An organized PCD (a depth camera's frame) keeps where its sensor stood
    in the object's recentred frame, so the render's cloud orients its
    estimated normals toward it (tests/python/test_sensor_normals.py)."""
    from pointnpr.blender import sync
    frame = os.path.join(helpers.IO_DATA, "mug_crop.pcd")
    assert bpy.ops.import_scene.pointnpr_cloud(filepath=frame) == {'FINISHED'}
    obj = next(o for o in bpy.data.objects if o.type == 'MESH')
    origin = np.array(obj["pointnpr_origin"], dtype=np.float64)
    assert np.allclose(list(obj["pointnpr_sensor"]), -origin)  # VIEWPOINT 0 0 0, recentred
    cloud = sync.resolved(sync.cloud_for(obj, ()))
    assert np.allclose(cloud.sensor, -origin)
    # A file with no sensor leaves none.
    assert bpy.ops.import_scene.pointnpr_cloud(filepath=PLY) == {'FINISHED'}
    assert not any("pointnpr_sensor" in o for o in bpy.data.objects if o.type == 'MESH' and o is not obj)


def test_imported_cloud_renders(scene, tmp_path):
    bpy.ops.import_scene.pointnpr_cloud(filepath=SAMPLE_LAS)
    obj = next(o for o in bpy.data.objects if o.type == 'MESH')
    # Look at the cloud from above, framing its bounding box.
    co = np.empty(len(obj.data.vertices) * 3, dtype=np.float32)
    obj.data.vertices.foreach_get("co", co)
    co = co.reshape(-1, 3)
    centre = (co.min(axis=0) + co.max(axis=0)) / 2
    cam = helpers.add_camera(location=(centre[0], centre[1], co[:, 2].max() + 50.0), ortho=True)
    cam.data.ortho_scale = float(max(np.ptp(co[:, 0]), np.ptp(co[:, 1])))
    cam.data.clip_end = 1000.0
    px, _ = helpers.render_pixels(tmp_path)
    lit = (px[:, :, :3].max(axis=2) > 0.05).mean()
    assert lit > 0.3, lit


@pytest.mark.parametrize("kind", ["truncated", "garbage"])
def test_broken_file_leaves_scene_unchanged(scene, tmp_path, kind):
    helpers.new_collection("Existing")
    path = tmp_path / ("broken.las")
    if kind == "truncated":
        with open(SAMPLE_LAS, "rb") as f:
            path.write_bytes(f.read()[:400])
    else:
        path.write_bytes(b"LASF" + bytes(range(256)) * 3)
    before = _scene_snapshot()
    with pytest.raises(RuntimeError) as info:
        bpy.ops.import_scene.pointnpr_cloud(filepath=str(path), split_by_classification=True)
    assert "broken.las" in str(info.value)
    assert _scene_snapshot() == before


def test_import_menu_entry():
    funcs = getattr(bpy.types.TOPBAR_MT_file_import.draw, "_draw_funcs", [])
    assert import_operators.menu_func_import in funcs


def test_progress_is_reported_per_step(scene):
    data = pointnpr.read(CLASSIFIED_LAS)
    classes = len(np.unique(data.attributes["classification"]))
    calls = []
    objs = importer.import_point_cloud(bpy.context, CLASSIFIED_LAS, split_by_classification=True,
                                       progress=lambda done, total, stage: calls.append(
                                           (done, total, stage)))
    assert len(objs) == classes
    assert calls[0][0] == 0 and calls[0][2].startswith("reading laspy_nebraska_classified")
    assert calls[-1] == (classes + 2, classes + 2, "done")
    dones = [c[0] for c in calls]
    assert dones == sorted(dones) and len(set(dones)) == len(dones)
    assert sum(1 for c in calls if c[2].startswith("creating mesh")) == classes


@pytest.mark.parametrize("cancel_after", [1, 2, 4])
def test_cancel_between_steps_leaves_scene_unchanged(scene, cancel_after):
    helpers.new_collection("Existing")
    before = _scene_snapshot()
    asked = []

    def cancelled():
        asked.append(1)
        return len(asked) > cancel_after

    with pytest.raises(importer.ImportCancelled):
        importer.import_point_cloud(bpy.context, CLASSIFIED_LAS, split_by_classification=True,
                                    cancelled=cancelled)
    assert len(asked) == cancel_after + 1
    assert _scene_snapshot() == before


def test_threaded_job_and_cleanup(scene):
    import time

    before = _scene_snapshot()
    job = importer.ImportJob(bpy.context, CLASSIFIED_LAS, split_by_classification=True)
    job.start_reading_in_thread()
    deadline = time.time() + 60
    while not job.step():
        assert time.time() < deadline
        time.sleep(0.001)
    assert job.steps_done == job.total_steps and len(job.objects) > 1
    assert bpy.data.collections["laspy_nebraska_classified"].name in \
        [c.name for c in bpy.context.scene.collection.children_recursive]
    # A job stopped half-way (as Esc does) removes what it made.
    job2 = importer.ImportJob(bpy.context, SAMPLE_LAS, split_by_classification=True)
    job2.start_reading_in_thread()
    while job2.steps_done < 2:
        job2.step()
        time.sleep(0.001)
    # Its first mesh exists, but nothing of it is in the scene yet.
    assert len(bpy.data.objects) == len(job.objects) + 1
    assert "sample_c" in bpy.data.collections
    assert "sample_c" not in [c.name for c in bpy.context.scene.collection.children_recursive]
    job2.cleanup()
    assert "sample_c" not in bpy.data.collections
    for obj in job.objects:  # the finished import stays
        assert obj.name in bpy.data.objects
    assert len(bpy.data.objects) == len(job.objects)
    job.cleanup()
    assert _scene_snapshot() == before


def test_broken_file_in_thread_raises_read_error(scene, tmp_path):
    path = tmp_path / "broken.pcd"
    path.write_bytes(b"VERSION 0.7\nFIELDS x y z\nDATA binary\n")
    before = _scene_snapshot()
    job = importer.ImportJob(bpy.context, str(path))
    job.start_reading_in_thread()
    with pytest.raises(pointnpr.ReadError, match="broken.pcd"):
        while not job.step():
            pass
    job.cleanup()
    assert _scene_snapshot() == before


def test_import_asc_text(scene, tmp_path):
    assert "asc" in importer.FILE_EXTENSIONS
    path = tmp_path / "survey.asc"
    path.write_text("x y z intensity\n1 2 3 10\n4 5 6 20\n7 8 9 30\n")
    assert bpy.ops.import_scene.pointnpr_cloud(filepath=str(path)) == {'FINISHED'}
    obj = bpy.data.objects["survey"]
    assert len(obj.data.vertices) == 3
    assert list(_attribute(obj.data, "intensity", "value", np.float32)) == [10, 20, 30]


# The interactive path (modal job: file read in a thread, one mesh per timer
# tick, Esc cancels) needs a window: a second Blender under Xvfb with event
# simulation imports once to the end, then again pressing Esc half-way.
INTERACTIVE_SCRIPT = r"""
import os, sys, bpy
sys.path.insert(0, os.environ["POINTNPR_BUILD_DIR"])
import pointnpr
pointnpr.register()
path = os.environ["CLOUD"]
state = {"phase": "full", "ticks": 0, "before": None}

def snapshot():
    return (sorted(o.name for o in bpy.data.objects), sorted(m.name for m in bpy.data.meshes),
            sorted(c.name for c in bpy.data.collections))

def start():
    win = bpy.context.window_manager.windows[0]
    with bpy.context.temp_override(window=win, area=win.screen.areas[0]):
        result = bpy.ops.import_scene.pointnpr_cloud(filepath=path, split_by_classification=True)
    print("STARTED", state["phase"], sorted(result), flush=True)

def tick():
    state["ticks"] += 1
    if state["ticks"] > 200:
        print("RESULT timeout", flush=True)
        os._exit(1)
    linked = [c.name for c in bpy.context.scene.collection.children_recursive]
    if state["phase"] == "full":
        if "laspy_nebraska_classified" in linked:
            objs = bpy.data.collections["laspy_nebraska_classified"].all_objects
            print("FULL", len(objs), sum(len(o.data.vertices) for o in objs), flush=True)
            bpy.data.collections.remove(bpy.data.collections["laspy_nebraska_classified"])
            for c in list(bpy.data.collections):
                if c.name.endswith(")"):
                    bpy.data.collections.remove(c)
            for o in [o for o in bpy.data.objects if o.name.startswith("laspy")]:
                bpy.data.objects.remove(o)
            for m in [m for m in bpy.data.meshes if m.name.startswith("laspy")]:
                bpy.data.meshes.remove(m)
            state["phase"], state["before"], state["ticks"] = "cancel", snapshot(), 0
            start()
        return 0.1
    if state["ticks"] == 1:
        bpy.context.window_manager.windows[0].event_simulate(type='ESC', value='PRESS')
        return 0.1
    if state["ticks"] < 30:
        return 0.1
    print("CANCEL", "unchanged" if snapshot() == state["before"] else "changed",
          "linked" if "laspy_nebraska_classified" in linked else "not-linked", flush=True)
    os._exit(0)

bpy.app.timers.register(start, first_interval=0.5)
bpy.app.timers.register(tick, first_interval=0.6)
"""


@pytest.mark.window
def test_interactive_import_shows_progress_and_cancels_with_esc(tmp_path):
    script = tmp_path / "interactive.py"
    script.write_text(INTERACTIVE_SCRIPT)
    proc = helpers.run_blender_in_window(script, env={"CLOUD": CLASSIFIED_LAS})
    out = proc.stdout
    assert proc.returncode == 0, out[-3000:] + proc.stderr[-3000:]
    data = pointnpr.read(CLASSIFIED_LAS)
    classes = len(np.unique(data.attributes["classification"]))
    assert "STARTED full ['FINISHED']" in out, out[-3000:]
    assert "FULL %d %d" % (classes, data.num_points) in out, out[-3000:]
    assert "CANCEL unchanged not-linked" in out, out[-3000:]


def test_empty_las_with_split_leaves_no_residue(scene, tmp_path):
    # A LAS with a header and no points (written by the project's writer).
    empty = pointnpr.PointData(np.zeros((0, 3)), {"classification": np.zeros(0, np.uint8)})
    path = str(tmp_path / "empty.las")
    pointnpr.write(path, empty)
    assert las_header_point_count(path) == 0
    before = _scene_snapshot()
    with pytest.raises(RuntimeError, match="contains no points"):
        bpy.ops.import_scene.pointnpr_cloud(filepath=path, split_by_classification=True)
    assert _scene_snapshot() == before


def test_ply_with_more_vertex_lines_than_declared_imports_with_a_warning(scene, tmp_path):
    # MeshLab/VCG write such files: the declared vertices are imported, the rest said.
    path = tmp_path / "extra.ply"
    path.write_text("ply \nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                    "property float z\nend_header\n0 0 0\n1 0 0\n0 1 0\n1 1 0\n")
    warnings = []
    objects = importer.import_point_cloud(bpy.context, str(path), warnings=warnings)
    assert len(objects) == 1 and len(objects[0].data.vertices) == 3
    assert warnings == ["ignored 6 bytes (1 lines) after the last element declared in the header"]


LAZ = os.path.join(helpers.IO_DATA, "laz", "pdal_lone-star-split-1.laz")  # 3 chunks


def test_import_laz(scene):
    assert bpy.ops.import_scene.pointnpr_cloud(filepath=LAZ) == {'FINISHED'}
    objs = [o for o in bpy.data.objects if o.type == 'MESH']
    assert len(objs) == 1 and len(objs[0].data.vertices) == 122893
    assert "laz" in importer.FILE_EXTENSIONS


def test_laz_read_progress_and_cancel(scene, monkeypatch):
    import time

    before = _scene_snapshot()
    job = importer.ImportJob(bpy.context, LAZ)
    job.start_reading_in_thread()
    deadline = time.time() + 60
    while not job.step():
        assert time.time() < deadline
        assert 0 <= job.steps_done <= job.total_steps
        time.sleep(0.001)
    assert job._reading.fraction == 1.0  # the reader reported every chunk
    job.cleanup()
    # Cancelled (as Esc does) before the first chunk: the read stops with
    # Cancelled, the scene is left as it was. The Progress is cancelled from
    # its creation so that the read cannot finish first.
    real_progress = pointnpr.Progress

    def cancelled_progress():
        p = real_progress()
        p.cancel()
        return p

    monkeypatch.setattr(pointnpr, "Progress", cancelled_progress)
    job = importer.ImportJob(bpy.context, LAZ)
    job.start_reading_in_thread()
    job.cancel_reading()
    with pytest.raises(pointnpr.Cancelled):
        while not job.step():
            assert time.time() < deadline
            time.sleep(0.001)
    job.cleanup()
    assert _scene_snapshot() == before


def test_a_dropped_file_imports_without_the_file_browser(scene):
    """Dropping a scan on the viewport invokes the importer with its path
    (Blender 4.1+'s FileHandler): it imports at once."""
    assert bpy.ops.import_scene.pointnpr_cloud('INVOKE_DEFAULT', filepath=PLY) == {'FINISHED'}
    assert len(bpy.data.objects["tinyply_elephant"].data.vertices) == ply_vertex_count(PLY)
    if bpy.app.version >= (4, 1, 0):
        handler = bpy.types.FileHandler.bl_rna_get_subclass_py("IO_FH_pointnpr_cloud")
        assert handler is not None and handler.bl_import_operator == "import_scene.pointnpr_cloud"
        assert set(handler.bl_file_extensions.split(";")) >= {".las", ".laz", ".ply", ".pcd", ".xyz"}
    else:
        assert not hasattr(bpy.types, "FileHandler")


TWO_SCANS_E57 = os.path.join(helpers.IO_DATA, "e57", "pointnpr_two_scans_odd_widths.e57")
PUMP_E57 = os.path.join(helpers.IO_DATA, "e57", "pye57_pumpAVisualReferenceImage.e57")


def test_import_e57_gives_one_object_per_scan_in_the_files_collection(scene):
    assert bpy.ops.import_scene.pointnpr_cloud(filepath=TWO_SCANS_E57) == {'FINISHED'}
    scans = pointnpr.read_e57_scans(TWO_SCANS_E57)
    assert [s.metadata["scan_name"] for s in scans] == ["odd widths", "spherical"]
    objs = {o.name: o for o in bpy.data.objects if o.type == 'MESH'}
    assert set(objs) == {"odd widths", "spherical"}
    for scan in scans:
        obj = objs[scan.metadata["scan_name"]]
        assert obj.users_collection[0].name == "pointnpr_two_scans_odd_widths"
        assert obj["pointnpr_coordinate_metadata"] == "EPSG:2154"
        local = np.empty(len(obj.data.vertices) * 3, np.float32)
        obj.data.vertices.foreach_get("co", local)
        origin = np.asarray(obj["pointnpr_origin"], np.float64)
        expected = (scan.positions - origin).astype(np.float32)
        np.testing.assert_array_equal(local.reshape(-1, 3), expected)


def test_import_e57_merged_into_one_object(scene):
    assert bpy.ops.import_scene.pointnpr_cloud(filepath=TWO_SCANS_E57, split_by_scan=False) == {'FINISHED'}
    objs = [o for o in bpy.data.objects if o.type == 'MESH']
    assert len(objs) == 1
    assert len(objs[0].data.vertices) == sum(s.num_points for s in pointnpr.read_e57_scans(TWO_SCANS_E57))


def test_import_e57_lists_its_images(scene):
    warnings, notes = [], []
    objects = importer.import_point_cloud(bpy.context, PUMP_E57, warnings=warnings, notes=notes)
    assert [o.name for o in objects] == ["pumpA"]
    assert len(objects[0].data.vertices) == 155201
    assert warnings == []
    assert notes == ["The file holds 1 image(s), not imported: "
                     "pumpVisual (visualReferenceRepresentation, 3072x2304)"]
    assert "pointnpr_coordinate_metadata" not in objects[0]  # the file has none


def test_broken_e57_leaves_scene_unchanged(scene, tmp_path):
    helpers.new_collection("Existing")
    path = tmp_path / "broken.e57"
    with open(TWO_SCANS_E57, "rb") as f:
        raw = bytearray(f.read())
    raw[2000] ^= 0x40  # a CRC mismatch in page 1
    path.write_bytes(bytes(raw))
    before = _scene_snapshot()
    with pytest.raises(RuntimeError) as info:
        bpy.ops.import_scene.pointnpr_cloud(filepath=str(path))
    assert "CRC-32C mismatch in page 1" in str(info.value)
    assert _scene_snapshot() == before


def test_import_e57_gives_structured_scans_grid_normals_facing_the_scanner(scene):
    assert bpy.ops.import_scene.pointnpr_cloud(filepath=TWO_SCANS_E57) == {'FINISHED'}
    (gridded, spherical) = pointnpr.read_e57_scans(TWO_SCANS_E57)
    obj = bpy.data.objects["odd widths"]
    normals = _attribute(obj.data, "N", "vector", np.float32, 3)
    expected = pointnpr.grid_normals(gridded.positions, gridded.attributes["row_index"].astype(np.int64),
                                     gridded.attributes["column_index"].astype(np.int64),
                                     np.asarray(gridded.metadata["pose_translation"]))
    np.testing.assert_array_equal(normals, expected)
    np.testing.assert_allclose(np.linalg.norm(normals, axis=1), 1.0, atol=1e-6)
    facing = np.einsum("ij,ij->i", normals, np.asarray(gridded.metadata["pose_translation"]) - gridded.positions)
    assert (facing >= 0).all()
    # The spherical scan has no row/column grid: no normals, the render estimates them.
    assert "N" not in bpy.data.objects["spherical"].data.attributes


def test_import_e57_keeps_the_files_normals(scene):
    path = os.path.join(helpers.IO_DATA, "e57", "pye57_testWithNormals.e57")
    objects = importer.import_point_cloud(bpy.context, path)
    (scan,) = pointnpr.read_e57_scans(path)
    np.testing.assert_array_equal(_attribute(objects[0].data, "N", "vector", np.float32, 3),
                                  scan.attributes["normals"])
