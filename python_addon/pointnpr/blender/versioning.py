"""Opening files saved by older versions of the add-on.

Before the mark stage a style began with a Rasterize node
(``PointNPRRasterizeNode``) and the scene chose the rasterizer
(``Scene.pointnpr.rasterizer``). ``migrate_legacy_nodes`` replaces every
Rasterize node of every local style tree by a Points mark node with

* the same node name, so F-Curves and drivers on ``nodes["Rasterize"].*``
  keep animating it (the property identifiers are the same);
* the same location, size, label, parent frame, mute state and links;
* the same parameter values; ``color_source`` is set explicitly to the value
  the old node had ("rgb" where it was never changed: the points mark's
  default is "auto");
* ``rasterizer`` = the ``Scene.pointnpr.rasterizer`` of a scene that uses
  the style (the first scene when none does): ``gl`` with that
  ``gl_method`` (compute or gl_points).

A parameter added since files were saved without it, or whose default
changed since, may declare the value that renders them as before (the
schema's ``older_files_value``, e.g. the brush splats' ``shading``:
``none``, where new nodes take ``auto``; the hatching mark's
``light_space``: ``world``, its former default): ``migrate_added_params``
gives it to nodes made before the parameter existed or before its default
changed, where they store no value of their own (a node records the
parameters it knew when made, with their defaults where those changed).

A parameter renamed since (the schema's ``former_names``, e.g. the
stipples mark's ``implementation``, now ``rasterizer`` as on every mark
with two backends) keeps its saved value and animation:
``migrate_former_names`` moves them to the current name.

Enum values spelt otherwise now, or moved in their list (the schema's
``former_items`` and ``older_files_items``: every mark's ``rasterizer`` is
gl / native / auto now; the points' compute and gl_points are rasterizer gl
with that ``gl_method``, the gaussians' compute is gl), keep their meaning:
Blender saved their index, which ``migrate_changed_items`` reads through the
older list (schema_versions.py); a keyed gl_points also keys gl_method. A
filter renamed (the schema's
``former_ids``: ``hatching``, the hatching mark's id too, is
``pencil_hatching``) keeps its nodes: ``migrate_former_ids`` replaces each
by one of the current class, as a Rasterize node is.

It runs on every file load (a persistent load_post handler) and when the
add-on is enabled, for a file that is already open. Trees linked from a
library file cannot be edited: their Rasterize nodes are read as Points
marks, values saved under a former name or into the older items as those
(nodes.read_style), until the library file is migrated itself.
"""

import bpy
from bpy.app.handlers import persistent

from . import nodes, schema_versions

# Temporary name of a Rasterize node while its replacement takes its name.
_TMP_NAME = "__pointnpr_legacy_rasterize__"


def _scenes_using(tree):
    found = []
    for scene in bpy.data.scenes:
        if scene.pointnpr_default_style == tree:
            found.append(scene)
            continue
        colls = [scene.collection] + list(scene.collection.children_recursive)
        if any(getattr(c, "pointnpr_style", None) == tree for c in colls):
            found.append(scene)
    return found


def legacy_rasterizer(tree):
    """The scene-wide rasterizer that applied to ``tree`` before the mark
    stage: that of the first scene using it, else of the first scene."""
    scenes = _scenes_using(tree) or list(bpy.data.scenes)
    for scene in scenes:
        settings = getattr(scene, "pointnpr", None)
        if settings is not None and "rasterizer" in settings.bl_rna.properties:
            return settings.rasterizer
    return "compute"


def _copy_node_state(old, new):
    for attr in ("location", "width", "height", "label", "mute", "hide", "show_options",
                 "use_custom_color", "color", "select"):
        try:
            setattr(new, attr, getattr(old, attr))
        except (AttributeError, TypeError, ValueError):
            pass
    if old.parent is not None:
        new.parent = old.parent
        new.location = old.location


def _replace_node(tree, old, new_cls, only_set=False):
    """A node of class ``new_cls`` in the place of ``old``, which is removed:
    the same name (its F-Curves and drivers follow), location, frame, state,
    links, and the values of the parameters both have (only those ``old``
    stores itself, with its record of the parameters it knew, when
    ``only_set``: then the later migrations treat it as they would
    ``old``). Returns the new node."""
    name = old.name
    # F-Curves follow a node's renames and die with it: move the old node
    # away first (its curves follow), give its name to the new node, then
    # point the curves at the new node before removing the old one.
    old.name = _TMP_NAME
    tmp_name = old.name
    new = tree.nodes.new(new_cls.bl_idname)
    new.name = name
    nodes.repoint_curves(tree, tmp_name, new.name)
    _copy_node_state(old, new)
    new_pids = {param["name"]: pid for param, pid in new.pointnpr_params}
    for param, pid in old.pointnpr_params:
        if param["name"] in new_pids and not (only_set and not _is_set(old, pid)):
            setattr(new, new_pids[param["name"]], getattr(old, pid))
    if only_set:
        if old.get(nodes.KNOWN_PARAMS_KEY) is None:
            del new[nodes.KNOWN_PARAMS_KEY]
        else:
            new[nodes.KNOWN_PARAMS_KEY] = old[nodes.KNOWN_PARAMS_KEY]
    targets = [link.to_socket for out in old.outputs for link in out.links]
    sources = [link.from_socket for inp in old.inputs for link in inp.links]
    tree.nodes.remove(old)
    for sock in targets:
        tree.links.new(new.outputs[0], sock)
    for sock in sources:
        if new.inputs:
            tree.links.new(sock, new.inputs[0])
    return new


def migrate_node(tree, old, rasterizer):
    """Replaces the legacy Rasterize node ``old`` of ``tree`` by a Points
    mark node; returns the new node. ``rasterizer`` is the scene's former
    setting (compute or gl_points: now the mark's rasterizer gl with that
    gl_method)."""
    points_cls = nodes.find_node_class(nodes.ROLE_MARK, nodes.POINTS_MARK)
    # Every value explicit, never left to the class default: the defaults
    # differ (color_source "rgb" before, "auto" now).
    new = _replace_node(tree, old, points_cls)
    if any(param["name"] == "rasterizer" for param, _pid in new.pointnpr_params):
        schema_versions.set_item(new, "rasterizer", rasterizer)
    return new


def migrate_former_ids(tree):
    """Replaces the nodes of a local style tree whose filter was renamed
    (the schema's ``former_ids``: the pencil_hatching filter was
    ``hatching``) by nodes of the current class. Returns how many."""
    if not nodes.is_style_tree(tree) or tree.library is not None:
        return 0
    former = [n for n in tree.nodes if getattr(n, "pointnpr_current_class", None) is not None]
    for node in former:
        _replace_node(tree, node, node.pointnpr_current_class, only_set=True)
    if former:
        nodes.bump_generation()
    return len(former)


def migrate_changed_items(tree):
    """Reads the enum values that a local style tree's nodes saved before
    their items changed (the schema's ``older_files_items``, e.g. the points'
    rasterizer compute / gl_points / native / auto, now gl / native / auto
    with gl_method) as the current items, keyframes included. Returns how
    many values and curves changed."""
    if not nodes.is_style_tree(tree) or tree.library is not None:
        return 0
    changed = sum(schema_versions.migrate_items(tree, node, nodes.tree_curves, nodes.node_path_prefix)
                  for node in tree.nodes)
    if changed:
        nodes.bump_generation()
    return changed


def migrate_tree(tree):
    """Migrates the legacy nodes of one style tree; returns how many."""
    if not nodes.is_style_tree(tree) or tree.library is not None:
        return 0
    legacy = [n for n in tree.nodes if n.bl_idname == nodes.LEGACY_RASTERIZE_IDNAME]
    if not legacy:
        return 0
    if nodes.find_node_class(nodes.ROLE_MARK, nodes.POINTS_MARK) is None:
        return 0
    rasterizer = legacy_rasterizer(tree)
    for node in legacy:
        migrate_node(tree, node, rasterizer)
    keep_paper_inpainting(tree)
    nodes.bump_generation()
    return len(legacy)


def keep_paper_inpainting(tree):
    """Styles saved before the inpainting methods existed keep Listing 1
    ("paper"), so they render as they did; new styles get the default."""
    tree[nodes.LEGACY_INPAINT_KEY] = "paper"
    for node in tree.nodes:
        if getattr(node, "pointnpr_role", None) != nodes.ROLE_INPAINT:
            continue
        for param, pid in node.pointnpr_params:
            if param["name"] == "method" and node.get(pid) is None:
                setattr(node, pid, "paper")


def migrate_former_names(tree):
    """Moves what a local style tree's nodes saved under a parameter's
    former name (a renamed parameter: the schema's ``former_names``) to its
    current one: the value, and the F-Curves and drivers that animate it.
    Returns how many values or curves moved."""
    if not nodes.is_style_tree(tree) or tree.library is not None:
        return 0
    moved = 0
    for node in tree.nodes:
        for param, pid in getattr(node, "pointnpr_params", ()):
            for old in nodes.former_identifiers(param):
                if old == pid:
                    continue
                saved = node.get(old)
                if saved is not None:
                    if node.get(pid) is None:
                        setattr(node, pid, nodes.saved_value(param, saved))
                    del node[old]
                    moved += 1
                prefix = nodes.node_path_prefix(node.name) + "."
                for fc in nodes.tree_curves(tree):
                    path = fc.data_path
                    if path == prefix + old or path.startswith(prefix + old + "["):
                        fc.data_path = prefix + pid + path[len(prefix + old):]
                        moved += 1
    if moved:
        nodes.bump_generation()
    return moved


def _is_set(node, pid):
    """Whether a node stores a value of its own for property ``pid``. Blender
    5 keeps bpy.props values apart from the dict interface (``node.get``
    no longer sees them), so RNA is asked first."""
    return node.is_property_set(pid) or node.get(pid) is not None


def migrate_added_params(tree):
    """Gives the nodes of a local style tree that were made before a
    parameter existed or before its default changed (the schema's
    ``older_files_value``) the value that renders them as before, where
    they store none, and records that they know every parameter of their
    class now. Returns how many values it set."""
    if not nodes.is_style_tree(tree) or tree.library is not None:
        return 0
    changed = 0
    for node in tree.nodes:
        params = getattr(node, "pointnpr_params", ())
        if not params:
            continue
        stamp = " ".join(nodes.known_token(param) for param, _pid in params)
        known = node.get(nodes.KNOWN_PARAMS_KEY)
        if known == stamp:
            continue
        known = set(str(known).split()) if known is not None else set()
        for param, pid in params:
            older = param.get("older_files_value")
            if older is not None and nodes.known_token(param) not in known and not _is_set(node, pid):
                setattr(node, pid, older)
                changed += 1
        node[nodes.KNOWN_PARAMS_KEY] = stamp
    if changed:
        nodes.bump_generation()
    return changed


def migrate_legacy_nodes():
    """Migrates every local style tree of the open file; returns the number
    of nodes replaced, of values moved to a parameter's current name or
    item, and of added parameters given their older files' value."""
    # In this order: a node replaced, or one of a renamed filter, then
    # carries what it saved, under the current names, to the later steps.
    return sum(migrate_tree(tree) + migrate_former_names(tree) + migrate_changed_items(tree) +
               migrate_former_ids(tree) + migrate_added_params(tree)
               for tree in list(bpy.data.node_groups))


@persistent
def _on_load_post(*_args):
    migrate_legacy_nodes()


def _migrate_open_file():
    try:
        migrate_legacy_nodes()
    except AttributeError:
        # bpy.data is restricted while add-ons are enabled at startup; the
        # load_post handler covers the file loaded next, a timer this one.
        bpy.app.timers.register(_migrate_later, first_interval=0.0)


def _migrate_later():
    try:
        migrate_legacy_nodes()
    except AttributeError:
        return 0.5
    return None


def register():
    if _on_load_post not in bpy.app.handlers.load_post:
        bpy.app.handlers.load_post.append(_on_load_post)
    _migrate_open_file()


def unregister():
    while _on_load_post in bpy.app.handlers.load_post:
        bpy.app.handlers.load_post.remove(_on_load_post)
    if bpy.app.timers.is_registered(_migrate_later):
        bpy.app.timers.unregister(_migrate_later)
