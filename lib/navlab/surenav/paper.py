"""SuReNav's printed results: Table I's numbers and the success rates its text states for Fig. 4.

Fig. 4 is a scatter without printed values, so of it only the success rates stated in the text are
numbers here ("all methods achieve 100% SR except ViPlanner, which records 51%"). The paper's claims
about both, quoted, and the rules that decide them on our episodes are in ``navlab.surenav.claims``.
"""

from __future__ import annotations

CITIES = ("milan", "baltimore", "capitol_hill")

TABLE1 = (
    {"method": "D* Lite", "frechet": 0.429, "relaxation_iou": 0.223},
    {"method": "COA*", "frechet": 0.701, "relaxation_iou": 0.271},
    {"method": "RCR", "frechet": 0.626, "relaxation_iou": 0.259},
    {"method": "SuReNav", "frechet": 0.334, "relaxation_iou": 0.416},
)

FIG4_SR = (
    *({"method": m, "city": c, "sr": 1.0} for m in ("D* Lite", "COA*", "RCR", "SuReNav") for c in CITIES),
    {"method": "ViPlanner^OSRM", "city": "all", "sr": 0.51},
)
