"""Where the catalogue motions move (``phav_spec.motion_activity``, ``motion.start: active``)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

import phav_spec.motion_activity
from phav_generator.motion.activity import MOVING_SPEED_M_S, approach, fastest_point_speed, moving_spans, table_source
from phav_generator.motion.library import BUILTIN_MOTIONS
from phav_spec.motion_activity import APPROACHES, MOVING_SPANS
from phav_spec.motions import MOTIONS


def test_the_shipped_table_is_what_the_motions_compute():
    """The spec's table is data written from the engine; an edited motion must rewrite it
    (``python -m phav_generator.motion.activity > phav_spec/motion_activity.py``)."""
    assert Path(phav_spec.motion_activity.__file__).read_text(encoding="utf-8") == table_source()
    assert list(MOVING_SPANS) == list(MOTIONS.names)


def test_standing_still_never_moves_and_a_walk_always_does():
    assert moving_spans(BUILTIN_MOTIONS["idle_standing_01"]) == ()
    walk = BUILTIN_MOTIONS["walk_forward_01"]
    assert moving_spans(walk) == ((0.0, walk.length_s),)


def test_a_dive_moves_for_a_part_of_its_take_only():
    dive = BUILTIN_MOTIONS["dive_onto_floor_artist_01"]
    speed = fastest_point_speed(dive)
    spans = moving_spans(dive)
    assert len(spans) >= 1 and 0.0 < spans[0][0] and spans[-1][1] < dive.length_s
    moving = sum(b - a for a, b in spans)
    assert 0.5 < moving < 0.6 * dive.length_s
    # Inside a span the body is fast somewhere; long pauses between spans are slow throughout.
    inside = [i for i in range(len(speed)) if any(a <= i / 10 < b for a, b in spans)]
    assert speed[inside].max() > 2.0 and np.mean(speed[inside] > MOVING_SPEED_M_S) > 0.8


def test_spans_are_ordered_disjoint_and_within_the_take():
    for name, spans in MOVING_SPANS.items():
        ends = [t for span in spans for t in span]
        assert ends == sorted(ends), name
        assert all(b > a for a, b in spans) and (not ends or (ends[0] >= 0 and ends[-1] <= MOTIONS[name].length_s))


def test_a_take_that_walks_up_to_a_stop_is_an_approach_and_a_walk_or_a_gesture_is_not():
    """The walk and bump walks 1.2 m/s, slows to a stop at 4.3–4.6 s and steps back: its
    approach ends at 4.6 s, a little under 1.2 m/s over it. A walk never pauses; a hand
    brushing hair pauses between strokes but the body stands."""
    end, pace = approach(BUILTIN_MOTIONS["walk_bump_into_someone_01"])
    assert end == 4.6 and 1.1 < pace < 1.2
    assert approach(BUILTIN_MOTIONS["walk_forward_01"]) is None
    assert (
        len(MOVING_SPANS["brush_hair_left_hand_01"]) > 1
        and approach(BUILTIN_MOTIONS["brush_hair_left_hand_01"]) is None
    )
    assert set(APPROACHES) <= set(MOVING_SPANS) and "walk_bump_into_someone_01" in APPROACHES
