"""The `Link` on ROS 1, through rospy: one node a process, callbacks on rospy's threads.

Baxter's messages and sound_play's are built from their carried definitions
where their packages are missing (messages.py), so every type the face uses
is there. A ROS 1 node also outlives a restarted master (`stay_connected`).
"""

from __future__ import annotations

import threading
import warnings
from typing import Any, Callable, List, Optional

from .link import Link, Publisher, Subscription
from .messages import message_class

MASTER_CHECK = 1.0  # seconds between checks that the master still knows this node
IMAGE_BUFFER = 1 << 24  # bytes: room for a whole 1280x800 image, so only the newest is kept


class _RospyPublisher(Publisher):
    def __init__(self, rospy: Any, topic: str, cls: Any, latched: bool, queue: int) -> None:
        self.cls, self.time = cls, rospy.Time
        if queue <= 0:  # synchronous: when publish returns, the message is in the listeners' sockets
            with warnings.catch_warnings():  # rospy warns of a publisher without a queue: that is the point
                warnings.simplefilter("ignore")
                self.pub = rospy.Publisher(topic, cls, latch=latched)
        else:
            self.pub = rospy.Publisher(topic, cls, latch=latched, queue_size=queue)
        self.topic = self.pub.resolved_name

    def publish(self, **fields: Any) -> None:
        if "stamp" in fields:  # (sec, nanosec): the message's header.stamp (images.py)
            from std_msgs.msg import Header

            fields["header"] = Header(stamp=self.time(*fields.pop("stamp")))
        self.pub.publish(self.cls(**fields))

    def listeners(self) -> int:
        return self.pub.get_num_connections()

    def close(self) -> None:
        self.pub.unregister()


class _RospySubscription(Subscription):
    def __init__(self, sub: Any) -> None:
        self.sub = sub
        self.topic = sub.resolved_name

    def publishers(self) -> int:
        return self.sub.get_num_connections()

    def close(self) -> None:
        self.sub.unregister()


class RospyLink(Link):
    version = 1

    def __init__(self, name: str, argv: List[str], anonymous: bool) -> None:
        import rospy

        self.rospy = rospy
        self.argv = argv
        if not rospy.core.is_initialized():  # rospy has one node a process: a second link shares it
            rospy.init_node(name, argv=argv, anonymous=anonymous, disable_signals=True)
        self.name = rospy.get_name()
        self.stop = threading.Event()
        self._levels = {"info": rospy.loginfo, "warn": rospy.logwarn, "error": rospy.logerr}

    def resolve(self, topic: str) -> str:
        return self.rospy.resolve_name(topic)

    def param(self, name: str, default: Any) -> Any:
        return self.rospy.get_param("~" + name, default)

    def has(self, kind: str) -> bool:
        try:
            message_class(kind)
        except (ImportError, AttributeError, KeyError):
            return False
        return True

    def publisher(self, topic: str, kind: str, latched: bool = False, queue: int = 10) -> Publisher:
        return _RospyPublisher(self.rospy, topic, message_class(kind), latched, queue)

    def subscribe(
        self,
        topic: str,
        kind: str,
        callback: Callable[[Any], None],
        queue: int = 10,
        latched: bool = False,
        sensor: bool = False,
    ) -> Subscription:
        # A latched ROS 1 publisher sends its last message to every new subscriber anyway.
        extra = {"buff_size": IMAGE_BUFFER} if sensor else {}
        size = 1 if sensor else queue
        sub = self.rospy.Subscriber(topic, message_class(kind), callback, queue_size=size, **extra)
        return _RospySubscription(sub)

    def _emit(self, level: str, text: str) -> None:
        self._levels[level](text)

    def stay_connected(self, info: Callable[[str], None]) -> None:
        threading.Thread(
            target=self._watch_master, args=(info,), name="baxterface-master", daemon=True
        ).start()

    def _watch_master(self, info: Callable[[str], None]) -> None:
        """Register again with a master that no longer knows this node (it was restarted)."""
        import rosgraph

        master = rosgraph.Master(self.name)
        while not self.stop.wait(MASTER_CHECK):
            try:
                master.lookupNode(self.name)
            except rosgraph.MasterError:  # up, but it has never heard of us: a new master
                info("the ROS master was restarted: registering again")
                register_again()
            except Exception:
                pass  # down: rospy's own calls will fail until it is back

    def forget_bad(self, name: str) -> Optional[str]:
        """rospy puts `_fps:=abc` on the server, where it would outlive this run and fail the
        next one: take it off. A value someone else set there is left, and named."""
        where = self.rospy.resolve_name("~" + name)
        if any(word.startswith(f"_{name}:=") for word in self.argv):
            self.rospy.delete_param(where)
            return None
        return f"on the parameter server: 'rosparam delete {where}'"

    def ok(self) -> bool:
        return not self.rospy.is_shutdown()

    def spin(self) -> None:
        self.rospy.spin()

    def close(self, reason: str = "done") -> None:
        self.stop.set()
        self.rospy.signal_shutdown(reason)


def register_again() -> None:
    """Tell the (new) master every topic and service this process has, as rospy does at start."""
    from rospy.impl.registration import (
        Registration,
        RegManager,
        get_registration_listeners,
        get_service_manager,
        get_topic_manager,
    )

    managers = [m for m in get_registration_listeners().listeners if isinstance(m, RegManager)]
    if not managers:
        return
    manager = managers[0]
    for name, kind in get_topic_manager().get_publications():
        manager.reg_added(name, kind, Registration.PUB)
    for name, kind in get_topic_manager().get_subscriptions():
        manager.reg_added(name, kind, Registration.SUB)
    for name, uri in get_service_manager().get_services():
        manager.reg_added(name, uri, Registration.SRV)
