"""The studio's robot switch: presses go to the robot too, over ROS 1, once switched on."""

from __future__ import annotations

from typing import Any, Dict, Optional


class RobotSwitch:
    """Presses go to the robot too, once switched on and a ROS master answers."""

    def __init__(self, topic: str = "display_chatter") -> None:
        self.topic = topic
        self.link: Optional[Any] = None
        self.on = False
        self.reason = "off"

    def switch(self, on: bool) -> Dict[str, Any]:
        if on and self.link is None:
            from ..ros.connect import RosUnavailable, require_master, require_ros

            try:
                require_ros(1)
                require_master(timeout=1.0)
                from ..ros.chatter import ChatterLink

                self.link = ChatterLink(self.topic)
            except RosUnavailable as e:
                self.reason = str(e)
                return self.as_json()
        self.on = on and self.link is not None
        self.reason = "off" if not on else self.reason
        return self.as_json()

    def send(self, text: str) -> None:
        if self.on and self.link is not None:
            self.link.send(text)

    def as_json(self) -> Dict[str, Any]:
        status = self.link.status() if self.on and self.link is not None else self.reason
        return {"on": self.on, "available": self.link is not None, "status": status}
