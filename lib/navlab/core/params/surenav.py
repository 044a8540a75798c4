"""params.yaml `surenav`: parameters of the surenav track."""

from __future__ import annotations

from dataclasses import dataclass

from navlab.core.params.fields import between


@dataclass(frozen=True)
class SuReNavParams:
    seed: int = between(0)
