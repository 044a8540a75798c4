"""params.yaml `pacer`: parameters of the pacer track."""

from __future__ import annotations

from dataclasses import dataclass

from navlab.core.params.fields import between


@dataclass(frozen=True)
class PacerParams:
    seed: int = between(0)
