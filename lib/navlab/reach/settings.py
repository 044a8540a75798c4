"""SolverSettings: the few numerical choices of a level-set solve, instead of a long argument list."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

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
    convergence_band / convergence_tolerance / convergence_window: if a band is given, stop once the
        values of the states with |V| < band (and, in a tube, l > 0) moved by less than the tolerance
        (value units) over the last window (seconds of τ). Far from the zero level set the value keeps
        drifting long after the set itself has settled, so a global test stops too late; comparing
        across a window rather than one step lets bounded stencil-switching flicker of ENO/WENO pass.
    """

    scheme: Literal["upwind1", "eno2", "weno5"] = "weno5"
    rk_order: int = 3
    cfl: float = 0.75
    dissipation: Literal["local", "global"] = "local"
    value_postprocessor: Literal["backward_reachable_tube", "none"] = "backward_reachable_tube"
    convergence_band: float | None = None
    convergence_tolerance: float = 1e-2
    convergence_window: float = 0.5

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
            problems.append(
                f"value_postprocessor must be 'backward_reachable_tube' or 'none', "
                f"got {self.value_postprocessor!r}"
            )
        if self.convergence_band is not None and not self.convergence_band > 0:
            problems.append(f"convergence_band must be positive or None, got {self.convergence_band!r}")
        if not self.convergence_tolerance > 0:
            problems.append(f"convergence_tolerance must be positive, got {self.convergence_tolerance!r}")
        if not self.convergence_window > 0:
            problems.append(f"convergence_window must be positive, got {self.convergence_window!r}")
        if problems:
            raise ValueError("SolverSettings: " + "; ".join(problems))


DEFAULT_SETTINGS = SolverSettings()  # WENO5 + TVD-RK3 + local Lax-Friedrichs, CFL 0.75, tube postprocessing
