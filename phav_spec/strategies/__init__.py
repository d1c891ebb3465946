"""Public hypothesis strategies for θ, recipes and encoded frames.

Our suite uses them, and users property-test their own loaders with them. They reach the
hard cases on purpose (degenerate and wrapped triangles, single-value supports, zero rows,
empty datasets, saturated encodings) and label each with ``hypothesis.event``.
"""

from phav_spec.strategies.frames import (
    depth_codes,
    depth_maps_m,
    flow_codes,
    flow_fields,
    frame_shapes,
)
from phav_spec.strategies.model import recipe_lists, recipes, thetas

__all__ = [
    "depth_codes",
    "depth_maps_m",
    "flow_codes",
    "flow_fields",
    "frame_shapes",
    "recipe_lists",
    "recipes",
    "thetas",
]
