"""Bad input gets a specific message, once (issue 17, part 3)."""
import os
import subprocess
import sys

import numpy as np
import pytest

import pointnpr
from conftest import BUILD_DIR, plane

W, H = 64, 48


def _camera():
    return pointnpr.Camera.perspective(np.eye(4), width=W, height=H)


def test_non_finite_points_are_left_out_and_reported_once_per_object(renderer):
    pos = np.array([[0, 0, -5], [0.1, 0, -5], [np.nan, 0, -5], [0, np.inf, -5], [0.2, 0.1, -5]], float)
    cloud = pointnpr.PointCloud(pos)
    assert cloud.num_points == 3 and cloud.skipped_points == 2
    assert sorted(cloud.point_index) == [0, 1, 4]  # the others keep their ids
    scene = pointnpr.Scene()
    scene.add_segment("s", pointnpr.Style(), [(cloud, np.eye(4), "Scan.003")])
    result = renderer.render(scene, _camera(), W, H)
    assert "object 'Scan.003': 2 of 5 points have non-finite coordinates and were skipped" in result.warnings
    assert (np.asarray(result.color)[..., 3] > 0).any()  # the rest renders


def test_big_counts_are_written_with_separators(renderer):
    pos = np.zeros((1_204_511, 3))
    pos[:, 2] = -5
    pos[:3, 0] = np.nan
    scene = pointnpr.Scene()
    scene.add_segment("s", pointnpr.Style(), [(pointnpr.PointCloud(pos), np.eye(4), "Scan")])
    warnings = renderer.render(scene, _camera(), W, H).warnings
    assert warnings == ["object 'Scan': 3 of 1,204,511 points have non-finite coordinates and were skipped"]


def test_one_warning_per_cause_with_counts_and_the_first_names(renderer):
    scene = pointnpr.Scene()
    uncoloured = pointnpr.PointCloud(np.array([[0, 0, -5.0], [0.1, 0, -5.0]]))
    style = pointnpr.Style(mark=("points", {"color_source": "rgb"}))
    for s in range(2):
        scene.add_segment("C%02d" % s, style, [(uncoloured, np.eye(4), "O%03d" % (250 * s + k)) for k in range(250)])
    warnings = renderer.render(scene, _camera(), W, H).warnings
    assert warnings == ["500 objects have no colors for their style's colour source ('O000', 'O001', 'O002' and "
                        "497 more); drawn in the constant colour"]
    # Unnamed clouds are named by their segment.
    scene = pointnpr.Scene()
    scene.add_segment("ground", style, [uncoloured])
    assert renderer.render(scene, _camera(), W, H).warnings == [
        "1 object has no colors for its style's colour source (a cloud of segment 'ground'); drawn in the constant "
        "colour"]


@pytest.mark.parametrize("bad,message", [
    ([("x", np.eye(4))], r"instance 0: expected a PointCloud, CachedCloud or TriangleMesh, or \(one of them, 4x4 "
                         r"matrix\[, object name\]\), got 'str' where the cloud or mesh goes"),
    (["x"], r"instance 0: expected a PointCloud.*, got 'str'"),
    ([None], r"got 'NoneType'"),
    ("cloud", r"instances must be a list of PointCloud .*got 'str'"),
])
def test_add_segment_says_what_it_expected_and_what_it_got(bad, message):
    scene = pointnpr.Scene()
    with pytest.raises(ValueError, match=message):
        scene.add_segment("s", pointnpr.Style(), bad)


def test_add_segment_checks_the_matrix_and_the_name():
    cloud = plane(0, 1, 0, 1, -5, 0.5, (1, 2, 3))
    scene = pointnpr.Scene()
    with pytest.raises(ValueError, match="instance 1: world_from_object must be a 4x4 matrix"):
        scene.add_segment("s", pointnpr.Style(), [cloud, (cloud, np.eye(3))])
    with pytest.raises(ValueError, match="non-finite"):
        scene.add_segment("s", pointnpr.Style(), [(cloud, np.full((4, 4), np.nan))])
    with pytest.raises(ValueError, match="object name must be a str"):
        scene.add_segment("s", pointnpr.Style(), [(cloud, np.eye(4), 7)])
    with pytest.raises(ValueError, match="a sequence of 4 items"):
        scene.add_segment("s", pointnpr.Style(), [(cloud, np.eye(4), "a", "b")])
    assert scene.num_segments == 0


def test_cameras_that_cannot_see_are_refused():
    nan = np.eye(4)
    nan[0, 3] = np.nan
    with pytest.raises(ValueError, match="non-finite"):
        pointnpr.Camera.perspective(nan, width=W, height=H)
    flat = np.diag([0.0, 0.0, 0.0, 1.0])
    with pytest.raises(ValueError, match="singular"):
        pointnpr.Camera.perspective(flat, width=W, height=H)
    with pytest.raises(ValueError, match="singular"):
        pointnpr.Camera.orthographic(flat, width=W, height=H)
    with pytest.raises(ValueError, match="non-finite"):
        pointnpr.Camera.from_matrices(nan, np.eye(4))


def test_a_camera_made_for_another_size_is_refused(renderer, two_planes):
    cam = pointnpr.Camera.perspective(np.eye(4), width=320, height=240)
    with pytest.raises(ValueError, match="made for 320x240 but the render is 160x120"):
        renderer.render(two_planes, cam, 160, 120)


def _egl_error(env_changes):
    env = dict(os.environ, **env_changes)
    code = ("import sys; sys.path.insert(0, sys.argv[1]); import pointnpr\n"
            "try:\n    pointnpr.gl_info()\nexcept pointnpr.GLError as e:\n    print('GLError:', e)\n")
    out = subprocess.run([sys.executable, "-c", code, os.path.abspath(BUILD_DIR)], env=env, capture_output=True,
                         text=True, timeout=60)
    return out.stdout


def test_an_unknown_egl_device_setting_is_refused():
    out = _egl_error({"POINTNPR_EGL_DEVICE": "99"})
    assert "GLError: POINTNPR_EGL_DEVICE is '99'; accepted values: 'auto'" in out and "'software'" in out
    assert "GLError" not in _egl_error({"POINTNPR_EGL_DEVICE": "auto"})


def test_no_display_message_says_what_was_tried_without_stray_separators():
    # No EGL vendor library: nothing can open (libglvnd reads this variable).
    out = _egl_error({"POINTNPR_EGL_DEVICE": "software", "__EGL_VENDOR_LIBRARY_FILENAMES": "/nonexistent.json"})
    assert out.startswith("GLError: no EGL display could be opened"), out
    assert "; )" not in out and "( " not in out
    assert "POINTNPR_EGL_DEVICE=software is set" in out
    assert "Set POINTNPR_EGL_DEVICE=software to force" not in out  # no advice to do what is done


@pytest.mark.parametrize("kind", ["fifo", "device"])
def test_reading_a_special_file_is_refused_at_once(tmp_path, kind):
    if kind == "fifo":
        path = str(tmp_path / "scan.las")
        os.mkfifo(path)  # no writer: a blocking open would wait forever
    else:
        path = "/dev/zero"
    code = ("import sys, time; sys.path.insert(0, sys.argv[1]); import pointnpr\n"
            "t0 = time.monotonic()\n"
            "try:\n    pointnpr.read(sys.argv[2])\nexcept pointnpr.ReadError as e:\n"
            "    print('%.3f' % (time.monotonic() - t0), e)\n")
    # A subprocess with a timeout: a regression hangs it, not the test run.
    out = subprocess.run([sys.executable, "-c", code, os.path.abspath(BUILD_DIR), path], capture_output=True,
                         text=True, timeout=30).stdout
    seconds, _, message = out.partition(" ")
    assert float(seconds) < 1.0
    assert "is not a regular file (a named pipe, device or socket is not a point cloud file)" in message
    assert path in message
