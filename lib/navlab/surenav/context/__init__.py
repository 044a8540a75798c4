"""The context demonstrator of the SuReNav benchmark (issue 25, step 1).

Relaxations decided per region from context (``rules``: sidewalk ends, crosswalk detours, patch size,
new obstacles; ``personas``: tolerances), not per label and metre as ``experts`` does. ``walker`` plans
with the rules, ``environments`` redraws Table I's environments with it, ``measure`` tests the two
properties that make it a benchmark for SuReNav's claim (``benchmarks/surenav_context.py``).

Measured before any method was trained on it (``default``, the 100 Table I environments, Table I's
executor, paired 95% bootstrap; ``benchmarks/surenav_context.json``): Expert 0.072 Fréchet / 0.703
IoU; best per-label field (the per-label demonstrator's personas' mean costs) 0.163 / 0.403; SuReNav's
executor with the rule Psi 0.091 / 0.640. Context share +0.300 [0.218, 0.379] (at least 0.20: holds);
region-expressible +0.237 [0.157, 0.311] (at least 0.10: holds).

The benchmark built on it (issues 25 and 60; stages ``surenav_context_demos``,
``surenav_context_estimator``, notebooks ``surenav/01``-``04``): ``tiles`` cuts real training and
validation tiles disjoint from the test tiles, ``dataset`` stores the demonstrations of every split and
their relaxation mix, ``features`` gives the estimator the rules' context per node, ``training`` trains it
as the paper does (``surenav_estimator``'s architecture, Eq. 12-14 on the closed set through the
straight-through differentiable A*) beside our variants (blackbox gradient, ``surenav.blackbox``; false
positives on the plan) and the leave-one-city-out runs; ``benchmark`` runs every Table I row on the
context environments and decides the paper's Table I claims (``reports/surenav/table1_human_likeness``),
``safety`` Fig. 4 and Fig. 5 on the safety-efficiency episodes with every method trained on context
demonstrations, ``held_out`` the leave-one-city-out table.
"""
