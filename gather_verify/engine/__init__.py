"""The engine: the explorer's state encoding, reference and bulk searches, and limits."""
