"""`baxterface buttons`: the navigator and cuff controller, publishing commands to display_chatter."""

from __future__ import annotations

import json
from typing import Any, List

from ..robot.event_sensors import CUFF_INPUTS
from ..robot.navigator_buttons import NAVIGATORS, ButtonMap, Buttons
from .effect_messages import CUFF_SIDES, CUFF_TOPIC, NAVIGATOR_TOPIC
from .messages import message_class


def run_buttons(mapping: ButtonMap, argv: List[str]) -> int:
    import rospy
    from std_msgs.msg import String

    rospy.init_node("baxter_face_buttons", argv=argv)
    buttons = Buttons(mapping)
    chatter = rospy.Publisher("display_chatter", String, queue_size=10)

    def pressed(msg: Any, navigator: str) -> None:
        for command in buttons.update(navigator, list(msg.buttons), msg.wheel):
            rospy.loginfo("%s navigator: %s", navigator, command)
            chatter.publish(String(command))

    def cuff(msg: Any, where: tuple) -> None:
        for command in buttons.cuff(*where, msg.state == 1):
            rospy.loginfo("%s cuff: %s", where[0], command)
            chatter.publish(String(command))

    def face_state(msg: Any) -> None:
        try:
            emotion = json.loads(msg.data).get("emotion")
        except (ValueError, AttributeError):
            return
        if emotion:
            buttons.heard(emotion)

    navigator_state = message_class("NavigatorState")
    for navigator in NAVIGATORS:
        topic = NAVIGATOR_TOPIC.format(navigator)
        rospy.Subscriber(topic, navigator_state, pressed, navigator, queue_size=10)
    if any(key.partition(".")[0].endswith("_cuff") for key in buttons.mapping.buttons):
        digital_io = message_class("DigitalIOState")
        for side in CUFF_SIDES:
            for io_name in CUFF_INPUTS:
                topic = CUFF_TOPIC.format(side, io_name)
                rospy.Subscriber(topic, digital_io, cuff, (side, io_name), queue_size=10)
    rospy.Subscriber("/baxter_face/state", String, face_state, queue_size=1)
    rospy.spin()
    return 0
