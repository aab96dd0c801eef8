"""What the schema says changed since files were saved, as the add-on reads
it: enum values spelt otherwise now or moved in their list (a parameter's
``former_items`` and ``older_files_items``) and filters renamed (a schema's
``former_ids``). versioning.py moves saved nodes to the current names when
a file opens; nodes.py registers a class for each former filter id so that
such nodes load with their values until then.

Blender stores an enum property as its item's index, so a node made before
its items changed stores an index into ``older_files_items``. A node records
the parameters it knew when made (``known_token``): one whose record lacks
the current items has its saved index read through the older list, keys
too; where a former item also set a second parameter, the migration keys
that one at the same frames. A node that is never migrated (a tree linked
from a library file is read-only) is read the same way whenever its style
is read (``older_values``), so it renders as its library file did.
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


def _known(node):
    known = node.get(KNOWN_PARAMS_KEY)
    return set(str(known).split()) if known is not None else set()


def _older_params(node):
    """The enum parameters whose saved values (and keys) index the older
    items: those of a node made before the items changed."""
    params = [(param, pid) for param, pid in getattr(node, "pointnpr_params", ()) if param.get("older_files_items")]
    if not params:
        return []
    known = _known(node)
    return [(param, pid) for param, pid in params if known_token(param) not in known]


def _curves_holding(fc):
    """The F-Curve collection that holds ``fc`` (its action's, or its
    channelbag's in a layered action, Blender 4.4+), or None (a driver)."""
    owner = fc.id_data
    for layer in getattr(owner, "layers", ()):
        for strip in layer.strips:
            for bag in getattr(strip, "channelbags", ()):
                if bag.fcurves.find(fc.data_path, index=fc.array_index) == fc:
                    return bag.fcurves
    return getattr(owner, "fcurves", None)


def _key_also(node, fc, alsos, before, path_prefix):
    """Keys, beside the keys of ``fc`` ({frame: (parameter, item) or None}
    in ``alsos``), the other parameter that a former item also set, so the
    animation keeps that meaning: the item at those frames, elsewhere the
    value it had (its own curve's, else the node's before migration). Steps
    (CONSTANT), as enums do. Returns how many curves it keyed."""
    fcurves = _curves_holding(fc)
    if fcurves is None:
        return 0
    pids = {param["name"]: (param, pid) for param, pid in node.pointnpr_params}
    keyed = 0
    for name in sorted({also[0] for also in alsos.values() if also and also[0] in pids}):
        param, pid = pids[name]
        items = list(param["items"])
        path = path_prefix(node.name) + "." + pid
        curve = fcurves.find(path, index=0)
        held = before[pid] if before[pid] in items else param["default"]
        values = [(frame, items.index(also[1]) if also and also[0] == name else
                   curve.evaluate(frame) if curve is not None else items.index(held))
                  for frame, also in sorted(alsos.items())]
        if curve is None:
            curve = fcurves.new(path, index=0)
        for frame, value in values:
            curve.keyframe_points.insert(frame, float(value)).interpolation = 'CONSTANT'
        curve.update()
        keyed += 1
    return keyed


def migrate_items(tree, node, tree_curves, path_prefix):
    """Reads what a node made before its enums' items changed saved (the
    value and keyframes: indices into the older items) as the current
    items. Returns how many values and curves it changed."""
    older = _older_params(node)
    if not older:
        return 0
    # The values of the parameters a former item also sets, before it does.
    also = {f["also"][0] for param, _pid in older for f in param.get("former_items") or () if f.get("also")}
    before = {pid: getattr(node, pid) for param, pid in node.pointnpr_params if param["name"] in also}
    changed = 0
    for param, pid in older:
        saved = stored_value(node, pid)
        if saved is not None:
            set_item(node, param["name"], older_item(param, saved))
            changed += 1
        for fc in _node_curves(tree, node, pid, tree_curves, path_prefix):
            alsos = {}
            for key in fc.keyframe_points:
                now, alsos[key.co[0]] = current_item(param, older_item(param, key.co[1]))
                index = float(param["items"].index(now))
                key.co[1] = key.handle_left[1] = key.handle_right[1] = index
            if any(alsos.values()):
                changed += _key_also(node, fc, alsos, before, path_prefix)
            changed += 1
    return changed


def older_values(node, frame, curve):
    """{parameter: value at ``frame``} that a node made before its enums'
    items changed means, where it is read unmigrated (a tree linked from a
    library file, which cannot be edited): its saved index or key read
    through the older items, and the parameter a former item also sets.
    ``curve(pid)`` is the F-Curve animating property ``pid``, or None."""
    values = {}
    for param, pid in _older_params(node):
        fc = curve(pid)
        saved = fc.evaluate(frame) if fc is not None else stored_value(node, pid)
        if saved is None:
            continue
        now, also = current_item(param, older_item(param, saved))
        values[param["name"]] = now
        if also and any(p["name"] == also[0] for p, _pid in node.pointnpr_params):
            values[also[0]] = also[1]
    return values


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
