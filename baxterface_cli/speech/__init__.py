"""Speech: text to sound with the time of every phoneme and word, and the mouth that follows it.

espeak (the espeak-ng C library through ctypes) -> synthesis (utterances) -> visemes (timed
mouth shapes); soundtrack mixes a script's utterances; sound_device plays them on this machine.
"""
