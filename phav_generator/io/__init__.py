"""Bytes on disk: PNG encoding of the modality arrays and reproducible tar shards.

Nothing here renders or measures: per-frame annotations come from ``render.annotations``.
"""
