"""The engine: a syntax tree to a timeline, and the face state at any time.

compiler (syntax tree -> timeline of tracks and robot cues) -> timeline (`sample(t)`, pure) ->
animation (with idle blinks and darts); effects are the robot effects as typed values;
live_session is the same engine driven by commands and events as they arrive (session_program,
session_steps, session_handlers and session_records are its parts, live_face the face it plays
on, session_intake the worker that drives it on a real clock); explanation is `explain`'s words.
"""
