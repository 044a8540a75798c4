"""Helpers shared by the params.yaml section schemas."""

from dataclasses import field

PROFILES = ("smoke", "default", "gpu", "paper")  # gpu: PACER at a CUDA-machine size (pacer only; else default)


def between(lo: float | None = None, hi: float | None = None, length: int | None = None, ordered: bool = False):
    """A dataclass field whose value (or each item of a list) must lie in [lo, hi]; lists of ``length``;
    ``ordered`` lists (a ``[min, max]`` range) must not decrease.

    Scalar ranges spelled as two keys ``min_<x>`` / ``max_<x>`` are checked for order by the loader.
    """
    return field(metadata={"min": lo, "max": hi, "length": length, "ordered": ordered})
