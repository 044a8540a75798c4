"""Baselines of PACER's Tables I-II: a semantic patch classifier and STERLING-style representation learning."""
