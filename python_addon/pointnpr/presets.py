"""Ready-made styles an artist can pick (issue 5): name -> {"mark": (id,
params), "filters": [(id, params), ...]}, the arguments of `pointnpr.Style`.
The first six draw the points mark then image filters; the hatching presets
replace the points by strokes (seed 002, docs/marks.md); the feature
strokes presets draw seed 001's feature and dithering points; the stipple
presets draw dots by density (seed 003). Plain data,
validated against the C++ schemas by tests/python/test_presets.py;
`style(name)` builds one.

    import pointnpr, pointnpr.presets
    style = pointnpr.presets.style("Watercolor")
"""

# The image-space looks' splats (issue 40): as wide as each point's own
# spacing where the scan is sparse on screen (an aerial tile near the
# camera, a canopy of lone returns), so the filters see a closed surface,
# and 3 px where it is dense. bench/look_audit.py: the aerial tiles' holes
# 0.4-2.1 % -> 0.02-0.3 %, the LiDAR HD tile's Watercolor 0.8 s -> 0.5 s a
# frame (docs/filter_measurements.md).
SPLATS = {"size_mode": "spacing", "point_size": 3.0}

PRESETS = {
    # Flat colour bands with outlines; a light oil-paint pass first removes
    # scan noise so the bands are clean.
    "Toon": {
        "mark": ("points", dict(SPLATS)),
        "filters": [
            ("kuwahara", {"radius": 3.0}),
            ("cartoon", {"levels": 4, "outline_width": 2, "smoothing": 2}),
        ],
    },
    # Black XDoG lines and silhouettes over a pale, desaturated fill; the
    # oil-paint pass first keeps scan noise from turning into specks. No
    # impasto: XDoG drew its relief as squiggles over every plane (lines on
    # planes 10-14 % -> 0-2.2 %, bench/look_audit.py).
    "Ink outlines": {
        "mark": ("points", dict(SPLATS)),
        "filters": [
            ("kuwahara", {"radius": 4.0, "impasto": 0.0}),
            ("xdog", {"thickness": 2.0, "sharpen": 25.0}),
            ("color_grade", {"saturation": 0.0, "exposure": 1.5}),
        ],
    },
    # Pen lines that follow the image's flow (FDoG: XDoG smoothed along the
    # structure tensor's edge direction), over a pale wash of the colours:
    # coherent strokes where the isotropic lines break into specks.
    "Flow ink": {
        "mark": ("points", dict(SPLATS)),
        "filters": [
            ("kuwahara", {"radius": 3.0, "impasto": 0.0}),
            ("xdog", {"thickness": 1.5, "sharpen": 60.0, "threshold": 0.02, "flow_length": 3.0}),
            ("color_grade", {"saturation": 0.35, "exposure": 1.2}),
        ],
    },
    # The watercolor filter over the splats.
    "Watercolor": {
        "mark": ("points", dict(SPLATS)),
        "filters": [("watercolor", {})],
    },
    # Kuwahara oil paint, a little more saturation and contrast.
    "Oil paint": {
        "mark": ("points", dict(SPLATS)),
        "filters": [
            ("kuwahara", {"radius": 6.0}),
            ("color_grade", {"saturation": 1.15, "contrast": 1.1}),
        ],
    },
    # Oil paint after Semmo et al. 2016: strokes that follow the image's flow
    # (the structure tensor), colours smoothed along it into lightness
    # bands, bristle streaks fixed to the surface and lit as paint relief.
    "Flow oil paint": {
        "mark": ("points", dict(SPLATS)),
        "filters": [
            ("flow_oil", {}),
            ("color_grade", {"saturation": 1.15, "contrast": 1.1}),
        ],
    },
    # Five lightness levels with XDoG lines, after an oil-paint pass (no
    # impasto: its relief is no form of the scan, and XDoG outlined it).
    "Posterize": {
        "mark": ("points", dict(SPLATS)),
        "filters": [
            ("kuwahara", {"radius": 3.0, "impasto": 0.0}),
            ("posterize", {"levels": 5, "space": "lightness"}),
            ("xdog", {"thickness": 1.5, "sharpen": 10.0}),
        ],
    },
    # Seed 000 Fig. 1: class colours, eye-dome shading (ambient-occlusion
    # like) with depth outlines, watercolor over all.
    "Urban map": {
        "mark": ("points", dict(SPLATS, color_source="classification")),
        "filters": [
            ("edge_enhance", {"edl_strength": 1.0, "outline_width": 1}),
            ("watercolor", {"wobble": 1.5, "edge_darkening": 0.8}),
        ],
    },

    # ---- Hatching presets (seed 002, Wagner et al.): one stroke mark per
    # point, tuned on the lion scan and the LiDAR HD tile at 320x224. The
    # light is the mark's default key light: with the camera (light_space
    # camera), from the upper left, 45 degrees off the view axis (35 for
    # Chalk), so every scan reads whichever way up it was captured (a
    # world light came from below a Y-down depth sensor's scene); normals
    # are turned toward the camera (two_sided). bench/marks_audit.py: ink
    # against Lambert shading on the lion 0.83 -> 0.93, the aerial tile
    # 0.52 -> 0.71, flicker at most the points mark's.
    #
    # Graphite on white paper: pencil X-Toon (strokes where the light does
    # not reach, crossed in the darkest tones), thin grey depth outlines.
    "Pencil": {
        "mark": ("hatching", {"xtoon": "pencil", "stroke_texture": "pencil", "coloring": "constant",
                              "stroke_coverage": 2.5, "line_length": 12.0, "cross_hatch": 0.6,
                              "light_azimuth": 135.0, "light_elevation": 45.0, "paper_color": (1.0, 1.0, 1.0, 1.0)}),
        "filters": [
            ("edge_enhance", {"edl_strength": 0.0, "outline_width": 1, "silhouette": False,
                              "edge_color": (0.2, 0.2, 0.24, 0.7)}),
        ],
    },
    # Coloured pencils (the paper's pencil quantization): each stroke the
    # point's colour, snapped to two of 24 pencils mixed by chance plus
    # black and white; the two-coloured X-Toon keeps strokes in the light.
    "Coloured crayons": {
        "mark": ("hatching", {"xtoon": "two_colored", "coloring": "point", "point_blend": 0.25,
                              "pencil_quantize": True, "pencil_set": "box_24", "stroke_texture": "pencil",
                              "stroke_coverage": 5.0, "line_length": 10.0, "line_width": 2.0, "cross_hatch": 0.6,
                              "opacity": 1.0, "alpha_jitter": 0.2, "alpha_modification": 0.6,
                              "light_azimuth": 135.0, "light_elevation": 45.0, "paper_color": (1.0, 1.0, 1.0, 1.0)}),
        "filters": [],
    },
    # Wax crayons: the wax-crayon X-Toon's three warm bands give the colour
    # and the omission; broad, waxy strokes.
    "Wax crayons": {
        "mark": ("hatching", {"xtoon": "wax_crayon", "coloring": "xtoon", "stroke_texture": "crayon",
                              "stroke_coverage": 4.0, "line_length": 14.0, "line_width": 3.0, "cross_hatch": 0.4,
                              "opacity": 0.9, "light_azimuth": 135.0, "light_elevation": 45.0,
                              "paper_color": (1.0, 1.0, 1.0, 1.0)}),
        "filters": [],
    },
    # White ink on blue paper: regular, nearly parallel ruled lines along
    # world X in the shade, white depth and silhouette outlines.
    "Blueprint": {
        "mark": ("hatching", {"xtoon": "pencil", "coloring": "constant", "stroke_color": (0.92, 0.95, 1.0, 1.0),
                              "stroke_texture": "ink", "paper_color": (0.08, 0.24, 0.52, 1.0),
                              "placement": "regular", "cross_hatch": 0.1, "length_jitter": 0.1, "alpha_jitter": 0.1,
                              "line_length": 14.0, "line_width": 1.0, "stroke_coverage": 2.0, "curvature_length": 0.3,
                              "direction_azimuth": 0.0, "direction_elevation": 0.0,
                              "light_azimuth": 135.0, "light_elevation": 45.0}),
        "filters": [
            ("edge_enhance", {"edl_strength": 0.0, "outline_width": 1, "silhouette": True,
                              "edge_color": (0.92, 0.95, 1.0, 0.9)}),
        ],
    },
    # Chalk on a blackboard: the chalk X-Toon puts light, grainy strokes
    # where the light falls, on dark green-grey paper.
    "Chalk": {
        "mark": ("hatching", {"xtoon": "chalk", "coloring": "xtoon", "stroke_texture": "crayon",
                              "paper_color": (0.13, 0.17, 0.15, 1.0), "stroke_coverage": 1.8, "line_length": 10.0,
                              "line_width": 1.2, "cross_hatch": 0.5, "opacity": 0.95, "alpha_jitter": 0.2,
                              "light_azimuth": 135.0, "light_elevation": 35.0}),
        "filters": [],
    },
    # Pointillism: short soft dots, no crossing, jittered, in the point's
    # colour quantized to 12 pencils; a saturation boost afterwards brings
    # the dull scan colours toward pure pigments.
    "Pointillism": {
        "mark": ("hatching", {"xtoon": "two_colored", "coloring": "point", "point_blend": 0.15,
                              "pencil_quantize": True, "pencil_set": "box_12", "stroke_texture": "soft",
                              "line_length": 3.5, "line_width": 3.5, "length_jitter": 0.2, "cross_hatch": 0.0,
                              "placement": "irregular", "position_jitter": 0.5, "curvature_length": 0.0,
                              "stroke_coverage": 3.5, "opacity": 1.0, "alpha_modification": 0.3, "alpha_jitter": 0.1,
                              "light_azimuth": 135.0, "light_elevation": 45.0, "paper_color": (1.0, 1.0, 1.0, 1.0)}),
        "filters": [("color_grade", {"saturation": 1.8})],
    },
    # Seed 001 Fig. 7(a): stippling, every class of point a Gaussian point
    # sprite: feature points dense along edges, dithering points for tone
    # (the tone of the key light on the shape, at any density and size).
    "Feature stippling": {
        "mark": ("feature_strokes", {"directional": "point_sprite", "non_directional": "point_sprite",
                                     "dithering": "point_sprite", "sprite_size": 2.0, "feature_threshold": 0.3,
                                     "tone": 1.2, "shading": "diffuse", "line_tone": 1.0, "color_source": "constant",
                                     "density_mode": "constant_on_screen", "queue_level": 0.25}),
        "filters": [],
    },
    # Seed 001 Fig. 1 / 7(b): directional feature points as long tapered
    # textured strokes along their fitted 3D lines, the other feature points
    # and the dithering points as Gaussian point sprites (stipples) for the
    # tone; the continuous resolution queue keeps the density on screen.
    "Feature strokes + stipples": {
        "mark": ("feature_strokes", {"directional": "textured_stroke", "stroke_texture": "taper",
                                     "directional_length": 16.0, "stroke_width": 3.0,
                                     "non_directional": "point_sprite", "dithering": "point_sprite",
                                     "sprite_size": 2.5, "feature_threshold": 0.3, "line_error": 0.25,
                                     "tone": 1.2, "shading": "diffuse", "line_tone": 1.0, "color_source": "constant",
                                     "density_mode": "constant_on_screen", "queue_level": 0.25}),
        "filters": [],
    },
    # Seed 001 Fig. 7(c)-(d): directional points as bristle-brush strokes,
    # non-directional and dithering points as short line segments in one
    # constant screen direction (a hatched tone on flat surfaces).
    "Feature strokes + hatching": {
        "mark": ("feature_strokes", {"directional": "textured_stroke", "stroke_texture": "brush",
                                     "directional_length": 18.0, "stroke_width": 3.5,
                                     "non_directional": "line_segment", "dithering": "line_segment",
                                     "other_length": 5.0, "line_width": 1.0, "screen_angle": 45.0,
                                     "feature_threshold": 0.45, "line_error": 0.25,
                                     "tone": 1.2, "shading": "diffuse", "line_tone": 1.0, "color_source": "constant",
                                     "density_mode": "constant_on_screen", "queue_level": 0.25}),
        "filters": [],
    },
    # Stippling (seed 003): black dots on white paper, no normals needed;
    # hidden points removed in image space, lit surfaces thinned by the
    # light-view quadtree (diffuse only), its cells from each point's own
    # spacing, the dots' density set by the tone whatever the scan's.
    "Stipple diffuse": {
        "mark": ("stipples", {"level": 8.5, "level_scale": "spacing", "tone": 0.7, "light_azimuth": 135.0,
                              "light_elevation": 50.0}),
        "filters": [],
    },
    # The same with highlights opened where the surface faces between eye
    # and light (diffuse + specular).
    "Stipple specular": {
        "mark": ("stipples", {"level": 8.5, "level_scale": "spacing", "tone": 0.7, "light_azimuth": 135.0,
                              "light_elevation": 50.0, "specular": True, "tau": 0.25}),
        "filters": [],
    },
    # Ink stippling: smaller sepia dots of varying size on cream paper, a
    # key light from higher left and a narrower highlight.
    # (Colours are binary fractions: float32 Blender properties hold them exactly.)
    "Ink stippling": {
        "mark": ("stipples", {"dot_size": 1.6, "size_jitter": 0.5, "dot_color": (0.1875, 0.09375, 0.046875, 1.0),
                              "paper_color": (0.96875, 0.9296875, 0.84375, 1.0), "level": 8.5, "level_scale": "spacing", "tone": 0.7,
                              "light_azimuth": 120.0,
                              "light_elevation": 45.0, "specular": True, "tau": 0.15}),
        "filters": [],
    },
    # Brush splats (seed 004, stroke-based splatting): every point a brush
    # of Gaussians on a splat sized by its neighbours' spacing.
    # Impressionist: the seed's Fig. 4c brush (nine Gaussians, A = 1,
    # dev = 0.38, lambda = 2.7, sigma 0.142 x 0.071), columns turned by up
    # to 12 degrees each, a light blur between patches.
    "Impressionist": {
        "mark": ("brush_splats", {"gaussians": 9, "amplitude": 1.0, "dev": 0.38, "lambda": 2.7, "sigma_x": 0.142,
                                  "sigma_y": 0.071, "size_scale": 2.0, "angle_jitter": 12.0, "blending": "blur",
                                  "blur_radius": 1, "max_radius": 11.0}),
        "filters": [],
    },
    # Pointillist: one round Gaussian per point, opaque centres, no blur,
    # saturated afterwards toward pure pigments.
    "Pointillist": {
        "mark": ("brush_splats", {"gaussians": 1, "amplitude": 3.0, "lambda": 2.0, "sigma_x": 0.16, "sigma_y": 0.16,
                                  "size_scale": 2.0, "angle_jitter": 0.0, "blending": "none", "depth_tolerance": 0.5,
                                  "max_radius": 9.5}),
        "filters": [("color_grade", {"saturation": 1.6})],
    },
    # Painterly: the seed's Fig. 4d brush (six Gaussians, A = 2.27,
    # dev = 0.3, lambda = 2.4) in two layers, the smaller one lighter.
    "Painterly": {
        "mark": ("brush_splats", {"gaussians": 6, "amplitude": 2.27, "dev": 0.3, "lambda": 2.4, "sigma_x": 0.099,
                                  "sigma_y": 0.1259, "layers": "two", "layer_tint": 0.2, "size_scale": 2.0,
                                  "angle_jitter": 15.0, "blending": "blur", "blur_radius": 1, "max_radius": 11.0}),
        "filters": [],
    },
}


def style(name):
    """The preset `name` as a validated `pointnpr.Style`."""
    from . import _self as pointnpr

    if name not in PRESETS:
        raise KeyError(f"unknown preset {name!r} (presets: {', '.join(PRESETS)})")
    preset = PRESETS[name]
    return pointnpr.Style(mark=preset["mark"], filters=preset.get("filters", []))
