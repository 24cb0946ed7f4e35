"""The studio's timeline under the preview: the run's log as bars in time, in four lanes (events,
handlers, states, said), made as `render LOG.jsonl --out session.eaf` makes its tiers
(export/annotations.py), on the preview's clock, so a click on them seeks the preview there.

A long run (an hour of events) is shown around the preview's position: its log's lines within
`AROUND` seconds of it, so a fired event costs the same at the 2,000th as at the first.
"""

from __future__ import annotations

import bisect
from typing import Any, Dict, List

from ..export.annotations import log_tiers
from ..language.event_trace import Posted

AROUND = 120.0  # seconds either side of the position whose bars are shown
LANES = ("events", "handlers", "states", "said")


def lanes(preview: Any, t: float) -> Dict[str, List[Dict[str, Any]]]:
    """The bars of what `preview` (preview.py's) plays, around its position `t`."""
    run = preview.run
    log = run.log if run is not None else ()
    events = [i for i in run.inputs if isinstance(i, Posted)] if run is not None else []
    low, high = t - AROUND, t + AROUND
    log = log[bisect.bisect_left([line.at for line in log], low) :]
    events = events[bisect.bisect_left([e.at for e in events], low) :]
    speech = [s for s in preview.animation.timeline.speech if s.end >= low and s.at <= high]
    end = min(preview.duration, high)
    tiers = log_tiers(
        [line for line in log if line.at <= high], [e for e in events if e.at <= high], speech, end
    )
    return {
        lane: [
            {"start": round(a, 3), "end": round(b, 3), "text": text} for a, b, text in tiers[lane] if b >= low
        ]
        for lane in LANES
    }
