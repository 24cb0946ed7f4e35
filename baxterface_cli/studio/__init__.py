"""The web studio: editor, live preview, button panel and session log, served by Starlette.

workspace (the script, preview, panel and robot switch, without the web), preview, reacting and
event_run (the one live session: the editor's script run over the events fired and the commands
pressed), panel, robot_switch, api (the studio's routes over
the face routes every page has, which the web room holds with the pump, the guard and the
server).
"""
