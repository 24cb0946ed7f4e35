"""Files: a rendered animation written in the format its name asks for.

sink is the writers' interface; registry lists the formats by extension and imports each
writer when asked (png_gif, video, apng, bag, wav); render_to_file runs a render start to end.
"""
