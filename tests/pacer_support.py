"""Test helper shared by the PACER tests: a profile with some ``pacer.data`` keys changed."""

from __future__ import annotations

import dataclasses

from navlab.core.params import Params


def with_pacer_data(params: Params, **changes) -> Params:
    """``params`` with ``pacer.data``'s ``changes`` (e.g. ``train_target="in_view"``), every other key as given."""
    data = dataclasses.replace(params.pacer.data, **changes)
    return dataclasses.replace(params, pacer=dataclasses.replace(params.pacer, data=data))
