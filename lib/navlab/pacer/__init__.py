"""navlab.pacer: PACER (Mao et al., RA-L 2025), preference-conditioned all-terrain costmaps.

Data half (one concept per module; everything seeded from params.yaml ``pacer``):

* ``terrain``: ``load_terrain_bank(data_dir, params.pacer.data) -> TerrainBank`` (seen / unseen /
  synthetic terrain classes from the photographs in data/raw/terrain or terrain_photos/; ids, realistic ranks).
* ``layouts``: procedural label layouts (warped Voronoi regions, trails) for BEV images and aerial maps.
* ``bev``: ``render_bev`` (texture fill, lighting, shadows, ground-plane homography, FOV trapezoid),
  ``render_aerial``, ``fov_mask``.
* ``preferences``: orderings (realistic / inverted / random), ``rank_costs`` ((l-1)/(L-1)),
  ``target_costmap``, ``environment_tiers`` (low / medium / high thirds of one environment's ordering);
  ``IGNORE`` = -1.
* ``context``: ``preference_context(bank, ordering, rng, params, cover) -> ((3n, 2h, w), pairs)`` (pairs
  naming every terrain of ``cover`` where n allows), ``superset_terrains`` (in view + others, as deployed)
  and ``uninformative_context(bank, shown_group, preference, rng, params)`` (terrains of the other group).
* ``datasets``: ``pacer_dataset(params, data_dir, "real" | "shuffled" | "synthetic", split)`` and
  ``evaluation_dataset(params, data_dir, "seen" | "unseen", "realistic" | "inverted", informative)``:
  torch Datasets of dicts ``image, context, costmap, fov_mask, labels, ordering``.
* ``aerial``: ``aerial_maps(params, data_dir, "seen" | "unseen") -> list[AerialMap]`` for Tables I-II.

Model half: ``model``, ``loss`` (masked BCE, entropy floor), ``train`` (three phases, cosine LR, early
stopping on the selection score keeping the best checkpoint), ``checkpoints``, ``baselines`` (STERLING-style,
semantic classifier), ``artifacts`` (the DVC stage builders).

Measurement: ``evaluate`` (stitched BEV windows, window oracle, A*), ``experiments`` (Tables I-V and the
``context_following`` report, with bootstrap intervals and the uniform / window-oracle reference rows),
``claims`` (the paper's numbers and the checks of its claims), ``margin_ranking`` (Table V's metric, used by
PACER alone). Metrics shared with the other tracks live in ``navlab.metrics.cost_tiers`` and
``navlab.metrics.intervals``.
"""
