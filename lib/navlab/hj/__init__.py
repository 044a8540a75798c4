"""HJ-search (Hu, Siu, Chen 2026): value functions, planning, closed loop and tables on ``reach``'s solver.

The HJ track's package beside ``surenav`` and ``pacer``: ``reachability`` poses the paper's value functions
(general and map TTR, static BRT, human-robot BRT) as HJ problems for ``reach``; ``grids`` stores them as the
``hj_grids`` artefacts (and the forward-only car's variant) and ``brt_margin`` measures the static BRT's
margin (Eq. 12's m) against a finer solve. ``guidance`` (the four heuristics) and ``pruners`` (OBS, static
BRT, FS/FI human BRT) turn the stored grids into what the compiled lattice search evaluates; ``planning``
(tasks of Tables I-V), ``state_lattice_runs`` and ``timing`` (Table VII); ``humans``, ``receding_horizon``,
``lattice_policy`` and ``scenarios`` (the walking humans, the 12 Hz loop, the car and the closed-loop cells
of Tables VI, VIII, IX); ``paper``, ``closed_loop``, ``sensitivity`` and ``sweeps`` (the paper's numbers,
summaries and the sensitivity sweep); ``claims`` (the paper's claims, quoted, the rules that decide them
and our own checks); ``tables`` and ``value_functions`` (the reports). The figures are in ``viz.hj_*``.
"""
