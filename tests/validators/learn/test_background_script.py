"""docs/measure/background_split.py: the two arms of the background measurement."""

from __future__ import annotations

import numpy as np

from phav_validators.learn.data import Clip
from tests.validators.learn.helpers import measure_script


def test_both_arms_train_on_as_many_clips_and_test_the_same():
    script = measure_script("background_split")
    rgb, flow = np.zeros((1, 2, 2, 3), np.uint8), np.zeros((1, 2, 2, 2), np.float16)
    clips = [Clip(f"v{i:06d}", i % 3, "virtual", rgb, flow,
                  {"actor": (f"m{i % 10}",), "motion": ("walk",), "background": (f"m{(i * 7 + 1) % 10}",) * (i % 2)})
             for i in range(80)]  # fmt: skip
    arms = script.equal_arms(clips, seed=1)
    excluded, kept = arms["exclude"], arms["keep (subsampled)"]
    assert len(excluded.train) == len(kept.train) and excluded.test == kept.test
    assert not excluded.background_seen and excluded.background_dropped > 0
    assert kept.background_seen and set(kept.background_seen) <= set(kept.train)
    assert arms == script.equal_arms(clips, seed=1)  # seeded
