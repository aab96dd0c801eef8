"""The shipped presets validate against the C++ schemas and render."""
import numpy as np
import pytest

from conftest import plane


def test_the_issue_5_presets_are_all_there():
    from pointnpr import presets

    assert set(presets.PRESETS) == {"Toon", "Ink outlines", "Watercolor", "Oil paint", "Posterize", "Urban map"}


@pytest.mark.parametrize("name", ["Toon", "Ink outlines", "Watercolor", "Oil paint", "Posterize", "Urban map"])
def test_preset_validates_and_renders(renderer, name):
    import pointnpr
    from pointnpr import presets

    filters = {s["id"] for s in pointnpr.schemas()}
    for step in presets.PRESETS[name]["filters"]:
        step_id = step[0] if isinstance(step, tuple) else step
        assert step_id in filters
    style = presets.style(name)
    assert [f[0] for f in style.filters] == [s[0] for s in presets.PRESETS[name]["filters"]]
    scene = pointnpr.Scene()
    scene.add_segment("plane", style, [(plane(-1, 1, -1, 1, 0, 0.04, (180, 120, 60)), np.eye(4))])
    cam = pointnpr.Camera.perspective(np.array([[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 6], [0, 0, 0, 1]], float),
                                      width=96, height=64)
    result = renderer.render(scene, cam, 96, 64)
    assert np.isfinite(result.color).all()
    assert (result.color[..., 3] > 0).sum() > 500


def test_unknown_preset_names_the_known_ones():
    from pointnpr import presets

    with pytest.raises(KeyError, match="Watercolor"):
        presets.style("Pastel")
