"""The typed schema of params.yaml: the root, assembled from one section module per track."""

from __future__ import annotations

from typing import Annotated, Literal

from navlab.core.params.constraints import cross_section_problems
from navlab.core.params.data import DataParams
from navlab.core.params.fields import PROFILES, between, section
from navlab.core.params.hj import HJParams
from navlab.core.params.pacer import PacerParams
from navlab.core.params.quickstart import QuickstartParams
from navlab.core.params.stack import StackParams
from navlab.core.params.surenav import SuReNavParams

__all__ = ["PROFILES", "Params"]


@section
class Params:
    profile: Literal["smoke", "default", "gpu", "paper"]
    seed: Annotated[int, between(0)]
    data: DataParams
    quickstart: QuickstartParams
    surenav: SuReNavParams
    hj: HJParams
    pacer: PacerParams
    stack: StackParams

    def __post_init__(self):
        """Refuse keys of different sections that do not fit together (constraints.py) at load time, so a
        profile that cannot run stops here, not hours into a stage."""
        problems = cross_section_problems(self)
        if problems:
            from navlab.core.params import ParamsError  # the package imports this module first

            raise ParamsError(problems[0])
