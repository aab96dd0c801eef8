"""Panels and operators: render settings, a collection's style (drawn
inline, so no node editor is needed), and Blender's own panels made
available for the PointNPR engine."""

import bpy

from . import nodes, sync, viewport_worker
from .engine import ENGINE_ID


def _engine_is_ours(context):
    return context.engine == ENGINE_ID


# ---------------------------------------------------------------------------
# Operators

_preset_item_cache = []


def _preset_items(_self, _context):
    # Blender needs the strings of dynamic enum items kept alive.
    if not _preset_item_cache:
        from .. import presets
        _preset_item_cache.append(("NONE", "Empty", "A Points mark and the Output, nothing else"))
        for i, name in enumerate(presets.PRESETS):
            _preset_item_cache.append((name, name, "The '%s' preset" % name))
    return _preset_item_cache


class POINTNPR_OT_new_style(bpy.types.Operator):
    """Create a PointNPR style (Points -> Output) and assign it"""
    bl_idname = "pointnpr.new_style"
    bl_label = "New Style"
    bl_options = {'REGISTER', 'UNDO'}

    target: bpy.props.EnumProperty(
        name="Target",
        items=(("COLLECTION", "Collection", "The active collection"),
               ("SCENE", "Scene", "The scene's default style"),
               ("NONE", "None", "Only create the style")),
        default="COLLECTION")
    preset: bpy.props.EnumProperty(name="Preset", items=_preset_items,
                                   description="Ready-made style (pointnpr.presets) to start from")

    def execute(self, context):
        name = "Style"
        coll = getattr(context, "collection", None)
        if self.target == 'COLLECTION' and coll is not None:
            name = coll.name + " Style"
        if self.preset and self.preset != "NONE":
            tree = nodes.new_style_from_preset(self.preset, name)
        else:
            tree = nodes.new_style(name)
        if self.target == 'COLLECTION':
            if coll is None:
                self.report({'WARNING'}, "No active collection: style created unassigned")
            else:
                coll.pointnpr_style = tree
        elif self.target == 'SCENE':
            context.scene.pointnpr_default_style = tree
        return {'FINISHED'}


def _filter_items(_self, _context):
    items = []
    for cls in nodes.node_classes():
        # (Not the class kept for a filter's former id: old files only.)
        if cls.pointnpr_role == nodes.ROLE_FILTER and not hasattr(cls, "pointnpr_current_class"):
            items.append((cls.pointnpr_schema_id, cls.bl_label, cls.bl_description))
    inpaint = nodes.find_node_class(nodes.ROLE_INPAINT, "inpaint")
    if inpaint is not None:
        items.append(("inpaint", inpaint.bl_label, inpaint.bl_description))
    return items or [("", "None", "")]


class POINTNPR_OT_add_step(bpy.types.Operator):
    """Add a filter (or depth inpainting) before the style's Output"""
    bl_idname = "pointnpr.add_step"
    bl_label = "Add Step"
    bl_options = {'REGISTER', 'UNDO'}
    bl_property = "step"

    tree: bpy.props.StringProperty(name="Style")
    step: bpy.props.EnumProperty(name="Step", items=_filter_items)

    def execute(self, context):
        tree = bpy.data.node_groups.get(self.tree)
        if not nodes.is_style_tree(tree):
            self.report({'ERROR'}, "No PointNPR style named '%s'" % self.tree)
            return {'CANCELLED'}
        role = nodes.ROLE_INPAINT if self.step == "inpaint" else nodes.ROLE_FILTER
        nodes.append_node(tree, role, self.step)
        nodes.bump_generation()
        return {'FINISHED'}

    def invoke(self, context, event):
        context.window_manager.invoke_search_popup(self)
        return {'RUNNING_MODAL'}


def _mark_items(_self, _context):
    items = [(cls.pointnpr_schema_id, cls.bl_label, cls.bl_description)
             for cls in nodes.node_classes()
             if cls.pointnpr_role == nodes.ROLE_MARK and cls.pointnpr_schema_id != nodes.SURFACE_MARK]
    return items or [("", "None", "")]


class POINTNPR_OT_set_mark(bpy.types.Operator):
    """Change how the style's points become marks (Points, Hatching, ...)"""
    bl_idname = "pointnpr.set_mark"
    bl_label = "Set Mark"
    bl_options = {'REGISTER', 'UNDO'}

    tree: bpy.props.StringProperty(name="Style")
    mark: bpy.props.EnumProperty(name="Mark", items=_mark_items)

    def execute(self, context):
        tree = bpy.data.node_groups.get(self.tree)
        if not nodes.is_style_tree(tree):
            self.report({'ERROR'}, "No PointNPR style named '%s'" % self.tree)
            return {'CANCELLED'}
        current = nodes.mark_node(tree)
        if current is None or current.pointnpr_schema_id != self.mark or \
                current.pointnpr_role != nodes.ROLE_MARK:
            nodes.replace_mark(tree, self.mark)
        nodes.bump_generation()
        return {'FINISHED'}


class POINTNPR_OT_remove_step(bpy.types.Operator):
    """Remove this step from the style, relinking its neighbours"""
    bl_idname = "pointnpr.remove_step"
    bl_label = "Remove Step"
    bl_options = {'REGISTER', 'UNDO'}

    tree: bpy.props.StringProperty(name="Style")
    node: bpy.props.StringProperty(name="Node")

    def execute(self, context):
        tree = bpy.data.node_groups.get(self.tree)
        node = tree.nodes.get(self.node) if nodes.is_style_tree(tree) else None
        if node is None:
            self.report({'ERROR'}, "Node not found")
            return {'CANCELLED'}
        prev = node.inputs[0].links[0].from_socket if node.inputs and node.inputs[0].is_linked else None
        nexts = [l.to_socket for l in node.outputs[0].links] if node.outputs else []
        tree.nodes.remove(node)
        if prev is not None:
            for sock in nexts:
                tree.links.new(prev, sock)
        nodes.bump_generation()
        return {'FINISHED'}


# ---------------------------------------------------------------------------
# Drawing a style inline

def draw_style(layout, tree):
    chain = nodes.style_chain(tree)
    if nodes.find_output_node(tree) is None:
        layout.label(text="Style has no Output node", icon='ERROR')
    for node in chain:
        box = layout.box()
        row = box.row()
        row.label(text=node.label or node.bl_label, icon='NODE')
        if node.pointnpr_role in (nodes.ROLE_MARK, nodes.ROLE_RASTERIZE):
            row.operator_menu_enum(POINTNPR_OT_set_mark.bl_idname, "mark", text="", icon='DOWNARROW_HLT') \
                .tree = tree.name
        else:
            op = row.operator(POINTNPR_OT_remove_step.bl_idname, text="", icon='X', emboss=False)
            op.tree = tree.name
            op.node = node.name
        nodes.draw_node_properties(node, box.column())
    op = layout.operator(POINTNPR_OT_add_step.bl_idname, icon='ADD')
    op.tree = tree.name


class PointNPRPanel:
    bl_space_type = 'PROPERTIES'
    bl_region_type = 'WINDOW'
    COMPAT_ENGINES = {ENGINE_ID}

    @classmethod
    def poll(cls, context):
        return _engine_is_ours(context)


class RENDER_PT_pointnpr(PointNPRPanel, bpy.types.Panel):
    bl_label = "PointNPR"
    bl_context = "render"

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        layout.use_property_decorate = True
        scene = context.scene
        settings = scene.pointnpr
        col = layout.column()
        for _param, pid in settings.pointnpr_params:
            col.prop(settings, pid)
        col.prop(settings, "memory_budget_gb")
        col.prop(settings, "point_budget_millions")
        col.prop(settings, "viewport_point_budget_millions")
        col.prop(settings, "navigation_resolution")
        col.prop(settings, "refine_delay")
        col.prop(scene.render, "film_transparent", text="Transparent Film")
        if scene.world is not None:
            col.prop(scene.world, "color", text="Background")
        col = layout.column()
        col.prop(context.view_layer, "use_pass_z", text="Depth Pass")
        layout.separator()
        layout.use_property_split = False
        layout.label(text="Default Style")
        layout.template_ID(scene, "pointnpr_default_style", new=POINTNPR_OT_new_style.bl_idname)


class POINTNPR_MT_style_presets(bpy.types.Menu):
    """The presets menu of the style panel's header (Blender's preset icon)"""
    bl_idname = "POINTNPR_MT_style_presets"
    bl_label = "Style Presets"

    def draw(self, _context):
        from .. import presets
        layout = self.layout
        for name in presets.PRESETS:
            op = layout.operator(POINTNPR_OT_new_style.bl_idname, text=name)
            op.preset = name
            op.target = 'COLLECTION'


class COLLECTION_PT_pointnpr_style(PointNPRPanel, bpy.types.Panel):
    bl_label = "PointNPR Style"
    bl_context = "collection"

    @classmethod
    def poll(cls, context):
        return _engine_is_ours(context) and getattr(context, "collection", None) is not None

    def draw_header_preset(self, _context):
        # As Blender's own panels offer presets: a new style from one, assigned here.
        self.layout.menu(POINTNPR_MT_style_presets.bl_idname, text="", icon='PRESET')

    def draw(self, context):
        layout = self.layout
        coll = context.collection
        scene = context.scene
        layout.template_ID(coll, "pointnpr_style", new=POINTNPR_OT_new_style.bl_idname)
        # The preset list: a new style from pointnpr.presets, assigned here.
        layout.operator_menu_enum(POINTNPR_OT_new_style.bl_idname, "preset", text="New from Preset", icon='PRESET')
        tree = coll.pointnpr_style
        if nodes.is_style_tree(tree):
            draw_style(layout, tree)
            return
        inherited = sync.resolve_style(scene, coll)
        if inherited is not None:
            layout.label(text="Inherits '%s'" % inherited.name, icon='LINKED')
            draw_style(layout, inherited)
        else:
            layout.label(text="Built-in default style (plain points)", icon='INFO')


class NODE_PT_pointnpr_style(bpy.types.Panel):
    """Node editor sidebar: which collections use the edited style."""
    bl_space_type = 'NODE_EDITOR'
    bl_region_type = 'UI'
    bl_category = "Node"
    bl_label = "PointNPR Style"

    @classmethod
    def poll(cls, context):
        space = context.space_data
        return space is not None and nodes.is_style_tree(getattr(space, "edit_tree", None))

    def draw(self, context):
        layout = self.layout
        tree = context.space_data.edit_tree
        users = [c.name for c in bpy.data.collections if c.pointnpr_style == tree]
        if context.scene.pointnpr_default_style == tree:
            users.insert(0, "Scene default")
        col = layout.column(align=True)
        if users:
            col.label(text="Used by:")
            for name in users:
                col.label(text=name, icon='OUTLINER_COLLECTION')
        else:
            col.label(text="Not assigned to a collection", icon='INFO')
        if not nodes.style_chain(tree):
            layout.label(text="Link a mark (Points, ...) -> ... -> Output", icon='ERROR')
        op = layout.operator(POINTNPR_OT_add_step.bl_idname, icon='ADD')
        op.tree = tree.name


# ---------------------------------------------------------------------------
# Blender's own panels

_EXCLUDED_PANEL_WORDS = ("freestyle", "gpencil", "PARTICLE_", "PHYSICS_", "TEXTURE_", "lightprobe",
                         "MATERIAL_", "EEVEE_", "DATA_PT_light", "DATA_PT_spot", "DATA_PT_area",
                         "DATA_PT_falloff", "NODE_DATA_PT_light", "DATA_PT_preview")
_EXTRA_PANELS = ("RENDER_PT_color_management", "RENDER_PT_color_management_curves",
                 "RENDER_PT_format", "RENDER_PT_frame_range", "RENDER_PT_output",
                 "RENDER_PT_post_processing", "RENDER_PT_stamp", "RENDER_PT_time_stretching",
                 "RENDER_PT_color_management_display_settings", "RENDER_PT_format_presets",
                 "RENDER_PT_output_color_management")
_added_panels = []


def _compatible_builtin_panels():
    """Blender panels that work for any engine: those that declare the
    generic 'BLENDER_RENDER' engine, minus features PointNPR does not use."""
    panels = []
    for panel in bpy.types.Panel.__subclasses__():
        engines = getattr(panel, "COMPAT_ENGINES", None)
        if not isinstance(engines, set):
            continue
        name = panel.__name__
        if name in _EXTRA_PANELS:
            panels.append(panel)
            continue
        if 'BLENDER_RENDER' in engines and not any(w in name for w in _EXCLUDED_PANEL_WORDS):
            panels.append(panel)
    return panels


def add_engine_to_builtin_panels():
    for panel in _compatible_builtin_panels():
        if ENGINE_ID not in panel.COMPAT_ENGINES:
            panel.COMPAT_ENGINES.add(ENGINE_ID)
            _added_panels.append(panel)


def remove_engine_from_builtin_panels():
    for panel in _added_panels:
        panel.COMPAT_ENGINES.discard(ENGINE_ID)
    _added_panels.clear()


class POINTNPR_OT_viewport_cancel(bpy.types.Operator):
    """Cancel the viewport's pending PointNPR frames (Esc in a 3D view); the
    last frame stays until the view changes"""
    bl_idname = "pointnpr.viewport_cancel"
    bl_label = "Cancel Viewport Render"

    @classmethod
    def poll(cls, context):
        return any(s.busy() for s in viewport_worker.sessions())

    def invoke(self, context, event):
        return self.execute(context)

    def execute(self, context):
        for session in viewport_worker.sessions():
            session.cancel()
        # Esc keeps its other meanings in the 3D view.
        return {'PASS_THROUGH'}


_classes = (
    POINTNPR_OT_viewport_cancel,
    POINTNPR_OT_new_style,
    POINTNPR_OT_add_step,
    POINTNPR_OT_set_mark,
    POINTNPR_OT_remove_step,
    RENDER_PT_pointnpr,
    POINTNPR_MT_style_presets,
    COLLECTION_PT_pointnpr_style,
    NODE_PT_pointnpr_style,
)


_keymap_items = []


def _register_keymap():
    wm = getattr(bpy.context, "window_manager", None)
    keyconfig = wm.keyconfigs.addon if wm is not None else None
    if keyconfig is None:   # blender -b
        return
    keymap = keyconfig.keymaps.new(name="3D View", space_type='VIEW_3D')
    _keymap_items.append((keymap, keymap.keymap_items.new(POINTNPR_OT_viewport_cancel.bl_idname, 'ESC', 'PRESS')))


def register():
    for cls in _classes:
        bpy.utils.register_class(cls)
    add_engine_to_builtin_panels()
    _register_keymap()


def unregister():
    for keymap, item in _keymap_items:
        keymap.keymap_items.remove(item)
    _keymap_items.clear()
    remove_engine_from_builtin_panels()
    for cls in reversed(_classes):
        bpy.utils.unregister_class(cls)
