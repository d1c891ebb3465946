"""The catalogue of atomic base motions B and the regex-driven action → motion table θ_AB.

The paper draws each video's base motion from 859 CMU MoCap takes plus 3 motions designed
by animation artists, and decides which motions may serve an action purely by matching a
list of regular expressions against each motion's short text description (paper, "Base
motions"):

    (θ_AB)_ab = 1 if match(regex_a, desc_b) else 0.

No CMU MoCap download is possible here, so this module declares a smaller catalogue of
procedural stand-ins. Each entry plays the part of one MoCap take: it has a stable name, a
free-text description written the way the CMU database describes its takes ("walk forward,
turn left, stop", "jog in a circle"), and the natural length of the take in seconds, which
the minimum-length weighting P(B = b | T_min) uses. Three entries stand for the paper's
artist-designed motions (annotated with text for the same reason the paper gives: so that
Eq. θ_AB can find them). The animation curves behind each name (parametric gait, arm, hand
and torso cycles) are built later by the generator; this module holds only the searchable
metadata, so the selection logic is exactly the paper's and a user bringing real MoCap files
with their descriptions can reuse it unchanged.

Descriptions are lowercase and describe what the body does, not the action label, so the
regular expressions of θ (``theta_ab.regex`` in a θ file) do real work: one motion may serve several
actions (a walking take is also a valid base for ``car_hit``), and distractor takes such as
"do push-ups on the floor" or "hip hop dance, freestyle" must not be picked up by ``push``
or ``hop``.
"""

from __future__ import annotations

import math
import re
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from phav_spec.motion_activity import APPROACHES, MOVING_SPANS
from phav_spec.vocab import ACTIONS, Registry

#: Where a motion comes from: a procedural stand-in for a CMU MoCap take, or one of the three
#: artist-designed motions of the paper.
MOTION_SOURCES: tuple[str, ...] = ("mocap_style", "artist")


@dataclass(frozen=True)
class Motion:
    """One atomic base motion: a stable name, a CMU-style description and its length."""

    name: str
    description: str
    length_s: float
    source: str

    def __post_init__(self) -> None:
        if self.source not in MOTION_SOURCES:
            raise ValueError(f"motion {self.name!r}: unknown source {self.source!r}")
        if not (math.isfinite(self.length_s) and self.length_s > 0):
            raise ValueError(f"motion {self.name!r}: length must be finite and > 0")
        if not self.description or self.description != self.description.lower():
            raise ValueError(f"motion {self.name!r}: description must be non-empty lowercase")


_M = "mocap_style"
_A = "artist"

# (name, description, natural length in seconds, source). Grouped by what the take shows;
# the order is the column order of θ_AB.
_CATALOGUE: tuple[tuple[str, str, float, str], ...] = (
    # Walking.
    ("walk_forward_01", "walk forward at a normal pace", 12.4, _M),
    ("walk_forward_turn_left_01", "walk forward, turn left, stop", 15.0, _M),
    ("walk_circle_01", "walk in a circle", 28.0, _M),
    ("walk_looking_at_phone_01", "walk while looking at phone", 19.2, _M),
    ("walk_distracted_01", "walk distracted, head turned to the side", 17.6, _M),
    ("walk_side_by_side_01", "walk side by side with a partner", 30.4, _M),
    ("walk_hand_in_hand_01", "walk hand in hand, relaxed pace", 27.0, _M),
    ("walk_heel_to_toe_01", "walk heel to toe along a straight line", 20.8, _M),
    ("walk_balance_beam_01", "walk on a balance beam, arms out to the side", 24.0, _M),
    ("walk_backwards_01", "walk backwards slowly", 14.4, _M),
    ("walk_backward_look_back_01", "walking backward, looking over shoulder", 16.2, _M),
    ("walk_injured_knee_01", "walk with injured left knee", 22.0, _M),
    ("walk_with_limp_01", "walking with a limp, slow", 27.6, _M),
    ("walk_up_to_friend_hug_01", "walk up to a friend and hug", 13.0, _M),
    ("walk_bump_into_someone_01", "walk and bump into someone, step back", 10.8, _M),
    ("walk_dizzy_01", "walk dizzy, swaying side to side", 18.6, _M),
    ("walk_stop_wave_01", "walk, stop and wave hello", 15.8, _M),
    ("walk_pick_up_litter_01", "walk, pick up litter, continue walking", 25.4, _M),
    # Running, jogging, sprinting.
    ("run_forward_01", "run forward at a steady pace", 11.6, _M),
    ("jog_circle_01", "jog in a circle", 33.0, _M),
    ("jog_slow_tired_01", "jog slowly, tired", 41.0, _M),
    ("sprint_short_01", "sprint a short distance, then slow down", 9.2, _M),
    ("run_away_panic_01", "run away in panic, look back over shoulder", 14.2, _M),
    ("sprint_away_01", "sprint away from danger", 10.4, _M),
    ("turn_escape_running_01", "turn around and escape, running hard", 12.0, _M),
    ("startled_flee_01", "startled, flee from an attacker", 8.8, _M),
    # Stairs and climbing.
    ("climb_up_stairs_01", "climb up stairs", 16.0, _M),
    ("climb_staircase_handrail_01", "climb up the staircase, holding handrail", 22.4, _M),
    ("go_down_stairs_01", "go down stairs slowly", 18.8, _M),
    ("run_up_stairs_01", "run up stairs two at a time", 9.6, _M),
    # Hair.
    ("comb_hair_right_hand_01", "comb hair with right hand while standing", 18.0, _M),
    ("brush_hair_left_hand_01", "brush hair with left hand, slow strokes", 25.0, _M),
    ("brush_long_hair_seated_01", "brushing long hair while seated", 30.0, _M),
    # Catching and throwing.
    ("catch_ball_front_01", "catch a ball thrown from the front", 6.4, _M),
    ("catch_ball_step_back_01", "catch ball with both hands, step back", 5.8, _M),
    ("play_catch_partner_01", "play catch: throw the ball to a partner and catch it", 36.0, _M),
    ("throw_baseball_overhand_01", "throw a baseball overhand", 5.0, _M),
    ("throw_frisbee_01", "throw a frisbee, backhand", 5.6, _M),
    # Clapping and waving.
    ("clap_rhythm_01", "clap hands rhythmically", 17.0, _M),
    ("clap_once_01", "clap hands once", 0.6, _M),
    ("clap_above_head_01", "clapping above head", 10.6, _M),
    ("applause_cheer_01", "applause, clapping hands and cheering", 13.4, _M),
    ("wave_hello_right_01", "wave hello with right hand", 6.0, _M),
    ("wave_goodbye_both_arms_01", "wave goodbye with both arms above head", 9.6, _M),
    ("waving_across_street_01", "waving to a friend across the street", 11.2, _M),
    ("wave_once_01", "wave once, quick", 0.8, _M),
    # Sports.
    ("golf_full_swing_01", "swing golf club, full swing", 8.0, _M),
    ("golf_putt_01", "golf putt, short stroke", 7.0, _M),
    ("golf_chip_practice_01", "golf chip shot after two practice swings", 14.4, _M),
    ("kick_soccer_ball_01", "kick soccer ball with right foot", 5.6, _M),
    ("dribble_kick_ball_01", "dribble and kick the ball toward goal", 12.2, _M),
    ("penalty_kick_01", "penalty kick: run up and kick the ball", 7.8, _M),
    ("martial_front_kick_01", "martial arts front kick, quick snap", 0.7, _M),
    ("basketball_set_shot_01", "shoot basketball at hoop, two handed set shot", 7.2, _M),
    ("basketball_jump_shot_01", "dribble basketball then take a jump shot", 11.8, _M),
    ("basketball_free_throw_01", "basketball free throw, bend knees and release", 8.0, _M),
    ("dribble_basketball_01", "dribble basketball in place", 19.6, _M),
    ("baseball_swing_right_01", "swing baseball bat, right-handed batter", 6.2, _M),
    ("baseball_batting_stance_01", "baseball batting stance and swing", 8.8, _M),
    ("bat_practice_swings_01", "swing the bat, practice swings, left-handed", 18.4, _M),
    # Archery and firearms.
    ("archery_draw_release_01", "draw a bow and release an arrow", 10.4, _M),
    ("archery_nock_aim_01", "archery: nock arrow, draw and aim", 16.0, _M),
    ("longbow_kneeling_01", "shoot a longbow while kneeling", 12.8, _M),
    ("take_a_bow_01", "take a bow, bend at the waist", 4.4, _M),
    ("pistol_two_hands_01", "aim and fire a pistol with both hands", 9.0, _M),
    ("rifle_shoulder_standing_01", "shoot a rifle from the shoulder, standing", 12.0, _M),
    ("handgun_walking_01", "fire a handgun while walking forward", 14.6, _M),
    # Jumping and hopping.
    ("jump_forward_both_feet_01", "jump forward with both feet", 4.8, _M),
    ("jump_vertical_01", "jump in place, high vertical jump", 6.0, _M),
    ("jumping_jacks_01", "jumping jacks", 21.0, _M),
    ("standing_long_jump_01", "standing long jump, land and stand up", 7.6, _M),
    ("jump_rope_01", "jump rope, two feet", 28.0, _M),
    ("hop_one_foot_01", "hop on one foot", 10.0, _M),
    ("hopping_left_leg_01", "hopping on the left leg", 12.4, _M),
    ("bunny_hops_01", "hop forward on both feet, bunny hops", 14.0, _M),
    ("hop_once_01", "hop once in place", 0.5, _M),
    ("hip_hop_dance_01", "hip hop dance, freestyle", 44.0, _M),
    # Object manipulation.
    ("push_heavy_box_01", "push a heavy box across the floor", 12.6, _M),
    ("push_shopping_cart_01", "push a shopping cart", 23.6, _M),
    ("push_open_door_01", "push open a heavy door", 6.8, _M),
    ("push_ups_01", "do push-ups on the floor", 32.0, _M),
    ("pick_up_box_01", "bend down and pick up a box", 8.4, _M),
    ("pick_up_object_floor_01", "pick up an object from the floor", 6.2, _M),
    ("pour_water_bottle_cup_01", "pour water from a bottle into a cup", 11.0, _M),
    ("pour_from_pitcher_01", "pouring a drink from a pitcher, standing at a table", 13.6, _M),
    ("pour_cereal_bowl_01", "pour cereal into a bowl", 9.8, _M),
    ("sweep_floor_broom_01", "sweep the floor with a broom", 26.0, _M),
    ("prune_hedge_01", "prune a hedge with shears", 32.0, _M),
    # Exercise on a bar or mat.
    ("pull_ups_bar_01", "pull-ups on a bar", 24.0, _M),
    ("chin_ups_01", "chin-ups, five repetitions", 28.4, _M),
    ("hang_pull_ups_01", "hang from a bar and do pull ups", 21.6, _M),
    ("sit_ups_mat_01", "do sit-ups on a mat", 37.0, _M),
    ("stretch_arms_overhead_01", "stretch arms overhead, yawn", 8.0, _M),
    ("split_slide_stretch_01", "stretching, legs wide apart, slide into a split", 24.0, _M),
    ("front_split_floor_01", "front split on the floor", 19.0, _M),
    ("side_split_warm_up_01", "side split stretch, warm up", 32.6, _M),
    ("tai_chi_form_01", "tai chi, slow form", 50.0, _M),
    # Sitting, standing up, getting down.
    ("sit_down_chair_01", "sit down on a chair", 6.6, _M),
    ("sit_floor_cross_legged_01", "sit on the floor cross-legged", 12.0, _M),
    ("sit_down_stand_up_01", "sit down, then stand up again", 13.2, _M),
    ("stand_up_from_chair_01", "stand up from a chair", 5.4, _M),
    ("get_up_from_floor_01", "get up from the floor", 8.6, _M),
    ("rise_from_kneeling_01", "rise from a kneeling position", 6.0, _M),
    ("forward_roll_stand_up_01", "forward roll then stand up", 9.2, _M),
    ("idle_standing_01", "idle standing, shift weight", 30.0, _M),
    ("flinch_startle_01", "flinch, quick startle", 0.5, _M),
    # Crawling, diving, falling.
    ("crawl_hands_and_knees_01", "crawl forward on hands and knees", 19.4, _M),
    ("army_crawl_01", "army crawl, belly on the ground", 25.8, _M),
    ("crawling_all_fours_01", "crawling on all fours, look around", 31.2, _M),
    ("dive_onto_floor_artist_01", "dive forward onto the floor", 5.2, _A),
    ("drop_to_ground_prone_01", "drop to the ground and lie prone", 7.0, _M),
    ("fall_to_ground_01", "fall to the ground face first, break the fall with hands", 7.4, _M),
    # Impaired gaits and balance.
    ("limp_right_leg_01", "limp, favoring the right leg", 21.2, _M),
    ("stagger_drunk_01", "stagger around like a drunk", 28.8, _M),
    ("stumble_recover_01", "stumble forward and recover balance", 7.8, _M),
    ("tightrope_walk_01", "tightrope walk, careful steps", 31.0, _M),
    ("moonwalk_artist_01", "moonwalk dance, slide backward", 12.0, _A),
    # Hands up.
    ("raise_both_hands_hold_01", "raise both hands above head and hold", 12.0, _M),
    ("surrender_kneel_artist_01", "surrender, hands up, kneel down", 15.0, _A),
    ("hands_up_behind_head_01", "put hands up, then hands behind head", 11.6, _M),
    # Two-person interactions and street scenes.
    ("hug_pat_back_01", "hug a person, pat on the back", 9.4, _M),
    ("greet_friend_hug_01", "greet a friend with a hug", 7.8, _M),
    ("stroll_park_01", "leisurely stroll in the park, swinging arms", 40.0, _M),
    ("holding_hands_walking_01", "holding hands while walking slowly", 24.4, _M),
    ("collide_shoulder_passerby_01", "collide shoulder to shoulder with a passerby", 5.6, _M),
    ("crowd_dodge_01", "brisk walk through a crowd, dodging people", 23.0, _M),
    ("cross_street_look_01", "cross the street, look left and right", 17.2, _M),
    ("wait_bus_stop_01", "waiting at a bus stop, shifting weight", 48.0, _M),
)

#: The motion catalogue, in θ_AB column order.
MOTIONS: Registry[Motion] = Registry(
    "motion",
    tuple((name, Motion(name, desc, length, src)) for name, desc, length, src in _CATALOGUE),
)


def theta_ab(regexes: Mapping[str, str], motions: Registry[Motion] = MOTIONS) -> np.ndarray:
    """The paper's θ_AB: ``(θ_AB)_ab = 1`` if ``re.search(regex_a, desc_b)`` else ``0``.

    Rows follow ``ACTIONS`` order and columns ``motions`` order; actions absent from
    ``regexes`` get an all-zero row. Raises ``KeyError`` for an unknown action name and
    ``ValueError`` (naming the action) for a pattern that does not compile.
    """
    compiled: dict[int, re.Pattern[str]] = {}
    for action, pattern in regexes.items():
        row = ACTIONS.index(action)
        try:
            compiled[row] = re.compile(pattern)
        except (re.error, TypeError) as exc:
            raise ValueError(f"invalid regular expression for action {action!r}: {pattern!r} ({exc})") from exc
    theta = np.zeros((len(ACTIONS), len(motions)), dtype=np.float64)
    descriptions = [motions[name].description for name in motions.names]
    for row, regex in compiled.items():
        for col, description in enumerate(descriptions):
            if regex.search(description):
                theta[row, col] = 1.0
    return theta


#: ``motion.start: active`` keeps the windows that move at least this share of the best
#: window's moving time.
ACTIVE_SHARE = 0.75
#: Starts are considered every 1/30 s (a 30 fps frame grid, whatever the video's frame rate).
_START_STEP_S = 1.0 / 30.0


def moving_share(spans: tuple[tuple[float, float], ...], starts: np.ndarray, window_s: float) -> np.ndarray:
    """Per start (s), the share of the window [start, start + ``window_s``] that ``spans``
    (moving (start, end) seconds of a take) cover."""
    starts = np.asarray(starts, dtype=np.float64)
    covered = np.zeros_like(starts)
    for a, b in spans:
        covered += np.clip(np.minimum(b, starts + window_s) - np.maximum(a, starts), 0.0, None)
    return covered / window_s if window_s > 0 else np.ones_like(starts)


def active_start(name: str, length_s: float, window_s: float, u: float) -> float:
    """Where a window of ``window_s`` seconds starts in take ``name`` (``length_s`` long),
    from one uniform draw ``u`` ∈ [0, 1): uniform over the frame-grid starts whose window
    moves at least ``ACTIVE_SHARE`` of the best window's moving time (``MOVING_SPANS``),
    so a short clip shows the action rather than a held pose. A take that never moves, or
    one the table does not know (a user's clip), starts uniformly as ``motion.start: uniform``."""
    room = max(0.0, length_s - window_s)
    spans = MOVING_SPANS.get(name)
    if spans is None or room == 0.0:
        return u * room
    starts = np.arange(int(np.floor(room / _START_STEP_S)) + 1) * _START_STEP_S
    share = moving_share(spans, starts, window_s)
    if not share.max() > 0:
        return u * room
    keep = starts[share >= ACTIVE_SHARE * share.max() - 1e-12]
    return float(keep[min(int(u * len(keep)), len(keep) - 1)])


#: Two people walking into each other meet when their pelvises are this far apart (m): their
#: chests touching, as the physics' capsules of most bodies put it.
MEETING_GAP_M = 0.4
#: … and this long (s) before their take would stop them, so that they walk into each other
#: rather than stop short.
MEETING_LEAD_S = 0.3


def meeting_start(name: str, length_s: float, window_s: float, distance_m: float) -> float | None:
    """Where take ``name`` starts for two people ``distance_m`` apart who both play it
    towards each other (``facing``), so that they meet just before it stops them: each
    covers half the distance at the take's pace (``APPROACHES``; a body's own pace differs
    by its legs and stride, and the plan halts a pair that would meet sooner). A window of
    ``window_s`` still fits in the take. None for a take that does not walk up to a stop,
    where it starts does not decide whether they meet, and for a window too short to reach
    the meeting."""
    found = APPROACHES.get(name)
    if found is None:
        return None
    stop, pace = found
    start = stop - MEETING_LEAD_S - max(0.0, distance_m - MEETING_GAP_M) / (2.0 * pace)
    start = min(max(0.0, start), max(0.0, length_s - window_s))
    # A window too short to hold the walk up to the meeting shows two people still apart
    # wherever it starts; θ's start keeps what else the take shows (its stop, the step back).
    return start if start + window_s >= stop - MEETING_LEAD_S else None
