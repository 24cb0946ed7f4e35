"""The ROS 2 transport's choice (ros/transport.py), without ROS: what is set for each setting."""

from __future__ import annotations

import xml.etree.ElementTree as ET

import pytest

from baxterface_cli.ros import transport
from baxterface_cli.ros.transport import PROFILES, TransportError, from_ros_args, plan


def test_by_default_the_shared_memory_profile_is_loaded_beside_udp(tmp_path):
    chosen = plan("shm", {}, str(tmp_path))
    assert chosen["FASTDDS_DEFAULT_PROFILES_FILE"] == str(PROFILES[False])
    assert "ROS_AUTOMATIC_DISCOVERY_RANGE" not in chosen
    assert chosen[""].startswith("shm (")


@pytest.mark.parametrize("env", [{"ROS_AUTOMATIC_DISCOVERY_RANGE": "LOCALHOST"}, {"ROS_LOCALHOST_ONLY": "1"}])
def test_localhost_keeps_the_process_on_this_host_through_the_profile(tmp_path, env):
    chosen = plan("shm", env, str(tmp_path))
    assert chosen["FASTDDS_DEFAULT_PROFILES_FILE"] == str(PROFILES[True])
    # rmw_fastrtps would add its own 512 KB segments beside the profile's under LOCALHOST
    assert chosen["ROS_AUTOMATIC_DISCOVERY_RANGE"] == "SUBNET"
    assert "this host only" in chosen[""]


@pytest.mark.parametrize(
    "env, why",
    [
        ({"FASTDDS_DEFAULT_PROFILES_FILE": "/etc/mine.xml"}, "FASTDDS_DEFAULT_PROFILES_FILE is set"),
        ({"FASTRTPS_DEFAULT_PROFILES_FILE": "/etc/mine.xml"}, "FASTRTPS_DEFAULT_PROFILES_FILE is set"),
        ({"FASTDDS_BUILTIN_TRANSPORTS": "UDPv4"}, "FASTDDS_BUILTIN_TRANSPORTS is set"),
        ({"RMW_IMPLEMENTATION": "rmw_cyclonedds_cpp"}, "RMW_IMPLEMENTATION is rmw_cyclonedds_cpp"),
    ],
)
def test_what_the_user_set_wins(tmp_path, env, why):
    assert plan("shm", env, str(tmp_path)) == {"": f"default: yours ({why})"}


def test_a_default_profile_file_in_the_working_folder_is_the_users(tmp_path):
    (tmp_path / "DEFAULT_FASTDDS_PROFILES.xml").write_text("<dds/>")
    assert plan("shm", {}, str(tmp_path))[""].startswith("default: yours")
    assert plan("shm", {"SKIP_DEFAULT_XML_FILE": "1"}, str(tmp_path))[""].startswith("shm")


def test_default_sets_nothing(tmp_path):
    assert plan("default", {"ROS_AUTOMATIC_DISCOVERY_RANGE": "LOCALHOST"}, str(tmp_path)) == {
        "": "default (ROS's own Fast DDS set-up)"
    }


def test_the_node_parameter_is_read_before_ros_starts():
    assert from_ros_args(["--ros-args", "-p", "fps:=20", "-p", "transport:=default"]) == "default"
    assert from_ros_args(["--ros-args", "-p", "fps:=20"]) is None
    with pytest.raises(TransportError, match="parameter transport must be shm or default, not 'udp'"):
        from_ros_args(["--ros-args", "-p", "transport:=udp"])


def test_the_node_parameter_is_read_from_a_params_file(tmp_path):
    pytest.importorskip("yaml")  # rclpy's: the ros2 extra brings it
    params = tmp_path / "face.yaml"
    params.write_text("baxter_face:\n  ros__parameters:\n    transport: shm\n    fps: 20\n")
    assert from_ros_args(["--ros-args", "--params-file", str(params)]) == "shm"
    params.write_text("baxter_face: [unclosed\n")  # rclpy itself says what is wrong with it
    assert from_ros_args(["--ros-args", "--params-file", str(params)]) is None


def test_the_environment_choice_is_checked(monkeypatch):
    monkeypatch.setattr(transport, "_asked", None)
    monkeypatch.setenv("BAXTERFACE_ROS_TRANSPORT", "fast")
    with pytest.raises(TransportError, match="BAXTERFACE_ROS_TRANSPORT must be shm or default"):
        transport.requested()


def test_the_shipped_profiles_are_fast_dds_xml_with_segments_that_hold_a_frame():
    for profile in PROFILES.values():
        root = ET.parse(str(profile)).getroot()
        ns = {"f": "http://www.eprosima.com"}
        sizes = [int(e.text) for e in root.iterfind(".//f:segment_size", ns)]
        assert sizes and min(sizes) >= 1920 * 1200 * 3  # an upgraded head's frame, whole
        assert root.find(".//f:participant[@is_default_profile='true']", ns) is not None
