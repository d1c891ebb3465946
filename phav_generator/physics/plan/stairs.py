"""The flight of stairs a climb_stairs clip walks on, and where its protagonist stands."""

from __future__ import annotations

import math

import numpy as np

from phav_generator.motion.animation import placement
from phav_generator.motion.gait import STAIR_RISE, STAIR_RUN, STAIR_START, stair_height
from phav_generator.motion.library import get_motion
from phav_generator.motion.rotations import yaw_matrix
from phav_generator.motion.skeleton import BONE_INDEX, BONES, capsule_points
from phav_generator.physics.plan.builder import PlanBuilder
from phav_generator.physics.plan.people import body_poses
from phav_generator.physics.plan.scene_plan import PersonPlan, StaticBox

#: Half width of a built flight of stairs (m).
STAIRS_HALF_WIDTH_M = 0.6


def build_stairs(b: PlanBuilder, probe: PersonPlan, start: np.ndarray) -> np.ndarray:
    """Build the flight a climb_stairs clip walks on; return where to stand the protagonist.

    A catalogue stairs motion plants its feet on its own treads (``motion.gait.STAIR_*``,
    in the motion frame): those treads are built in the world through the clip's
    ``Placement``, so every plant lands on a tread whatever the person's height, the
    clip's start in the flight or the handedness. Going up, the tread under the feet at
    the clip's start is the waypoint's floor (or, where the swing foot is still coming up
    from the tread below, that tread is); going down, the lowest tread the clip reaches is;
    the person starts on the tread (or landing) above the floor: ``stand_offset_z``.
    """
    motion = get_motion(probe.motion)
    direction = motion.stairs
    if direction == 0:
        return _stairs_from_rise(b, probe, start)
    r = b.recipe
    pl = placement(motion, r.motion.start_s, probe.params, probe.dims, tuple(start), r.protagonist.heading_deg)
    pos, rot = body_poses(probe.dims, probe.targets.take(slice(None, None, b.substeps)))
    feet = [BONE_INDEX["left_foot"], BONE_INDEX["right_foot"]]
    ends = np.concatenate(capsule_points(probe.dims, pos, rot), axis=-2)[:, feet + [f + len(BONES) for f in feet]]
    in_motion = pl.to_motion(ends.reshape(-1, 3)).reshape(*ends.shape)
    motion_x = in_motion[..., 0]
    # The tread the clip starts on: the lowest one a sole stands on (within 2 cm) at the
    # first frame. Not the lowest sole: going down, the swing foot is lower, in the air.
    radius = probe.dims.capsules[feet[0]].radius / pl.scale
    under = stair_height(motion_x[0], direction)
    clearance = np.abs(in_motion[0, :, 2] - radius - under)
    standing = clearance < 0.02 / pl.scale
    h0 = float(under[standing].min() if standing.any() else under[np.argmin(clearance)])
    lo, hi = float(motion_x.min()) - 0.3, float(motion_x.max()) + STAIR_RUN
    if direction < 0:
        h_low = float(stair_height(np.array([hi]), direction)[0])
    else:
        # Going up from part-way along the flight, the swing foot may still be coming up
        # from the tread below: the floor is the lowest tread a sole comes down past, and
        # the person starts on the tread above it.
        below = in_motion[..., 2] - radius < h0 - 0.005 / pl.scale
        h_low = min(h0, float(stair_height(motion_x[below], direction).min())) if below.any() else h0
    z0 = float(start[2])
    b.stand_offset_z = pl.scale * (h0 - h_low)
    stand = np.array([start[0], start[1], z0 - pl.scale * h0])
    base = z0 - pl.scale * h_low  # the animation's z: the motion's floor in the world
    yaw = math.degrees(pl.heading_rad - pl.yaw0)
    n_lo = max(0, math.floor((lo - STAIR_START) / STAIR_RUN) + 1)
    n_hi = math.floor((hi - STAIR_START) / STAIR_RUN) + 1
    for n in range(n_lo, n_hi + 1):
        # Tread n spans [start + (n − 1)·run, start + n·run) at n rises; tread 0 is the floor
        # (a landing, going down) before the first riser.
        x_from = STAIR_START + (n - 1) * STAIR_RUN if n else min(lo, STAIR_START - STAIR_RUN)
        x_to = STAIR_START + n * STAIR_RUN
        top = base + pl.scale * direction * STAIR_RISE * n
        if top - z0 < 1e-3:
            continue
        centre = pl.to_world(np.array([(x_from + x_to) / 2, 0.0, 0.0]))
        half = (pl.scale * (x_to - x_from) / 2, STAIRS_HALF_WIDTH_M, (top - z0) / 2)
        b.boxes.append(StaticBox("stairs", (float(centre[0]), float(centre[1]), (z0 + top) / 2), half, yaw))
    return stand


def _stairs_from_rise(b: PlanBuilder, probe: PersonPlan, start: np.ndarray) -> np.ndarray:
    """Steps for a stairs motion without its own flight (an imported clip): the clip's
    climb taken out of its start, then steps of 17 cm × 30 cm following the pelvis's rise."""
    climbed = probe.targets.root_pos[0, 2] - start[2] - probe.dims.standing_pelvis_height
    start = start - np.array([0.0, 0.0, climbed])
    pelvis = probe.targets.root_pos
    rise = pelvis[-1, 2] - pelvis[0, 2]
    heading = b.recipe.protagonist.heading_deg
    fwd = yaw_matrix(np.deg2rad(heading)) @ np.array([1.0, 0.0, 0.0])
    x0 = np.array(b.recipe.protagonist.position)
    step_rise, step_run = 0.17, 0.30
    n_steps = max(3, int(abs(rise) / step_rise + 0.999) + 2)
    for k in range(n_steps):
        if rise >= 0:  # up: step k's top at (k + 1)·rise, starting 0.4 m ahead
            top = (k + 1) * step_rise
            along = 0.4 + (k + 0.5) * step_run
            length = step_run
        else:  # down: the person starts on a landing; steps fall ahead of it
            top = (n_steps - k) * step_rise
            along = (k + 0.5) * step_run if k else 0.0
            length = step_run if k else 2.0
        c = x0 + along * fwd
        b.boxes.append(
            StaticBox("stairs", (float(c[0]), float(c[1]), x0[2] + top / 2), (length / 2, 0.6, top / 2), heading)
        )
    if rise < 0:
        b.stand_offset_z = n_steps * step_rise
    return start
