"""A running screen's or studio's API from the command line: `state --url` reads it, `send --event
--url` raises an event at it. The token is the one given, else the address's own (`?token=`, as
the server printed it), else BAXTERFACE_TOKEN; every failure is one line."""

from __future__ import annotations

import contextlib
import json
import os
from typing import Any, Dict, Optional
from urllib.parse import parse_qs, urlsplit

import typer

from .app import fail

LARGEST_ANSWER = 8 * 1024 * 1024  # bytes: a studio's state carries its script (at most 256 KiB) and more
TOKEN_VARIABLE = "BAXTERFACE_TOKEN"  # as the screen and the studio read it (cli/screen_command.py)


def url_option(help: str) -> Any:
    return typer.Option(None, "--url", metavar="URL", help=help)


# The token, as `state` and `send` take it.
TOKEN_OPT = typer.Option(
    None,
    "--token",
    metavar="TOKEN",
    help=f"The token of a screen or studio served off loopback (default: the URL's, else {TOKEN_VARIABLE}).",
)


def call(
    command: str, url: str, token: Optional[str], path: str, timeout: float, body: Optional[str] = None
) -> Dict[str, Any]:
    """The JSON object `url`'s server answers at `path` (a POST of `body`, if given); a one-line
    exit naming `command` when it cannot be had."""
    import urllib.error
    import urllib.request

    parts = urlsplit(url)
    if parts.scheme not in ("http", "https") or not parts.hostname:
        raise fail(f"baxterface {command}: --url must be an http:// address, not {url[:80]!r}", 2)
    token = token or (parse_qs(parts.query).get("token") or [None])[0] or os.environ.get(TOKEN_VARIABLE)
    address = f"{parts.scheme}://{parts.netloc}{path}"
    data = None if body is None else body.encode("utf-8")
    request = urllib.request.Request(address, data=data, headers={"Accept": "application/json"})
    if token:
        request.add_header("X-Baxterface-Token", token)
    try:
        with urllib.request.urlopen(request, timeout=timeout) as answer:
            raw = answer.read(LARGEST_ANSWER + 1)
    except urllib.error.HTTPError as e:
        said = e.read(500).decode("utf-8", "replace").strip()
        with contextlib.suppress(ValueError, AttributeError):  # the API's own words, where it gave them
            said = json.loads(said).get("error") or said
        raise fail(f"baxterface {command}: {address}: {e.code} {said or e.reason}") from None
    except (urllib.error.URLError, OSError) as e:
        why = getattr(e, "reason", None) or e
        raise fail(
            f"baxterface {command}: cannot reach {address}: {getattr(why, 'strerror', None) or why}"
        ) from None
    try:
        if len(raw) > LARGEST_ANSWER:
            raise ValueError("the answer is too large")
        found = json.loads(raw.decode("utf-8"))
        if not isinstance(found, dict):
            raise ValueError("not a JSON object")
    except ValueError as e:
        raise fail(f"baxterface {command}: {address} is not a screen or a studio: {e}") from None
    return found
