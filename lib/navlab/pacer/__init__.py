"""navlab.pacer: PACER (Mao et al., RA-L 2025), preference-conditioned all-terrain costmaps.

Data half (one concept per module; everything seeded from params.yaml ``pacer``):

* ``terrain``: ``load_terrain_bank(data_dir, params.pacer.data) -> TerrainBank`` (seen / unseen /
  synthetic terrain classes from the photographs in data/raw/terrain; ids, realistic ranks, tiers).
* ``layouts``: procedural label layouts (warped Voronoi regions, trails) for BEV images and aerial maps.
* ``bev``: ``render_bev`` (texture fill, lighting, shadows, ground-plane homography, FOV trapezoid),
  ``render_aerial``, ``fov_mask``.
* ``preferences``: orderings (realistic / inverted / random), ``rank_costs`` ((l-1)/(L-1)),
  ``target_costmap``, ``tier_table``; ``IGNORE`` = -1.
* ``context``: ``preference_context(bank, ordering, rng, params) -> ((3n, 2h, w), pairs)`` and
  ``uninformative_context(bank, shown_group, preference, rng, params)`` (terrains of the other group).
* ``datasets``: ``pacer_dataset(params, data_dir, "real" | "shuffled" | "synthetic", split)`` and
  ``evaluation_dataset(params, data_dir, "seen" | "unseen", "realistic" | "inverted", informative)``:
  torch Datasets of dicts ``image, context, costmap, fov_mask, labels, ordering``.
* ``aerial``: ``aerial_maps(params, data_dir, "seen" | "unseen") -> list[AerialMap]`` for Tables I-II.

Metrics live in ``navlab.metrics.cost_tiers`` and ``navlab.metrics.margin_ranking``.
"""
