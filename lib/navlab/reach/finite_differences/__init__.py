"""One-sided spatial derivatives (left, right) of a value function along one axis.

Each scheme module exposes ``left_right(values, dim, spacing, periodic) -> (left, right)``:
``left`` is the derivative biased to the lower side (φ_x⁻), ``right`` to the upper side (φ_x⁺).
The two never share memory, so the caller may overwrite them in place.
"""

from navlab.reach.finite_differences import eno2, upwind_first, weno5

SCHEMES = {"upwind1": upwind_first, "eno2": eno2, "weno5": weno5}


def scheme(name: str):
    if name not in SCHEMES:
        raise ValueError(f"unknown finite-difference scheme {name!r}; choose one of {sorted(SCHEMES)}")
    return SCHEMES[name]
