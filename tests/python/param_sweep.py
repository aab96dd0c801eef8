"""The parameter sweep shared by the filters' and the marks' tests (issues
39 and 40, "every parameter acts or is greyed out"): each parameter of a
schema, set to other valid values, must change the picture measurably, or
its schema must say that it does not apply with the other settings (its
"when" condition, the rule the Blender UI greys parameters out by and
docs/parameters.md states).

Measure: the share of pixels whose colour moves by more than CHANGE (8/255
in some channel) must reach MIN_SHARE (0.5 % of the image, ~290 pixels at
320x180) on at least one of the scans given.

Values tried: for numbers the points a quarter and three quarters into the
range (the ends are often "off" twice over: a crease angle of 0 and of 180
both draw nothing), or the end of the range on that side where that point
is within a tenth of the range of the default (in log for ranges over two
decades and more: thresholds and scales); for angles that wrap (deg over
360 or more) the default +-90; every other enum item; the other bool; the
complement colour; for an image path, another image (its tones raised to
the power 2.2, its alpha following them: other colours, another palette)
and none, which may be
refused with a ParameterError (no image where a setting draws with one:
the user is told, not left with a control that does nothing). Each of those
must act, and for numbers one of the two (some ranges end in a setting that
rarely fires: a crease angle of 135 deg, a depth jump of 18 % of the
distance on these scans)."""
import numpy as np

import pointnpr

CHANGE = 8.0 / 255.0
MIN_SHARE = 0.005


DEPTH_CHANGE = 0.01  # relative: a segment's depth decides what it hides when composited
FAR = 1e9  # uncovered pixels' depth is the background's, 1e10


def changed_share(a, b):
    """The share of pixels that change: colour (an RGB array) by more than
    CHANGE, or, for (colour, depth) pairs, also depth by more than
    DEPTH_CHANGE of itself (or covered in only one)."""
    if not isinstance(a, tuple):
        return float((np.abs(a - b).max(axis=-1) > CHANGE).mean())
    (ca, da), (cb, db) = a, b
    colour = np.abs(ca - cb).max(axis=-1) > CHANGE
    fa, fb = da < FAR, db < FAR
    both = fa & fb
    depth = fa != fb
    depth[both] = np.abs(da[both] - db[both]) > DEPTH_CHANGE * np.maximum(np.abs(da[both]), 1e-12)
    return float((colour | depth).mean())


def grey_ramp_image(path):
    """A 4-level inverting LUT strip: as a look-up table clearly not the
    identity, as a paper or stroke texture a height ramp, as an X-Toon or
    pencil image a ramp of tones. Beside it (other_image) the same strip
    with its tones raised to the power 2.2, and an alpha that follows them."""
    n = 4
    strip = np.zeros((n, n * n, 4), np.float32)
    for b in range(n):
        for g in range(n):
            for r in range(n):
                strip[g, b * n + r] = (1 - r / (n - 1), 1 - g / (n - 1), 1 - b / (n - 1), 1)
    pointnpr.save_image(path, strip)
    raised = strip[..., :3] ** 2.2
    # Its alpha follows its tone too (X-Toon images are read for their alpha).
    pointnpr.save_image(other_image(path), np.concatenate([raised, 0.25 + 0.75 * raised.mean(-1, keepdims=True)], -1))
    return path


def other_image(path):
    return path[:-4] + "_gamma.png" if path.endswith(".png") else path + "_gamma.png"


def _when_value(value):
    """A value as "when" conditions spell it (docs/parameters.md)."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, (int, float)):
        return "nonzero" if value != 0 else "zero"
    return value


def _holding(when, other):
    """A value of parameter `other` (schema dict) for which `when` holds."""
    wanted = when["values"][0]
    if other["type"] == "bool":
        return wanted == "true"
    if other["type"] in ("float", "int"):
        return other["max"] if wanted == "nonzero" else type(other["default"])(0)
    return wanted


def other_values(param, current, image):
    kind, default = param["type"], current
    lo, hi = param["min"], param["max"]
    if kind in ("float", "int"):
        if param["unit"] == "deg" and hi - lo >= 360:
            candidates = [default - 90, default + 90]
        elif lo > 0 and hi >= 100 * lo:
            # Ranges over decades (thresholds, scales): quarter points in log.
            candidates = [lo * (hi / lo) ** 0.25, lo * (hi / lo) ** 0.75]
        else:
            # A quarter point within a tenth of the range of the default
            # moves to the end of the range on its side.
            candidates = [v if abs(v - default) >= 0.1 * (hi - lo) else end
                          for v, end in ((lo + 0.25 * (hi - lo), lo), (lo + 0.75 * (hi - lo), hi))]
        if kind == "int":
            candidates = [int(round(v)) for v in candidates]
        return [v for v in dict.fromkeys(candidates) if lo <= v <= hi and v != default]
    if kind == "bool":
        return [not default]
    if kind == "enum":
        return [item for item in param["items"] if item != default]
    if kind == "color":
        return [tuple(1.0 - c for c in default[:3]) + (default[3],)]
    if kind == "path":
        return [image] if current == "" else [other_image(current), ""]
    raise AssertionError("no sweep values for a %s parameter" % kind)


def base_settings(schema, image):
    """The defaults, with path parameters set (an image) so that what reads
    them applies; the sweep of the path itself then tries none."""
    by_name = {p["name"]: p for p in schema["params"]}
    return {p["name"]: (image if by_name[p["name"]]["type"] == "path" else p["default"]) for p in schema["params"]}


def applying(schema, settings, param, _seen=()):
    """`settings` with `param`'s condition made to hold (its first
    alternative, where it has several; and that of the parameter the
    condition names: conditions chain), so it is swept where it applies."""
    by_name = {p["name"]: p for p in schema["params"]}
    when = param["when"]
    if not when or param["name"] in _seen:
        return settings
    # The first alternative, and every condition that must hold as well.
    for condition in [when] + list(when.get("and", ())):
        if condition["param"] in _seen:
            continue  # (a cycle: what the chain set stays)
        if _when_value(settings[condition["param"]]) not in condition["values"]:
            settings = dict(settings, **{condition["param"]: _holding(condition, by_name[condition["param"]])})
        settings = applying(schema, settings, by_name[condition["param"]], tuple(_seen) + (param["name"],))
    return settings


def dead_parameters(schema, render, n_scans, image, skip=(), skip_values=()):
    """The parameters of `schema` that change no picture, each with the
    shares it moved. render(settings, scan_index) gives an RGB image (or a
    colour and depth pair); a scan is rendered only while no earlier one
    showed the change. `skip` names parameters and `skip_values` (name,
    value) pairs the caller checks otherwise."""
    base = base_settings(schema, image)
    dead = []
    for param in schema["params"]:
        if param["name"] in skip:
            continue
        settings = applying(schema, base, param)
        references = {}
        tried = []
        for value in other_values(param, settings[param["name"]], image):
            if (param["name"], value) in skip_values:
                continue
            changed = dict(settings, **{param["name"]: value})
            share = 0.0
            for scan in range(n_scans):
                if scan not in references:
                    references[scan] = render(settings, scan)
                try:
                    picture = render(changed, scan)
                except pointnpr.ParameterError:
                    if param["type"] != "path" or value != "":
                        raise
                    share = 1.0  # no image where one is needed: refused, the user is told
                    break
                share = max(share, changed_share(picture, references[scan]))
                if share >= MIN_SHARE:
                    break
            tried.append((value, share))
            if share >= MIN_SHARE and param["type"] in ("float", "int"):
                break  # one acting value is enough for a number
        numeric = param["type"] in ("float", "int")
        acting = [share >= MIN_SHARE for _value, share in tried]
        if not tried or not (any(acting) if numeric else all(acting)):
            dead.append("%s (from %r): %s" % (param["name"], settings[param["name"]],
                                               ", ".join("%r: %.4f" % t for t in tried)))
    return dead
