"""The script language: text to a checked syntax tree.

source (reading within limits) -> parser (the grammar, with builder making the syntax_tree's
dataclasses and recovery going on after syntax errors) -> checker (whole-script checks);
diagnostics say what is wrong and where; durations is how long each statement takes.
"""
