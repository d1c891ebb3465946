"""Supporting characters: the partner of two-person actions, tied to the protagonist by the
hands (walk holding hands) or hand to shoulder (walking hug), with compliant tied arms."""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from phav_generator.motion.animation import Pose
from phav_generator.motion.skeleton import BONE_INDEX, DOF_INDEX
from phav_generator.physics.plan.builder import PlanBuilder
from phav_generator.physics.plan.people import halt, plan_person, planted_before
from phav_generator.physics.plan.scene_plan import HandTie, Manipulation, PersonPlan

#: Servo strength of an arm whose hand is tied to someone else's body.
TIED_ARM_STRENGTH = 0.4
#: A partner walking with the protagonist keeps pace where both go at least this far (m).
TRAVEL_MATCHED_M = 0.5
#: How far back (s) from where two people walking into each other would meet the stances
#: they stop at are looked for.
BUMP_LOOKBACK_S = 1.5


def supporting_people(b: PlanBuilder, protagonist: PersonPlan) -> list[PersonPlan]:
    """The protagonist and the supporting characters, doing the protagonist's motion; the
    first is tied to the protagonist in the two-person actions (hand in hand, or a hand on
    the far shoulder), or walks into it (``facing``: both stop where they meet)."""
    r = b.recipe
    out = []
    for s in r.supporting_characters:

        def planned(speed: float, s=s) -> PersonPlan:
            return plan_person(
                b, s.person_id, "supporting", s.human, r.motion.base_motion, r.motion.start_s, speed,
                r.motion.mirror, s.position, s.heading_deg,
            )  # fmt: skip

        person = planned(r.motion.speed)
        if s.placement in ("side_by_side", "behind"):
            # Walking with the protagonist: its own strides (as long as its legs and its
            # amplitude make them) at the cadence that keeps pace. The same motion at the same
            # speed travels in proportion to those, and held hands came apart by over a metre.
            mine, theirs = _travel(protagonist), _travel(person)
            if mine > TRAVEL_MATCHED_M and theirs > TRAVEL_MATCHED_M:
                person = planned(r.motion.speed * mine / theirs)
        out.append(person)
    if not out:
        return [protagonist]
    if r.supporting_characters[0].placement == "facing":
        protagonist, out[0] = bump(b, protagonist, out[0])
    partner = out[0]
    scale = protagonist.dims.height_m / 1.75
    if r.action == "walk_holding_hands":
        # The partner is on the protagonist's right: right hand holds left hand.
        palm = -0.08 * scale
        b.ties.append(HandTie(0, "right_hand", partner.person_id, "left_hand", (0.0, -0.01, palm), (0.0, 0.01, palm)))
        b.manipulations.append(Manipulation("hand", 0, "right_hand", "hold", 0.0, float(b.times[-1])))
    elif r.action == "walking_hug":
        shoulder = (0.0, -0.12 * scale, 0.17 * scale)  # the partner's far (right) shoulder
        b.ties.append(HandTie(0, "right_hand", partner.person_id, "chest", (0.0, 0.0, -0.08 * scale), shoulder))
        b.manipulations.append(Manipulation("hug", 0, "right_hand", "hold", 0.0, float(b.times[-1])))
    return [protagonist, *out]


def bump(b: PlanBuilder, a: PersonPlan, c: PersonPlan) -> tuple[PersonPlan, PersonPlan]:
    """Two people walking into each other (``facing``): where their plans would pass chest
    through chest, each halts at one of its own stances (both feet down) before, the pair
    of stances that leaves them nearest to touching. Pinned, they would walk through each
    other; people who never meet in the clip walk on."""
    times = b.times
    touching = a.dims.capsules[BONE_INDEX["chest"]].radius + c.dims.capsules[BONE_INDEX["chest"]].radius
    ra, rc = a.targets.root_pos[:, :2], c.targets.root_pos[:, :2]
    meet = np.flatnonzero(np.linalg.norm(ra - rc, axis=1) < touching)
    if not meet.size:
        return a, c
    back = round(BUMP_LOOKBACK_S * b.fps * b.substeps)  # plan steps
    grid = range(int(meet[0]), max(-1, int(meet[0]) - back), -b.substeps)  # a frame apart
    stances_a = sorted({planted_before(a, times, k) for k in grid})
    stances_c = sorted({planted_before(c, times, k) for k in grid})
    gaps = np.linalg.norm(ra[stances_a][:, None] - rc[stances_c][None], axis=2)
    apart = gaps >= touching
    # The nearest pair still apart; where none is (they meet within a stance of the
    # clip's start), the farthest.
    i, j = np.unravel_index(np.argmin(np.where(apart, gaps, np.inf)) if apart.any() else np.argmax(gaps), gaps.shape)
    return halt(a, times, float(times[stances_a[i]])), halt(c, times, float(times[stances_c[j]]))


def _travel(p: PersonPlan) -> float:
    """How far (m) a person's pelvis goes over the ground from the clip's first frame to its last."""
    root = p.targets.root_pos
    return float(np.linalg.norm(root[-1, :2] - root[0, :2]))


def arm_pose_for_tie(p: PersonPlan, action: str) -> PersonPlan:
    """Two-person rules: reach the arm to the partner (holding hands low, hug around shoulders)."""
    q = p.targets.q.copy()
    if action == "walk_holding_hands":
        q[:, DOF_INDEX["right_shoulder_abd"]] = 0.35
        q[:, DOF_INDEX["right_shoulder_flex"]] = 0.1
        q[:, DOF_INDEX["right_elbow_flex"]] = 0.25
    elif action == "walking_hug":
        q[:, DOF_INDEX["right_shoulder_abd"]] = 1.45
        q[:, DOF_INDEX["right_shoulder_flex"]] = 0.35
        q[:, DOF_INDEX["right_elbow_flex"]] = 0.9
    else:
        return p
    return replace(p, targets=Pose(p.targets.root_pos, p.targets.root_quat, q))


def loosen_tied_arms(people: list[PersonPlan], ties: list[HandTie]) -> list[PersonPlan]:
    """Tied arms go compliant so the tie, not the servos, decides where the hands meet."""
    people = list(people)
    for tie in ties:
        for side, body in ((tie.person_a, tie.body_a), (tie.person_b, tie.body_b)):
            if body.endswith("_hand"):
                arm = [f"{body[: -len('hand')]}{part}" for part in ("upper_arm", "lower_arm", "hand")]
                k = next(i for i, x in enumerate(people) if x.person_id == side)
                s = people[k].strengths.copy()
                s[:, [BONE_INDEX[m] for m in arm]] *= TIED_ARM_STRENGTH
                people[k] = replace(people[k], strengths=s)
    return people
