"""Background pedestrians: kinematic walkers between the recipe's waypoints."""

from __future__ import annotations

import math

import numpy as np

from phav_generator.body.model import rest_body
from phav_generator.motion.animation import MotionParams, Pose, animate, motion_params
from phav_generator.motion.library import get_motion
from phav_generator.physics.plan.builder import PlanBuilder
from phav_generator.physics.plan.scene_plan import PersonPlan
from phav_spec.scene import MAX_STEP_M, walkable_heights
from phav_spec.vocab import MUSCLES

#: How far ahead of and behind its pelvis a background walker's feet reach (m), and how
#: far to either side of its path (a foot's width off the hip's line).
BACKGROUND_REACH_M = 0.5
BACKGROUND_SIDE_M = 0.2


def background_people(b: PlanBuilder) -> list[PersonPlan]:
    """Background pedestrians: kinematic walkers between waypoints, posed at frame times only."""
    r = b.recipe
    frame_times = np.arange(r.n_frames + 1) / r.video.fps
    walk = get_motion("walk_forward_01")
    ends = walk.fn(np.array([0.0, walk.length_s]), MotionParams())
    nominal = float(np.linalg.norm(ends.root_pos[1, :2] - ends.root_pos[0, :2])) / walk.length_s
    out = []
    for actor in r.background_actors:
        dims = rest_body(actor.human.phenotype).dims
        start = np.array(actor.start)
        dest = np.array(actor.destination)
        delta = dest - start
        dist = float(np.linalg.norm(delta[:2]))
        heading = math.degrees(math.atan2(delta[1], delta[0])) if dist > 1e-6 else 0.0
        scale = dims.height_m / 1.75
        speed = actor.speed_mps / max(nominal * scale, 1e-6)
        params = motion_params(speed, False, r.seeds.background, f"background/{actor.person_id}")
        pose = animate(walk, frame_times, params.phase * walk.length_s, params, dims, (0.0, 0.0, 0.0), heading)
        # Progress along the path, clamped at the destination; the gait's own advance is
        # replaced by the straight segment so the actor arrives where the recipe says.
        travelled = np.minimum(actor.speed_mps * frame_times, dist)
        along = delta / max(dist, 1e-9)
        root = start[None, :] + travelled[:, None] * along[None, :]
        # Walkers step up onto kerbs and terraces on their way instead of wading through them:
        # the highest surface within a stride ahead of or behind the pelvis and a foot's
        # width to either side, where the feet reach (the pelvis alone stepped up only once
        # the front foot was in the kerb; a path along a terrace's edge put one foot in it).
        reach = max(start[2], dest[2]) + MAX_STEP_M
        side = np.array([-along[1], along[0]])
        root[:, 2] = np.max(
            [
                walkable_heights(r.environment.name, *(root[:, :2] + o * along[:2] + w * side).T, reach)
                for o in (-BACKGROUND_REACH_M, -BACKGROUND_REACH_M / 2, 0.0, BACKGROUND_REACH_M / 2, BACKGROUND_REACH_M)
                for w in (-BACKGROUND_SIDE_M, 0.0, BACKGROUND_SIDE_M)
            ],
            axis=0,
        )
        root[:, 2] += pose.root_pos[:, 2]  # the gait's own bob and standing height
        arrived = travelled >= dist
        q = pose.q.copy()
        q[arrived] = 0.0
        n = len(frame_times)
        out.append(
            PersonPlan(
                person_id=actor.person_id,
                role="background",
                dims=dims,
                params=params,
                motion="walk_forward_01",
                targets=Pose(root, pose.root_quat, q),
                strengths=np.ones((n, len(MUSCLES))),
                pin=np.ones(n),
                physical=False,
            )
        )
    return out
