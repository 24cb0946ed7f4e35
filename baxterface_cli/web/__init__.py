"""What every page that shows a face shares, the studio's and the screen's, served by Starlette.

face_api (the routes every face page has: the page, commands, the frame, sounds, the live
WebSocket), frame_pump (frames and status to the open pages), sounds (what the face says, by key,
as WAV; static/sound.js plays it on the page), request_guard (loopback, origins and the token),
server (uvicorn) and connections (its limits).
"""
