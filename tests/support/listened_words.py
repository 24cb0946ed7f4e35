"""Phrases to listen for, for the tests and the bench of how much hearing costs: words each in
pocketsphinx's dictionary, and one phrase of many spellings."""

WORDS = [
    "hello",
    "goodbye",
    "robot",
    "morning",
    "baxter",
    "table",
    "window",
    "yellow",
    "purple",
    "orange",
    "banana",
    "kitchen",
    "garden",
    "doctor",
    "teacher",
    "student",
    "mountain",
    "river",
    "ocean",
    "forest",
    "castle",
    "dragon",
    "wizard",
    "pirate",
    "rocket",
    "planet",
    "comet",
    "button",
    "ladder",
    "pencil",
    "paper",
    "glass",
    "water",
    "bottle",
]
# A phrase the language takes (8 words, 55 letters) of words the dictionary spells four or five
# ways each: 25 spellings of it, 1,323 phones, where "hello" has 2 and 8.
HEAVY = "uses humid florida directv graduates uses humid florida"
