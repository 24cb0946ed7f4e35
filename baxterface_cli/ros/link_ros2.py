"""The `Link` on ROS 2, through rclpy: a node in a context of its own, spun on a thread of its own.

Each link is independent (its own context, node and executor), so a process may
hold several. Parameters come from `--ros-args -p name:=value` (or a parameter
file) and need no declaring. ROS 1's latching is ROS 2's transient-local
durability; a subscription asks for it only when `latched`, so the volatile
publishers of `ros2 topic pub` reach the node's command topics. Message types
are the installed packages' (`std_msgs.msg.String`); a type whose package is
not installed (Baxter's own, on most ROS 2 machines) is one `has` says no to.
Images go out and come in as CDR bytes written and read by images.py (a
subscriber gets an object with the Image's fields, `data` a memoryview): rclpy's
own conversion of a frame's 1.8 MB costs more than the rest of the trip.
The transport (Fast DDS's shared memory sized for a frame, or ROS's own) is
set up before the node joins: transport.py.
"""

from __future__ import annotations

import array
import importlib
import os
import threading
import time
import uuid
from typing import Any, Callable, Dict, List

from .images import image_cdr, image_from_cdr
from .link import Link, Publisher, Subscription
from .transport import environment

IMAGE = "sensor_msgs/Image"
MOST_SPIN_FAILURES = 100  # executor errors, while the link is open, before it gives up


def _qos(depth: int, latched: bool, sensor: bool) -> Any:
    """Keep the last `depth` messages (0: keep them all, until every reader has them)."""
    from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy

    return QoSProfile(
        history=HistoryPolicy.KEEP_LAST if depth > 0 else HistoryPolicy.KEEP_ALL,
        depth=max(1, depth),
        # Best effort hears every publisher, reliable or not: cameras publish best effort.
        reliability=ReliabilityPolicy.BEST_EFFORT if sensor else ReliabilityPolicy.RELIABLE,
        durability=DurabilityPolicy.TRANSIENT_LOCAL if latched else DurabilityPolicy.VOLATILE,
    )


def _uint8_arrays(fields: Dict[str, Any]) -> Dict[str, Any]:
    """Bytes as array('B'): rclpy copies bytes into one element by element (ms for a frame)."""
    out = {}
    for name, value in fields.items():
        if isinstance(value, (bytes, bytearray, memoryview)):
            buffer = array.array("B")
            buffer.frombytes(value)
            value = buffer
        out[name] = value
    return out


class _RclpyPublisher(Publisher):
    def __init__(self, node: Any, topic: str, cls: Any, latched: bool, queue: int, kind: str) -> None:
        self.node, self.cls = node, cls
        self.serialized = kind == IMAGE  # frames go out as CDR written here: rclpy's own takes 15 ms
        # No queue is ROS 1's synchronous publisher: here, every message is kept until delivered.
        self.pub = node.create_publisher(cls, topic, _qos(queue, latched, sensor=False))
        self.topic = self.pub.topic_name

    def publish(self, **fields: Any) -> None:
        if self.serialized:
            self.pub.publish(image_cdr(fields))
        else:
            self.pub.publish(self.cls(**_uint8_arrays(fields)))  # no `stamp`: only images have one

    def listeners(self) -> int:
        return self.pub.get_subscription_count()

    def wait_delivered(self, timeout: float) -> bool:
        from rclpy.duration import Duration

        return self.pub.wait_for_all_acked(Duration(nanoseconds=int(timeout * 1e9)))

    def close(self) -> None:
        self.node.destroy_publisher(self.pub)


class _RclpySubscription(Subscription):
    def __init__(self, node: Any, sub: Any) -> None:
        self.node, self.sub = node, sub
        self.topic = sub.topic_name

    def publishers(self) -> int:
        return self.node.count_publishers(self.topic)

    def close(self) -> None:
        self.node.destroy_subscription(self.sub)


class RclpyLink(Link):
    version = 2

    def __init__(self, name: str, argv: List[str], anonymous: bool, serve_parameters: bool) -> None:
        import rclpy
        from rclpy.context import Context
        from rclpy.executors import SingleThreadedExecutor
        from rclpy.signals import SignalHandlerOptions

        self.rclpy = rclpy
        self.context = Context()
        self.closed = False
        if anonymous:  # ROS 2 has no anonymous names: a unique suffix, as ROS 1's
            name = f"{name}_{os.getpid()}_{uuid.uuid4().hex[:8]}"
        # rcl reads the discovery range at init, Fast DDS its profile when the node's participant is
        # made: both inside. Only the face node takes a `transport` parameter.
        with environment(argv if serve_parameters else ()) as self.transport:
            # Signals stay the program's own: the face node ends at its next frame on SIGTERM.
            rclpy.init(args=argv, context=self.context, signal_handler_options=SignalHandlerOptions.NO)
            self.node = rclpy.create_node(
                name,
                context=self.context,
                allow_undeclared_parameters=True,
                automatically_declare_parameters_from_overrides=True,
                start_parameter_services=serve_parameters,
            )
        self.name = self.node.get_fully_qualified_name()
        self.logger = self.node.get_logger()
        self._classes: Dict[str, Any] = {}
        self.executor = SingleThreadedExecutor(context=self.context)
        self.executor.add_node(self.node)
        self.thread = threading.Thread(target=self._spin, name="baxterface-ros2", daemon=True)
        self.thread.start()

    def _spin(self) -> None:
        from rclpy.executors import ExternalShutdownException

        failures = 0
        while True:
            try:
                self.executor.spin()
                return
            except ExternalShutdownException:
                return
            except Exception as e:  # noqa: BLE001 - the context went while a wait was under way
                if not self.ok():  # the link is closing
                    return
                # A subscription or publisher closed from another thread while the executor waited
                # on it ("destruction was requested"): the others still need their messages.
                failures += 1
                if failures > MOST_SPIN_FAILURES:
                    self.logger.error(f"the ROS 2 executor stopped: {e}")
                    return

    def resolve(self, topic: str) -> str:
        return self.node.resolve_topic_name(_ros2_name(topic))

    def param(self, name: str, default: Any) -> Any:
        if not self.node.has_parameter(name):
            return default
        value = self.node.get_parameter(name).value
        return default if value is None else value

    def _class(self, kind: str) -> Any:
        if kind not in self._classes:
            package, short = kind.split("/")
            self._classes[kind] = getattr(importlib.import_module(f"{package}.msg"), short)
        return self._classes[kind]

    def has(self, kind: str) -> bool:
        try:
            self._class(kind)
        except (ImportError, AttributeError):
            return False
        return True

    def publisher(self, topic: str, kind: str, latched: bool = False, queue: int = 10) -> Publisher:
        return _RclpyPublisher(self.node, _ros2_name(topic), self._class(kind), latched, queue, kind)

    def subscribe(
        self,
        topic: str,
        kind: str,
        callback: Callable[[Any], None],
        queue: int = 10,
        latched: bool = False,
        sensor: bool = False,
    ) -> Subscription:
        raw = kind == IMAGE  # images come as CDR, read here in microseconds: rclpy's own takes 6 ms

        def heard(msg: Any) -> None:
            try:
                callback(image_from_cdr(msg) if raw else msg)
            except Exception as e:  # one bad message must not stop the executor, and every callback
                self.log("error", f"a message on {name} could not be taken: {e}", every=5.0)

        name = _ros2_name(topic)
        qos = _qos(1 if sensor else queue, latched, sensor)
        sub = self.node.create_subscription(self._class(kind), name, heard, qos, raw=raw)
        return _RclpySubscription(self.node, sub)

    def _emit(self, level: str, text: str) -> None:
        # rclpy keys its loggers by the calling line, and refuses one line two severities.
        if level == "info":
            self.logger.info(text)
        elif level == "warn":
            self.logger.warning(text)
        else:
            self.logger.error(text)

    def ok(self) -> bool:
        return not self.closed and self.context.ok()

    def spin(self) -> None:
        # Sleeps, not joins: a Ctrl-C that breaks into Thread.join leaves the process to abort at exit.
        while self.thread.is_alive():
            time.sleep(0.1)

    def close(self, reason: str = "done") -> None:
        if not self.ok():
            return
        self.closed = True
        # The spin thread ends before the node goes: a node destroyed while a wait holds its
        # entities can crash the process (rclpy #663), as `send` did now and then at its exit.
        self.executor.shutdown(timeout_sec=1.0)
        self.thread.join(timeout=5.0)
        self.node.destroy_node()
        self.context.try_shutdown()
        # The middleware's participant goes now, not in the interpreter's last collection, when
        # Fast DDS's own threads may already be gone.
        self.context.destroy()


def _ros2_name(topic: str) -> str:
    """ROS 1's private names ("~state") in ROS 2's spelling ("~/state")."""
    if topic.startswith("~") and not topic.startswith("~/"):
        return "~/" + topic[1:]
    return topic
