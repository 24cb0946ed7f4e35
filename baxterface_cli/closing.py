"""Resources a `with` block closes at its end, however the block ends, as the export sinks are.

The ROS link, the speakers, the camera watch, the command intake and the JPEG publisher hold
threads, nodes or devices until their `close()`; with this, a caller writes
`with open_link(...) as link:` instead of nesting `try`/`finally` by hand.
"""

from __future__ import annotations

from typing import Any, TypeVar

Resource = TypeVar("Resource", bound="ClosedOnExit")


class ClosedOnExit:
    """A resource whose `close()` a `with` block calls on leaving it."""

    def close(self) -> None:  # pragma: no cover - each resource has its own
        raise NotImplementedError

    def __enter__(self: Resource) -> Resource:
        return self

    def __exit__(self, kind: Any, error: Any, trace: Any) -> None:
        self.close()
