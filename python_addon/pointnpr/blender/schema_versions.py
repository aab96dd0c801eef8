"""What the schema says changed since files were saved, as the add-on reads
it: enum values spelt otherwise now or moved in their list (a parameter's
``former_items`` and ``older_files_items``) and filters renamed (a schema's
``former_ids``). versioning.py moves saved nodes to the current names when
a file opens; nodes.py registers a class for each former filter id so that
such nodes load with their values until then.

Blender stores an enum property as its item's index, so a node made before
its items changed stores an index into ``older_files_items``. A node records
the parameters it knew when made (``known_token``): one whose record lacks
the current items has its saved index read through the older list.
"""

# The parameters a node's class had when the node was made (space-separated
# known_token()s): a parameter added later, or whose default or items
# changed, is migrated (versioning.py) only on nodes made before that.
KNOWN_PARAMS_KEY = "pointnpr_known_params"


def known_token(param):
    """How a node records that it knows a parameter: its name, with its
    default where that changed since older files, and with its items where
    they changed (so a node made before either change does not count as
    knowing the current ones)."""
    token = param["name"]
    if param.get("default_changed"):
        token += "=%s" % (param["default"],)
    if param.get("older_files_items"):
        token += ":" + "/".join(param["items"])
    return token


def current_item(param, item):
    """(the current item, and (other parameter, its item) or None) that
    enum item ``item`` of ``param``, current or former, means now."""
    if item in param["items"]:
        return item, None
    for former in param.get("former_items") or ():
        if former["name"] == item:
            also = former.get("also")
            return former["now"], tuple(also) if also else None
    raise ValueError("%s has no item %r (items: %s)" % (param["name"], item, ", ".join(param["items"])))


def older_item(param, index):
    """The item an older file meant by the saved index ``index``."""
    older = list(param.get("older_files_items") or param["items"])
    return older[min(max(int(index), 0), len(older) - 1)]


def set_item(node, param_name, item):
    """Sets enum parameter ``param_name`` of ``node`` to ``item``, current or
    former (a former item folded into two parameters sets both)."""
    pids = {param["name"]: (param, pid) for param, pid in node.pointnpr_params}
    param, pid = pids[param_name]
    now, also = current_item(param, item)
    setattr(node, pid, now)
    if also and also[0] in pids:
        setattr(node, pids[also[0]][1], also[1])


def stored_value(node, pid):
    """What ``node`` saved for its property ``pid`` (an enum: the index), or
    None. Blender 5 keeps bpy.props values apart from the dict interface
    (``bl_system_properties_get``); earlier versions keep them in it."""
    if not node.is_property_set(pid):
        return None
    system = getattr(node, "bl_system_properties_get", None)
    group = system() if system is not None else None
    if group is not None and group.get(pid) is not None:
        return group.get(pid)
    return node.get(pid)


def _node_curves(tree, node, pid, tree_curves, path_prefix):
    path = path_prefix(node.name) + "." + pid
    return [fc for fc in tree_curves(tree) if fc.data_path == path]


def migrate_items(tree, node, tree_curves, path_prefix):
    """Reads what a node made before its enums' items changed saved (the
    value and keyframes: indices into the older items) as the current
    items. Returns how many values and curves it changed."""
    known = node.get(KNOWN_PARAMS_KEY)
    known = set(str(known).split()) if known is not None else set()
    changed = 0
    for param, pid in getattr(node, "pointnpr_params", ()):
        if not param.get("older_files_items") or known_token(param) in known:
            continue
        saved = stored_value(node, pid)
        if saved is not None:
            set_item(node, param["name"], older_item(param, saved))
            changed += 1
        for fc in _node_curves(tree, node, pid, tree_curves, path_prefix):
            for key in fc.keyframe_points:
                now, _also = current_item(param, older_item(param, key.co[1]))
                index = float(param["items"].index(now))
                key.co[1] = key.handle_left[1] = key.handle_right[1] = index
            changed += 1
    return changed


def former_id_classes(schemas, role, make_class, classes):
    """A node class for each former id of the filters in ``schemas`` (a
    filter renamed): nodes saved under it load with their values, and
    versioning.py replaces them by nodes of the current class, among
    ``classes``, which the former one names (``pointnpr_current_class``;
    it stays out of the Add menu)."""
    formers = []
    for schema in schemas:
        if schema.get("kind") != "filter":
            continue
        current = next((c for c in classes if c.pointnpr_role == role and c.pointnpr_schema_id == schema["id"]),
                       None)
        for former in schema.get("former_ids") or ():
            cls = make_class(role, dict(schema, id=former))
            cls.pointnpr_current_class = current
            formers.append(cls)
    return formers
