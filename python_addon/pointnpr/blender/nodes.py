"""Styles as node trees.

A style is a ``PointNPRStyleTree``: a chain Rasterize -> filters ->
Inpaint Depth -> Output. Every node class and every node property is
generated at register() time from ``pointnpr.schemas()``, so a parameter is
declared once, in the C++ schema. Styles are read back per frame by
``read_style`` which evaluates the tree's animation itself (custom node
trees are not reliably evaluated by the depsgraph during final renders).
"""

import math
import re

import bpy

TREE_IDNAME = "PointNPRStyleTree"
SOCKET_IDNAME = "PointNPRStyleSocket"
OUTPUT_IDNAME = "PointNPROutputNode"
NODE_CATEGORY_ID = "POINTNPR_STYLE_NODES"

# Role of a node in the pipeline.
ROLE_RASTERIZE = "rasterize"
ROLE_FILTER = "filter"
ROLE_INPAINT = "inpaint"
ROLE_OUTPUT = "output"

# Bumped whenever a style changes (property edit, relink): the viewport
# compares it to decide whether to re-render.
_generation = [0]

# Generated classes, in registration order.
_generated_classes = []


def generation():
    return _generation[0]


def bump_generation():
    _generation[0] += 1
    _tag_view3d_redraw()


def on_property_update(_self, _context):
    """Update callback of every style and setting property."""
    bump_generation()


def _tag_view3d_redraw():
    wm = getattr(bpy.context, "window_manager", None)
    if wm is None:
        return
    for window in wm.windows:
        screen = window.screen
        if screen is None:
            continue
        for area in screen.areas:
            if area.type == 'VIEW_3D':
                area.tag_redraw()


def _core():
    import pointnpr
    return pointnpr


# ---------------------------------------------------------------------------
# Tree and socket

class PointNPRStyleTree(bpy.types.NodeTree):
    """PointNPR style: the pipeline a segment's points go through"""
    bl_idname = TREE_IDNAME
    bl_label = "PointNPR Style"
    bl_icon = 'NODETREE'

    def update(self):
        bump_generation()


def _socket_color():
    return (0.95, 0.62, 0.25, 1.0)


class PointNPRStyleSocket(bpy.types.NodeSocket):
    """Image flowing through a PointNPR style"""
    bl_idname = SOCKET_IDNAME
    bl_label = "Image"

    def draw(self, context, layout, node, text):
        layout.label(text=text)

    def draw_color(self, context, node):
        return _socket_color()

    @classmethod
    def draw_color_simple(cls):  # Blender 4.x
        return _socket_color()


# ---------------------------------------------------------------------------
# Node classes generated from schemas

def _reserved_node_names():
    names = set(dir(bpy.types.Node))
    names.update(p.identifier for p in bpy.types.Node.bl_rna.properties)
    names.update({"init", "draw_buttons", "draw_buttons_ext", "update", "poll", "copy", "free"})
    return names


def property_identifier(param_name, reserved=None):
    """The node property that stores schema parameter ``param_name``.

    Parameter names are used as is, except where they would shadow a
    built-in Node attribute (e.g. ``color``): those get a ``param_`` prefix.
    """
    if reserved is None:
        reserved = _reserved_node_names()
    if param_name in reserved or param_name.startswith("_"):
        return "param_" + param_name
    return param_name


def _title(name):
    return name.replace("_", " ").title()


def _enum_default(param):
    items = list(param.get("items") or [])
    default = param.get("default")
    if isinstance(default, (list, tuple)):
        default = default[0] if default else 0
    if isinstance(default, str):
        return default if default in items else items[0]
    index = int(default if default is not None else 0)
    return items[min(max(index, 0), len(items) - 1)]


def _scalar_default(param):
    default = param.get("default")
    if isinstance(default, (list, tuple)):
        default = default[0] if default else 0.0
    return default


def make_property(param, update=None):
    """A bpy property for one schema parameter (dict from pointnpr.schemas())."""
    ptype = param["type"]
    unit = param.get("unit") or ""
    name = _title(param["name"]) + (" (%s)" % unit if unit else "")
    doc = param.get("doc") or ""
    if unit:
        doc = "%s [%s]" % (doc, unit) if doc else "[%s]" % unit
    common = {"name": name, "description": doc}
    if update is not None:
        common["update"] = update
    if ptype == "float":
        lo, hi = float(param["min"]), float(param["max"])
        span = hi - lo
        # UI drag step, in hundredths (Blender's convention), ~1% of the range.
        step = max(1, min(100, int(round(span))))
        digits = 3 if span <= 10 else 2
        return bpy.props.FloatProperty(default=float(_scalar_default(param)), min=lo, max=hi,
                                       step=step, precision=digits, **common)
    if ptype == "int":
        return bpy.props.IntProperty(default=int(_scalar_default(param)), min=int(param["min"]),
                                     max=int(param["max"]), **common)
    if ptype == "bool":
        return bpy.props.BoolProperty(default=bool(_scalar_default(param)), **common)
    if ptype == "color":
        default = tuple(float(v) for v in param["default"])
        return bpy.props.FloatVectorProperty(subtype='COLOR_GAMMA', size=4, min=0.0, max=1.0,
                                             default=default, **common)
    if ptype == "enum":
        items = [(item, _title(item), "%s: %s" % (_title(item), doc) if doc else "")
                 for item in param["items"]]
        return bpy.props.EnumProperty(items=items, default=_enum_default(param), **common)
    if ptype == "path":
        # '//'-relative paths are resolved against the .blend when rendering.
        return bpy.props.StringProperty(default="", subtype='FILE_PATH', **common)
    raise ValueError("unknown parameter type %r for %r" % (ptype, param["name"]))


class _StyleNodeMixin:
    """Behaviour shared by every PointNPR style node."""
    # Filled per generated class.
    pointnpr_role = ROLE_FILTER
    pointnpr_schema_id = ""
    pointnpr_params = ()      # tuple of (param dict, property identifier)

    @classmethod
    def poll(cls, ntree):
        return ntree.bl_idname == TREE_IDNAME

    def init(self, context):
        if self.pointnpr_role != ROLE_RASTERIZE:
            self.inputs.new(SOCKET_IDNAME, "Image")
        if self.pointnpr_role != ROLE_OUTPUT:
            self.outputs.new(SOCKET_IDNAME, "Image")

    def draw_buttons(self, context, layout):
        draw_node_properties(self, layout)

    def draw_label(self):
        return self.bl_label


def draw_node_properties(node, layout):
    for _param, pid in getattr(node, "pointnpr_params", ()):
        layout.prop(node, pid)


def _class_name(role, schema_id):
    if role == ROLE_OUTPUT:
        return OUTPUT_IDNAME
    parts = "".join(p.capitalize() for p in schema_id.split("_"))
    if role == ROLE_FILTER:
        return "PointNPRFilter%sNode" % parts
    return "PointNPR%sNode" % parts


def node_idname(role, schema_id=""):
    return _class_name(role, schema_id)


def _make_node_class(role, schema):
    reserved = _reserved_node_names()
    annotations = {}
    params = []
    for param in (schema.get("params") if schema else ()) or ():
        pid = property_identifier(param["name"], reserved)
        annotations[pid] = make_property(param, update=on_property_update)
        params.append((dict(param), pid))
    idname = _class_name(role, schema["id"] if schema else "")
    label = schema.get("label", _title(schema["id"])) if schema else "Output"
    doc = (schema.get("doc") if schema else None) or "Final image of the style"
    attrs = {
        "bl_idname": idname,
        "bl_label": label,
        "bl_description": doc,
        "__doc__": doc,
        "__annotations__": annotations,
        "pointnpr_role": role,
        "pointnpr_schema_id": schema["id"] if schema else "",
        "pointnpr_params": tuple(params),
    }
    if role == ROLE_RASTERIZE:
        attrs["bl_width_default"] = 200
    return type(idname, (_StyleNodeMixin, bpy.types.Node), attrs)


def build_node_classes(schemas):
    """Node classes for a list of schema dicts (not registered)."""
    by_id = {s["id"]: s for s in schemas}
    classes = []
    if "rasterize" in by_id:
        classes.append(_make_node_class(ROLE_RASTERIZE, by_id["rasterize"]))
    for schema in schemas:
        if schema.get("kind") == "filter":
            classes.append(_make_node_class(ROLE_FILTER, schema))
    if "inpaint" in by_id:
        classes.append(_make_node_class(ROLE_INPAINT, by_id["inpaint"]))
    classes.append(_make_node_class(ROLE_OUTPUT, None))
    return classes


def node_classes():
    return list(_generated_classes)


def find_node_class(role, schema_id=""):
    for cls in _generated_classes:
        if cls.pointnpr_role == role and (role == ROLE_OUTPUT or cls.pointnpr_schema_id == schema_id):
            return cls
    return None


# ---------------------------------------------------------------------------
# Creating styles

def new_style(name="Style"):
    """A new style tree with Rasterize -> Output linked."""
    tree = bpy.data.node_groups.new(name, TREE_IDNAME)
    rast = tree.nodes.new(node_idname(ROLE_RASTERIZE, "rasterize"))
    rast.name = "Rasterize"
    rast.location = (-250.0, 0.0)
    out = tree.nodes.new(OUTPUT_IDNAME)
    out.name = "Output"
    out.location = (150.0, 0.0)
    tree.links.new(rast.outputs[0], out.inputs[0])
    return tree


def append_node(tree, role, schema_id="", name=None):
    """Insert a node just before the Output node of ``tree``'s chain."""
    node = tree.nodes.new(node_idname(role, schema_id))
    if name:
        node.name = name
    out = find_output_node(tree)
    if out is None:
        return node
    prev = None
    if out.inputs and out.inputs[0].is_linked:
        prev = out.inputs[0].links[0].from_node
    if prev is not None:
        tree.links.new(prev.outputs[0], node.inputs[0])
        node.location = (prev.location.x + 200.0, prev.location.y)
        out.location = (node.location.x + 220.0, out.location.y)
    tree.links.new(node.outputs[0], out.inputs[0])
    return node


def is_style_tree(tree):
    return tree is not None and getattr(tree, "bl_idname", "") == TREE_IDNAME


def poll_style_tree(_self, tree):
    return is_style_tree(tree)


def find_output_node(tree):
    outputs = [n for n in tree.nodes if getattr(n, "pointnpr_role", None) == ROLE_OUTPUT]
    if not outputs:
        return None
    for n in outputs:
        if n.name == "Output":
            return n
    return sorted(outputs, key=lambda n: n.name)[0]


def style_chain(tree):
    """Nodes from the first step to the Output node (Output excluded), in
    pipeline order, following links back from the Output node. Reroutes are
    passed through; muted nodes are left out."""
    out = find_output_node(tree)
    if out is None:
        return []
    chain = []
    seen = {out.name}
    node = out
    while True:
        if not node.inputs:
            break
        sock = node.inputs[0]
        links = [l for l in sock.links if not getattr(l, "is_muted", False)]
        if not links:
            break
        prev = links[0].from_node
        if prev.name in seen:
            break  # a cycle: stop rather than loop
        seen.add(prev.name)
        if getattr(prev, "pointnpr_role", None) is not None and not prev.mute:
            chain.append(prev)
        node = prev
    chain.reverse()
    return chain


# ---------------------------------------------------------------------------
# Reading a style for a frame (with self-evaluated animation)

_PATH_RE = re.compile(r'^nodes\["((?:[^"\\]|\\.)*)"\]\.([A-Za-z_][A-Za-z0-9_]*)$')


def _action_fcurves(anim, action):
    """The F-Curves animating the tree: its slot's channelbags for layered
    actions (Blender 4.4+), else the legacy flat list."""
    slot = getattr(anim, "action_slot", None)
    layers = getattr(action, "layers", None)
    if slot is not None and layers is not None and len(layers) > 0:
        curves = []
        for layer in layers:
            for strip in layer.strips:
                find = getattr(strip, "channelbag", None)
                bag = find(slot) if find is not None else None
                if bag is not None:
                    curves.extend(bag.fcurves)
        return curves
    fcurves = getattr(action, "fcurves", None)
    return list(fcurves) if fcurves is not None else []


def animated_values(tree):
    """{(node name, property identifier): {array_index: fcurve}}"""
    anim = getattr(tree, "animation_data", None)
    action = getattr(anim, "action", None) if anim else None
    if action is None:
        return {}
    found = {}
    for fc in _action_fcurves(anim, action):
        if getattr(fc, "mute", False):
            continue
        m = _PATH_RE.match(fc.data_path)
        if not m:
            continue
        node_name = m.group(1).replace('\\"', '"').replace("\\\\", "\\")
        found.setdefault((node_name, m.group(2)), {})[fc.array_index] = fc
    return found


def _param_value(node, param, pid, curves, frame):
    """A parameter's value for the core at ``frame``: static value, or the
    fcurve's, coerced like Blender's animation system and clamped."""
    ptype = param["type"]
    static = getattr(node, pid)
    fcs = curves.get((node.name, pid)) if curves else None
    if ptype == "color":
        values = [float(v) for v in static]
        if fcs:
            for idx, fc in fcs.items():
                if 0 <= idx < len(values):
                    values[idx] = fc.evaluate(frame)
        return tuple(min(max(v, 0.0), 1.0) for v in values)
    fc = fcs.get(0, fcs.get(-1)) if fcs else None
    if ptype == "float":
        v = float(fc.evaluate(frame)) if fc else float(static)
        if not math.isfinite(v):
            v = float(static)
        return min(max(v, float(param["min"])), float(param["max"]))
    if ptype == "int":
        v = int(fc.evaluate(frame)) if fc else int(static)
        return min(max(v, int(param["min"])), int(param["max"]))
    if ptype == "bool":
        return bool(fc.evaluate(frame) >= 0.5) if fc else bool(static)
    if ptype == "enum":
        items = list(param["items"])
        if fc:
            index = min(max(int(fc.evaluate(frame)), 0), len(items) - 1)
            return items[index]
        return str(static)
    if ptype == "path":
        # Not animatable; relative to the .blend file (or its library).
        return bpy.path.abspath(static, library=node.id_data.library) if static else ""
    raise ValueError("unknown parameter type %r" % ptype)


def node_values(node, frame, curves=None):
    if curves is None:
        curves = animated_values(node.id_data)
    return {param["name"]: _param_value(node, param, pid, curves, frame)
            for param, pid in node.pointnpr_params}


def read_style(tree, frame):
    """Style description of ``tree`` at ``frame``: a dict with keys
    rasterize (dict), filters (list of (id, dict)), inpaint (dict or None),
    warnings (list of str). ``tree`` None gives the built-in default."""
    desc = {"rasterize": {}, "filters": [], "inpaint": None, "warnings": []}
    if tree is None:
        return desc
    tree = getattr(tree, "original", tree)
    curves = animated_values(tree)
    chain = style_chain(tree)
    rasterizers = [n for n in chain if n.pointnpr_role == ROLE_RASTERIZE]
    if not rasterizers:
        if find_output_node(tree) is None:
            desc["warnings"].append("style '%s' has no Output node: default style used" % tree.name)
        else:
            desc["warnings"].append("style '%s' has no Rasterize node linked to its Output: "
                                    "default rasterize settings used" % tree.name)
    for node in chain:
        role = node.pointnpr_role
        values = node_values(node, frame, curves)
        if role == ROLE_RASTERIZE:
            desc["rasterize"] = values
        elif role == ROLE_FILTER:
            desc["filters"].append((node.pointnpr_schema_id, values))
        elif role == ROLE_INPAINT:
            desc["inpaint"] = values
    return desc


def make_core_style(desc):
    kwargs = {"rasterize": desc["rasterize"], "filters": desc["filters"]}
    if desc.get("inpaint") is not None:
        kwargs["inpaint"] = desc["inpaint"]
    return _core().Style(**kwargs)


# ---------------------------------------------------------------------------
# Registration

def _node_categories():
    try:
        import nodeitems_utils
    except ImportError:
        return None, None

    class PointNPRNodeCategory(nodeitems_utils.NodeCategory):
        @classmethod
        def poll(cls, context):
            space = context.space_data
            return space is not None and getattr(space, "tree_type", "") == TREE_IDNAME

    stages = [nodeitems_utils.NodeItem(c.bl_idname) for c in _generated_classes
              if c.pointnpr_role != ROLE_FILTER]
    filters = [nodeitems_utils.NodeItem(c.bl_idname) for c in _generated_classes
               if c.pointnpr_role == ROLE_FILTER]
    cats = [PointNPRNodeCategory("POINTNPR_STAGES", "Stages", items=stages)]
    if filters:
        cats.append(PointNPRNodeCategory("POINTNPR_FILTERS", "Filters", items=filters))
    return nodeitems_utils, cats


_static_classes = (PointNPRStyleTree, PointNPRStyleSocket)


def register():
    for cls in _static_classes:
        bpy.utils.register_class(cls)
    _generated_classes[:] = build_node_classes(_core().schemas())
    for cls in _generated_classes:
        bpy.utils.register_class(cls)
    utils, cats = _node_categories()
    if utils is not None:
        try:
            utils.register_node_categories(NODE_CATEGORY_ID, cats)
        except Exception:
            pass


def unregister():
    try:
        import nodeitems_utils
        nodeitems_utils.unregister_node_categories(NODE_CATEGORY_ID)
    except Exception:
        pass
    for cls in reversed(_generated_classes):
        bpy.utils.unregister_class(cls)
    _generated_classes.clear()
    for cls in reversed(_static_classes):
        bpy.utils.unregister_class(cls)
