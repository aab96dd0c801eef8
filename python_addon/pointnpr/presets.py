"""Ready-made styles an artist can pick (issue 5): name -> keyword arguments
of `pointnpr.Style`. Plain data, validated against the C++ schemas by
tests/python/test_presets.py; `style(name)` builds one.

    import pointnpr, pointnpr.presets
    style = pointnpr.presets.style("Watercolor")
"""

PRESETS = {
    # Flat colour bands with outlines; a light oil-paint pass first removes
    # scan noise so the bands are clean.
    "Toon": {
        "rasterize": {"point_size": 3.0},
        "filters": [
            ("kuwahara", {"radius": 3.0}),
            ("cartoon", {"levels": 4, "outline_width": 2, "smoothing": 2}),
        ],
    },
    # Black XDoG lines and silhouettes over a pale, desaturated fill; the
    # oil-paint pass first keeps scan noise from turning into specks.
    "Ink outlines": {
        "rasterize": {"point_size": 3.0},
        "filters": [
            ("kuwahara", {"radius": 4.0}),
            ("xdog", {"thickness": 2.0, "sharpen": 25.0}),
            ("color_grade", {"saturation": 0.0, "exposure": 1.5}),
        ],
    },
    "Watercolor": {
        "rasterize": {"point_size": 3.0},
        "filters": [("watercolor", {})],
    },
    "Oil paint": {
        "rasterize": {"point_size": 3.0},
        "filters": [
            ("kuwahara", {"radius": 6.0}),
            ("color_grade", {"saturation": 1.15, "contrast": 1.1}),
        ],
    },
    "Posterize": {
        "rasterize": {"point_size": 3.0},
        "filters": [
            ("kuwahara", {"radius": 3.0}),
            ("posterize", {"levels": 5, "space": "lightness"}),
            ("xdog", {"thickness": 1.5, "sharpen": 10.0}),
        ],
    },
    # Seed 000 Fig. 1: class colours, eye-dome shading (ambient-occlusion
    # like) with depth outlines, watercolor over all.
    "Urban map": {
        "rasterize": {"point_size": 3.0, "color_source": "classification"},
        "filters": [
            ("edge_enhance", {"edl_strength": 1.0, "outline_width": 1}),
            ("watercolor", {"wobble": 1.5, "edge_darkening": 0.8}),
        ],
    },
}


def style(name):
    """The preset `name` as a validated `pointnpr.Style`."""
    import pointnpr

    if name not in PRESETS:
        raise KeyError(f"unknown preset {name!r} (presets: {', '.join(PRESETS)})")
    return pointnpr.Style(**PRESETS[name])
