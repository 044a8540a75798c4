"""params.yaml `hj`: parameters of the hj track."""

from __future__ import annotations

from dataclasses import dataclass

from navlab.core.params.fields import between


@dataclass(frozen=True)
class HJParams:
    seed: int = between(0)
