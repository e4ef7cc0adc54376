"""The scenes of 7-Scenes and their numbers of training and test sequences, shared by the reader
and the stand-in that is written in the same layout."""

#: The seven scenes, in the order that seeds the stand-in's random draws.
SCENE_NAMES = ("chess", "fire", "heads", "office", "pumpkin", "redkitchen", "stairs")

#: 7-Scenes' numbers of (training, test) sequences per scene.
SEQUENCE_COUNTS = {
    "chess": (4, 2),
    "fire": (2, 2),
    "heads": (1, 1),
    "office": (6, 4),
    "pumpkin": (4, 2),
    "redkitchen": (7, 5),
    "stairs": (4, 2),
}
