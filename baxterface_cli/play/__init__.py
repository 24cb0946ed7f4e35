"""Real time on this machine: player (a window or the terminal, with sound) and rehearsal
(following against a recorded file instead of the robot's sensors).
"""
