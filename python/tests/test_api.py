"""The Python API against `pllvo run --single-thread` and `pllvo eval`, and its errors."""
import json
import subprocess

import numpy as np
import pytest

import pllvo


def read_tum(path):
    rows = [line.split() for line in open(path) if line.strip() and not line.startswith("#")]
    return np.array([[float(v) for v in row] for row in rows])


def tum_rows(stamps, poses):
    """(t, x, y, z) of each pose: trajectory.tum holds them as %.17g text, which reads back bit-exact."""
    return np.column_stack([stamps, poses[:, :3, 3]])


@pytest.fixture(scope="module")
def cli_run(cli, synthetic_stereo, tmp_path_factory):
    out = tmp_path_factory.mktemp("cli_run")
    subprocess.run([cli, "run", str(synthetic_stereo), "--single-thread", "--out", str(out)], check=True,
                   capture_output=True)
    return out


def test_streaming_api_gives_the_cli_trajectory_bitwise(cli_run, synthetic_stereo, tmp_path):
    dataset = pllvo.Dataset(str(synthetic_stereo))
    assert dataset.calibration.stereo
    odometry = pllvo.Odometry(dataset.calibration, single_thread=True)
    results = [odometry.track(*dataset.frame(i)) for i in range(len(dataset))]
    odometry.finish()
    stamps, poses = odometry.trajectory()
    reference = read_tum(cli_run / "trajectory.tum")
    assert len(stamps) == len(reference) >= 50
    np.testing.assert_array_equal(tum_rows(stamps, poses), reference[:, :4])
    tracked = [r for r in results if r.tracked]
    assert len(tracked) == len(stamps)
    np.testing.assert_array_equal(tracked[-1].T_world_cam0, poses[-1])
    assert tracked[-1].state == "tracking" and tracked[-1].points.shape[1] == 2
    assert sum(r.keyframe for r in results) == json.load(open(cli_run / "stats.json"))["keyframes"]
    odometry.save(str(tmp_path))
    assert (tmp_path / "trajectory.tum").read_text() == (cli_run / "trajectory.tum").read_text()
    anchored_stamps, anchored_poses = odometry.anchored_trajectory()
    np.testing.assert_array_equal(anchored_stamps, stamps)
    np.testing.assert_array_equal(tum_rows(anchored_stamps, anchored_poses),
                                  read_tum(cli_run / "trajectory_anchored.tum")[:, :4])
    assert not np.array_equal(anchored_poses, poses)
    assert (tmp_path / "map.ply").read_text() == (cli_run / "map.ply").read_text()


def test_run_gives_the_cli_trajectory(cli_run, synthetic_stereo, tmp_path):
    stats = pllvo.run(synthetic_stereo, out=tmp_path, single_thread=True)
    assert stats["tracked_frames"] == json.load(open(cli_run / "stats.json"))["tracked_frames"]
    assert (tmp_path / "trajectory.tum").read_text() == (cli_run / "trajectory.tum").read_text()
    assert stats["trajectory_error"]["ate_percent_of_path"] < 5.0  # against the sequence's ground truth


def test_rgbd_frames_give_the_cli_trajectory(cli, shared, tmp_path):
    tum = shared / "data" / "tum_fr3_office_snippet"
    subprocess.run([cli, "run", str(tum), "--single-thread", "--out", str(tmp_path)], check=True, capture_output=True)
    reference = read_tum(tmp_path / "trajectory.tum")
    dataset = pllvo.Dataset(str(tum))
    assert dataset.calibration.depth and dataset.calibration.depth_units_per_metre == 5000
    for sixteen_bit in (False, True):
        odometry = pllvo.Odometry(dataset.calibration, single_thread=True)
        assert odometry.rgbd and not odometry.stereo
        for i in range(len(dataset)):
            t, image, right, depth = dataset.frame(i, with_depth=True)
            assert right is None and depth.dtype == np.float32
            if sixteen_bit:  # as the sensor gives it: 5000 per metre
                depth = np.round(depth * 5000).astype(np.uint16)
            assert odometry.track_rgbd(t, image, depth).tracked
        odometry.finish()
        stamps, poses = odometry.trajectory()
        assert len(stamps) == len(reference) == 16
        np.testing.assert_array_equal(tum_rows(stamps, poses), reference[:, :4])
    t, image, _, depth = dataset.frame(0, with_depth=True)
    with pytest.raises(TypeError, match="uint16 or float32"):
        odometry.track_rgbd(t + 10, image, depth.astype(np.float64))
    mono = pllvo.Odometry(dataset.calibration.left_only().with_depth(1000), single_thread=True)
    assert mono.rgbd


def test_wrong_arrays_raise_and_tracking_goes_on(synthetic_stereo):
    dataset = pllvo.Dataset(str(synthetic_stereo))
    odometry = pllvo.Odometry(dataset.calibration, single_thread=True, overrides={"frontend.type": "orb"})
    t, left, right = dataset.frame(0)
    assert odometry.track(t, left, right).frame_index == 0
    t, left, right = dataset.frame(1)
    with pytest.raises(TypeError, match="uint8"):
        odometry.track(t, left.astype(np.float32), right)
    with pytest.raises(TypeError, match="numpy array"):
        odometry.track(t, left.tolist(), right)
    with pytest.raises(ValueError, match="shape"):
        odometry.track(t, np.zeros(left.shape + (2,), np.uint8), right)
    with pytest.raises(ValueError, match="contiguous"):
        odometry.track(t, np.asfortranarray(left), right)
    with pytest.raises(pllvo.InputError, match="calibration"):
        odometry.track(t, left[:100, :100].copy(), right)
    with pytest.raises(pllvo.InputError, match="right image"):
        odometry.track(t, left)
    with pytest.raises(pllvo.InputError, match="increase"):
        odometry.track(dataset.frame(0)[0], left, right)
    bgr = np.repeat(left[:, :, None], 3, axis=2)
    assert odometry.track(t, bgr, np.repeat(right[:, :, None], 3, axis=2)).frame_index == 1
    with pytest.raises(pllvo.InputError, match="no_such_key"):
        pllvo.Odometry(dataset.calibration, overrides={"no_such_key": 1})
    with pytest.raises(pllvo.InputError):
        pllvo.Calibration.mono(pllvo.CameraIntrinsics(640, 480, float("nan"), 500, 320, 240))
    with pytest.raises(pllvo.InputError):
        pllvo.Dataset("/no/such/folder")


def test_live_push_drops_frames_when_the_tracker_is_busy(synthetic_stereo):
    dataset = pllvo.Dataset(str(synthetic_stereo))
    frames = [dataset.frame(i) for i in range(len(dataset))]
    odometry = pllvo.Odometry(dataset.calibration, live=True, overrides={"frontend.type": "orb"})
    seen = []
    odometry.on_result(lambda r: seen.append(r.frame_index))
    dropped = sum(odometry.push(*f) for f in frames)  # a burst: far faster than tracking
    odometry.finish()
    stats = odometry.stats()
    assert dropped > 0 and stats["realtime"]["frames_dropped"] == dropped
    assert len(seen) + dropped == len(frames) and seen[-1] == len(frames) - 1


EVO_CASES = ["ape_tum_e1_se3_trans_part_none", "ape_tum_e2_sim3_trans_part_sim3", "ape_tum_e3_async_trans_part_se3",
             "ape_tum_e1_se3_angle_deg_se3"]


@pytest.mark.parametrize("case_id", EVO_CASES)
def test_evaluate_equals_pllvo_eval_and_evo(case_id, cli, shared, tmp_path):
    vectors = shared / "testvectors" / "eval"
    cases = {c["id"]: c for c in json.load(open(vectors / "expected.json"))}
    assert case_id in cases, f"{case_id} is not among the evo vectors"
    case = cases[case_id]
    o = case["options"]
    align = "sim3" if o["align"] and o["correct_scale"] else "se3" if o["align"] else "scale" if o["correct_scale"] else "none"
    est, ref = vectors / case["est_file"], vectors / case["ref_file"]
    args = ["--metric", "ape", "--relation", o["pose_relation"], "--align", align, "--t-max-diff", str(o["t_max_diff"]),
            "--t-offset", str(o["t_offset"])]
    subprocess.run([cli, "eval", str(est), str(ref), *args, "--json", str(tmp_path / "eval.json")], check=True,
                   capture_output=True)
    from_cli = json.load(open(tmp_path / "eval.json"))
    from_python = pllvo.evaluate(str(est), str(ref), metric="ape", relations=[o["pose_relation"]], align=align,
                                 t_max_diff=o["t_max_diff"], t_offset=o["t_offset"])
    assert from_python == from_cli
    assert _rmse_close(from_python, case["stats"]["rmse"]), f"evo's rmse {case['stats']['rmse']} not in {from_python}"


def _rmse_close(report, expected):
    found = []

    def walk(node):
        if isinstance(node, dict):
            for k, v in node.items():
                if k == "rmse" and isinstance(v, float):
                    found.append(v)
                walk(v)
        elif isinstance(node, list):
            for v in node:
                walk(v)

    walk(report)
    return any(abs(v - expected) <= 1e-9 + 1e-6 * abs(expected) for v in found)
