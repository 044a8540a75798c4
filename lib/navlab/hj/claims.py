"""HJ-search's claims (Hu, Siu & Chen): every comparative or numeric statement its text makes about Tables
I-IX and Figs. 2-3, quoted (``CLAIMS``), and the functions that decide each report's claims on its units.

Why a registry: a verdict is only as good as the sentence it tests, so each claim carries the paper's own
words (``quote``), where they stand and the numbers the paper prints; a report decides the claims that
name it, and the registry says why the others are not tested (real-robot only, a measurement we do not
make). Sentences that only repeat a table's cells (e.g. "an average node expansion of 326.8") are not
claims of their own: the cells are the report's paper rows.

Every verdict comes from a strict rule of ``navlab.metrics.claims`` on the table's own units, paired: the
tasks of Tables I-V (the same start-goal pairs for every method), the seeded runs of Table VI, the trips of
Tables VIII-IX (trip k of run r is the same leg, from the same seed, for every method), the deterministic
values of Figs. 2-3. A tie is never "holds"; too few units for a verdict (Tables I and III have 4 tasks,
Table VI 5 runs) is "inconclusive", saying what the test would need. Our own diagnostics (the dense check,
Table VII against the paper's hardware, the sensitivity curves) are ``ours`` claims, counted apart.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Callable, Mapping, Sequence

import numpy as np
from scipy.stats import fisher_exact

from navlab.core.seeding import rng
from navlab.hj.closed_loop import detour_start, run_success
from navlab.metrics.claims import (
    ALPHA,
    MIN_UNITS,
    Claim,
    PaperClaim,
    Test,
    all_of,
    best_of,
    equal_count,
    every,
    exact_comparison,
    magnitude,
    on_par,
    ours,
    paired_difference,
    paired_success,
    ratio_of_values,
    registry,
)
from navlab.metrics.intervals import RESAMPLES

PAR_RATIO = 1.05  # "similar", "comparable": ratio of means within 5%; the paper's own such pairs differ <= 1.7%
SUCCESS_MARGIN = 0.10  # "no improvement in success rate": the paired rate difference within 10 points
DETOUR_MARGIN_M = 0.5  # Fig. 8's "approximately 3.5 m": within half a metre
FIG7_HEADING_RAD = 0.52  # Fig. 7's start heading
TABLE7_TARGET = 5.0  # issue 11 (ours): our look-ups at least 5x cheaper per evaluated state than the paper's
# Table VII's timings are single runs on a shared 2-core machine, no repeats: a ratio of two of them is
# allowed ±50% (the per-call TTR / Dist ratio of this notebook ranged 0.81-1.85 over its last 12 committed runs).
TIMING_TOLERANCE = 0.5


FIG2, FIG3 = "fig2_heuristic_values", "fig3_brt_growth"
T1, T2, T3, T4, T5 = ("table1_heuristics_astar", "table2_heuristics_anastar", "table3_pruning_astar",
                      "table4_pruning_anastar", "table5_static_general")
T6, T7, T8, T9 = "table6_dynamic", "table7_compute", "table8_rooms", "table9_humans"
NOT_TIMED = ("our compiled search does not time its look-ups apart from the rest of an expansion (a timer per "
             "look-up would cost more than the look-up); Table VII times the look-ups alone")
REAL_ROBOT = ("real-robot experiments (QBot, people tracked by a ZED 2): we simulate Tables VIII and IX with pose "
              "and human-position noise, no robot")

_c = PaperClaim  # key, claim, quote, where, paper, report, not_tested, margin: short for the registry's lines
CLAIMS: dict[str, PaperClaim] = registry(
    # Sec. VI-A, Fig. 2: the four heuristics at one robot, heading up and reversed
    _c("fig2_ttr_over_dist", "TTR above Dist, map-based and general alike, at both headings",
       "with dynamics-aware (TTR) dominating distance-based (Dist) methods", "Sec. VI-A, Fig. 2",
       "map TTR 7.57 / 9.06 s vs map Dist 5.09 s; general TTR 5.81 / 7.89 s vs general Dist 4.20 s", FIG2),
    _c("fig2_map_over_general", "map-based above general, TTR and Dist alike, at both headings",
       "and map-based versions dominating their general counterparts", "Sec. VI-A, Fig. 2",
       "TTR 7.57 vs 5.81 s and 9.06 vs 7.89 s; Dist 5.09 vs 4.20 s", FIG2),
    _c("fig2_general_ttr_over_dist", "general TTR above both Dist heuristics at both headings",
       "the general TTR achieves a favorable balance, retaining substantially greater informativeness than "
       "distance-based heuristics", "Sec. VI-A, Fig. 2", "5.81 / 7.89 s vs 5.09 and 4.20 s", FIG2),
    _c("fig2_map_ttr_rises", "map TTR rises when the heading is reversed",
       "This reversed orientation substantially increases the TTR values, yielding 9.06 s for the map-based TTR",
       "Sec. VI-A, Fig. 2", "7.57 -> 9.06 s", FIG2),
    _c("fig2_general_ttr_rises", "general TTR rises when the heading is reversed",
       "This reversed orientation substantially increases the TTR values, yielding 9.06 s for the map-based TTR "
       "and 7.89 s for the general TTR", "Sec. VI-A, Fig. 2", "5.81 -> 7.89 s", FIG2),
    _c("fig2_dist_unchanged", "both Dist heuristics unchanged when the heading is reversed",
       "while the distance-based heuristics remain unchanged at 5.09 s and 4.20 s, respectively",
       "Sec. VI-A, Fig. 2", "5.09 and 4.20 s at both headings", FIG2),
    # Sec. VI-B, Fig. 3
    _c("fig3_brt_grows", "the static BRT grows with speed", "the volume of the BRT increases with the robot’s speed",
       "Sec. VI-B, Fig. 3", "slices only, no numbers", FIG3),
    # Sec. VII-A, Table I: A*, Dist vs TTR, 4 start headings
    _c("t1_success", "both A* planners solve all four tasks",
       "As shown in Table I, both planners finished all four tasks.", "Sec. VII-A, Table I", "4/4 and 4/4", T1),
    _c("t1_fewer_nodes", "A* with TTR expands fewer nodes than with Dist",
       "Notably, A* with TTR achieved this with significantly fewer node expansions", "Sec. VII-A, Table I",
       "node counts blank in the text", T1),
    _c("t1_shorter_time", "A* with TTR searches for less time than with Dist",
       "a much shorter total search time (20.97 s vs. 414.16 s) compared to A* with Dist", "Sec. VII-A, Table I",
       "20.97 vs 414.16 s", T1),
    _c("t1_heuristic_share", "the heuristic's share of the run time: TTR 8.85%, Dist 3.66%",
       "TTR took 1.86 s (8.85% of its total time), while Dist required 15.16 s (3.66% of its total time)",
       "Sec. VII-A, Table I", "TTR 1.86 s (8.85%), Dist 15.16 s (3.66%)", not_tested=NOT_TIMED),
    _c("t1_gain_from_expansions", "TTR's gain comes from fewer expansions, not faster evaluations",
       "This indicates that the performance improvement of the TTR heuristic stems primarily from reducing node "
       "expansions rather than accelerating heuristic evaluations.", "Sec. VII-A, Table I",
       not_tested="it rests on the heuristic's share of the run time, which we do not measure: " + NOT_TIMED),
    _c("t1_same_cost", "both A* return the same optimal cost",
       "Finally, both planners achieved identical average optimal costs (5.25)", "Sec. VII-A, Table I",
       "5.25 and 5.25", T1),
    _c("t1_smac_estimate", "Dist's expansions would take over 6.8 s even in Nav2's C++ SmacPlanner",
       "expanding the nodes required by the Dist heuristic in our four-dimensional state space would theoretically "
       "consume over 6.8 seconds", "Sec. VII-A", "> 6.8 s",
       not_tested="an estimate from the SmacPlanner's iteration rate on the paper's machine; we run no SmacPlanner, "
                  "and the paper's node counts are blank in its text"),
    # Sec. VII-A, Table II: ANA*, Dist vs TTR, 12 start headings
    _c("t2_ttr_solves_all", "ANA* with TTR solves all 12 tasks",
       "ANA* with the TTR heuristic successfully solved all 12 tasks", "Sec. VII-A, Table II", "12/12", T2),
    _c("t2_dist_count", "ANA* with Dist solves 7 of the 12 tasks (fails 5)",
       "while ANA* with the Dist heuristic failed in 5 out of 12 tasks", "Sec. VII-A, Table II", "7/12", T2),
    _c("t2_ttr_more", "ANA* with TTR solves more tasks than with Dist",
       "the choice of heuristic significantly impacted the success rate", "Sec. VII-A, Table II", "12/12 vs 7/12",
       T2),
    _c("t2_misaligned", "Dist fails mostly where the car starts misaligned with the goal",
       "The failures of the Dist heuristic occurred primarily when the robot was initially misaligned with the goal.",
       "Sec. VII-A, Table II", "5 failures (their headings are not in the text)", T2),
    _c("t2_common_nodes_par", f"on the common tasks both heuristics expand about as many nodes (within "
                              f"{PAR_RATIO - 1:.0%})",
       "ANA* with Dist achieved almost similar node expansions (257.0 vs. 258.6)", "Sec. VII-A, Table II",
       "257.0 vs 258.6", T2, margin=PAR_RATIO),
    _c("t2_common_dist_cheaper", "on the common tasks Dist's plans cost less than TTR's",
       "and marginally lower trajectory costs (8.06 vs. 8.20)", "Sec. VII-A, Table II", "8.06 vs 8.20", T2),
    _c("t2_marginal_effort", "TTR over all 12 tasks costs only marginally more effort than Dist over its 7",
       "This indicates that the TTR heuristic extends the planner’s capability to solve complex orientation tasks "
       "with only a marginal increase in computational effort compared to the baseline.", "Sec. VII-A, Table II",
       "273.4 (TTR, 12 tasks) vs 257.0 (Dist, 7 tasks)",
       not_tested="it compares TTR over all 12 tasks with Dist over the 7 it solved: different task sets, so no "
                  "paired test exists; both means are in the rows (nodes_all, nodes_common)"),
    _c("fig6_reversal", "TTR guides the car through a slight reversal, then a reorientation",
       "it effectively guided the robot to execute a slight reversal followed by a precise reorientation toward "
       "the goal", "Sec. VII-A, Fig. 6", "a reversal, then a reorientation", T2),
    # Sec. VII-B, Table III: A* (Dist), OBS vs BRT, 4 start headings
    _c("t3_success", "both A* planners solve all 4 tasks",
       "both A*-based planners finished all 4 tasks within the maximum iteration limit", "Sec. VII-B, Table III",
       "4/4 and 4/4", T3),
    _c("t3_same_cost", "OBS and BRT return the same optimal cost",
       "while maintaining the same optimal average costs of 89.5", "Sec. VII-B, Table III", "89.5 and 89.5", T3),
    _c("t3_fewer_nodes", "A* with BRT expands 15.1% fewer nodes than with OBS",
       "A* with BRT pruner demonstrated superior search efficiency, reducing the average node expansions by 15.1%",
       "Sec. VII-B, Table III", "-15.1% (counts blank in the text)", T3),
    _c("t3_longer_time", "A* with BRT searches longer than with OBS (the paper's implementation)",
       "the total searching time A* with BRT pruner is longer than A* with OBS pruner (335.84 vs. 303.32)",
       "Sec. VII-B, Table III", "335.84 vs 303.32 s",
       not_tested="a timing of the paper's Python implementation, in which the BRT look-up takes 12.5% of the run; "
                  "ours is compiled, for which the paper expects the opposite (t3_optimized_gain)"),
    _c("t3_pruner_share", "the pruner's share of the run time: BRT 12.5%, OBS 1.57%",
       "BRT pruner operation itself required 41.97 s (12.5% of its total time) which is substantially more than "
       "the 4.77 s (1.57% of its total time) needed for the OBS pruner approach", "Sec. VII-B, Table III",
       "BRT 41.97 s (12.5%), OBS 4.77 s (1.57%)", not_tested=NOT_TIMED),
    _c("t3_optimized_gain", "in an optimised (compiled) search, BRT's fewer expansions make it faster than OBS",
       "it is therefore expected to translate into runtime gains in optimized implementations where reachability "
       "queries are accelerated", "Sec. VII-B, Table III", "a prediction, no number", T3),
    # Sec. VII-B, Table IV: ANA* (Dist), OBS vs BRT, 12 start headings
    _c("t4_obs_count", "ANA* with OBS solves 8 of the 12 tasks (fails 4)",
       "ANA* equipped with the OBS pruner failed in 4 out of the 12 tasks", "Sec. VII-B, Table IV", "8/12", T4),
    _c("t4_brt_solves_all", "ANA* with BRT solves all 12 tasks",
       "whereas the version with the BRT pruner successfully solved all 12", "Sec. VII-B, Table IV", "12/12", T4),
    _c("t4_higher_success", "BRT solves more tasks than OBS",
       "the BRT pruner not only guarantees higher success rates by enabling safer maneuvers",
       "Sec. VII-B, Table IV", "12/12 vs 8/12", T4),
    _c("t4_obs_fail_mode", "OBS's failures are plans that fail the dense check",
       "The OBS pruner failed the feasibility interpolation check because densified trajectories intersected "
       "static obstacles.", "Sec. VII-B, Table IV", "4 failures", T4),
    _c("t4_fig7", "at the 0.52 rad start OBS fails and BRT finds a feasible plan",
       "In this case, the planner with the OBS pruner approached the obstacle too closely and failed to "
       "circumvent it within the time limit.", "Sec. VII-B, Fig. 7", "OBS fails, BRT succeeds", T4),
    _c("t4_fewer_nodes", "on the common tasks BRT expands fewer nodes than OBS",
       "Within this common subset, ANA* with the BRT pruner expanded fewer nodes on average (373.1 vs. 401.4)",
       "Sec. VII-B, Table IV", "373.1 vs 401.4", T4),
    _c("t4_similar_cost", f"on the common tasks BRT's and OBS's plans cost about the same (within "
                          f"{PAR_RATIO - 1:.0%})",
       "while achieving similar path quality (408.79 vs. 404.57)", "Sec. VII-B, Table IV", "408.79 vs 404.57", T4,
       margin=PAR_RATIO),
    # Sec. VII-C, Table V: ANA*, every heuristic x pruner, 100 random pairs
    _c("t5_best_success", "TTR + BRT has the highest success",
       "the proposed combination of the TTR heuristic and the BRT pruner achieves the superior overall performance, "
       "successfully completing 97 out of 100 tasks—the highest success rate among all tested settings",
       "Sec. VII-C, Table V", "97/100 vs 81, 85, 83", T5),
    _c("t5_ttr_nodes_brt", "with BRT, TTR expands fewer nodes than Dist on the common tasks",
       "when paired with the BRT pruner, replacing the Dist heuristic with TTR reduces the average node expansions",
       "Sec. VII-C, Table V", "229.3 vs 299.9", T5),
    _c("t5_ttr_nodes_brt_size", "with BRT, TTR's expansions are 23.5% below Dist's on the common tasks",
       "by 23.5% (from 299.9 to 229.3)", "Sec. VII-C, Table V", "229.3 / 299.9 = 0.765", T5),
    _c("t5_ttr_cost_brt", "with BRT, TTR's plans cost less than Dist's on the common tasks",
       "and lowers the trajectory cost from 188.98 to 146.37", "Sec. VII-C, Table V", "146.37 vs 188.98", T5),
    _c("t5_ttr_success_obs", "with OBS, TTR succeeds more often than Dist",
       "TTR improves the success rate from 81/100 to 83/100", "Sec. VII-C, Table V", "83/100 vs 81/100", T5),
    _c("t5_ttr_nodes_obs", "with OBS, TTR expands fewer nodes than Dist on the common tasks",
       "decreases node expansions from 311.1 to 235.4", "Sec. VII-C, Table V", "235.4 vs 311.1", T5),
    _c("t5_ttr_cost_obs", "with OBS, TTR's plans cost less than Dist's on the common tasks",
       "and reduces trajectory cost from 191.44 to 146.58", "Sec. VII-C, Table V", "146.58 vs 191.44", T5),
    _c("t5_brt_cost_par", f"with TTR, BRT's and OBS's plans cost about the same on the common tasks (within "
                          f"{PAR_RATIO - 1:.0%})",
       "maintaining comparable costs of 146.37 vs. 146.58 under the TTR heuristic", "Sec. VII-C, Table V",
       "146.37 vs 146.58", T5, margin=PAR_RATIO),
    _c("t5_brt_success_ttr", "with TTR, BRT succeeds more often than OBS",
       "upgrading from the OBS pruner to the BRT pruner boosts the success rate from 83% to 97%",
       "Sec. VII-C, Table V", "97/100 vs 83/100", T5),
    _c("t5_brt_success_dist", "with Dist, BRT succeeds more often than OBS",
       "the BRT pruner improves the success rate from 81% to 85%", "Sec. VII-C, Table V", "85/100 vs 81/100", T5),
    # Sec. VII-D, Table VI and Fig. 8: simulated humans, 5 runs per cell
    _c("t6_f2f_fi_all", "Face-to-Face: FI-BRT clears every run",
       "In the Face-to-Face scenario, the FI-BRT completed all 5 tests.", "Sec. VII-D, Table VI", "5/5", T6),
    _c("t6_f2f_others_fail", "Face-to-Face: FS-BRT and OBS fail every run",
       "In contrast, both the OBS baseline and the FS-BRT ablation failed completely (0/5).", "Sec. VII-D, Table VI",
       "0/5 and 0/5", T6),
    _c("t6_f2f_fi_beats", "Face-to-Face: FI-BRT succeeds more often than FS-BRT and than OBS",
       "First, predictive safety enabled by FI-BRT is essential for avoiding head-on collisions, where reactive "
       "methods often fail.", "Sec. VII-D, Table VI", "5/5 vs 0/5 and 0/5", T6),
    _c("t6_detour", f"Face-to-Face: FI-BRT starts its detour about 3.5 m from the human (within "
                    f"{DETOUR_MARGIN_M:g} m)",
       "the robot starts to detour when the relative distance is still approximately 3.5 m", "Sec. VII-D, Fig. 8",
       "3.5 m", T6, margin=DETOUR_MARGIN_M),
    _c("t6_fs_late", "Face-to-Face: FS-BRT starts its detour closer to the human than FI-BRT",
       "it delays the evasion maneuver until the robot is close to the human", "Sec. VII-D, Table VI",
       "no number", T6),
    _c("t6_zz_obs_fastest", "Zig-Zag: OBS takes the least time",
       "The OBS pruner recorded the shortest average time (30.41 s)", "Sec. VII-D, Table VI",
       "30.41 vs 31.17 and 39.85 s", T6),
    _c("t6_zz_obs_count", "Zig-Zag: OBS clears 1 of the 5 runs",
       "resulting in a high failure rate (only 1/5 success)", "Sec. VII-D, Table VI", "1/5", T6),
    _c("t6_zz_fs_faster", "Zig-Zag: FS-BRT is faster than FI-BRT",
       "Comparing the two, FS-BRT (31.17 s) is faster than FI-BRT (39.85 s).", "Sec. VII-D, Table VI",
       "31.17 vs 39.85 s", T6),
    # Sec. VII-E, Table VII: 10,000 calls per component
    _c("t7_ttr_ratio", "a TTR heuristic call takes 3.5x a Dist call",
       "runs 3.5 times slower than the two-dimensional Dist heuristic", "Sec. VII-E, Table VII",
       "0.187 vs 0.053 s: 3.5x", T7),
    _c("t7_brt_ratio", "a BRT pruner call takes 3.3x an OBS call",
       "exhibits a 3.3x slowdown compared to the OBS pruner", "Sec. VII-E, Table VII", "0.247 vs 0.076 s: 3.3x",
       T7),
    _c("t7_more_expensive", "the 4-D TTR and BRT cost more per call than the 2-D Dist and OBS",
       "but also are notably more expensive than their two-dimensional counterparts", "Sec. VII-E, Table VII",
       "3.5x and 3.3x", T7),
    _c("t7_human_brt", "the human-robot BRT pruner costs as the static BRT pruner",
       "The same computational profile applies to the human-robot BRT pruner", "Sec. VII-E, Table VII",
       not_tested="Table VII here times the heuristics and the static pruners; the human-robot BRT pruner is not "
                  "timed"),
    # Sec. VIII-B, Table VIII: the paper's real QBot; simulated here
    _c("t8_hall_dist_count", "Long Hallway: both Dist planners clear 2 of 9 trips",
       "planners employing the Dist heuristic struggled significantly, achieving a low success rate of only 2/9",
       "Sec. VIII-B, Table VIII", "2/9 and 2/9", T8),
    _c("t8_hall_dist_brt_no_gain", f"Long Hallway: with Dist, BRT succeeds as often as OBS (within "
                                   f"{SUCCESS_MARGIN:.0%} points)",
       "The inclusion of our BRT pruner yielded no improvement in success rate over the OBS pruner for the Dist "
       "heuristic", "Sec. VIII-B, Table VIII", "2/9 vs 2/9", T8, margin=SUCCESS_MARGIN),
    _c("t8_hall_dist_brt_faster", "Long Hallway: with Dist, BRT's trips take less time than OBS's",
       "although it slightly reduced the navigation time", "Sec. VIII-B, Table VIII", "24.5 vs 29.8 s", T8),
    _c("t8_hall_ttr_all", "Long Hallway: TTR clears every trip with either pruner",
       "the TTR heuristic proved highly effective, achieving a perfect 9/9 success rate with both pruners",
       "Sec. VIII-B, Table VIII", "9/9 and 9/9", T8),
    _c("t8_hall_heuristic", "Long Hallway: TTR succeeds more often than Dist under both pruners",
       "In the Long Hallway scenario, the performance gap is primarily dictated by the choice of heuristic rather "
       "than the pruner.", "Sec. VIII-B, Table VIII", "9/9 vs 2/9 with either pruner", T8),
    _c("t8_hall_ttr_brt_faster", "Long Hallway: with TTR, BRT's trips take less time than OBS's",
       "reducing the total navigation time to 85.9 s compared to 89.6 s with the OBS pruner",
       "Sec. VIII-B, Table VIII", "85.9 vs 89.6 s", T8),
    _c("t8_dense_obs_fail", "Dense Room: both OBS planners fail every trip",
       "All planners utilizing the basic OBS pruner failed completely, achieving a 0/6 success rate irrespective "
       "of the heuristic", "Sec. VIII-B, Table VIII", "0/6 and 0/6", T8),
    _c("t8_dense_dist_brt_count", "Dense Room: Dist + BRT clears 1 of 6 trips",
       "The planner using the Dist heuristic and the BRT pruner achieved a marginal success rate of 1/6.",
       "Sec. VIII-B, Table VIII", "1/6", T8),
    _c("t8_dense_only", "Dense Room: only TTR + BRT clears every trip",
       "This method is the only one to achieve a 100 success rate (6/6)", "Sec. VIII-B, Table VIII",
       "6/6 vs 0/6, 1/6, 0/6", T8),
    _c("t8_dense_superior", "Dense Room: TTR + BRT succeeds more often than every other combination",
       "the synergistic combination of the TTR heuristic and the BRT pruner (our method) demonstrated superior "
       "efficacy", "Sec. VIII-B, Table VIII", "6/6 vs 0/6, 1/6, 0/6", T8),
    # Sec. VIII-C, Table IX: the paper's real QBot among people; simulated here
    _c("t9_safer_than_obs", "FI-BRT and FS-BRT have fewer trips with a collision than OBS, with 1 and 2 humans",
       "both the FI-BRT and FS-BRT methods outperformed the OBS baseline", "Sec. VIII-C, Table IX",
       "0 and 0 vs 1 (1 human); 0 and 0 vs 3 (2 humans) collisions", T9),
    _c("t9_zero_collisions", "FI-BRT and FS-BRT never collide, with 1 and 2 humans",
       "by maintaining a zero-collision record", "Sec. VIII-C, Table IX", "0 collisions in each", T9),
    _c("t9_obs_collides", "OBS collides with 1 and with 2 humans",
       "resulted in inevitable collisions in both scenarios", "Sec. VIII-C, Table IX", "1 and 3 collisions", T9),
    _c("t9_obs_fastest", "OBS takes the least time, with 1 and 2 humans",
       "despite achieving the shortest navigation times", "Sec. VIII-C, Table IX",
       "111.5 vs 118.2, 157.6 s; 134.9 vs 171.3, 264.3 s", T9),
    _c("t9_fi_longest", "FI-BRT takes the most time, with 1 and 2 humans",
       "leading to the longest completion time (157.6 s and 264.3 s)", "Sec. VIII-C, Table IX",
       "157.6 and 264.3 s", T9),
    _c("t9_fs_faster", "FS-BRT takes less time than FI-BRT, with 1 and 2 humans",
       "allowing for more fluent motion and reduced travel time (118.2 s and 171.3 s)", "Sec. VIII-C, Table IX",
       "118.2 vs 157.6 s; 171.3 vs 264.3 s", T9),
    _c("t9_video", "the video shows FI-BRT's stop-and-go against FS-BRT's fluent motion",
       "The qualitative difference in behavior, particularly the conservative stop-and-go motion of the FI-BRT "
       "method versus the fluent navigation of the FS-BRT method, is clearly demonstrated in the supplementary "
       "video.", "Sec. VIII-C, Table IX", not_tested="a statement about the real robot's supplementary video"),
    _c("real_world", "the framework generalises to the real robot",
       "Real-world experiments confirm that the framework generalizes beyond simulation and remains effective "
       "under sensing and control constraints.", "Sec. IX", not_tested=REAL_ROBOT),
)


# ---------------------------------------------------------------------------------------------- rules

def exact_equal(a: float, b: float, names: tuple[str, str], tolerance: float = 0.0) -> Test:
    """An equality of two deterministic values ("remain unchanged"): holds when they differ by at most
    ``tolerance``, does not hold otherwise. (Not in ``metrics.claims``: its rules test differences.)"""
    verdict = "holds" if abs(a - b) <= tolerance else "does not hold"
    return Test(verdict, f"{names[0]} {a:.4g} vs {names[1]} {b:.4g} (deterministic; tolerance {tolerance:g})")


def some(events: Sequence[bool], unit: str, name: str) -> Test:
    """"X collides", "X does not clear every trip": holds when at least one unit has the event."""
    e = np.asarray(events, dtype=bool)
    return Test("holds" if e.any() else "does not hold", f"{name}: {int(e.sum())} of {e.size} {unit}")


def on_both(rule: Callable[[np.ndarray, np.ndarray], Test], a, b, keep, unit: str,
            which: str = "both finished") -> Test:
    """A paired rule on the units ``keep`` marks (those both methods finished, or all solved), saying how many."""
    keep = np.asarray(keep, dtype=bool)
    if not keep.any():
        return Test("inconclusive", f"no {unit} {which}: nothing to pair")
    t = rule(np.asarray(a, float)[keep], np.asarray(b, float)[keep])
    return Test(t.verdict, f"{t.evidence} (the {int(keep.sum())} of {keep.size} {unit} {which})")


def ratio_on_par(a, b, ratio: float, rng: np.random.Generator, unit: str = "units",
                 names: tuple[str, str] = ("A", "B")) -> Test:
    """"Similar", "comparable" on a positive quantity (expansions, cost): the ratio of means mean(a) / mean(b),
    resampling the paired units, within [1/ratio, ratio]: holds if its 95% interval lies inside, does not hold
    if wholly outside, else inconclusive. (Not in ``metrics.claims``: its ``on_par`` bounds a difference in the
    quantity's own units, and no one margin in expansions or cost fits both our tasks and the paper's.)"""
    a, b = np.asarray(a, float), np.asarray(b, float)
    n = len(a)
    head = f"{names[0]} / {names[1]} = {a.mean() / b.mean():.3g} (on par: within [{1 / ratio:.3g}, {ratio:.3g}])"
    if n < MIN_UNITS:
        return Test("inconclusive", f"{head}; {n} {unit}: too few for a verdict (at least {MIN_UNITS} paired {unit})")
    draws = rng.integers(0, n, size=(RESAMPLES, n))
    lo, hi = np.percentile(a[draws].mean(axis=1) / b[draws].mean(axis=1), [100 * ALPHA / 2, 100 * (1 - ALPHA / 2)])
    verdict = ("holds" if 1 / ratio < lo and hi < ratio else
               "does not hold" if lo >= ratio or hi <= 1 / ratio else "inconclusive")
    return Test(verdict, f"{head}, 95% CI [{lo:.3g}, {hi:.3g}] over {n} {unit}")


def _rng(seed: int, key: str) -> np.random.Generator:
    return rng(seed, "hj.claims", key)


def _fmt(x: float | None) -> str:
    return "none" if x is None or not np.isfinite(x) else f"{x:.4g}"


def _fmt3(x: float | None) -> str:
    return "none" if x is None or not np.isfinite(x) else f"{x:.3f}"


# ---------------------------------------------------------------------------------- Tables I-V (search)

def dense_check(results: Mapping[str, Sequence]) -> list[Claim]:
    """Ours, on our swept-check variant rows (``hj.planning.SWEPT``; none: no check): no plan they returned
    fails the paper's densified feasibility check, which their swept collision check rules out. The paper's
    own pruners check the sampled states only: their dense-check failures are failures, counted in the
    table's notes (``hj.paper.failure_modes``), not a bug."""
    from navlab.hj.planning import SWEPT  # here: planning loads numba, which the results page needs not

    swept = {m: rs for m, rs in results.items() if rs and rs[0].pruner in SWEPT}
    if not swept:
        return []
    feasible = [r.feasible for rs in swept.values() for r in rs if r.found]
    detail = ", ".join(f"{m} {sum(r.found and not r.feasible for r in rs)}" for m, rs in swept.items())
    test = every(feasible, "plans found", "feasible") if feasible else Test("inconclusive", "no plan found")
    return [ours("no plan of a swept-check row fails the dense check", test, f"failing plans: {detail}",
                 "a plan failing the dense check is a bug there: the swept collision check rules it out")]


FORWARD_ONLY = ", forward-only car (ours)"  # suffix of the forward-only car's variant rows (Tables I-IX, Fig. 2)


def reversing_checks(results: Mapping[str, Sequence], rows: Sequence[str], seed: int) -> list[Claim]:
    """Ours, for each of ``rows`` that the table also runs with the forward-only car (``row + FORWARD_ONLY``,
    ``navlab.hj.grids.forward_only``): the paper's reversing car solves more of the tasks, and its plans cost
    less, paired over the tasks (both solved); what reversing buys the search the paper describes (Sec. VII-A,
    Fig. 6)."""
    out = []
    for a in rows:
        b = a + FORWARD_ONLY
        if b in results:
            key = "reversing_" + a.replace(" w/ ", "_").replace(" ", "_")  # Tables I-II: reversing_A*_Dist
            out += [ours(f"{a}: the reversing car solves more tasks than the forward-only car", _more(results, a, b),
                         f"solved: {a} {sum(r.success for r in results[a])}, forward-only "
                         f"{sum(r.success for r in results[b])} of {len(results[a])}"),
                    ours(f"{a}: the reversing car's plans cost less than the forward-only car's",
                         _below(results, a, b, "cost", seed, key), _means(results, (a, b), "cost"))]
    return out


def _col(results, method: str, attr: str) -> np.ndarray:
    return np.array([getattr(r, attr) for r in results[method]], dtype=np.float64)


def _ok(results, *methods: str) -> np.ndarray:
    return np.all([[r.success for r in results[m]] for m in methods], axis=0)


def _below(results, a: str, b: str, attr: str, seed: int, key: str) -> Test:
    """``a``'s ``attr`` (expansions, cost) below ``b``'s, paired over the tasks both solved."""
    return on_both(lambda x, y: paired_difference(x, y, "lower", _rng(seed, key), "tasks", (a, b)),
                   _col(results, a, attr), _col(results, b, attr), _ok(results, a, b), "tasks", "both solved")


def _par(results, a: str, b: str, attr: str, seed: int, key: str) -> Test:
    """``a`` and ``b`` on par in ``attr`` (their ratio of means within the claim's margin), over the tasks both
    solved."""
    def par(x, y):
        return ratio_on_par(x, y, CLAIMS[key].margin, _rng(seed, key), "tasks", (a, b))

    return on_both(par, _col(results, a, attr), _col(results, b, attr), _ok(results, a, b), "tasks", "both solved")


def _solves(results, method: str) -> Test:
    return every([r.success for r in results[method]], "tasks", method)


def _count(results, method: str, paper: int, paper_of: int) -> Test:
    res = results[method]
    return equal_count(sum(r.success for r in res), len(res), paper, paper_of)


def _more(results, a: str, b: str) -> Test:
    return paired_success([r.success for r in results[a]], [r.success for r in results[b]], "higher", "tasks", (a, b))


def _means(results, methods: Sequence[str], attr: str) -> str:
    """Mean ``attr`` of each method over the tasks all of them solved."""
    ok = _ok(results, *methods)
    return ", ".join(f"{m} {_fmt(_col(results, m, attr)[ok].mean() if ok.any() else None)}" for m in methods) + (
        f" mean {attr} over the {int(ok.sum())} tasks all solved")


def table1_claims(results: Mapping[str, Sequence], lattice, seed: int) -> list[Claim]:
    """Table I on the continuous lattice's tasks (``results``), "same optimal cost" on the true state lattice
    (``lattice``: ``hj.state_lattice_runs.StateLatticeRuns``): both A* return Dijkstra's cost on every task."""
    # imported here, not at the top: it loads torch and numba, which the results page (importing CLAIMS) needs not
    from navlab.hj.state_lattice_runs import DIJKSTRA, DIST, TOLERANCE_S, TTR, same_cost

    d, t = "A* w/ Dist", "A* w/ TTR"
    c = CLAIMS
    state = lattice.results
    nodes = (f"state lattice: A* w/ TTR {np.mean([r.expansions for r in state[TTR]]):.0f} vs A* w/ Dist "
             f"{np.mean([r.expansions for r in state[DIST]]):.0f} vs Dijkstra "
             f"{np.mean([r.expansions for r in state[DIJKSTRA]]):.0f} mean expansions")
    agree = {m: [same_cost(a, b) for a, b in zip(state[DIJKSTRA], state[m], strict=True)] for m in (DIST, TTR)}
    costs = ", ".join("none" if not r.found else f"{r.cost:.3f}" for r in state[DIJKSTRA])
    ok = _ok(results, d, t)
    cont = {m: _col(results, m, "cost")[ok].mean() if ok.any() else None for m in (d, t)}
    differs = cont[d] is None or cont[t] is None or abs(cont[t] - cont[d]) >= 1e-6
    same = (f"Dijkstra's costs {costs} s (agreement within {TOLERANCE_S:g} s); paper-style continuous lattice: "
            f"A* w/ TTR {_fmt3(cont[t])} vs A* w/ Dist {_fmt3(cont[d])} s mean over the tasks both solved"
            + ("; they differ because that lattice keeps one node per (x, y, v, θ) cell, the first best one to reach "
               "it (Smac-style duplicate detection), so A* is optimal only over those representatives; on the state "
               "lattice every primitive ends on a lattice state, so the search graph is fixed and A* with an "
               "admissible heuristic is exact" if differs else ", the same"))
    return [
        c["t1_success"].decide(all_of({m: _solves(results, m) for m in (d, t)})),
        c["t1_fewer_nodes"].decide(_below(results, t, d, "expansions", seed, "t1_fewer_nodes"), nodes),
        c["t1_shorter_time"].decide(paired_difference(_col(results, t, "seconds"), _col(results, d, "seconds"),
                                                      "lower", _rng(seed, "t1_shorter_time"), "tasks", (t, d)),
                                    "our compiled search's seconds per task",
                                    "absolute seconds are not comparable (compiled search here, Python in the paper)"),
        c["t1_same_cost"].decide(all_of({f"{m} = Dijkstra": every(agree[m], "tasks", m) for m in (DIST, TTR)}),
                                 same, "a heuristic that overestimates the lattice's cost-to-go (not admissible) "
                                       "returns a costlier plan"),
        *dense_check(results),
        *reversing_checks(results, (d, t), seed),
    ]


def _bearing_off(r) -> float:
    """How far the start heading turns from the bearing to the goal (rad, 0..pi)."""
    x, y, _, theta = r.start
    return abs(math.remainder(theta - math.atan2(r.goal[1] - y, r.goal[0] - x), math.tau))


def _misaligned_failures(results, method: str) -> Test | None:
    """Do ``method``'s failures fall on misaligned starts (heading more than 90° off the goal's bearing)?
    Fisher's exact test on failures x alignment; None when it fails no task (nothing to locate)."""
    res = results[method]
    fail = np.array([not r.success for r in res])
    if not fail.any():
        return None
    mis = np.array([_bearing_off(r) > math.pi / 2 for r in res])
    table = [[int((fail & mis).sum()), int((fail & ~mis).sum())],
             [int((~fail & mis).sum()), int((~fail & ~mis).sum())]]
    p = fisher_exact(table).pvalue
    rate = [table[0][i] / max(table[0][i] + table[1][i], 1) for i in (0, 1)]
    verdict = "inconclusive" if p >= ALPHA else "holds" if rate[0] > rate[1] else "does not hold"
    return Test(verdict, f"{method} fails {table[0][0]} of {table[0][0] + table[1][0]} misaligned starts (> 90° off "
                         f"the goal's bearing) and {table[0][1]} of {table[0][1] + table[1][1]} aligned; Fisher's "
                         f"exact p = {p:.3g}")


def table2_claims(results: Mapping[str, Sequence], seed: int) -> list[Claim]:
    d, t = "ANA* w/ Dist", "ANA* w/ TTR"
    c = CLAIMS
    located = _misaligned_failures(results, d)
    reverse = ("Dist solves every task here although our car reverses as the paper's does: within our lattice, "
               "budget and room the anytime search leaves the local minima the paper reports (persistent backward "
               "movements)" if all(r.success for r in results[d]) else "")
    fig6 = max(range(len(results[t])), key=lambda i: abs(math.cos(results[t][i].start[3]) - 1))  # as notebook 01
    shown = results[t][fig6]
    reversal = every([shown.found and shown.min_speed < 0.0], "plan", "reversing (a negative speed)")
    return [
        c["t2_ttr_solves_all"].decide(_solves(results, t)),
        c["fig6_reversal"].decide(reversal, f"{t} from heading {math.degrees(shown.start[3]):.0f}° (the most "
                                            f"misaligned start, Fig. 6's): lowest speed {shown.min_speed:.3f} m/s"),
        c["t2_dist_count"].decide(_count(results, d, 7, 12), why=reverse),
        c["t2_ttr_more"].decide(_more(results, t, d), why=reverse),
        c["t2_misaligned"].untested(f"{d} fails none of our {len(results[d])} tasks: no failure to locate")
        if located is None else c["t2_misaligned"].decide(located),
        c["t2_common_nodes_par"].decide(_par(results, d, t, "expansions", seed, "t2_common_nodes_par"),
                                        _means(results, (d, t), "expansions")),
        c["t2_common_dist_cheaper"].decide(_below(results, d, t, "cost", seed, "t2_common_dist_cheaper"),
                                           _means(results, (d, t), "cost")),
        *dense_check(results),
        *reversing_checks(results, (d, t), seed),
    ]


def table3_claims(results: Mapping[str, Sequence], seed: int) -> list[Claim]:
    o, b = "A* w/ OBS", "A* w/ BRT"
    c = CLAIMS
    ok = _ok(results, o, b)
    gap = np.abs(_col(results, b, "cost") - _col(results, o, "cost"))[ok]
    nodes = on_both(lambda x, y: magnitude(x, y, 1 - 0.151, _rng(seed, "t3_fewer_nodes"), "tasks", (b, o)),
                    _col(results, b, "expansions"), _col(results, o, "expansions"), ok, "tasks", "both solved")
    return [
        c["t3_success"].decide(all_of({m: _solves(results, m) for m in (o, b)})),
        c["t3_same_cost"].decide(every(gap <= 1e-6, "tasks both solved", "same cost (within 1e-6)") if ok.any()
                                 else Test("inconclusive", "no task both solved"), _means(results, (o, b), "cost"),
                                 "the BRT prunes states the optimal OBS plan passes through, so its optimum can cost "
                                 "more"),
        c["t3_fewer_nodes"].decide(nodes),
        c["t3_optimized_gain"].decide(paired_difference(_col(results, b, "seconds"), _col(results, o, "seconds"),
                                                        "lower", _rng(seed, "t3_optimized_gain"), "tasks", (b, o)),
                                      "our compiled search's seconds per task"),
        *dense_check(results),
        *reversing_checks(results, (o,), seed),
    ]


def table4_claims(results: Mapping[str, Sequence], seed: int) -> list[Claim]:
    o, b = "ANA* w/ OBS", "ANA* w/ BRT"
    c = CLAIMS
    res = results[o]
    fig7 = min(range(len(res)), key=lambda i: abs(math.remainder(res[i].start[3] - FIG7_HEADING_RAD, math.tau)))
    at = f"our start heading {res[fig7].start[3]:.2f} rad (our room's own start and goal)"
    failed = [r for r in res if not r.success]
    obs_fails = ("OBS solves every task here: none of its plans grazes an obstacle between the sampled states within "
                 "our lattice (0.5 s steps, 4 samples each) and room" if not failed else "")
    found_bad = sum(r.found and not r.feasible for r in failed)
    return [
        c["t4_obs_count"].decide(_count(results, o, 8, 12), why=obs_fails),
        c["t4_brt_solves_all"].decide(_solves(results, b)),
        c["t4_higher_success"].decide(_more(results, b, o), why=obs_fails),
        c["t4_fig7"].decide(all_of({"OBS fails": every([not res[fig7].success], "task", o),
                                      "BRT succeeds": every([results[b][fig7].success], "task", b)}), at, obs_fails),
        c["t4_obs_fail_mode"].untested(f"{o} fails none of our {len(res)} tasks: no failure to classify")
        if not failed else c["t4_obs_fail_mode"].decide(
            every([r.found and not r.feasible for r in failed], "failed tasks", "plans failing the dense check"),
            f"{o}: {found_bad} plan(s) failing the dense check, {len(failed) - found_bad} task(s) without a plan"),
        c["t4_fewer_nodes"].decide(_below(results, b, o, "expansions", seed, "t4_fewer_nodes"),
                                   _means(results, (b, o), "expansions")),
        c["t4_similar_cost"].decide(_par(results, b, o, "cost", seed, "t4_similar_cost"),
                                    _means(results, (b, o), "cost")),
        *dense_check(results),
        *reversing_checks(results, (o,), seed),
    ]


def table5_claims(results: Mapping[str, Sequence], seed: int) -> list[Claim]:
    do, db, to, tb = "Dist + OBS", "Dist + BRT", "TTR + OBS", "TTR + BRT"
    c = CLAIMS
    everyone = _ok(results, do, db, to, tb)

    def common(key, a, b, attr, rule):
        """``rule(a's, b's, rng, names)`` on the tasks all four solved (the table's common subset)."""
        test = on_both(lambda x, y: rule(x, y, _rng(seed, key), (a, b)), _col(results, a, attr),
                       _col(results, b, attr), everyone, "tasks", "all four solved")
        return c[key].decide(test)

    def lower(x, y, g, names):
        return paired_difference(x, y, "lower", g, "tasks", names)

    def size(x, y, g, names):
        return magnitude(x, y, round(229.3 / 299.9, 3), g, "tasks", names)

    def par(x, y, g, names):
        return ratio_on_par(x, y, c["t5_brt_cost_par"].margin, g, "tasks", names)

    success = {m: [r.success for r in results[m]] for m in (do, db, to, tb)}
    return [
        c["t5_best_success"].decide(best_of(success, tb, "higher", _rng(seed, "t5_best_success"), "tasks",
                                            success=True)),
        common("t5_ttr_nodes_brt", tb, db, "expansions", lower),
        common("t5_ttr_nodes_brt_size", tb, db, "expansions", size),
        common("t5_ttr_cost_brt", tb, db, "cost", lower),
        c["t5_ttr_success_obs"].decide(_more(results, to, do)),
        common("t5_ttr_nodes_obs", to, do, "expansions", lower),
        common("t5_ttr_cost_obs", to, do, "cost", lower),
        common("t5_brt_cost_par", tb, to, "cost", par),
        c["t5_brt_success_ttr"].decide(_more(results, tb, to)),
        c["t5_brt_success_dist"].decide(_more(results, db, do)),
        *dense_check(results),
        *reversing_checks(results, (do, to), seed),
    ]


SEARCH_CLAIMS = {T2: table2_claims, T3: table3_claims, T4: table4_claims, T5: table5_claims}


def search_claims(table_id: str, results: Mapping[str, Sequence], seed: int) -> list[Claim]:
    """The claims of Table II, III, IV or V on its per-task results (``hj.planning.TaskResult`` by method)."""
    if table_id not in SEARCH_CLAIMS:
        raise ValueError(f"search_claims: no claims for {table_id!r}; use one of {', '.join(SEARCH_CLAIMS)}")
    return SEARCH_CLAIMS[table_id](results, seed)


# ------------------------------------------------------------------------------ Tables VI, VIII, IX (loop)

HUMAN_METHODS = ("FI-BRT", "FS-BRT", "OBS")  # Tables VI and IX
ROOM_METHODS = ("Dist + OBS", "Dist + BRT", "TTR + OBS", "TTR + BRT")  # Table VIII


def _causes(trips: Mapping[str, Sequence]) -> str:
    """Failed trips by cause, per method."""
    return "failed trips by cause (wall hits / deadlocks / timeouts): " + ", ".join(
        f"{m} " + "/".join(str(sum(t.outcome == k for t in ts)) for k in ("collision", "deadlock", "timeout"))
        for m, ts in trips.items())


def _detour_m(run, dynamic) -> float:
    """Fig. 8: the distance to the human where the car first left the head-on line (NaN: it never did)."""
    t6 = dynamic.table6
    d = detour_start(run, t6.face_to_face.robot_start[:2], t6.face_to_face.robot_goal, t6.detour_lateral_m)
    return math.nan if d is None else d["distance_to_human_m"]


def table6_claims(runs: Mapping[tuple[str, str], Sequence], dynamic) -> list[Claim]:
    """Table VI and Fig. 8 on their seeded runs (``runs``: {(method, scenario): runs}, as
    ``hj.scenarios.run_cells`` returns them; run r of every method has the same seed): success per run,
    times over runs, detour distances over the runs that detoured."""
    c, seed = CLAIMS, dynamic.seed
    fi, fs, obs = HUMAN_METHODS
    face = {m: runs[(m, "Face-to-Face")] for m in HUMAN_METHODS}
    zig = {m: runs[(m, "Zig-Zag")] for m in HUMAN_METHODS}
    ok_face = {m: [run_success(r) for r in rs] for m, rs in face.items()}
    ok_zig = {m: [run_success(r) for r in rs] for m, rs in zig.items()}
    detour = {m: np.array([_detour_m(r, dynamic) for r in face[m]]) for m in (fi, fs)}
    seen = np.isfinite(detour[fi])
    near = (on_par(detour[fi][seen], np.full(int(seen.sum()), 3.5), c["t6_detour"].margin, _rng(seed, "t6_detour"),
                   "runs", (f"{fi} detour", "3.5 m"))
            if seen.any() else Test("inconclusive", f"{fi} never left the line"))
    late = on_both(lambda x, y: paired_difference(x, y, "lower", _rng(seed, "t6_fs_late"), "runs", (fs, fi)),
                   detour[fs], detour[fi], np.isfinite(detour[fs]) & seen, "runs", "both detoured")
    early = (f"FS-BRT detoured {np.nanmean(detour[fs]):.2f} m before the human (FI-BRT {np.nanmean(detour[fi]):.2f} "
             f"m): re-planning at {dynamic.closed_loop.replan_hz:g} Hz with the feasible-set test alone already turns "
             "early enough on this head-on line"
             if any(ok_face[fs]) and np.isfinite(detour[fs]).any() and seen.any() else "")
    time_all = {m: [r.navigation_time for r in rs] for m, rs in zig.items()}
    both = np.array(ok_zig[fs]) & np.array(ok_zig[fi])

    def faster(x, y):
        return paired_difference(x, y, "lower", _rng(seed, "t6_zz_fs_faster"), "runs", (fs, fi))

    return [
        c["t6_f2f_fi_all"].decide(every(ok_face[fi], "runs", fi)),
        c["t6_f2f_others_fail"].decide(all_of({m: every(np.logical_not(ok_face[m]), "runs", f"{m} failed")
                                                 for m in (fs, obs)}), why=early),
        c["t6_f2f_fi_beats"].decide(all_of({f"vs {m}": paired_success(ok_face[fi], ok_face[m], "higher", "runs",
                                                                        (fi, m)) for m in (fs, obs)}), why=early),
        c["t6_detour"].decide(near),
        c["t6_fs_late"].decide(late),
        c["t6_zz_obs_fastest"].decide(best_of(time_all, obs, "lower", _rng(seed, "t6_zz_obs_fastest"), "runs"),
                                      "navigation time of every run (a contact does not stop a run: time_all_s)"),
        c["t6_zz_obs_count"].decide(equal_count(sum(ok_zig[obs]), len(ok_zig[obs]), 1, 5, "runs")),
        c["t6_zz_fs_faster"].decide(on_both(faster, time_all[fs], time_all[fi], both, "runs", "both cleared"),
                                    "navigation time of the runs both cleared (time_s)"),
    ]


def _trips(runs: Mapping, key) -> list:
    return [t for r in runs[key] for t in r.trips]


def _paired_trips(cells: Mapping[str, Sequence]) -> None:
    """Trips pair by position (run r, leg k): every method's list must be as long."""
    lengths = {m: len(ts) for m, ts in cells.items()}
    if len(set(lengths.values())) != 1:
        raise ValueError(f"trips pair by run and leg, but the methods ran different numbers of trips: {lengths}")


def loop_reversing_checks(runs: Mapping[tuple[str, object], Sequence]) -> list[Claim]:
    """Ours, where a closed-loop table (VI, VIII, IX) has the forward-only car's rows (``method + FORWARD_ONLY``):
    per method, the paper's reversing car completes more trips than the forward-only car, trips paired by cell,
    run and leg (the same seeds and humans for both cars), exact McNemar."""
    out = []
    for method in dict.fromkeys(m for m, _ in runs if not m.endswith(FORWARD_ONLY)):
        cells = [cell for m, cell in runs if m == method and (method + FORWARD_ONLY, cell) in runs]
        if not cells:
            continue
        mine = [t.success for cell in cells for t in _trips(runs, (method, cell))]
        forward = [t.success for cell in cells for t in _trips(runs, (method + FORWARD_ONLY, cell))]
        if len(mine) != len(forward):
            test = Test("inconclusive", f"the two cars ran different numbers of trips ({len(mine)}, {len(forward)})")
        else:
            test = paired_success(mine, forward, "higher", "trips", (method, method + FORWARD_ONLY))
        out.append(ours(f"{method}: the reversing car completes more trips than the forward-only car", test,
                        f"over {', '.join(map(str, cells))}"))
    return out


def table8_claims(runs: Mapping[tuple[str, str], Sequence], seed: int) -> list[Claim]:
    """Table VIII on its trips (``runs``: {(method, room label): runs}; trip k of run r is the same leg from
    the same seed for every method): success per trip, times over the trips both completed."""
    c = CLAIMS
    do, db, to, tb = ROOM_METHODS
    hall = {m: _trips(runs, (m, "Long Hallway")) for m in ROOM_METHODS}
    dense = {m: _trips(runs, (m, "Dense Room")) for m in ROOM_METHODS}
    for cells in (hall, dense):
        _paired_trips(cells)
    ok = {room: {m: np.array([t.success for t in ts]) for m, ts in cells.items()}
          for room, cells in (("hall", hall), ("dense", dense))}
    time = {m: np.array([t.time_s for t in ts]) for m, ts in hall.items()}

    def faster(key, a, b):
        """``a``'s hallway trips take less time than ``b``'s, paired over the trips both completed."""
        test = on_both(lambda x, y: paired_difference(x, y, "lower", _rng(seed, key), "trips", (a, b)), time[a],
                       time[b], ok["hall"][a] & ok["hall"][b], "trips", "both completed")
        return c[key].decide(test, "time per trip")

    h, d = ok["hall"], ok["dense"]
    no_gain = c["t8_hall_dist_brt_no_gain"]
    budget = ("Dist clears more of the hallway than the paper's 2/9: within our per-re-plan budget and the loop's "
              "rules (notes) the anytime search finds the hallway's route from either heuristic (the paper's time "
              "budget is not in its text; sensitivity_budget varies ours)"
              if min(h[do].mean(), h[db].mean()) > 2 / 9 else "")
    return [
        c["t8_hall_dist_count"].decide(all_of({m: equal_count(int(h[m].sum()), h[m].size, 2, 9, "trips")
                                                 for m in (do, db)}), why=budget),
        no_gain.decide(on_par(h[db], h[do], no_gain.margin, _rng(seed, no_gain.key), "trips", (db, do)),
                       "success per trip (1 or 0)"),
        faster("t8_hall_dist_brt_faster", db, do),
        c["t8_hall_ttr_all"].decide(all_of({m: every(h[m], "trips", m) for m in (to, tb)}), why=_causes(hall)),
        c["t8_hall_heuristic"].decide(all_of({p: paired_success(h[f"TTR + {p}"], h[f"Dist + {p}"], "higher",
                                                                  "trips", (f"TTR + {p}", f"Dist + {p}"))
                                                for p in ("OBS", "BRT")}), why=budget),
        faster("t8_hall_ttr_brt_faster", tb, to),
        c["t8_dense_obs_fail"].decide(all_of({m: every(~d[m], "trips", f"{m} failed") for m in (do, to)}),
                                      why=_causes(dense)),
        c["t8_dense_dist_brt_count"].decide(equal_count(int(d[db].sum()), d[db].size, 1, 6, "trips"),
                                            why=_causes(dense)),
        c["t8_dense_only"].decide(all_of({f"{tb} clears every trip": every(d[tb], "trips", tb),
                                            **{f"{m} fails a trip": some(~d[m], "trips", f"{m} failed")
                                               for m in (do, db, to)}}), why=_causes(dense)),
        c["t8_dense_superior"].decide(best_of(d, tb, "higher", _rng(seed, "t8_dense_superior"), "trips",
                                              success=True), why=_causes(dense)),
    ]


def table9_claims(runs: Mapping[tuple[str, int], Sequence], seed: int) -> list[Claim]:
    """Table IX on its trips (``runs``: {(method, humans): runs}; trip k of run r is the same leg from the
    same seed for every method), in each setting: collision-free trips paired (exact McNemar), trip times
    paired over every trip (failed trips included, as the table's completion time counts them)."""
    c = CLAIMS
    fi, fs, obs = HUMAN_METHODS
    settings = sorted({n for _, n in runs})
    trips = {n: {m: _trips(runs, (m, n)) for m in HUMAN_METHODS} for n in settings}
    for cells in trips.values():
        _paired_trips(cells)
    label = {n: f"{n} human" + ("s" if n > 1 else "") for n in settings}
    free = {n: {m: np.array([t.human_contacts == 0 and t.outcome != "collision" for t in ts])
                for m, ts in cells.items()} for n, cells in trips.items()}
    times = {n: {m: np.array([t.time_s for t in ts]) for m, ts in cells.items()} for n, cells in trips.items()}
    per_trip = "time per trip, failed trips included"
    why = "; ".join(f"{label[n]}: {_causes(trips[n])}" for n in settings)

    def each(test):
        return all_of({label[n]: test(n) for n in settings})

    return [
        c["t9_safer_than_obs"].decide(all_of({
            f"{label[n]}, {m} vs {obs}": paired_success(free[n][m], free[n][obs], "higher", "trips (collision-free)",
                                                        (m, obs)) for n in settings for m in (fi, fs)})),
        c["t9_zero_collisions"].decide(all_of({f"{label[n]}, {m}": every(free[n][m], "trips collision-free", m)
                                                 for n in settings for m in (fi, fs)})),
        c["t9_obs_collides"].decide(each(lambda n: some(~free[n][obs], "trips", f"{obs} trips with a collision"))),
        c["t9_obs_fastest"].decide(each(lambda n: best_of(times[n], obs, "lower", _rng(seed, f"t9_obs_fastest/{n}"),
                                                          "trips")), per_trip, why),
        c["t9_fi_longest"].decide(each(lambda n: best_of(times[n], fi, "higher", _rng(seed, f"t9_fi_longest/{n}"),
                                                         "trips")), per_trip, why),
        c["t9_fs_faster"].decide(each(lambda n: paired_difference(times[n][fs], times[n][fi], "lower",
                                                                  _rng(seed, f"t9_fs_faster/{n}"), "trips", (fs, fi))),
                                 per_trip, why),
    ]


# ------------------------------------------------------------------------------------------- Table VII

def table7_claims(rows: Sequence[dict]) -> list[Claim]:
    """Table VII's ratios on our timings of ``calls`` Python calls per component (``total_s``, the paper's own
    method: each function called in a tight loop), with ``TIMING_TOLERANCE`` for single-run timings; our
    compiled look-ups' ratio per state stated beside. Ours: each look-up at least ``TABLE7_TARGET`` times
    cheaper per evaluated state than the paper's."""
    c = CLAIMS
    by = {r["component"]: r for r in rows}
    pairs = {"t7_ttr_ratio": ("TTR heuristic", "Dist heuristic", 3.5),
             "t7_brt_ratio": ("BRT pruner", "OBS pruner", 3.3)}
    out = []
    single = (f"single-run timings on a shared machine, no repeats: ±{TIMING_TOLERANCE:.0%} allowed; a Python call "
              "here is mostly call overhead (the look-ups are compiled), which narrows the ratio")
    for key, (a, b, paper) in pairs.items():
        test = ratio_of_values(by[a]["total_s"], by[b]["total_s"], paper, TIMING_TOLERANCE, (a, b))
        cpu = by[a]["in_search_cpu_per_state_ns"] / by[b]["in_search_cpu_per_state_ns"]
        out.append(c[key].decide(test, f"total seconds of the calls; compiled look-ups per state {cpu:.2f}x",
                                 single))
    direction = {}
    for a, b, _ in pairs.values():  # "more expensive": the interval of the ratio wholly above 1
        ratio = by[a]["total_s"] / by[b]["total_s"]
        lo, hi = ratio * (1 - TIMING_TOLERANCE), ratio * (1 + TIMING_TOLERANCE)
        direction[f"{a} / {b}"] = Test("holds" if lo > 1 else "does not hold" if hi < 1 else "inconclusive",
                                       f"{ratio:.3g} [{lo:.3g}, {hi:.3g}]")
    out.append(c["t7_more_expensive"].decide(all_of(direction), why=single))
    for name in ("TTR heuristic", "BRT pruner"):
        r = by[name]
        ratio = r["paper_per_state_ns"] / r["in_search_cpu_per_state_ns"]
        lo, hi = ratio * (1 - TIMING_TOLERANCE), ratio * (1 + TIMING_TOLERANCE)
        test = Test("holds" if lo > TABLE7_TARGET else "does not hold" if hi < TABLE7_TARGET else "inconclusive",
                    f"paper {r['paper_per_state_ns']:.0f} ns / ours {r['in_search_cpu_per_state_ns']:.1f} ns per "
                    f"state = {ratio:.1f}x [{lo:.1f}, {hi:.1f}] (±{TIMING_TOLERANCE:.0%}, a single timing run)")
        out.append(ours(f"our {name} at least {TABLE7_TARGET:g}x cheaper per evaluated state than the paper's", test,
                        "CPU time of the compiled loop the search runs"))
    return out


# ------------------------------------------------------------------------------------------ Figs. 2, 3

FIG2_NAMES = {"map_ttr_s": "map TTR", "general_ttr_s": "general TTR", "map_dist_s": "map Dist",
              "general_dist_s": "general Dist"}
OUR_LAYOUT = ("our room, robot position and goal are our own (the paper's robot position and speed are blank in its "
              "text), so how the heuristics compare depends on our layout")


# two separately solved TTR grids: on the default grids the forward-only car's general TTR lies at most 0.041 s
# below the reversing car's (numerical error; the bound says never below), tests/test_hj_grids.py
FORWARD_ONLY_TOLERANCE_S = 0.05


def fig2_forward_only_check(reversing: Sequence[dict], forward: Sequence[dict]) -> Claim:
    """Ours, a bound: the forward-only car's controls are a subset of the reversing car's, so its TTR (Eq. 3's
    minimum over fewer controls) can be no lower at any state; it is higher only where backing out beats
    turning round. ``reversing``, ``forward``: the two cars' rows at the same robots. Holds when no TTR of the
    forward-only car lies below the reversing car's by more than ``FORWARD_ONLY_TOLERANCE_S`` (the two grids
    are solved apart); a violation is a solver bug. (Whether the TTR rises when the robot is reversed is the
    paper's claim on its layout: in ours the free path leaves downwards, so it need not.)"""
    below = {f"{fwd['heading']} {FIG2_NAMES[col]}": (fwd[col], rev[col])
             for rev, fwd in zip(reversing, forward, strict=True) for col in ("map_ttr_s", "general_ttr_s")}
    test = every([f >= r - FORWARD_ONLY_TOLERANCE_S for f, r in below.values()], "TTR values")
    detail = "; ".join(f"{k}: {f:.4g} vs reversing car {r:.4g}" for k, (f, r) in below.items())
    return ours("the forward-only car's TTR is never below the reversing car's (its controls are a subset)",
                test, detail + f" (tolerance {FORWARD_ONLY_TOLERANCE_S:g} s)")


def fig2_claims(rows: Sequence[dict], slack_s: float) -> list[Claim]:
    """Sec. VI-A's statements on Fig. 2's values (deterministic: read off the stored grids; no interpolation-
    error bound is measured at these states, so the tolerance is 0). ``rows``: the upward heading, then the
    reversed one (the paper's two rows); ``slack_s``: the goal disc's radius / v_max (the TTR is the time
    to the disc, Dist to its centre)."""
    if len(rows) != 2:
        raise ValueError(f"fig2_claims: two rows (upward, reversed), got {len(rows)}")
    c = CLAIMS
    up, down = rows

    def above(a, b):
        return all_of({r["heading"]: exact_comparison(
            r[a], r[b], "higher", (FIG2_NAMES[a], FIG2_NAMES[b])) for r in rows})

    def rises(col):
        return exact_comparison(down[col], up[col], "higher", (f"{down['heading']}", f"{up['heading']}"))

    disc = f"; the TTR is the time to the goal disc, Dist to its centre ({slack_s:.2f} s apart at v_max)"
    reverse = OUR_LAYOUT
    return [
        c["fig2_ttr_over_dist"].decide(all_of({"map-based": above("map_ttr_s", "map_dist_s"),
                                                 "general": above("general_ttr_s", "general_dist_s")}),
                                       why=OUR_LAYOUT + disc),
        c["fig2_map_over_general"].decide(all_of({"TTR": above("map_ttr_s", "general_ttr_s"),
                                                    "Dist": above("map_dist_s", "general_dist_s")}), why=OUR_LAYOUT),
        c["fig2_general_ttr_over_dist"].decide(all_of({"vs map Dist": above("general_ttr_s", "map_dist_s"),
                                                         "vs general Dist": above("general_ttr_s", "general_dist_s")}),
                                               why=OUR_LAYOUT + disc),
        c["fig2_map_ttr_rises"].decide(rises("map_ttr_s"), why=reverse),
        c["fig2_general_ttr_rises"].decide(rises("general_ttr_s"), why=reverse),
        c["fig2_dist_unchanged"].decide(all_of({FIG2_NAMES[k]: exact_equal(down[k], up[k], (down["heading"],
                                                                                               up["heading"]))
                                                  for k in ("map_dist_s", "general_dist_s")})),
    ]


def fig3_claims(speeds: Sequence[float], unsafe: Sequence[float]) -> list[Claim]:
    """Fig. 3: the BRT's share of the (x, y, θ) grid rises from each speed to the next (deterministic values
    of the stored grid, tolerance 0)."""
    steps = {f"{v0:.2f} -> {v1:.2f} m/s": exact_comparison(u1, u0, "higher", (f"{v1:.2f} m/s", f"{v0:.2f} m/s"))
             for (v0, u0), (v1, u1) in itertools.pairwise(zip(speeds, unsafe, strict=True))}
    return [CLAIMS["fig3_brt_grows"].decide(all_of(steps), "share of the (x, y, θ) grid inside the BRT")]


# ------------------------------------------------------------------------------ sensitivity curves (ours)

def _fmt_axis(v: float) -> str:
    return f"{v:,.0f}" if float(v).is_integer() else f"{v:g}"


def holding_range(values: Sequence[float], holds: Sequence[bool], unit: str) -> str:
    """Where along a sorted axis a check holds: "at every ...", "at none of ...", "at <= x", "at >= x", or the
    list of points."""
    order = sorted(range(len(values)), key=lambda i: values[i])
    v, h = [values[i] for i in order], [holds[i] for i in order]
    span = f"{_fmt_axis(v[0])}-{_fmt_axis(v[-1])} {unit}"
    if all(h):
        return f"holds at every point measured ({span})"
    if not any(h):
        return f"holds at none of the points measured ({span})"
    k = h.index(False) if h[0] else h.index(True)
    if all(h[:k]) and not any(h[k:]):
        return f"holds at <= {_fmt_axis(v[k - 1])} {unit}, not from {_fmt_axis(v[k])} (of {span})"
    if not any(h[:k]) and all(h[k:]):
        return f"holds at >= {_fmt_axis(v[k])} {unit}, not at {_fmt_axis(v[k - 1])} or below (of {span})"
    return f"holds at {', '.join(_fmt_axis(x) for x, ok in zip(v, h, strict=True) if ok)} {unit} only (of {span})"


def _curve(text: str, values: Sequence[float], holds: Sequence[bool], unit: str, counts: str) -> Claim:
    """Ours: a check along a curve holds at every point, at none (does not hold), or at some (inconclusive,
    saying where)."""
    verdict = "holds" if all(holds) else "does not hold" if not any(holds) else "inconclusive"
    return ours(text, Test(verdict, f"{holding_range(values, holds, unit)}; successes {counts}"))


def _successes(rows: Sequence[dict], **match) -> dict[str, int]:
    """method -> successes among ``rows`` matching every key of ``match``."""
    return {r["method"]: r["success"] for r in rows if all(r[k] == v for k, v in match.items())}


def _counts(cells: Sequence[tuple[float, list[dict]]], methods: Sequence[str], n_key: str) -> str:
    """The measured successes behind a verdict: "a / b / c of n at x; ..." per point (methods in order)."""
    parts = [f"{' / '.join(str(_successes(cell)[m]) for m in methods)} of {cell[0][n_key]} at {_fmt_axis(value)}"
             for value, cell in cells]
    return f"{', '.join(methods)}: " + "; ".join(parts)


def budget_claims(rows: Sequence[dict]) -> list[Claim]:
    """Ours: Table VIII's two room patterns (the paper's counts: TTR 9/9 and Dist 2/9 in the hallway, only
    TTR + BRT 6/6 in the Dense Room) at each per-re-plan budget (``hj.sensitivity.budget_rows``). One seeded
    run per point and the sweep keeps its rows' counts only, so each point is judged by the pattern of its
    counts (who clears every trip), not by a paired test; the curve's verdict says where it holds."""
    budgets = sorted({r["budget"] for r in rows})
    do, db, to, tb = ROOM_METHODS
    patterns = (("Long Hallway", "in the Long Hallway TTR clears every trip under both pruners and Dist does not",
                 lambda s, n: s[to] == n and s[tb] == n and s[do] < n and s[db] < n),
                ("Dense Room", "in the Dense Room only TTR + BRT clears every trip",
                 lambda s, n: s[tb] == n and all(s[m] < n for m in (do, db, to))))
    out = []
    for room, text, rule in patterns:
        cells = [(b, [r for r in rows if r["room"] == room and r["budget"] == b]) for b in budgets]
        holds = [rule(_successes(cell), cell[0]["trips"]) for _, cell in cells]
        out.append(_curve(text, budgets, holds, "expansions per re-plan", _counts(cells, ROOM_METHODS, "trips")))
    return out


def loop_claims(rows: Sequence[dict], own: tuple[float, float, float]) -> list[Claim]:
    """Ours: Table VI's two run patterns (the paper's 5/5 vs 0/5 and 0/5 head-on; FI and FS 5/5, OBS not, in
    the Zig-Zag) along each of the three axes (``hj.sensitivity.loop_curve``), judged by the pattern of each
    point's counts."""
    from navlab.hj.sensitivity import LOOP_AXES, loop_curve

    fi, fs, obs = HUMAN_METHODS
    patterns = (("Face-to-Face", "FI-BRT clears every Face-to-Face run, FS-BRT and OBS do not",
                 lambda s, n: s[fi] == n and s[fs] < n and s[obs] < n),
                ("Zig-Zag", "FI-BRT and FS-BRT clear every Zig-Zag run, OBS does not",
                 lambda s, n: s[fi] == n and s[fs] == n and s[obs] < n))
    out = []
    for scenario, text, rule in patterns:
        for axis, unit in LOOP_AXES.items():
            curve = [r for r in loop_curve(rows, axis, own) if r["scenario"] == scenario]
            values = sorted({r[axis] for r in curve})
            if len(values) < 2:
                continue
            cells = [(v, [r for r in curve if r[axis] == v]) for v in values]
            holds = [rule(_successes(cell), cell[0]["runs"]) for _, cell in cells]
            out.append(_curve(f"{text}, along {unit}", values, holds, unit, _counts(cells, HUMAN_METHODS, "runs")))
    return out
