"""The motion catalogue and the regex-driven θ_AB table (paper, "Base motions")."""

from __future__ import annotations

import math
import re

import numpy as np
import pytest

import phav_spec.motions as motions_module
from phav_spec.motions import (
    ACTIVE_SHARE,
    MEETING_GAP_M,
    MEETING_LEAD_S,
    MOTIONS,
    Motion,
    active_start,
    meeting_start,
    moving_share,
    theta_ab,
)
from phav_spec.theta import load_preset
from phav_spec.vocab import ACTIONS, Registry

# Written by hand from reading the descriptions, not computed from the regexes: a regex edit
# that changes what an action can draw from must show up here as a deliberate change.
_WALKING = {
    "walk_forward_01", "walk_forward_turn_left_01", "walk_circle_01",
    "walk_looking_at_phone_01", "walk_distracted_01", "walk_side_by_side_01",
    "walk_hand_in_hand_01", "walk_heel_to_toe_01", "walk_balance_beam_01",
    "walk_backwards_01", "walk_backward_look_back_01", "walk_injured_knee_01",
    "walk_with_limp_01", "walk_up_to_friend_hug_01", "walk_bump_into_someone_01",
    "walk_dizzy_01", "walk_stop_wave_01", "walk_pick_up_litter_01",
}  # fmt: skip
_RUNNING = {
    "run_forward_01", "jog_circle_01", "jog_slow_tired_01", "sprint_short_01",
    "run_away_panic_01", "sprint_away_01", "run_up_stairs_01",
}  # fmt: skip

EXPECTED: dict[str, set[str]] = {
    "brush_hair": {
        "comb_hair_right_hand_01", "brush_hair_left_hand_01", "brush_long_hair_seated_01",
    },
    "catch": {"catch_ball_front_01", "catch_ball_step_back_01", "play_catch_partner_01"},
    "clap": {"clap_rhythm_01", "clap_once_01", "clap_above_head_01", "applause_cheer_01"},
    "climb_stairs": {
        "climb_up_stairs_01", "climb_staircase_handrail_01", "go_down_stairs_01",
        "run_up_stairs_01",
    },
    "golf": {"golf_full_swing_01", "golf_putt_01", "golf_chip_practice_01"},
    "jump": {
        "jump_forward_both_feet_01", "jump_vertical_01", "jumping_jacks_01",
        "standing_long_jump_01", "jump_rope_01",
    },
    "kick_ball": {"kick_soccer_ball_01", "dribble_kick_ball_01", "penalty_kick_01"},
    "push": {"push_heavy_box_01", "push_shopping_cart_01", "push_open_door_01"},
    "pick": {"walk_pick_up_litter_01", "pick_up_box_01", "pick_up_object_floor_01"},
    "pour": {"pour_water_bottle_cup_01", "pour_from_pitcher_01", "pour_cereal_bowl_01"},
    "pull_up": {"pull_ups_bar_01", "chin_ups_01", "hang_pull_ups_01"},
    "run": _RUNNING,
    "shoot_ball": {
        "basketball_set_shot_01", "basketball_jump_shot_01", "basketball_free_throw_01",
    },
    "shoot_bow": {"archery_draw_release_01", "archery_nock_aim_01", "longbow_kneeling_01"},
    "shoot_gun": {"pistol_two_hands_01", "rifle_shoulder_standing_01", "handgun_walking_01"},
    "sit": {"sit_down_chair_01", "sit_floor_cross_legged_01", "sit_down_stand_up_01"},
    "stand": {
        "standing_long_jump_01", "sit_down_stand_up_01", "stand_up_from_chair_01",
        "get_up_from_floor_01", "rise_from_kneeling_01", "forward_roll_stand_up_01",
    },
    "swing_baseball": {
        "baseball_swing_right_01", "baseball_batting_stance_01", "bat_practice_swings_01",
    },
    "throw": {"play_catch_partner_01", "throw_baseball_overhand_01", "throw_frisbee_01"},
    "walk": _WALKING,
    "wave": {
        "walk_stop_wave_01", "wave_hello_right_01", "wave_goodbye_both_arms_01",
        "waving_across_street_01", "wave_once_01",
    },
    "car_hit": _WALKING | _RUNNING | {
        "cross_street_look_01", "wait_bus_stop_01", "clap_rhythm_01", "clap_once_01",
        "applause_cheer_01",
    },
    "crawl": {"crawl_hands_and_knees_01", "army_crawl_01", "crawling_all_fours_01"},
    "dive_floor": {"dive_onto_floor_artist_01", "drop_to_ground_prone_01", "fall_to_ground_01"},
    "flee": {
        "run_away_panic_01", "sprint_away_01", "turn_escape_running_01", "startled_flee_01",
    },
    "hop": {"hop_one_foot_01", "hopping_left_leg_01", "bunny_hops_01", "hop_once_01"},
    "leg_split": {"split_slide_stretch_01", "front_split_floor_01", "side_split_warm_up_01"},
    "limp": {"walk_injured_knee_01", "walk_with_limp_01", "limp_right_leg_01"},
    "moonwalk": {"walk_backwards_01", "walk_backward_look_back_01", "moonwalk_artist_01"},
    "stagger": {"walk_dizzy_01", "stagger_drunk_01", "stumble_recover_01"},
    "surrender": {
        "raise_both_hands_hold_01", "surrender_kneel_artist_01", "hands_up_behind_head_01",
    },
    "walking_hug": {"walk_up_to_friend_hug_01", "hug_pat_back_01", "greet_friend_hug_01"},
    "walk_holding_hands": {
        "walk_side_by_side_01", "walk_hand_in_hand_01", "stroll_park_01",
        "holding_hands_walking_01",
    },
    "walk_the_line": {"walk_heel_to_toe_01", "walk_balance_beam_01", "tightrope_walk_01"},
    "bump_into_each_other": {
        "walk_looking_at_phone_01", "walk_distracted_01", "walk_bump_into_someone_01",
        "collide_shoulder_passerby_01", "crowd_dodge_01",
    },
}  # fmt: skip

_SNAKE = re.compile(r"^[a-z][a-z0-9]*(_[a-z0-9]+)*$")

# The phav-v1 preset's regexes: the θ whose θ_AB the hand-written matrix below pins down.
PHAV_V1_MOTION_REGEX = load_preset("phav-v1").theta_ab.regex


def _matched(action: str) -> list[Motion]:
    row = theta_ab(PHAV_V1_MOTION_REGEX)[ACTIONS.index(action)]
    return [MOTIONS[name] for name, hit in zip(MOTIONS.names, row, strict=True) if hit]


def test_expected_covers_every_action_with_known_motions():
    assert set(EXPECTED) == set(ACTIONS.names)
    assert set(PHAV_V1_MOTION_REGEX) == set(ACTIONS.names)
    for action, names in EXPECTED.items():
        unknown = names - set(MOTIONS.names)
        assert not unknown, f"{action}: unknown motions {sorted(unknown)}"


def test_theta_ab_equals_hand_written_matrix():
    theta = theta_ab(PHAV_V1_MOTION_REGEX)
    assert theta.shape == (len(ACTIONS), len(MOTIONS))
    assert theta.dtype == np.float64
    assert set(np.unique(theta)) <= {0.0, 1.0}
    expected = np.zeros_like(theta)
    for action, names in EXPECTED.items():
        for name in names:
            expected[ACTIONS.index(action), MOTIONS.index(name)] = 1.0
    diffs = [
        (ACTIONS.names[a], MOTIONS.names[b], "matched" if theta[a, b] else "missed")
        for a, b in zip(*np.nonzero(theta != expected), strict=True)
    ]
    assert not diffs, f"θ_AB differs from EXPECTED at (action, motion, regex did): {diffs}"


@pytest.mark.parametrize("action", ACTIONS.names)
def test_every_action_has_three_long_enough_motions(action):
    long_enough = [m for m in _matched(action) if m.length_s >= 1.0]
    assert len(long_enough) >= 3, f"{action}: only {[m.name for m in long_enough]}"


@pytest.mark.parametrize("action", [a for a in ACTIONS.names if a != "car_hit"])
def test_regexes_are_specific(action):
    assert len(_matched(action)) < len(MOTIONS) / 2


def test_car_hit_uses_walking_running_and_other_motions():
    descriptions = [m.description for m in _matched("car_hit")]
    walking = [d for d in descriptions if re.search(r"\bwalk(s|ing)?\b", d)]
    running = [d for d in descriptions if re.search(r"\b(run|jog|sprint)\w*\b", d)]
    other = [d for d in descriptions if d not in walking and d not in running]
    assert walking and running and other


def test_word_boundaries_keep_distractors_out():
    theta = theta_ab(PHAV_V1_MOTION_REGEX)

    def hit(action: str, motion: str) -> bool:
        return bool(theta[ACTIONS.index(action), MOTIONS.index(motion)])

    assert not hit("run", "prune_hedge_01")
    assert not hit("hop", "hip_hop_dance_01")
    assert not hit("push", "push_ups_01")
    assert not hit("sit", "sit_ups_mat_01")
    assert not hit("jump", "basketball_jump_shot_01")
    assert not hit("shoot_bow", "take_a_bow_01")
    assert not hit("kick_ball", "martial_front_kick_01")
    assert not hit("shoot_ball", "dribble_basketball_01")


def test_names_unique_and_snake_case():
    names = [m.name for m in (MOTIONS[n] for n in MOTIONS.names)]
    assert names == list(MOTIONS.names)
    assert len(set(names)) == len(names)
    for name in names:
        assert _SNAKE.match(name), name


def test_descriptions_unique_lowercase_and_not_action_labels():
    descriptions = [MOTIONS[n].description for n in MOTIONS.names]
    assert len(set(descriptions)) == len(descriptions)
    labels = {a.replace("_", " ") for a in ACTIONS.names}
    for d in descriptions:
        assert d == d.lower() and d.strip() == d and d
        assert d not in labels, d


def test_catalogue_size_sources_and_lengths():
    motions = [MOTIONS[n] for n in MOTIONS.names]
    assert 90 <= len(motions) <= 130
    assert sum(m.source == "artist" for m in motions) == 3
    assert {m.source for m in motions} == {"mocap_style", "artist"}
    lengths = np.array([m.length_s for m in motions])
    assert all(math.isfinite(x) and x > 0 for x in lengths)
    assert (lengths < 1.0).sum() >= 3
    assert (lengths < 10.0).mean() >= 0.25
    assert (lengths >= 10.0).sum() >= 1


def test_motion_rejects_bad_fields():
    with pytest.raises(ValueError):
        Motion("x", "walk", 0.0, "mocap_style")
    with pytest.raises(ValueError):
        Motion("x", "walk", float("nan"), "mocap_style")
    with pytest.raises(ValueError):
        Motion("x", "walk", 1.0, "vicon")
    with pytest.raises(ValueError):
        Motion("x", "Walk", 1.0, "mocap_style")


def test_theta_ab_unknown_action_raises_key_error():
    with pytest.raises(KeyError, match="not_an_action"):
        theta_ab({"not_an_action": "walk"})


def test_theta_ab_bad_pattern_names_the_action():
    with pytest.raises(ValueError, match="golf"):
        theta_ab({"walk": "walk", "golf": "(unclosed"})


def test_theta_ab_omitted_actions_get_zero_rows():
    theta = theta_ab({"golf": r"\bgolf\b"})
    assert theta.shape == (len(ACTIONS), len(MOTIONS))
    golf = ACTIONS.index("golf")
    assert theta[golf].sum() == 3
    assert np.delete(theta, golf, axis=0).sum() == 0
    assert not theta_ab({}).any()


def test_theta_ab_uses_search_without_flags_on_a_custom_registry():
    motions = Registry(
        "motion",
        (
            ("a", Motion("a", "slow walk in the rain", 5.0, "mocap_style")),
            ("b", Motion("b", "jog", 5.0, "mocap_style")),
        ),
    )
    theta = theta_ab({"walk": "walk", "run": "JOG"}, motions)
    assert theta.shape == (len(ACTIONS), 2)
    assert theta[ACTIONS.index("walk")].tolist() == [1.0, 0.0]
    assert theta[ACTIONS.index("run")].tolist() == [0.0, 0.0]


def test_moving_share_is_the_covered_part_of_each_window():
    spans = ((1.0, 2.0), (3.0, 3.5))
    share = moving_share(spans, np.array([0.0, 0.5, 1.0, 2.5, 4.0]), 1.0)
    assert np.allclose(share, [0.0, 0.5, 1.0, 0.5, 0.0])


def test_an_active_start_falls_where_the_take_moves(monkeypatch):
    spans = ((6.0, 7.5),)
    table = dict(motions_module.MOVING_SPANS, probe=spans)
    monkeypatch.setattr(motions_module, "MOVING_SPANS", table)
    starts = [active_start("probe", 10.0, 1.5, u) for u in np.linspace(0.0, 0.999, 50)]
    assert starts == sorted(starts)
    # Every window keeps at least 3/4 of the best window's moving time (1.5 s, all of it).
    share = moving_share(spans, np.array(starts), 1.5)
    assert share.min() >= ACTIVE_SHARE - 1e-9 and 5.6 < min(starts) and max(starts) < 6.4
    assert all(0.0 <= s <= 10.0 - 1.5 for s in starts)


def test_an_unknown_or_still_take_starts_uniformly(monkeypatch):
    table = dict(motions_module.MOVING_SPANS, still=())
    monkeypatch.setattr(motions_module, "MOVING_SPANS", table)
    for name in ("still", "a_users_clip"):
        assert active_start(name, 10.0, 2.0, 0.5) == 4.0
    assert active_start("still", 1.0, 2.0, 0.7) == 0.0  # the window is longer than the take


def test_two_people_walking_into_each_other_meet_as_their_take_stops():
    """At the take's pace from the start given, each covers half the distance less the
    chests' gap by MEETING_LEAD_S before the take's stop; a window still fits the take;
    a walk that never stops, or a window too short to reach the meeting, has no such start."""
    name = "walk_bump_into_someone_01"
    stop, pace = motions_module.APPROACHES[name]
    length = MOTIONS[name].length_s
    for distance in (4.0, 6.0, 8.0):
        start = meeting_start(name, length, 5.0, distance)
        met = start + (distance - MEETING_GAP_M) / (2.0 * pace)
        assert met == pytest.approx(stop - MEETING_LEAD_S)
    assert meeting_start(name, length, 5.0, 40.0) == 0.0  # too far to meet: from the take's start
    assert meeting_start(name, length, 2.0, 8.0) is None  # 2 s cannot hold a 3.3 s walk: θ's start
    assert meeting_start(name, length, length - 0.5, 4.0) == 0.5  # the window fits
    assert meeting_start("walk_forward_01", MOTIONS["walk_forward_01"].length_s, 3.0, 6.0) is None
