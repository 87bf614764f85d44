"""import planemap, against the same ground truth as the C++ tests: a rendered room's box (the
simulator's true cuboid), a real sequence's camera poses (ICL-NUIM's ground truth), and what
wrong input from Python raises.

ctest runs this with PYTHONPATH at the built module and PLANEMAP_SOURCE_DIR at the source tree.
Tests that read ../shared/data skip when it is absent, and fail instead when
PLANEMAP_REQUIRE_SHARED_DATA=1 (CI sets it).
"""
import math
import os

import numpy as np
import pytest

import planemap

SOURCE = os.environ.get("PLANEMAP_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", ".."))
SHARED = os.environ.get("PLANEMAP_SHARED_DIR", os.path.join(SOURCE, "..", "shared"))
CM = 100.0  # [cm/m]


def source(relative):
    return os.path.join(SOURCE, relative)


def require_shared(relative):
    path = os.path.join(SHARED, relative)
    if not os.path.exists(path):
        message = f"{path} is missing (the real data sets live in ../shared beside the repository)"
        if os.environ.get("PLANEMAP_REQUIRE_SHARED_DATA") == "1":
            pytest.fail(message)
        pytest.skip(message)
    return path


@pytest.fixture(scope="module")
def xtion():
    return planemap.load_camera(source("configs/cameras/xtion_nao.yaml"))


def box_truth():
    (box,) = [o for o in planemap.scene_objects(source("configs/scenes/default.yaml")) if o["name"] == "box"]
    return box


def three_face_view():
    """The default box from 1.5 m, 1 m up, on the diagonal between its +x and -y faces (as the C++
    BoxViewpoints): two sides and the top in view."""
    box = box_truth()
    centre = box["T_world_object"][:3, 3]
    x_axis = box["T_world_object"][:3, 0]
    bearing = math.atan2(x_axis[1], x_axis[0]) - math.pi / 4
    eye = centre + 1.5 * np.array([math.cos(bearing), math.sin(bearing), 0.0])
    eye[2] = 1.0
    return planemap.look_at(eye, centre)


def test_a_rendered_box_from_numpy_depth_has_its_true_size_centre_and_axes(xtion):
    box = box_truth()
    T_world_camera = three_face_view()
    depth, color = planemap.render(source("configs/scenes/default.yaml"), xtion, T_world_camera, seed=7)
    assert depth.dtype == np.float32 and depth.shape == (480, 640)
    frontend = planemap.Frontend(xtion)
    model = frontend.process(depth, color)
    assert model.reason == ""
    assert len(model.planes) >= 4  # floor, wall(s), the box's faces
    boxes = [o for o in model.objects if o.label == "box"]
    assert len(boxes) == 1
    o = boxes[0]
    # Centre: camera frame -> world, against the true centre.
    centre_world = T_world_camera[:3, :3] @ o.center + T_world_camera[:3, 3]
    centre_error = np.linalg.norm(centre_world - box["T_world_object"][:3, 3])
    # Each complete dimension against the true edge it runs along.
    R_camera_box = T_world_camera[:3, :3].T @ box["T_world_object"][:3, :3]
    errors, axis_errors = [], []
    for a in range(3):
        b = int(np.argmax(np.abs(o.axes[:, a] @ R_camera_box)))
        axis_errors.append(math.degrees(math.acos(min(1.0, abs(o.axes[:, a] @ R_camera_box[:, b])))))
        if o.dimension_complete[a]:
            errors.append(abs(o.dimensions[a] - box["dimensions"][b]))
    print(f"box: dimensions {o.dimensions}, errors {[round(e * 1000, 1) for e in errors]} mm, centre {centre_error * 1000:.1f} mm, "
          f"axes {max(axis_errors):.2f} deg")
    assert len(errors) == 3
    assert max(errors) * CM < 1.0
    assert centre_error * CM < 2.0
    assert max(axis_errors) < 2.0
    assert o.grasp_axis is not None and abs(np.linalg.norm(o.grasp_axis) - 1.0) < 1e-9


def test_uint16_depth_in_sensor_units_gives_the_same_model_as_metres(xtion):
    depth, _ = planemap.render(source("configs/scenes/default.yaml"), xtion, three_face_view(), seed=7)
    units = np.round(depth.astype(np.float64) * xtion.depth_scale).astype(np.uint16)
    frontend = planemap.Frontend(xtion)
    a = frontend.process(units)
    b = frontend.process(units.astype(np.float64) / xtion.depth_scale)
    assert len(a.planes) == len(b.planes)
    assert [o.label for o in a.objects] == [o.label for o in b.objects]
    # A strided view (every row of a wider array) reads as numpy shows it.
    wide = np.zeros((480, 1280), dtype=np.uint16)
    wide[:, ::2] = units
    c = frontend.process(wide[:, ::2])
    assert [p.inliers for p in c.planes] == [p.inliers for p in a.planes]


def test_a_real_sequence_through_the_mapper_tracks_within_a_centimetre():
    sequence_dir = require_shared("data/icl_office_kt0")
    camera = planemap.load_camera(source("configs/cameras/icl_nuim.yaml"))
    sequence = planemap.Sequence(sequence_dir, camera)
    mapper = planemap.Mapper(camera, planemap.load_config(source("configs/default.yaml")))
    frames = min(60, len(sequence))
    tracked, smoothed = [], []
    for i in range(frames):
        f = sequence.frame(i)
        step = mapper.add(f["depth"], f["color"], stamp=f["stamp"])
        assert step.status != "lost", step.reason
        tracked.append((f["stamp"], step.T_world_camera))
        smoothed.append((f["stamp"], step.T_world_camera_smoothed))
    final = mapper.finish(refine=True)
    assert final.refine_usable, final.refine_termination
    truth = sequence.groundtruth
    ate = {name: planemap.ate(truth, t) * CM for name, t in
           (("tracked", tracked), ("smoothed", smoothed), ("refined", final.refined_trajectory))}
    print(f"ICL office kt0, {frames} frames: ATE {ate} cm; map {len(final.map.planes)} planes, {len(final.map.objects)} objects")
    # As the C++ test of the same frames (tests/test_pipeline.cpp).
    assert ate["tracked"] < 1.0
    assert ate["smoothed"] < 1.0
    assert ate["refined"] < ate["tracked"] + 0.1
    assert len(final.map.planes) >= 4
    assert len(mapper.trajectory) == frames
    for o in final.map.objects:
        assert np.all(o.dimensions >= 0.0)


def test_wrong_input_raises_an_exception_naming_what_is_wrong(xtion):
    frontend = planemap.Frontend(xtion)
    good = np.zeros((480, 640), dtype=np.uint16)
    with pytest.raises(TypeError, match="dtype int32"):
        frontend.process(good.astype(np.int32))
    with pytest.raises(TypeError, match="dtype >u2"):
        frontend.process(good.astype(">u2"))
    with pytest.raises(ValueError, match=r"shape \(240, 320\) does not match the camera's intrinsics \(480, 640\)"):
        frontend.process(np.zeros((240, 320), dtype=np.uint16))
    with pytest.raises(ValueError, match=r"expected a 2-D array"):
        frontend.process(np.zeros((480, 640, 1), dtype=np.float32))
    with pytest.raises(ValueError, match=r"shape \(640, 480\) does not match"):
        frontend.process(good.T)  # a transposed image
    nan = np.ones((480, 640), dtype=np.float32)
    nan[10, 20] = np.nan
    with pytest.raises(ValueError, match=r"depth\[10, 20\] is nan"):
        frontend.process(nan)
    with pytest.raises(ValueError, match=r"color: expected shape \(height, width, 3\)"):
        frontend.process(good, np.zeros((480, 640), dtype=np.uint8))
    with pytest.raises(TypeError, match="color: dtype float32"):
        frontend.process(good, np.zeros((480, 640, 3), dtype=np.float32))
    mapper = planemap.Mapper(xtion)
    mapper.add(good, stamp=1.0)
    with pytest.raises(ValueError, match="not after the last frame"):
        mapper.add(good, stamp=1.0)
    with pytest.raises(ValueError, match="T_world_first: not a rigid transform"):
        planemap.Mapper(xtion, T_world_first=2.0 * np.eye(4))


def test_the_librarys_own_errors_arrive_with_their_message(tmp_path):
    with pytest.raises(planemap.InputError, match="cannot open"):
        planemap.load_camera(str(tmp_path / "missing.yaml"))
    bad = tmp_path / "camera.yaml"
    bad.write_text("fx: -1\nfy: 500\ncx: 320\ncy: 240\n")
    with pytest.raises(planemap.InputError, match="fx"):
        planemap.load_camera(str(bad))
    with pytest.raises(ValueError, match=r"camera.fx must be > 0"):
        planemap.CameraIntrinsics(fx=0.0, fy=500.0, cx=320.0, cy=240.0)
    typo = tmp_path / "config.yaml"
    typo.write_text("frontend:\n  graph:\n    two_face_min_angel_deg: 60\n")
    with pytest.raises(planemap.InputError, match=r"config.yaml:3.*two_face_min_angel_deg"):
        planemap.load_config(str(typo))
    with pytest.raises(planemap.InputError):
        planemap.Sequence(str(tmp_path), planemap.CameraIntrinsics(525.0, 525.0, 319.5, 239.5))
    # A frame with no depth at all is a model that says why, not an error.
    model = planemap.Frontend(planemap.CameraIntrinsics(525.0, 525.0, 319.5, 239.5)).process(np.zeros((480, 640), np.uint16))
    assert model.planes == [] and model.reason != ""
