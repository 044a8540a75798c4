"""Helpers shared by the params.yaml section schemas."""

from dataclasses import field

PROFILES = ("smoke", "default", "paper")


def between(lo: float | None = None, hi: float | None = None, length: int | None = None):
    """A dataclass field whose value (or each item of a list) must lie in [lo, hi]; lists of ``length``."""
    return field(metadata={"min": lo, "max": hi, "length": length})
