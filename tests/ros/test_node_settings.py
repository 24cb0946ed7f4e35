"""The face node's settings, read without ROS: every bad value names its parameter."""

import pytest

from baxterface_cli.ros.node_settings import (
    NodeSettings,
    SettingError,
    camera_focal,
    camera_info_topic,
    theme_layers,
)


def read(**given):
    return NodeSettings.read(lambda name, default: given.get(name, default))


def test_nothing_given_is_the_documented_defaults():
    s = read()
    assert (s.fps, s.size, s.theme, s.idle, s.audio) == (30.0, (1024, 600), None, True, "soundplay")
    assert s.display_topic == "/robot/xdisplay" and s.camera == "/cameras/head_camera/image"
    # No field of view: the camera's camera_info says it, or else Baxter's head camera's is taken.
    assert s.camera_hfov is None and s.face_policy == "nearest"


def test_values_as_rospy_and_launch_files_give_them():
    s = read(fps="20", size="1920x1200", idle="false", selftest=True, camera_hfov=60, face_policy="central")
    assert (s.fps, s.size, s.idle, s.selftest, s.camera_hfov) == (20.0, (1920, 1200), False, True, 60.0)
    assert s.face_policy == "central"
    assert read(camera_hfov="").camera_hfov is None  # the launch file's way of leaving it unset


@pytest.mark.parametrize(
    "given, message",
    [
        ({"fps": "abc"}, "~fps must be a number, not 'abc'"),
        ({"fps": 0}, "~fps must be from 1 to 120, not 0"),
        ({"fps": float("nan")}, "~fps must be from 1 to 120, not nan"),
        ({"size": "huge"}, "~size must look like 1024x600, not 'huge'"),
        ({"audio": "loud"}, "~audio must be soundplay, local or none, not 'loud'"),
        (
            {"listen": "/nonexistent/hello.wav"},
            "~listen must be default or a WAV file, not '/nonexistent/hello.wav'",
        ),
        ({"listen": "mic"}, "~listen must be default or a WAV file, not 'mic'"),
        ({"barge_in": "maybe"}, "~barge_in must be true or false, not 'maybe'"),
        ({"idle": "maybe"}, "~idle must be true or false, not 'maybe'"),
        ({"camera_hfov": 200}, "~camera_hfov must be from 1 to 179 degrees, not 200"),
        ({"camera_hfov": "wide"}, "~camera_hfov must be a number, not 'wide'"),
        ({"face_policy": "tallest"}, "~face_policy must be nearest, central or longest, not 'tallest'"),
        ({"display_topic": "a b"}, "~display_topic must be a topic name, not 'a b'"),
        ({"theme": 3}, "~theme must be text, not 3"),
    ],
)
def test_a_bad_value_is_one_error_naming_its_parameter(given, message):
    with pytest.raises(SettingError) as caught:
        read(**given)
    assert str(caught.value) == message
    assert caught.value.name == next(iter(given))


def test_a_theme_that_cannot_be_used_names_the_theme_parameter(tmp_path):
    with pytest.raises(SettingError, match=r"^~theme cannot be used: .*nonexistent"):
        theme_layers(read(theme=str(tmp_path / "nonexistent")))


def test_recordings_is_a_folder_made_absolute_or_none(tmp_path, monkeypatch):
    assert read().recordings is None
    monkeypatch.chdir(tmp_path)
    (tmp_path / "sounds").mkdir()
    assert read(recordings="sounds").recordings == str(tmp_path / "sounds")
    with pytest.raises(SettingError, match=r"^~recordings must be a folder, not 'nowhere'$"):
        read(recordings="nowhere")


def test_binning_divides_the_focal_length_and_an_uncalibrated_camera_gives_none():
    assert camera_focal([410.0, 0, 640, 0, 410.0, 400, 0, 0, 1], 0) == 410.0
    assert camera_focal([410.0, 0, 640, 0, 410.0, 400, 0, 0, 1], 2) == 205.0
    assert camera_focal([0.0] * 9, 0) is None and camera_focal([], 0) is None
    assert camera_focal([float("nan")] * 9, 1) is None
    assert camera_info_topic("/cameras/head_camera/image") == "/cameras/head_camera/camera_info"
    assert camera_info_topic("image_raw") == "camera_info"
    assert camera_info_topic("/image") == "/camera_info"


def test_listen_is_off_the_default_device_or_a_recording(tmp_path):
    assert (read().listen, read().barge_in) == ("", False)
    assert read(listen="default", barge_in="true").listen == "default" and read(barge_in=True).barge_in
    wav = tmp_path / "hello.wav"
    wav.write_bytes(b"RIFF")  # read when the node listens: a bad one is said then, in the log
    assert read(listen=str(wav)).listen == str(wav)


def test_log_is_a_file_in_a_folder_that_is_there_and_log_size_megabytes(tmp_path):
    assert (read().log, read().log_size) == (None, 100.0)
    s = read(log=str(tmp_path / "face.jsonl"), log_size="5")
    assert (s.log, s.log_size) == (str(tmp_path / "face.jsonl"), 5.0)
    with pytest.raises(SettingError, match="~log must be a file in a folder that is there"):
        read(log=str(tmp_path / "nowhere" / "face.jsonl"))
    with pytest.raises(SettingError, match="~log must be a file"):
        read(log=str(tmp_path))
    with pytest.raises(SettingError, match="~log_size must be from"):
        read(log_size="0")
