"""The vocabulary as data and the geometry, depending on nothing else of the package.

Emotions, parts, units and limits (face_constants), easing curves, the eye ellipse and the head pan
(geometry), the face at one instant (face_state), the voices `say` knows, and files that
appear only once complete (partial_files).
"""
