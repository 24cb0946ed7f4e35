"""Drawing: a face state to a frame.

artwork and vector_shapes draw the default theme; theme (with theme_manifest reading a theme
folder and theme_fitting fitting it to a screen) holds the layers; compositing is the pixel
arithmetic; renderer draws a state, redrawing only what moved; face is the `Face` API.
"""
