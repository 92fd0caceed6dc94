"""The model layer: geometry, configurations, canonical forms, symmetry, the paper's strings, classes, and what a robot sees."""
