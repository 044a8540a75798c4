"""navlab.reach: a Hamilton-Jacobi level-set solver (torch, CPU/CUDA), as ``hj_reachability`` is one.

Numerics, one idea per module: ``grid`` (axes, periodic θ), ``boundary_conditions`` (ghost cells),
``finite_differences`` (upwind1 / ENO2 / WENO5), ``artificial_dissipation`` (Lax-Friedrichs),
``time_integration`` (TVD-RK 1-3), ``settings`` (SolverSettings), ``solver`` (``solve``, ``Backend``),
``dynamics`` (optimal Hamiltonians), ``store`` and ``lookup`` (grids on disk and their interpolants). The
HJ-search paper's value functions, their artefacts and the BRT margin are the HJ track's (``navlab.hj``).
"""
