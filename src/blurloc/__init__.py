"""blurloc: a step-by-step reproduction of "A Recurrent Deep Architecture for Enhancing Indoor
Camera Localization Using Motion Blur Elimination"."""

__version__ = "0.1.0"
