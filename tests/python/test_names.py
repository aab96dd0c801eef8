"""Consistent names (issue 38): every mark with two backends takes the same
`rasterizer` values (gl, native, auto), the points' two GL methods are its
`gl_method`, and the image filter once called `hatching` (the hatching
mark's id too) is `pencil_hatching`. What older scripts give is still taken
and renders the same bytes."""
import numpy as np
import pytest

import pointnpr
from test_marks import mark_cloud, render, sphere

BACKEND_MARKS = ("points", "gaussians", "hatching", "stipples", "feature_strokes", "brush_splats")


def _params(schema_id, kind="mark"):
    return {p["name"]: p for p in pointnpr.schema(schema_id, kind=kind)["params"]}


def _bytes(renderer, style, mark="points"):
    pos, _normals = sphere(3000)
    rng = np.random.default_rng(4)
    colors = (rng.random((len(pos), 3)) * 255).astype(np.uint8)
    r = render(renderer, style, [mark_cloud(mark, pos, colors=colors)], capture=False)
    return np.asarray(r.color).tobytes()


def test_every_mark_with_two_backends_takes_the_same_rasterizer_values():
    for mark in BACKEND_MARKS:
        rasterizer = _params(mark)["rasterizer"]
        assert rasterizer["items"] == ["gl", "native", "auto"] and rasterizer["default"] == "auto", mark
    gl_method = _params("points")["gl_method"]
    assert gl_method["items"] == ["compute", "gl_points"] and gl_method["default"] == "compute"
    assert gl_method["when"] == {"param": "rasterizer", "values": ["gl", "auto"]}


def test_the_schema_declares_the_former_values_and_the_indices_older_files_stored():
    points = _params("points")["rasterizer"]
    assert points["older_files_items"] == ["compute", "gl_points", "native", "auto"]
    assert points["former_items"] == [{"name": "compute", "now": "gl", "also": ("gl_method", "compute")},
                                      {"name": "gl_points", "now": "gl", "also": ("gl_method", "gl_points")}]
    gaussians = _params("gaussians")["rasterizer"]
    assert gaussians["older_files_items"] == ["native", "compute", "auto"]
    assert gaussians["former_items"] == [{"name": "compute", "now": "gl", "also": None}]
    assert _params("hatching")["rasterizer"]["older_files_items"] == []


@pytest.mark.parametrize("former,current", [
    ({"rasterizer": "compute"}, {"rasterizer": "gl", "gl_method": "compute"}),
    ({"rasterizer": "gl_points"}, {"rasterizer": "gl", "gl_method": "gl_points"}),
    ({"rasterizer": "gl_points", "shading": "diffuse"}, {"rasterizer": "gl", "gl_method": "gl_points",
                                                         "shading": "diffuse"}),
])
def test_a_former_points_rasterizer_is_read_as_gl_with_its_method_and_renders_the_same(renderer, former, current):
    style = pointnpr.Style(mark=("points", former))
    assert {k: style.mark[1][k] for k in current} == current
    assert _bytes(renderer, style) == _bytes(renderer, pointnpr.Style(mark=("points", current)))


def test_gl_points_and_compute_still_differ_so_the_method_is_kept():
    # (What keeps gl_method a choice: the two GL methods tie differently.)
    renderer = pointnpr.Renderer()
    a = _bytes(renderer, pointnpr.Style(mark=("points", {"rasterizer": "gl", "gl_method": "compute",
                                                         "point_size": 6})))
    b = _bytes(renderer, pointnpr.Style(mark=("points", {"rasterizer": "gl", "gl_method": "gl_points",
                                                         "point_size": 6})))
    assert a != b


def test_a_method_given_beside_a_former_value_wins():
    style = pointnpr.Style(mark=("points", {"gl_method": "compute", "rasterizer": "gl_points"}))
    assert (style.mark[1]["rasterizer"], style.mark[1]["gl_method"]) == ("gl", "compute")
    style = pointnpr.Style(mark=("points", {"rasterizer": "gl_points", "gl_method": "compute"}))
    assert (style.mark[1]["rasterizer"], style.mark[1]["gl_method"]) == ("gl", "compute")


def test_the_gaussians_former_compute_is_gl_and_renders_the_same(renderer):
    style = pointnpr.Style(mark=("gaussians", {"rasterizer": "compute"}))
    assert style.mark[1]["rasterizer"] == "gl"
    gl = pointnpr.Style(mark=("gaussians", {"rasterizer": "gl"}))
    assert _bytes(renderer, style, "gaussians") == _bytes(renderer, gl, "gaussians")


def test_an_unknown_value_names_the_current_items():
    with pytest.raises(pointnpr.ParameterError, match="'gl' 'native' 'auto'"):
        pointnpr.Style(mark=("points", {"rasterizer": "opengl"}))


def test_the_pencil_hatching_filter_answers_to_its_former_id_and_renders_the_same(renderer):
    schema = pointnpr.schema("hatching", kind="filter")
    assert schema["id"] == "pencil_hatching" and schema["former_ids"] == ["hatching"]
    assert pointnpr.schema("hatching")["kind"] == "mark"  # the current id first
    assert "hatching" not in {s["id"] for s in pointnpr.schemas() if s["kind"] == "filter"}
    params = {"layers": 2, "space": "screen"}
    former = pointnpr.Style(rasterize={"point_size": 3}, filters=[("hatching", params)])
    current = pointnpr.Style(rasterize={"point_size": 3}, filters=[("pencil_hatching", params)])
    assert [f[0] for f in former.filters] == ["pencil_hatching"]
    assert former.filters[0][1] == current.filters[0][1]
    assert _bytes(renderer, former) == _bytes(renderer, current)
    assert _bytes(renderer, current) != _bytes(renderer, pointnpr.Style(rasterize={"point_size": 3}))
