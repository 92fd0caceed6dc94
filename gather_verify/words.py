"""Counts in words: "1 question", "2 questions", "1 leaf", "3 leaves".

Every layer may use it (it imports nothing of the project), so that a report never says
"a decision tree of 1 questions" nor hedges with "configuration(s)".

>>> counted(1, "question"), counted(2, "question"), counted(3, "leaf", "leaves")
('1 question', '2 questions', '3 leaves')
>>> counted(0, "start")
'0 starts'
"""

from __future__ import annotations


def counted(n: int, noun: str, plural: str | None = None) -> str:
    """``n`` and the noun, singular for exactly one (``plural`` for nouns that do not take
    an ``s``)."""
    return f"{n} {noun if n == 1 else plural or noun + 's'}"
