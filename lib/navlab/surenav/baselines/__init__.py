"""The SuReNav benchmark's baselines and reference policies, each a ``surenav.semi_static.Policy``.

``DStarLitePolicy`` (Koenig & Likhachev 2002), ``ClassOrderedPolicy`` (COA*, Lim & Tsiotras 2021),
``RCRPolicy`` (Kim et al. 2024), ``ExpertPolicy`` (the synthetic expert, a reference row) and
``CostFieldPolicy`` (from-scratch grid A* on a label cost field: the oracle D* Lite is checked against).
"""

from navlab.surenav.baselines.coa_star import ClassOrderedPolicy
from navlab.surenav.baselines.cost_field import CostFieldPolicy
from navlab.surenav.baselines.dstar_lite import DStarLitePolicy
from navlab.surenav.baselines.expert import ExpertPolicy
from navlab.surenav.baselines.rcr import RCRPolicy

__all__ = ["ClassOrderedPolicy", "CostFieldPolicy", "DStarLitePolicy", "ExpertPolicy", "RCRPolicy"]
