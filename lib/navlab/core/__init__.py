"""Lowest layer: labels, raster frames, params, seeding, io, report files, package data sources."""
