"""Blender meshes with faces as surfaces (issue 15): the evaluated mesh
(modifiers, Geometry Nodes, instances), material colours and textures,
caching, the scene sun; golden images compared with idiff."""
import os
import shutil

import bpy
import numpy as np
import pytest

import helpers
from pointnpr.blender import engine, mesh_sync, nodes, sync

from example_renders import idiff

GOLDEN = os.path.join(helpers.REPO, "tests", "data", "golden")
CENTRE = (helpers.HEIGHT // 2, helpers.WIDTH // 2)


def _quad_mesh(name, half=1.0, z=0.0):
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata([(-half, -half, z), (half, -half, z), (half, half, z), (-half, half, z)], [], [(0, 1, 2, 3)])
    mesh.update()
    return mesh


def _material(name, rgb, image=None):
    mat = bpy.data.materials.new(name)
    if bpy.app.version < (5, 0, 0):
        mat.use_nodes = True  # always on in 5.0 (deprecated there)
    bsdf = mat.node_tree.nodes["Principled BSDF"]
    bsdf.inputs["Base Color"].default_value = (*rgb, 1.0)
    if image is not None:
        tex = mat.node_tree.nodes.new("ShaderNodeTexImage")
        tex.image = image
        mat.node_tree.links.new(tex.outputs["Color"], bsdf.inputs["Base Color"])
    return mat


def _unshaded_style(name="Flat"):
    tree = nodes.new_style(name)
    surface = helpers_append_surface(tree)
    surface.shading = "none"
    return tree, surface


def helpers_append_surface(tree):
    """A Mesh Surface node placed after the tree's mark."""
    return nodes.append_node(tree, nodes.ROLE_MARK, nodes.SURFACE_MARK)


def _scene_with(obj_builder):
    scene = helpers.reset_scene()
    helpers.add_camera()
    coll = helpers.new_collection("Building")
    tree, surface = _unshaded_style()
    coll.pointnpr_style = tree
    obj = obj_builder(coll)
    return scene, coll, obj, surface


def _add(coll, name, mesh, location=(0.0, 0.0, 0.0)):
    obj = bpy.data.objects.new(name, mesh)
    obj.location = location
    coll.objects.link(obj)
    return obj


def _golden(tmp_path, name, px_path):
    golden = os.path.join(GOLDEN, "mesh_%s.png" % name)
    if os.environ.get("POINTNPR_UPDATE_GOLDEN"):
        shutil.copyfile(px_path, golden)
    assert os.path.exists(golden), "no golden image " + golden
    code, out = idiff(golden, px_path, str(tmp_path / ("diff_%s.png" % name)))
    assert code == 0, out


def test_a_mesh_with_faces_renders_as_a_surface_in_its_material_colour(tmp_path):
    scene, coll, obj, _surface = _scene_with(
        lambda coll: _add(coll, "Roof", _quad_mesh("Roof")))
    obj.data.materials.append(_material("Red", (1.0, 0.0, 0.0)))
    px, _ = helpers.render_pixels(tmp_path, "quad.png")
    assert helpers.is_color(px[CENTRE], (1.0, 0.0, 0.0), tol=0.02), px[CENTRE]
    # Solid, not 4 vertices: the whole quad's footprint is covered.
    assert helpers.is_color(px[CENTRE[0] + 5, CENTRE[1] + 5], (1.0, 0.0, 0.0), tol=0.02)
    synced = sync.build_scene(bpy.context.evaluated_depsgraph_get(), 1.0)
    assert synced.num_objects == 1 and synced.num_points == 0


def test_modifiers_instances_and_a_texture_match_their_golden_image(tmp_path):
    def build(coll):
        # An arrayed cube (modifier), a collection instance of it turned and
        # moved (composed in double), a textured quad under both.
        bpy.ops.mesh.primitive_cube_add(size=1.0, location=(-1.5, 0.0, 0.5))
        cube = bpy.context.active_object
        for c in list(cube.users_collection):
            c.objects.unlink(cube)
        coll.objects.link(cube)
        cube.name = "Block"
        mod = cube.modifiers.new("Array", 'ARRAY')
        mod.count = 2
        mod.relative_offset_displace = (1.5, 0.0, 0.0)
        cube.data.materials.append(_material("Brick", (0.8, 0.3, 0.1)))
        source = bpy.data.collections.new("Source")
        source.objects.link(cube)
        inst = bpy.data.objects.new("Copy", None)
        inst.instance_type = 'COLLECTION'
        inst.instance_collection = source
        inst.location = (0.5, 2.0, 0.0)
        inst.rotation_euler = (0.0, 0.0, 0.6)
        coll.objects.link(inst)
        image = bpy.data.images.new("Checker", 64, 64)
        pixels = np.ones((64, 64, 4), np.float32)
        check = ((np.arange(64)[:, None] // 16 + np.arange(64)[None, :] // 16) % 2) == 0
        pixels[check, :3] = (0.1, 0.4, 0.9)
        image.pixels.foreach_set(pixels.ravel())
        image.update()
        ground = _add(coll, "Ground", _quad_mesh("Ground", half=3.0, z=-0.01))
        uv = ground.data.uv_layers.new(name="UVMap")
        uv.data.foreach_set("uv", np.array([[0, 0], [1, 0], [1, 1], [0, 1]], np.float32).ravel())
        ground.data.materials.append(_material("Tiles", (0.5, 0.5, 0.5), image=image))
        return cube

    scene, coll, cube, surface = _scene_with(build)
    surface.shading = "flat"
    scene.camera.location = (4.0, -6.0, 7.0)
    scene.camera.rotation_euler = (0.75, 0.0, 0.55)
    r = scene.render
    r.resolution_x, r.resolution_y = 160, 120
    path = helpers.render_to_png(str(tmp_path / "mesh_scene.png"))
    px = helpers.load_png(path)
    # Four blocks (two arrayed, twice through the instance) and the texture's two colours.
    synced = sync.build_scene(bpy.context.evaluated_depsgraph_get(), 1.0)
    assert synced.num_objects == 3  # the block, its instance, the ground
    rgb = px.reshape(-1, 4)[:, :3]
    blue = (rgb[:, 2] > 2.0 * rgb[:, 0] + 0.3).sum()
    white = (np.ptp(rgb, axis=1) < 0.02).sum() - (rgb.max(axis=1) < 0.05).sum()  # grey, not background
    brick = ((rgb[:, 0] > 1.5 * rgb[:, 1]) & (rgb[:, 1] > 1.5 * rgb[:, 2])).sum()
    assert blue > 500 and white > 500 and brick > 500, (blue, white, brick)
    _golden(tmp_path, "modifiers_instances_texture", path)


def test_per_corner_colour_attribute_and_materials_per_face(tmp_path):
    def build(coll):
        mesh = bpy.data.meshes.new("Two")
        mesh.from_pydata([(-2, -1, 0), (0, -1, 0), (0, 1, 0), (-2, 1, 0), (2, -1, 0), (2, 1, 0)], [],
                         [(0, 1, 2, 3), (1, 4, 5, 2)])
        mesh.materials.append(_material("A", (0.0, 1.0, 0.0)))
        mesh.materials.append(_material("B", (0.0, 0.0, 1.0)))
        mesh.polygons[1].material_index = 1
        mesh.update()
        return _add(coll, "Two", mesh)

    scene, coll, obj, _surface = _scene_with(build)
    px, _ = helpers.render_pixels(tmp_path, "two.png")
    assert helpers.is_color(px[CENTRE[0], CENTRE[1] - 8], (0.0, 1.0, 0.0), tol=0.02)
    assert helpers.is_color(px[CENTRE[0], CENTRE[1] + 8], (0.0, 0.0, 1.0), tol=0.02)
    # A corner colour attribute wins over the materials (colour source auto).
    attr = obj.data.color_attributes.new("Paint", 'BYTE_COLOR', 'CORNER')
    rgba = np.tile(np.array([1.0, 1.0, 0.0, 1.0], np.float32), (len(attr.data), 1))
    attr.data.foreach_set("color_srgb", rgba.ravel())
    obj.data.update()
    px, _ = helpers.render_pixels(tmp_path, "painted.png")
    assert helpers.is_color(px[CENTRE[0], CENTRE[1] + 8], (1.0, 1.0, 0.0), tol=0.02)


def test_geometry_nodes_mesh_is_evaluated(tmp_path):
    def build(coll):
        obj = _add(coll, "Grown", _quad_mesh("Small", half=0.2))
        tree = bpy.data.node_groups.new("Grow", 'GeometryNodeTree')
        if hasattr(tree, "interface"):
            tree.interface.new_socket("Geometry", in_out='INPUT', socket_type='NodeSocketGeometry')
            tree.interface.new_socket("Geometry", in_out='OUTPUT', socket_type='NodeSocketGeometry')
        else:
            tree.inputs.new('NodeSocketGeometry', "Geometry")
            tree.outputs.new('NodeSocketGeometry', "Geometry")
        gin, gout = tree.nodes.new('NodeGroupInput'), tree.nodes.new('NodeGroupOutput')
        scale = tree.nodes.new('GeometryNodeTransform')
        scale.inputs["Scale"].default_value = (10.0, 10.0, 1.0)
        tree.links.new(gin.outputs[0], scale.inputs["Geometry"])
        tree.links.new(scale.outputs["Geometry"], gout.inputs[0])
        obj.modifiers.new("Grow", 'NODES').node_group = tree
        obj.data.materials.append(_material("Blue", (0.0, 0.0, 1.0)))
        return obj

    _scene_with(build)
    px, _ = helpers.render_pixels(tmp_path, "gn.png")
    # 10 x 0.4 m = 4 m wide: covers a pixel 1.2 m from the centre (the
    # unmodified 0.4 m quad would not).
    off = int(round(1.2 / (10.0 * 36.0 / 50.0) * helpers.WIDTH))
    assert helpers.is_color(px[CENTRE[0], CENTRE[1] + off], (0.0, 0.0, 1.0), tol=0.02)


def test_a_mesh_is_read_and_uploaded_once_and_again_once_after_an_edit():
    scene, coll, obj, _surface = _scene_with(lambda coll: _add(coll, "Roof", _quad_mesh("Roof")))
    sync.clear_cache()
    r = engine.renderer()
    before = r.mesh_upload_count()
    depsgraph = bpy.context.evaluated_depsgraph_get()
    cam = engine.make_camera(depsgraph, scene.camera, 64, 48)

    def frame():
        synced = sync.build_scene(bpy.context.evaluated_depsgraph_get(), 1.0, trust_cache=True)
        r.render(synced.scene, cam, 64, 48)

    frame()
    uploads = r.mesh_upload_count()
    assert uploads > before and mesh_sync.cache_stats()["uploads"] == 1
    reads = len(mesh_sync.read_log)
    frame()
    # Unchanged: not read again, nothing uploaded.
    assert len(mesh_sync.read_log) == reads and r.mesh_upload_count() == uploads
    assert mesh_sync.cache_stats()["hits"] >= 1
    # An edit: the depsgraph update invalidates the object (as view_update
    # does), the next frame reads and uploads it once.
    obj.data.vertices[0].co.z += 0.3
    obj.data.update()
    sync.invalidate(obj.name)
    frame()
    assert mesh_sync.cache_stats()["uploads"] == 2
    once = r.mesh_upload_count()
    assert once > uploads
    frame()
    assert r.mesh_upload_count() == once


def test_only_the_attributes_the_style_reads_are_read():
    scene, coll, obj, surface = _scene_with(lambda coll: _add(coll, "Roof", _quad_mesh("Roof")))
    obj.data.materials.append(_material("Red", (1.0, 0.0, 0.0)))
    obj.data.color_attributes.new("Paint", 'BYTE_COLOR', 'CORNER')
    sync.clear_cache()
    surface.color_source = "constant"
    sync.build_scene(bpy.context.evaluated_depsgraph_get(), 1.0)
    assert [w for _o, w in mesh_sync.read_log] == []
    surface.color_source = "base_color"
    sync.build_scene(bpy.context.evaluated_depsgraph_get(), 1.0)
    assert [w for _o, w in mesh_sync.read_log] == ["base_color"]


def test_meshes_as_points_and_sampled_points():
    scene, coll, obj, surface = _scene_with(lambda coll: _add(coll, "Roof", _quad_mesh("Roof")))
    sync.build_scene(bpy.context.evaluated_depsgraph_get(), 1.0)
    assert mesh_sync.cache_stats()["objects"] == 1
    surface.meshes = "points"
    synced = sync.build_scene(bpy.context.evaluated_depsgraph_get(), 1.0)
    assert synced.num_points == 4  # its vertices, as before meshes had surfaces
    # Face-corner colours reach the vertices (each the mean of its corners').
    attr = obj.data.color_attributes.new("Paint", 'BYTE_COLOR', 'CORNER')
    rgba = np.tile(np.array([1.0, 1.0, 0.0, 1.0], np.float32), (len(attr.data), 1))
    attr.data.foreach_set("color_srgb", rgba.ravel())
    obj.data.update()
    assert sync.read_colors(obj).tolist() == [[255, 255, 0]] * 4
    assert mesh_sync.cache_stats()["objects"] == 0  # its mesh is no longer kept
    surface.meshes = "sampled"
    surface.sample_density = 100.0
    synced = sync.build_scene(bpy.context.evaluated_depsgraph_get(), 1.0)
    r = engine.renderer()
    cam = engine.make_camera(bpy.context.evaluated_depsgraph_get(), scene.camera, 64, 48)
    result = r.render(synced.scene, cam, 64, 48)
    assert abs(result.stats["points_drawn"] - 400) < 4 * 20


def test_the_scene_sun_lights_meshes_and_marks_of_a_style(tmp_path):
    scene, coll, obj, surface = _scene_with(lambda coll: _add(coll, "Roof", _quad_mesh("Roof")))
    obj.data.materials.append(_material("White", (1.0, 1.0, 1.0)))
    surface.shading = "flat"
    surface.light_space = "scene_sun"
    surface.light_elevation = 0.0   # its own light grazes the roof
    px, _ = helpers.render_pixels(tmp_path, "no_sun.png")
    grazing = float(px[CENTRE][0])
    sun = bpy.data.objects.new("Sun", bpy.data.lights.new("Sun", 'SUN'))
    scene.collection.objects.link(sun)   # pointing down -Z: straight onto the roof
    px, _ = helpers.render_pixels(tmp_path, "sun.png")
    assert float(px[CENTRE][0]) > 0.99 > grazing + 0.2
    desc = nodes.read_style(coll.pointnpr_style, 1.0)
    desc["mark"] = ("hatching", {"light_space": "world"})
    warnings = []
    sync._apply_scene_sun(desc, bpy.context.evaluated_depsgraph_get(), warnings, coll.pointnpr_style)
    # One switch per style: the hatching mark takes the same sun.
    assert desc["mark"][1]["light_space"] == "scene_sun"
    assert desc["mark"][1]["light_elevation"] == pytest.approx(90.0)
    assert desc["surface"]["light_elevation"] == pytest.approx(90.0) and not warnings
    # And so does the points mark's diffuse shading.
    desc["mark"] = ("points", {"shading": "diffuse", "light_space": "camera"})
    sync._apply_scene_sun(desc, bpy.context.evaluated_depsgraph_get(), warnings, coll.pointnpr_style)
    assert desc["mark"][1]["light_space"] == "scene_sun"
    assert desc["mark"][1]["light_elevation"] == pytest.approx(90.0) and not warnings
    core_style = nodes.make_core_style(desc)
    assert core_style.mark[1]["light_space"] == "scene_sun"
