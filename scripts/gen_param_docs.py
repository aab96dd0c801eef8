"""Writes docs/parameters.md from the C++ parameter schemas (the single
source of truth). tests/python/test_docs.py fails when the committed file
is out of date; regenerate on purpose with:

    PYTHONPATH=build python3 scripts/gen_param_docs.py > docs/parameters.md
"""
import pointnpr


def _value(p, v):
    if p["type"] == "color":
        return "(" + ", ".join(f"{c:g}" for c in v) + ")"
    if p["type"] == "float":
        return f"{v:g}"
    if p["type"] == "path":
        return v or "none"
    return str(v)


def _range(p):
    if p["type"] == "enum":
        return " / ".join(f"`{i}`" for i in p["items"])
    if p["type"] == "bool":
        return "on / off"
    if p["type"] == "color":
        return "RGBA in [0, 1]"
    if p["type"] == "path":
        return "a file path"
    return f"{p['min']:g} to {p['max']:g}"


def _former_item(f):
    also = f" with `{f['also'][0]}` = `{f['also'][1]}`" if f.get("also") else ""
    return f"`{f['name']}` = `{f['now']}`{also}"


def render():
    lines = [
        "# Parameters",
        "",
        "Generated from the C++ schemas by `scripts/gen_param_docs.py`; do not edit by hand.",
        "Every parameter appears with the same name, range and doc in the Python API",
        "(`pointnpr.Style`), in the Blender style nodes and here.",
        "",
    ]
    for s in pointnpr.schemas():
        former_ids = "".join(f"; formerly `{i}`, still read" for i in s.get("former_ids", ()))
        lines += [f"## {s['label']} (`{s['id']}`, {s['kind']}{former_ids})", "", s["doc"], "",
                  "| parameter | type | default | range | unit | description |",
                  "|---|---|---|---|---|---|"]
        for p in s["params"]:
            when = p.get("when")
            doc = p["doc"]
            if when:
                spell = lambda c: "`%s` is %s" % (c["param"], " or ".join(f"`{v}`" for v in c["values"]))
                doc += " (applies when %s%s)" % (", or ".join(spell(c) for c in [when] + list(when.get("or", ()))),
                                                 "".join(", and " + spell(c) for c in when.get("and", ())))
            if p.get("former_names"):
                doc += " (formerly %s: still read from scripts and saved files)" % " or ".join(
                    f"`{n}`" for n in p["former_names"])
            if p.get("former_items"):
                doc += " (former values, still read from scripts and saved files: %s)" % ", ".join(
                    _former_item(f) for f in p["former_items"])
            lines.append(f"| `{p['name']}` | {p['type']} | {_value(p, p['default'])} | {_range(p)} | "
                         f"{p['unit'] or ''} | {doc} |")
        lines.append("")
    return "\n".join(lines)


if __name__ == "__main__":
    print(render())
