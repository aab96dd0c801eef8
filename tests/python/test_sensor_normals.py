"""Estimated normals of a depth camera's frame face its sensor (issue 39:
whole figures flipped between lit and shaded on Kinect frames). The
consistent orientation starts each connected part at its highest point
turned to +z, right for Z-up scans but away from a camera that looks along
+z; an organized PCD frame knows where its sensor stood (VIEWPOINT), and
its parts start facing it instead."""
import os

import numpy as np
import pytest

import pointnpr

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
# PCL's textured mug scene (a stereo/Kinect-like organized frame), cropped: tests/data/io/make_pcd_crop.py.
KINECT = os.path.join(ROOT, "tests", "data", "io", "mug_crop.pcd")


def _two_planes():
    """Two separate patches facing a camera at the origin that looks along
    +z (a depth frame): each its own connected part."""
    g = np.linspace(-0.4, 0.4, 40)
    x, y = np.meshgrid(g, g)
    near = np.stack([x.ravel() - 1.0, y.ravel(), np.full(x.size, 2.0)], 1)
    far = np.stack([x.ravel() + 1.0, y.ravel(), np.full(x.size, 3.5)], 1)
    return np.concatenate([near, far])


def test_a_frame_with_a_sensor_gets_normals_facing_it_on_every_part():
    pos = _two_planes()
    facing = np.asarray(pointnpr.estimate_normals(pointnpr.PointCloud(pos, sensor=(0.0, 0.0, 0.0)), k=12))
    assert (facing[:, 2] < -0.99).all()  # toward the camera at z = 0, both patches
    # Without a sensor the Z-up rule turns them to +z: away from the camera.
    upward = np.asarray(pointnpr.estimate_normals(pointnpr.PointCloud(pos), k=12))
    assert (upward[:, 2] > 0.99).all()


def test_the_sensor_is_kept_and_checked():
    assert pointnpr.PointCloud(_two_planes(), sensor=(1.0, 2.0, 3.0)).sensor == (1.0, 2.0, 3.0)
    assert pointnpr.PointCloud(_two_planes()).sensor is None
    with pytest.raises(Exception, match="sensor"):
        pointnpr.PointCloud(_two_planes(), sensor=(0.0, float("nan"), 0.0))
    with pytest.raises(Exception, match="sensor"):
        pointnpr.PointCloud(_two_planes(), sensor=(0.0, 1.0))


def _pcd(path, height, viewpoint="VIEWPOINT 1.5 -2 3 1 0 0 0\n"):
    pts = _two_planes()[: 40 * height]
    with open(path, "w") as f:
        f.write("VERSION .7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\n"
                f"WIDTH {len(pts) // height}\nHEIGHT {height}\n{viewpoint}POINTS {len(pts)}\nDATA ascii\n")
        for p in pts:
            f.write("%g %g %g\n" % tuple(p))


def test_an_organized_pcd_reports_its_viewpoint_as_the_sensor_and_an_unorganized_one_none(tmp_path):
    _pcd(tmp_path / "frame.pcd", height=20)
    data = pointnpr.read(str(tmp_path / "frame.pcd"))
    assert tuple(data.metadata["sensor_origin"]) == (1.5, -2.0, 3.0)
    assert data.to_cloud().sensor == (1.5, -2.0, 3.0)
    _pcd(tmp_path / "list.pcd", height=1)
    assert "sensor_origin" not in pointnpr.read(str(tmp_path / "list.pcd")).metadata
    assert pointnpr.read(str(tmp_path / "list.pcd")).to_cloud().sensor is None
    # A VIEWPOINT that does not parse is the default, the origin (the file still reads).
    _pcd(tmp_path / "odd.pcd", height=20, viewpoint="VIEWPOINT a b c 1 0 0 0\n")
    assert tuple(pointnpr.read(str(tmp_path / "odd.pcd")).metadata["sensor_origin"]) == (0.0, 0.0, 0.0)


def test_a_real_kinect_frames_normals_face_the_camera():
    cloud = pointnpr.read(KINECT).to_cloud()
    assert cloud.sensor == (0.0, 0.0, 0.0)
    n = np.asarray(pointnpr.estimate_normals(cloud, k=16))
    # The camera looks along +z from the origin: surfaces it sees face -z.
    assert (n[:, 2] < 0.0).mean() > 0.9
