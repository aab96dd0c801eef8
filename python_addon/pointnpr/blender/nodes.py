"""Styles as node trees.

A style is a ``PointNPRStyleTree``: a chain of one mark node (how points
become marks: Points, Hatching, ...) -> filters -> Inpaint Depth -> Output.
Every node class and every node property is generated at register() time
from ``pointnpr.schemas()``, so a parameter is declared once, in the C++
schema; a parameter whose schema has a "when" condition is greyed out while
the condition does not hold (``param_applies``).

Files saved before the mark stage have Rasterize nodes: a legacy
``PointNPRRasterizeNode`` class stays registered (not in the Add menu) so
their stored values load, and ``migrate_legacy_nodes`` (run on file load and
when the add-on is enabled) replaces each by a Points mark node of the same
name, location, links, values and animation; a filter renamed keeps a class
under its former id for the same reason (schema_versions.py). Styles are
read back per frame by ``read_style`` which evaluates the tree's animation
itself (custom node trees are not reliably evaluated by the depsgraph during
final renders).
"""

import math
import re

import bpy

from .conditions import draw_node_properties, param_applies, when_holds  # noqa: F401 (the add-on's API)
from .schema_versions import KNOWN_PARAMS_KEY, former_id_classes, known_token, older_values, set_item

TREE_IDNAME = "PointNPRStyleTree"
SOCKET_IDNAME = "PointNPRStyleSocket"
OUTPUT_IDNAME = "PointNPROutputNode"
NODE_CATEGORY_ID = "POINTNPR_STYLE_NODES"

# Role of a node in the pipeline.
ROLE_MARK = "mark"
ROLE_RASTERIZE = "rasterize"   # legacy Rasterize node (files from before the mark stage)
ROLE_FILTER = "filter"
ROLE_INPAINT = "inpaint"
# Tree property set by versioning: the inpainting method of styles saved
# before there was a choice (Listing 1, "paper"), used where the style has
# no Inpaint Depth node of its own.
LEGACY_INPAINT_KEY = "pointnpr_inpaint_method"
ROLE_OUTPUT = "output"

POINTS_MARK = "points"        # the default mark: splats, what Rasterize was
SURFACE_MARK = "mesh_surface"  # how a style draws meshes with faces (beside its point mark)
LEGACY_RASTERIZE_IDNAME = "PointNPRRasterizeNode"
# Parameters of the points mark that the legacy Rasterize node did not have,
# and the legacy defaults that differ from the points mark's.
_LEGACY_ABSENT_PARAMS = ("rasterizer", "gl_method")
_LEGACY_DEFAULTS = {"color_source": "rgb"}

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
    from .. import _self as pointnpr
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
        self[KNOWN_PARAMS_KEY] = " ".join(known_token(param) for param, _pid in self.pointnpr_params)
        # Mesh Surface goes after the point mark (it draws beside it).
        if self.pointnpr_role not in (ROLE_MARK, ROLE_RASTERIZE) or self.pointnpr_schema_id == SURFACE_MARK:
            self.inputs.new(SOCKET_IDNAME, "Image")
        if self.pointnpr_role != ROLE_OUTPUT:
            self.outputs.new(SOCKET_IDNAME, "Image")

    def draw_buttons(self, context, layout):
        draw_node_properties(self, layout)

    def draw_label(self):
        return self.bl_label


def _class_name(role, schema_id):
    if role == ROLE_OUTPUT:
        return OUTPUT_IDNAME
    if role == ROLE_RASTERIZE:
        return LEGACY_RASTERIZE_IDNAME
    parts = "".join(p.capitalize() for p in schema_id.split("_"))
    if role == ROLE_FILTER:
        return "PointNPRFilter%sNode" % parts
    if role == ROLE_MARK:
        return "PointNPRMark%sNode" % parts
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
    if role in (ROLE_MARK, ROLE_RASTERIZE):
        attrs["bl_width_default"] = 200
    return type(idname, (_StyleNodeMixin, bpy.types.Node), attrs)


def legacy_rasterize_schema(points_schema):
    """The schema the legacy Rasterize node is generated from: the points
    mark's parameters without those Rasterize did not have, with Rasterize's
    defaults (color_source "rgb"), so values stored in old files (and values
    never set, which take the class default) read back as they were saved.
    Enum items keep the points mark's order: "auto" was appended last, so
    stored item indices mean the same item."""
    params = []
    for param in points_schema.get("params", ()):
        if param["name"] in _LEGACY_ABSENT_PARAMS:
            continue
        param = dict(param)
        if param["name"] in _LEGACY_DEFAULTS:
            param["default"] = _LEGACY_DEFAULTS[param["name"]]
        param["when"] = None   # the legacy node is never drawn for editing
        params.append(param)
    return {"id": "rasterize", "label": "Rasterize (legacy)", "kind": "legacy",
            "doc": "Rasterize node of a file saved before the mark stage; replaced by a Points "
                   "mark node when the file is loaded",
            "params": params}


def build_node_classes(schemas):
    """Node classes for a list of schema dicts (not registered): one per mark,
    filter and the inpaint stage, the Output node, and the legacy Rasterize
    node (from the points mark's schema)."""
    classes = []
    for schema in schemas:
        if schema.get("kind") == "mark":
            classes.append(_make_node_class(ROLE_MARK, schema))
    for schema in schemas:
        if schema.get("kind") == "filter":
            classes.append(_make_node_class(ROLE_FILTER, schema))
    classes += former_id_classes(schemas, ROLE_FILTER, _make_node_class, classes)
    for schema in schemas:
        if schema.get("kind") == "stage" and schema["id"] == "inpaint":
            classes.append(_make_node_class(ROLE_INPAINT, schema))
    classes.append(_make_node_class(ROLE_OUTPUT, None))
    points = next((s for s in schemas if s.get("kind") == "mark" and s["id"] == POINTS_MARK), None)
    if points is not None:
        classes.append(_make_node_class(ROLE_RASTERIZE, legacy_rasterize_schema(points)))
    return classes


def node_classes():
    return list(_generated_classes)


def find_node_class(role, schema_id=""):
    for cls in _generated_classes:
        if cls.pointnpr_role == role and (role == ROLE_OUTPUT or cls.pointnpr_schema_id == schema_id):
            return getattr(cls, "pointnpr_current_class", None) or cls  # (a former id's: the current)
    return None


# ---------------------------------------------------------------------------
# Creating styles

def new_style(name="Style", mark=POINTS_MARK):
    """A new style tree with <mark> -> Output linked (a Points mark node
    named "Points" by default)."""
    tree = bpy.data.node_groups.new(name, TREE_IDNAME)
    cls = find_node_class(ROLE_MARK, mark)
    if cls is None:
        raise KeyError("no mark named %r" % mark)
    node = tree.nodes.new(cls.bl_idname)
    node.name = cls.bl_label
    node.location = (-250.0, 0.0)
    out = tree.nodes.new(OUTPUT_IDNAME)
    out.name = "Output"
    out.location = (150.0, 0.0)
    tree.links.new(node.outputs[0], out.inputs[0])
    return tree


def replace_mark(tree, mark_id):
    """Makes ``tree`` start with a ``mark_id`` mark node instead of its
    current mark (which is removed; parameters of the same name keep their
    values). Returns the new node."""
    cls = find_node_class(ROLE_MARK, mark_id)
    if cls is None:
        raise KeyError("no mark named %r" % mark_id)
    old = mark_node(tree)
    new = tree.nodes.new(cls.bl_idname)
    new.name = cls.bl_label
    if old is None:
        out = find_output_node(tree)
        first = style_chain(tree)[0] if style_chain(tree) else out
        new.location = (first.location.x - 250.0, first.location.y) if first else (-250.0, 0.0)
        if first is not None and first.inputs and not first.inputs[0].is_linked:
            tree.links.new(new.outputs[0], first.inputs[0])
        return new
    new.location = old.location
    new_pids = {param["name"]: (param, pid) for param, pid in new.pointnpr_params}
    shared = set()
    for param, pid in old.pointnpr_params:
        target = new_pids.get(param["name"])
        if target is not None and target[0]["type"] == param["type"] and target[1] == pid:
            try:
                setattr(new, pid, getattr(old, pid))
                shared.add(pid)
            except (TypeError, ValueError):
                pass   # e.g. an enum item the new mark does not have
    # The animation of the parameters both marks have moves to the new
    # node (the rest goes with the old one).
    old.name = "__pointnpr_replaced_mark__"
    tmp_name = old.name
    targets = [link.to_socket for link in old.outputs[0].links]
    new.name = cls.bl_label
    repoint_curves(tree, tmp_name, new.name, shared)
    tree.nodes.remove(old)
    for sock in targets:
        tree.links.new(new.outputs[0], sock)
    return new


def node_path_prefix(name):
    return 'nodes["%s"]' % name.replace("\\", "\\\\").replace('"', '\\"')


def tree_curves(tree):
    """Every F-Curve and driver of ``tree``: the active action's, the NLA
    strips' actions', and the drivers."""
    anim = getattr(tree, "animation_data", None)
    if anim is None:
        return []
    curves = []
    if anim.action is not None:
        curves.extend(_action_fcurves(anim, anim.action))
    for track in getattr(anim, "nla_tracks", ()):
        for strip in track.strips:
            action = getattr(strip, "action", None)
            if action is not None and action != anim.action:
                curves.extend(_action_fcurves(anim, action))
    curves.extend(anim.drivers)
    return curves


def repoint_curves(tree, old_name, new_name, properties=None):
    """Points the F-Curves and drivers of node ``old_name``'s properties at
    node ``new_name`` (only those of ``properties``, a set of property
    identifiers, when given)."""
    old, new = node_path_prefix(old_name), node_path_prefix(new_name)
    for fc in tree_curves(tree):
        path = fc.data_path
        if not path.startswith(old + "."):
            continue
        prop = path[len(old) + 1:].split("[", 1)[0]
        if properties is None or prop in properties:
            fc.data_path = new + path[len(old):]


def mark_node(tree):
    """The mark node of ``tree``'s chain (the first step), or None."""
    chain = style_chain(tree)
    if chain and chain[0].pointnpr_role in (ROLE_MARK, ROLE_RASTERIZE) and \
            chain[0].pointnpr_schema_id != SURFACE_MARK:
        return chain[0]
    return None


def surface_node(tree):
    """The Mesh Surface node of ``tree``'s chain, or None."""
    return next((n for n in style_chain(tree) if n.pointnpr_role == ROLE_MARK and
                 n.pointnpr_schema_id == SURFACE_MARK), None)


def set_node_values(node, values):
    """Sets schema parameters of ``node`` from {name: value}; an enum's
    former value (schema_versions) is taken too."""
    known = {param["name"]: (param, pid) for param, pid in node.pointnpr_params}
    for name, value in values.items():
        if name not in known:
            raise KeyError("%s has no parameter %r" % (node.bl_label, name))
        if known[name][0]["type"] == "enum" and isinstance(value, str):
            set_item(node, name, value)
        else:
            setattr(node, known[name][1], value)


def _preset_mark(preset):
    """(mark id, params) of a pointnpr.presets.PRESETS entry: its "mark"
    (an id or (id, params)), or the older "rasterize" (params of the points
    mark)."""
    mark = preset.get("mark")
    if mark is None:
        return POINTS_MARK, dict(preset.get("rasterize") or {})
    if isinstance(mark, str):
        return mark, {}
    mark_id, params = mark
    return mark_id, dict(params or {})


def new_style_from_preset(preset_name, name=None):
    """A style tree built from ``pointnpr.presets.PRESETS[preset_name]``: its
    mark node, filters in order, Inpaint Depth if the preset has one."""
    from .. import presets

    preset = presets.PRESETS[preset_name]
    mark_id, mark_values = _preset_mark(preset)
    tree = new_style(name or preset_name, mark=mark_id)
    set_node_values(mark_node(tree), mark_values)
    for filter_id, values in preset.get("filters", ()):
        set_node_values(append_node(tree, ROLE_FILTER, filter_id), values or {})
    if preset.get("inpaint") is not None:
        set_node_values(append_node(tree, ROLE_INPAINT, "inpaint"), preset["inpaint"])
    return tree


def append_node(tree, role, schema_id="", name=None):
    """Insert a node just before the Output node of ``tree``'s chain."""
    cls = find_node_class(role, schema_id)
    if cls is None:
        raise KeyError("no %s node for %r" % (role, schema_id))
    node = tree.nodes.new(cls.bl_idname)
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


def saved_value(param, saved):
    """A value stored under a former name, as the current property takes
    it: an enum's stored index as its item (clamped to the items)."""
    if param["type"] != "enum":
        return saved
    items = list(param["items"])
    return items[min(max(int(saved), 0), len(items) - 1)]


_FORMER_IDENTIFIERS = {}


def former_identifiers(param):
    """The node properties that stored ``param`` under its former names
    (the schema's ``former_names``: files saved before a rename). Kept per
    name list: every style read asks for them."""
    names = tuple(param.get("former_names") or ())
    if not names:
        return ()
    if names not in _FORMER_IDENTIFIERS:
        reserved = _reserved_node_names()
        _FORMER_IDENTIFIERS[names] = tuple(property_identifier(name, reserved) for name in names)
    return _FORMER_IDENTIFIERS[names]


def _param_value(node, param, pid, curves, frame):
    """A parameter's value for the core at ``frame``: static value, or the
    fcurve's, coerced like Blender's animation system and clamped. A value
    (or curve) saved under a former name counts where the current name holds
    none: a file linked from a library is not migrated (versioning.py)."""
    ptype = param["type"]
    static = getattr(node, pid)
    fcs = curves.get((node.name, pid)) if curves else None
    for old in former_identifiers(param):
        saved = node.get(old)
        if node.get(pid) is None and saved is not None:
            static = saved_value(param, saved)
        if not fcs and curves:
            fcs = curves.get((node.name, old))
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
    values = {param["name"]: _param_value(node, param, pid, curves, frame)
              for param, pid in node.pointnpr_params}
    # Enum indices saved before the items changed, where not migrated (a
    # library's tree): read through the older items.
    values.update(older_values(node, frame, lambda pid: (curves.get((node.name, pid)) or {}).get(0)))
    return values


def read_style(tree, frame):
    """Style description of ``tree`` at ``frame``: a dict with keys
    mark ((id, dict)), filters (list of (id, dict)), inpaint (dict or None),
    warnings (list of str). ``tree`` None gives the built-in default (the
    points mark with its defaults)."""
    desc = {"mark": (POINTS_MARK, {}), "filters": [], "inpaint": None, "warnings": []}
    if tree is None:
        return desc
    tree = getattr(tree, "original", tree)
    curves = animated_values(tree)
    chain = style_chain(tree)
    marks = [n for n in chain if n.pointnpr_role in (ROLE_MARK, ROLE_RASTERIZE)]
    if not marks:
        if find_output_node(tree) is None:
            desc["warnings"].append("style '%s' has no Output node: default style used" % tree.name)
        else:
            desc["warnings"].append("style '%s' has no mark node linked to its Output: "
                                    "default Points mark used" % tree.name)
    for node in chain:
        role = node.pointnpr_role
        values = node_values(node, frame, curves)
        if role == ROLE_MARK and node.pointnpr_schema_id == SURFACE_MARK:
            # How the segment's meshes are drawn, beside the point mark.
            desc["surface"] = values
        elif role == ROLE_MARK:
            desc["mark"] = (node.pointnpr_schema_id, values)
        elif role == ROLE_RASTERIZE:
            # Only left where a tree could not be migrated (linked from a
            # library file): it is the points mark it was.
            desc["mark"] = (POINTS_MARK, values)
        elif role == ROLE_FILTER:
            desc["filters"].append((node.pointnpr_schema_id, values))
        elif role == ROLE_INPAINT:
            desc["inpaint"] = values
    legacy_method = tree.get(LEGACY_INPAINT_KEY)
    if legacy_method and desc["inpaint"] is None:
        desc["inpaint"] = {"method": str(legacy_method)}
    return desc


def make_core_style(desc):
    kwargs = {"mark": tuple(desc["mark"]), "filters": desc["filters"]}
    if desc.get("inpaint") is not None:
        kwargs["inpaint"] = desc["inpaint"]
    if desc.get("surface") is not None:
        kwargs["surface"] = desc["surface"]
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

    def items(role_test):
        return [nodeitems_utils.NodeItem(c.bl_idname) for c in _generated_classes
                if role_test(c.pointnpr_role) and not hasattr(c, "pointnpr_current_class")]

    cats = []
    marks = items(lambda role: role == ROLE_MARK)
    if marks:
        cats.append(PointNPRNodeCategory("POINTNPR_MARKS", "Marks", items=marks))
    filters = items(lambda role: role == ROLE_FILTER)
    if filters:
        cats.append(PointNPRNodeCategory("POINTNPR_FILTERS", "Filters", items=filters))
    # The legacy Rasterize node is not offered: files that have one are migrated.
    cats.append(PointNPRNodeCategory("POINTNPR_STAGES", "Stages",
                                     items=items(lambda role: role in (ROLE_INPAINT, ROLE_OUTPUT))))
    return nodeitems_utils, cats


def node_categories():
    """[(category id, label, [node idnames])] of the Add menu."""
    _utils, cats = _node_categories()
    return [(c.identifier, c.name, [i.nodetype for i in c.items(None)]) for c in cats or ()]


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
