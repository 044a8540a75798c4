"""SolverSettings: the few numerical choices of a level-set solve, instead of a long argument list."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal, Optional

from navlab.reach.finite_differences import SCHEMES


@dataclass(frozen=True)
class SolverSettings:
    """
    scheme: spatial derivatives, 'upwind1' | 'eno2' | 'weno5'.
    rk_order: order of the TVD Runge-Kutta time integrator, 1-3.
    cfl: Courant number; the step is cfl / max_x Σ_i α_i(x) / h_i.
    dissipation: 'local' (Lax-Friedrichs α_i evaluated per grid point) or 'global' (one α_i per axis,
        the maximum over the grid, as hj_reachability's default) .
    value_postprocessor: 'backward_reachable_tube' keeps V = min(V, l) after every step (a tube, not a
        set at one time); 'none' leaves the PDE solution as is.
    convergence_band / convergence_tolerance: if a band is given, stop once max |∂V/∂τ| over the states
        with |V| < band falls below the tolerance (value units per second). Far from the zero level set
        the value keeps drifting long after the set itself has settled, so a global test stops too late.
    """

    scheme: Literal["upwind1", "eno2", "weno5"] = "weno5"
    rk_order: int = 3
    cfl: float = 0.75
    dissipation: Literal["local", "global"] = "local"
    value_postprocessor: Literal["backward_reachable_tube", "none"] = "backward_reachable_tube"
    convergence_band: Optional[float] = None
    convergence_tolerance: float = 1e-3

    def __post_init__(self):
        problems = []
        if self.scheme not in SCHEMES:
            problems.append(f"scheme must be one of {sorted(SCHEMES)}, got {self.scheme!r}")
        if self.rk_order not in (1, 2, 3):
            problems.append(f"rk_order must be 1, 2 or 3, got {self.rk_order!r}")
        if not 0 < self.cfl <= 1:
            problems.append(f"cfl must lie in (0, 1], got {self.cfl!r}")
        if self.dissipation not in ("local", "global"):
            problems.append(f"dissipation must be 'local' or 'global', got {self.dissipation!r}")
        if self.value_postprocessor not in ("backward_reachable_tube", "none"):
            problems.append(f"value_postprocessor must be 'backward_reachable_tube' or 'none', "
                            f"got {self.value_postprocessor!r}")
        if self.convergence_band is not None and not self.convergence_band > 0:
            problems.append(f"convergence_band must be positive or None, got {self.convergence_band!r}")
        if not self.convergence_tolerance > 0:
            problems.append(f"convergence_tolerance must be positive, got {self.convergence_tolerance!r}")
        if problems:
            raise ValueError("SolverSettings: " + "; ".join(problems))
