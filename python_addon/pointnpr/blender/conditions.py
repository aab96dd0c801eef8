"""When a node's parameter applies: the schema's "when" conditions.

A condition is {"param": name, "values": [...]} and may carry "or": further
conditions, any of which also makes the parameter apply (a line width
applies while any class of strokes is drawn as lines), and "and":
conditions that must hold as well (the stipples' specular_share acts only
on the share rule's lit points). Values are spelled
as enum items, "true"/"false" for a bool and "zero"/"nonzero" for a number
(docs/parameters.md). The node UI greys out a parameter that does not apply
(``param_applies``); the sweep tests and the docs read the same rule.
"""


def when_spelling(value):
    """A parameter's value as a "when" condition names it: "true"/"false"
    for a bool, "zero"/"nonzero" for a number, the item for an enum."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, (int, float)):
        return "nonzero" if value != 0 else "zero"
    return str(value)


def _when_value(node, param_name):
    """The current value of ``node``'s parameter ``param_name`` as a "when"
    condition names it (when_spelling); None if the node has no such
    parameter."""
    for param, pid in getattr(node, "pointnpr_params", ()):
        if param["name"] == param_name:
            return when_spelling(getattr(node, pid))
    return None


def when_holds(when, value):
    """Whether one schema condition ({"param": name, "values": [...]}, or
    None) holds for the other parameter's ``value`` (enum item or
    "true"/"false"; a bool or None is accepted too)."""
    if not when:
        return True
    if isinstance(value, bool):
        value = "true" if value else "false"
    return value is not None and str(value) in [str(v) for v in when.get("values", ())]


def alternatives(when):
    """The conditions of a "when", any of which makes its parameter apply."""
    return [when] + list(when.get("or", ())) if when else []


def param_applies(node, param, _seen=None):
    """Whether ``param`` (a schema dict of one of ``node``'s parameters)
    applies with the node's current values: one of its conditions holds and
    the parameter that condition names applies itself (conditions chain: the
    hatching mark's pencil_image needs pencil_set "image", which needs
    pencil_quantize on). A condition naming a parameter the node does not
    have is taken to hold."""
    when = param.get("when")
    if not when:
        return True
    seen = set(_seen or ()) | {param["name"]}
    for condition in when.get("and", ()):
        value = _when_value(node, condition["param"])
        if value is None or condition["param"] in seen:
            continue
        if not when_holds(condition, value):
            return False
        other = next(p for p, _pid in node.pointnpr_params if p["name"] == condition["param"])
        if not param_applies(node, other, seen):
            return False
    for condition in alternatives(when):
        value = _when_value(node, condition.get("param"))
        if value is None:
            return True
        if not when_holds(condition, value):
            continue
        if condition["param"] in seen:
            return True   # a cycle in the schema: do not loop
        other = next(p for p, _pid in node.pointnpr_params if p["name"] == condition["param"])
        if param_applies(node, other, seen):
            return True
    return False


def draw_node_properties(node, layout):
    """One row per parameter; rows whose "when" condition does not hold are
    greyed out (still editable: the value is kept for when it applies)."""
    for param, pid in getattr(node, "pointnpr_params", ()):
        row = layout.row()
        row.active = param_applies(node, param)
        row.prop(node, pid)
