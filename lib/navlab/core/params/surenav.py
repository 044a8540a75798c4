"""params.yaml `surenav`: parameters of the surenav track."""

from __future__ import annotations

from navlab.core.params.fields import section
from navlab.core.params.surenav_benchmark import BenchmarkParams
from navlab.core.params.surenav_demos import SuReNavDemosParams
from navlab.core.params.surenav_graph import GraphParams
from navlab.core.params.surenav_model import EstimatorParams, PlannerParams, TrainParams


@section
class SuReNavParams:
    graph: GraphParams
    benchmark: BenchmarkParams
    model: EstimatorParams
    train: TrainParams
    planner: PlannerParams
    demos: SuReNavDemosParams
