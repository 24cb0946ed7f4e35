"""Real time on this machine: the player (a window or the terminal, with sound).

Following against a recorded file instead of the robot's sensors is the robot's side
(robot/rehearsal.py); the player hands it each frame.
"""
