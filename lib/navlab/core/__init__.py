"""Lowest layer: labels, raster frames, params, seeding, io."""
