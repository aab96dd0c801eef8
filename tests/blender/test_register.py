import bpy
import pointnpr
from pointnpr import blender as addon
from pointnpr.blender import engine, import_operators, nodes, ui


def _registered_state():
    return {
        "engine": engine.PointNPRRenderEngine.is_registered,
        "tree": nodes.PointNPRStyleTree.is_registered,
        "scene_settings": "pointnpr" in bpy.types.Scene.bl_rna.properties,
        "default_style": "pointnpr_default_style" in bpy.types.Scene.bl_rna.properties,
        "collection_style": "pointnpr_style" in bpy.types.Collection.bl_rna.properties,
        "importer": import_operators.IMPORT_SCENE_OT_pointnpr_cloud.is_registered,
        "new_style_op": hasattr(bpy.ops.pointnpr, "new_style") and
        bpy.ops.pointnpr.new_style.get_rna_type() is not None,
    }


def _engine_in_panels():
    return "POINTNPR" in bpy.types.RENDER_PT_format.COMPAT_ENGINES if hasattr(
        bpy.types.RENDER_PT_format, "COMPAT_ENGINES") else None


def _op_exists(name):
    try:
        getattr(bpy.ops.pointnpr, name).get_rna_type()
        return True
    except (AttributeError, KeyError):
        return False


def test_registered_after_enable():
    state = _registered_state()
    assert all(state.values()), state
    assert addon.is_registered()
    # (Blender 4.x's HydraRenderEngine base class has no bl_idname)
    assert "POINTNPR" in {getattr(e, "bl_idname", None) for e in bpy.types.RenderEngine.__subclasses__()}


def test_register_unregister_twice():
    node_count = len(nodes.node_classes())
    color_mgmt = bpy.types.RENDER_PT_color_management
    for _ in range(2):
        pointnpr.unregister()
        assert not addon.is_registered()
        assert not nodes.PointNPRStyleTree.is_registered
        assert "pointnpr" not in bpy.types.Scene.bl_rna.properties
        assert "pointnpr_style" not in bpy.types.Collection.bl_rna.properties
        assert not import_operators.IMPORT_SCENE_OT_pointnpr_cloud.is_registered
        assert not _op_exists("new_style")
        assert nodes.node_classes() == []
        assert "POINTNPR" not in color_mgmt.COMPAT_ENGINES
        assert not ui.RENDER_PT_pointnpr.is_registered
        assert not ui.COLLECTION_PT_pointnpr_style.is_registered
        assert not engine.PointNPRRenderEngine.is_registered
        pointnpr.register()
        assert addon.is_registered()
        state = _registered_state()
        assert all(state.values()), state
        assert len(nodes.node_classes()) == node_count
        assert "POINTNPR" in color_mgmt.COMPAT_ENGINES
        assert _op_exists("new_style")
    # Import menu entry appears once, not once per registration.
    draw_funcs = getattr(bpy.types.TOPBAR_MT_file_import.draw, "_draw_funcs", [])
    assert sum(1 for f in draw_funcs if f is import_operators.menu_func_import) == 1


def test_style_survives_reregistration(scene):
    tree = nodes.new_style("Keep")
    coll = bpy.data.collections.new("KeepColl")
    scene.collection.children.link(coll)
    coll.pointnpr_style = tree
    tree.nodes["Points"].point_size = 7.5
    pointer = tree.as_pointer()
    pointnpr.unregister()
    pointnpr.register()
    # Looked up again: a Python reference from before unregister() holds the
    # old class's RNA type, which Blender 4.x frees (using it can crash).
    assert coll.pointnpr_style.as_pointer() == pointer
    assert abs(bpy.data.node_groups["Keep"].nodes["Points"].point_size - 7.5) < 1e-6


def test_engine_panels_use_engine(scene):
    assert ui.RENDER_PT_pointnpr.is_registered
    assert "POINTNPR" in bpy.types.RENDER_PT_color_management.COMPAT_ENGINES
    assert "POINTNPR" in bpy.types.DATA_PT_lens.COMPAT_ENGINES
    assert "POINTNPR" not in getattr(bpy.types, "RENDER_PT_freestyle").COMPAT_ENGINES
