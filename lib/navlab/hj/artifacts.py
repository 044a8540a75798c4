"""HJ-search's artefact builders, in dependency order (the provider its manifest names)."""


def artifact_steps() -> list:
    """(stage name, fn(params, data_dir, artifacts_dir)): the value-function grids, the static BRT margins
    (which read the grids' static BRTs) and issue 26's sensitivity points (one per queued experiment:
    ``navlab.pipeline.experiments``)."""
    from navlab.hj.brt_margin import build_brt_margins
    from navlab.hj.grids import build_hj_grids
    from navlab.hj.sweeps import build_sweep

    return [("hj_grids", build_hj_grids), ("hj_margins", build_brt_margins), ("hj_sweep", build_sweep)]
