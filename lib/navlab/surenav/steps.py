"""SuReNav's build steps, in dependency order (the providers its manifest names)."""


def data_steps() -> list:
    """The data build's demonstrations (data/demos/): the synthetic expert's paths on the house's maps."""
    from navlab.surenav.experts import build_demos

    return [("demos", build_demos)]


def artifact_steps() -> list:
    """(stage name, fn(params, data_dir, artifacts_dir)): the semi-static episodes, the estimator seeds, the
    context benchmark's demonstrations and estimators."""
    from navlab.surenav.artifacts import artifact_steps as estimator_steps
    from navlab.surenav.context.artifacts import artifact_steps as context_steps
    from navlab.surenav.episodes import build_episodes

    return [("surenav_episodes", build_episodes), *estimator_steps(), *context_steps()]
