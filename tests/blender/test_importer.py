import os
import struct

import bpy
import numpy as np
import pointnpr
import pytest
from pointnpr.blender import importer

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
    assert importer.menu_func_import in funcs
