"""The model layer: geometry, configurations, canonical forms, symmetry, and what a robot sees (the paper's strings and classes: :mod:`gather_verify.paper`)."""
