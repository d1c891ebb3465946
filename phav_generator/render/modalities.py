"""A rendered frame → the six per-frame modalities of a PHAV sample, as arrays.

Colours of labels come from lookup tables: the pixel-class palette (``phav_spec.vocab``) and
the instance colours (``phav_spec.encoding.instance_rgb``); depth and flow use the spec's
encoders. Writers turn these arrays into PNGs; nothing here touches files.
"""

from __future__ import annotations

import numpy as np

from phav_generator.render.gl import Frame
from phav_spec.encoding import MAX_PERSON_ID, encode_depth, encode_flow, instance_rgb
from phav_spec.vocab import PIXEL_CLASSES


def _palette() -> np.ndarray:
    lut = np.zeros((max(PIXEL_CLASSES[n].class_id for n in PIXEL_CLASSES.names) + 1, 3), dtype=np.uint8)
    for name in PIXEL_CLASSES.names:
        c = PIXEL_CLASSES[name]
        lut[c.class_id] = c.rgb
    return lut


def _instances() -> np.ndarray:
    """Row i: the colour of instance value i (person id i − 1); row 0 black."""
    lut = np.zeros((MAX_PERSON_ID + 2, 3), dtype=np.uint8)
    for person_id in range(MAX_PERSON_ID + 1):
        lut[person_id + 1] = instance_rgb(person_id)
    return lut


PALETTE = _palette()
INSTANCE_COLOURS = _instances()


def encode_frame(frame: Frame) -> dict[str, np.ndarray]:
    """The six modalities of one frame, keyed by ``phav_spec.encoding.MODALITIES`` names.

    ``rgb`` is the post-processed colour (the raw colour when the frame has none).
    """
    if frame.instance.max(initial=0) >= len(INSTANCE_COLOURS):
        raise ValueError(f"instance value {int(frame.instance.max())} has no colour (person ids ≤ {MAX_PERSON_ID})")
    return {
        "rgb": frame.colour if frame.rgb is None else frame.rgb,
        "raw_rgb": frame.colour,
        # np.take reads a lookup table several times faster than fancy indexing.
        "semantic": np.take(PALETTE, frame.class_id, axis=0),
        "instance": np.take(INSTANCE_COLOURS, frame.instance, axis=0),
        "depth": encode_depth(frame.depth_m),
        "flow": encode_flow(frame.flow[..., 0], frame.flow[..., 1], frame.flow_valid),
    }
