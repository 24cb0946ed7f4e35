"""The `baxterface` command line: a thin adapter over the library.

app.py holds what every command shares and the entry point; each command lives
with its kin (script_commands, play_command, ros_commands, state_command,
studio_command, screen_command, asset_commands) and is registered here, in the
order `--help` lists them.
"""

import os

# The face does no linear algebra: OpenBLAS's threads, which numpy starts on import, would only
# spin (0.1 to 0.25 s of CPU at every `baxterface` command). Set before anything imports numpy.
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import typer

from .app import ROS_ARGS, app, main
from .asset_commands import gestures, theme_check, theme_export, voices
from .play_command import play
from .ros_commands import buttons, node, send, stream
from .screen_command import screen
from .script_commands import check, explain, render
from .state_command import state
from .studio_command import studio

for command in (render, explain, play):
    app.command()(command)
for command in (node, buttons, send, stream, state):
    app.command(context_settings=ROS_ARGS)(command)
for command in (check, studio, screen, voices, gestures):
    app.command()(command)
theme_app = typer.Typer(
    help="Themes: the face's layer images. Export the default one to edit, check your own.",
    no_args_is_help=True,
)
theme_app.command("export")(theme_export)
theme_app.command("check")(theme_check)
app.add_typer(theme_app, name="theme")

__all__ = ["app", "main"]
