"""navlab: cost-aware, human-aligned robot navigation (SuReNav, HJ-search, PACER) on one library."""

__version__ = "0.1.0"
