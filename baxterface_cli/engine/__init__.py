"""The engine: a syntax tree to a timeline, and the face state at any time.

compiler (syntax tree -> timeline of tracks and robot cues) -> timeline (`sample(t)`, pure) ->
animation (with idle blinks and darts); effects are the robot effects as typed values;
live_face, live_session and session_intake are the same engine driven by commands and events as
they arrive; explanation is `explain`'s words.
"""
