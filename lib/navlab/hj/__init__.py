"""HJ-search (Hu, Siu, Chen 2026): planning, closed loop and tables on the level sets of ``reach``.

The HJ track's package beside ``surenav`` and ``pacer`` (issue 27 item 1): ``guidance`` (heuristics) and
``pruners`` (OBS, static BRT, FS/FI human BRT) turn ``reach``'s stored value functions into what the compiled
lattice search evaluates; ``planning`` (tasks of Tables I-V), ``timing`` (Table VII); ``lattice_policy`` and
``scenarios`` (the receding-horizon car and the closed-loop cells of Tables VI, VIII, IX); ``paper``,
``closed_loop``, ``sensitivity`` and ``sweeps`` (the paper's numbers, summaries and the sensitivity sweep);
``claims`` (the paper's claims, quoted, and the rules that decide them and our own checks); ``tables`` and
``value_functions`` (the reports). ``reach`` stays a level-set library (and the BRT
margin it measures); the HJ figures are in ``viz`` (``viz.hj_*``), the layer above.
"""
