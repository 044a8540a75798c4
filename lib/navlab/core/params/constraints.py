"""Keys of different params.yaml sections that must fit together, checked when a profile is loaded.

A single key's type and range is checked by its section's schema; these rules tie keys to each other
(an aerial map is cut from a SuReNav test map, so it cannot cover more than one). They run inside
``load_params`` (``Params.__post_init__``) so that a profile that cannot run stops at its first line
with the key and the fix, not hours into a stage: the ``gpu`` profile once trained PACER for ~2 h and
then stopped at the navigation tables, its 512-px aerial maps larger than the 500-px test maps.

Each rule restates the check of the code that would fail at run time (named beside it); tests/
test_params_check.py pins each pair to agree. This module lives with the section declarations, which
code fingerprints leave out (navlab.core.fingerprint): it only accepts or refuses a profile and never
changes a value, so no result depends on it.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from navlab.core.params.schema import Params


def surenav_test_map_px(params: Params) -> int:
    """Pixels per side of a SuReNav test map: a real-city tile, cut as navlab.maps.tiles.cut_tiles does."""
    m = params.data.maps
    return round(m.tile_size_m / m.resolution_m)


def cross_section_problems(params: Params) -> list[str]:
    """One line per rule ``params`` breaks, naming the key, its value and the fix; [] when all fit."""
    d, p, problems = params.pacer.data, params.pacer, []
    side = surenav_test_map_px(params)
    cut = -(-d.aerial.size // d.layout.street_zoom)  # map pixels an aerial map covers
    if d.aerial.layout == "surenav" and cut > side:  # pacer.aerial.semantic_map_regions refuses it
        problems.append(f"pacer.data.aerial.size = {d.aerial.size} at pacer.data.layout.street_zoom = "
                        f"{d.layout.street_zoom} covers {cut} px, more than the {side}-px SuReNav test maps it is "
                        f"cut from (data.maps.tile_size_m / resolution_m = {params.data.maps.tile_size_m:g} / "
                        f"{params.data.maps.resolution_m:g}); the navigation tables would stop with a ValueError "
                        f"after training; use a size <= {side * d.layout.street_zoom}")
    if d.image_size >= d.aerial.size:  # pacer.evaluate.costmap_over_map reflect-pads the map by one BEV window
        problems.append(f"pacer.data.image_size = {d.image_size} must be smaller than pacer.data.aerial.size = "
                        f"{d.aerial.size} (the aerial costmap reflect-pads the map by one BEV window)")
    if p.baselines.patch_size > d.image_size:  # pacer.baselines.patches.sample_patches cuts them from BEV images
        problems.append(f"pacer.baselines.patch_size = {p.baselines.patch_size} exceeds the BEV image "
                        f"pacer.data.image_size = {d.image_size}; lower it")
    batches = [("pacer.train.batch_size", p.train.batch_size, "pacer.train.examples_per_epoch",
                p.train.examples_per_epoch),
               ("pacer.train.val_examples", p.train.val_examples, "pacer.data.sizes.val", d.sizes.val),
               ("pacer.baselines.sterling.batch_size", p.baselines.sterling.batch_size,
                "pacer.baselines.sterling.patches_per_epoch", p.baselines.sterling.patches_per_epoch),
               ("pacer.baselines.classifier.batch_size", p.baselines.classifier.batch_size,
                "pacer.baselines.classifier.patches_per_epoch", p.baselines.classifier.patches_per_epoch)]
    for key, value, of_key, of in batches:  # never happens as stated: the larger number is a typo
        if value > of:
            problems.append(f"{key} = {value} exceeds {of_key} = {of}, which it is drawn from; lower it")
    robot = params.hj.grids.robot
    if robot.v_min < -robot.v_max:  # search.dubins_lattice.LatticeSpec and reach.dynamics.DubinsCar4D refuse it
        problems.append(f"hj.grids.robot.v_min = {robot.v_min:g} is below -v_max = {-robot.v_max:g}: the heuristics "
                        f"and the human BRT's off-grid bound assume |v| <= v_max; raise v_min")
    return problems
