"""navlab.reach: Hamilton-Jacobi level-set solver (torch, CPU/CUDA) and the HJ-search value functions.

Numerics, one idea per module (after hj_reachability): ``grid`` (axes, periodic θ), ``boundary_conditions``
(ghost cells), ``finite_differences`` (upwind1 / ENO2 / WENO5), ``artificial_dissipation`` (Lax-Friedrichs),
``time_integration`` (TVD-RK 1-3), ``settings`` (SolverSettings), ``solver`` (``solve``, ``Backend``),
``dynamics`` (optimal Hamiltonians), ``value_functions`` (general TTR, static-map BRT, human-robot BRT).
"""
