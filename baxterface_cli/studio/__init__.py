"""The web studio: editor, live preview, button panel and session log, served by Starlette.

workspace (the script, preview, panel and robot switch, without the web), preview, session,
panel, guard (loopback, origins and the token), api (routes and the WebSocket), pump (frames
to the pages), server (uvicorn).
"""
