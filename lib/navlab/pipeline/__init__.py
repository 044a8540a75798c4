"""The pipeline layer: package downloads, the data snapshot, papermill runs and report files.

It sits above the method layers (it builds data/ with their generators) and below ``cli``; ``core``
stays the small pure bottom layer that every layer imports.
"""
