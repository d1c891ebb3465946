"""Background traffic: vehicles drive their lanes, stop short of people, of the vehicle
ahead and of a camera in their way, braking no harder than BRAKE_MPS2, never touch anyone,
and only where the environment has roads."""

from __future__ import annotations

import mujoco
import numpy as np
import pytest

from phav_generator.physics.simulate import simulate
from phav_generator.physics.traffic import (
    BRAKE_MPS2,
    CAMERA_HEADROOM_M,
    STOP_GAP_M,
    Traffic,
    Vehicle,
    footprint_points,
    plan_traffic,
)
from phav_generator.sampling import sample_recipes
from phav_spec.scene import ENVIRONMENT_SCENES, VEHICLE_HALF_SIZES, Lane
from phav_spec.theta import load_preset
from tests.generator.physics.support import recipe_for

LANE = Lane((0.0, -2.0, 0.0), (200.0, -2.0, 0.0), 2.0)
DT = 1.0 / 30.0
NONE = np.zeros((0, 3))


def _car(name: str, s0: float, cruise: float = 10.0) -> Vehicle:
    return Vehicle(name, "car", LANE, 0, VEHICLE_HALF_SIZES["car"], s0, cruise)


def _drive(vehicles: tuple[Vehicle, ...], obstacles: list[np.ndarray], cameras: np.ndarray | None = None) -> Traffic:
    return Traffic.drive(vehicles, obstacles, DT, cameras=cameras)


def _speeds(traffic: Traffic) -> np.ndarray:
    return np.diff(traffic.s, axis=1) / DT


def _decelerations(traffic: Traffic) -> np.ndarray:
    return -np.diff(_speeds(traffic), axis=1) / DT


def test_a_vehicle_stops_short_of_a_person_and_goes_on_when_the_way_is_clear():
    person = np.array([[60.0, -1.5, 1.0]])
    frames = [person] * 300 + [NONE] * 150  # 10 s in the way, then 5 s gone
    traffic = _drive((_car("a", 10.0),), frames)
    front = traffic.s[0, 299] + VEHICLE_HALF_SIZES["car"][0]
    assert _speeds(traffic)[0, 290:299].max() == 0.0
    assert STOP_GAP_M - 0.5 < 60.0 - front <= STOP_GAP_M + 0.5
    assert _speeds(traffic)[0, -1] == pytest.approx(10.0)  # accelerated back to its cruise
    assert _decelerations(traffic).max() <= BRAKE_MPS2 + 1e-6


def test_a_person_stepping_out_close_ahead_is_seen_coming():
    """A person who steps into the lane 6 m ahead of a car at 12 m/s: a driver who only
    reacts then must brake at 24 m/s² to stop short; one who sees them coming brakes at
    BRAKE_MPS2 in time."""
    car = _car("a", 10.0, cruise=12.0)
    half = VEHICLE_HALF_SIZES["car"][0]
    step_out = 60  # frame the person steps in, 6 m ahead of where the car's front would be
    ahead = 10.0 + 12.0 * step_out * DT + half + 6.0
    frames = [np.array([[ahead, 5.0, 1.0]])] * step_out + [np.array([[ahead, -2.0, 1.0]])] * 120
    traffic = _drive((car,), frames)
    assert _decelerations(traffic).max() <= BRAKE_MPS2 + 1e-6
    fronts = traffic.s[0] + half
    assert np.all(ahead - fronts[step_out:] >= STOP_GAP_M - 1e-6)
    assert _speeds(traffic)[0, -1] == 0.0
    assert traffic.s[0, step_out // 2] < 10.0 + 12.0 * (step_out // 2) * DT  # slowing before they step out


def test_someone_stepping_into_the_lane_behind_a_vehicle_does_not_stop_it():
    """Braking would stop the car where the person stands 4 s later; holding its speed, it
    has long passed them: it drives on."""
    car = _car("a", 10.0, cruise=12.0)
    rear_at = 10.0 + 12.0 * 120 * DT - VEHICLE_HALF_SIZES["car"][0]
    behind = np.array([[rear_at - 8.0, -2.0, 1.0]])  # steps in at frame 120, 8 m behind its rear
    traffic = _drive((car,), [NONE] * 120 + [behind] * 120)
    np.testing.assert_allclose(_speeds(traffic)[0], 12.0)


def test_a_vehicle_passes_someone_stepping_in_behind_it_then_stops_for_someone_ahead():
    """Neither braking at once (it would stop where the first person steps in) nor holding
    its speed (it would run into the second) is safe: it holds its speed until past the
    first, then brakes for the second."""
    car = _car("a", 10.0, cruise=12.0)
    half = VEHICLE_HALF_SIZES["car"][0]
    behind = [10.0 + 12.0 * 120 * DT - half - 8.0, -2.0, 1.0]  # steps in at frame 120, 8 m behind its rear
    ahead = [10.0 + 12.0 * 200 * DT + half + STOP_GAP_M, -2.0, 1.0]  # stands where its front would be at 200
    traffic = _drive((car,), [np.array([ahead])] * 120 + [np.array([ahead, behind])] * 180)
    np.testing.assert_allclose(_speeds(traffic)[0, :120], 12.0)
    assert np.min(traffic.s[0, 120:] - half) - behind[0] >= 8.0 - 1e-6
    assert ahead[0] - np.max(traffic.s[0] + half) >= STOP_GAP_M - 1e-6
    assert _speeds(traffic)[0, -1] == 0.0
    assert _decelerations(traffic).max() <= BRAKE_MPS2 + 1e-6


def test_a_stopped_vehicle_keeps_its_distance_from_someone_walking_up_to_it():
    """Someone stands in the lane, then steps 2 m towards the waiting car: it stopped far
    enough back to keep STOP_GAP_M from where they will be."""
    xs = [60.0] * 150 + list(np.linspace(60.0, 58.0, 31)) + [58.0] * 89
    traffic = _drive((_car("a", 10.0),), [np.array([[x, -2.0, 1.0]]) for x in xs])
    gaps = np.array(xs) - (traffic.s[0] + VEHICLE_HALF_SIZES["car"][0])
    assert gaps.min() >= STOP_GAP_M - 1e-6
    assert _decelerations(traffic).max() <= BRAKE_MPS2 + 1e-6


def test_the_first_frame_starts_as_fast_as_is_safe():
    """Someone a little nearer than a car at 12 m/s could stop for: it enters the clip
    already slowing, by no more than it must."""
    car = _car("a", 10.0, cruise=12.0)
    stop_m = 12.0**2 / (2.0 * BRAKE_MPS2)
    person = np.array([[10.0 + VEHICLE_HALF_SIZES["car"][0] + stop_m + STOP_GAP_M - 0.3, -2.0, 1.0]])
    speeds = _speeds(_drive((car,), [person] * 240))[0]
    assert 11.5 < speeds[0] < 12.0
    assert np.all(np.diff(speeds) <= 1e-9)


def test_people_beside_the_lane_do_not_stop_traffic():
    traffic = _drive((_car("a", 10.0),), [np.array([[60.0, 4.0, 1.0], [30.0, -6.0, 1.0]])] * 181)
    assert traffic.s[0, -1] == pytest.approx(10.0 + 6.0 * 10.0)


def test_a_vehicle_stops_short_of_a_camera_lower_than_its_roof_and_passes_under_a_higher_one():
    roof = 2.0 * VEHICLE_HALF_SIZES["car"][2]
    frames = [NONE] * 301

    def camera(z: float) -> np.ndarray:
        return np.tile([60.0, -2.0, z], (301, 1))

    low = _drive((_car("a", 10.0),), frames, camera(roof + CAMERA_HEADROOM_M - 0.1))
    assert _speeds(low)[0, -1] == 0.0
    assert STOP_GAP_M - 0.5 < 60.0 - (low.s[0, -1] + VEHICLE_HALF_SIZES["car"][0]) <= STOP_GAP_M + 0.5
    high = _drive((_car("a", 10.0),), frames, camera(roof + CAMERA_HEADROOM_M + 0.1))
    assert high.s[0, -1] == pytest.approx(10.0 + 10.0 * 10.0)  # drove on under it
    bus = _drive((Vehicle("b", "bus", LANE, 0, VEHICLE_HALF_SIZES["bus"], 10.0, 10.0),), frames,
                 camera(roof + CAMERA_HEADROOM_M + 0.1))  # fmt: skip
    assert _speeds(bus)[0, -1] == 0.0  # a taller vehicle stops for the same camera


def _camera_in_a_vehicle_m(trajectory) -> float:
    """The deepest the camera comes inside any traffic vehicle's box over the clip (m, ≤ 0
    means outside)."""
    deepest = -np.inf
    eyes = trajectory.cam_to_world[:, :3, 3]
    for track in trajectory.props:
        if not track.name.startswith("traffic_"):
            continue
        half = np.array(VEHICLE_HALF_SIZES[track.object])
        for eye, pos, quat in zip(eyes, track.pos, track.quat, strict=True):
            rot = np.empty(9)
            mujoco.mju_quat2Mat(rot, quat)
            local = rot.reshape(3, 3).T @ (eye - pos)
            deepest = max(deepest, float(np.min(half - np.abs(local))))
    return deepest


def test_traffic_does_not_drive_through_a_camera_hanging_in_its_lane():
    """phav-v1, seed 0, v000148 (`crawl` by an urban road): the kite hangs 0.4 m over the
    near lane, where a car drove through it for 21 frames before vehicles yielded to it."""
    recipe = next(iter(sample_recipes(load_preset("phav-v1"), n=1, seed=0, start=148)))
    assert (recipe.video_id, recipe.action, recipe.environment.name) == ("v000148", "crawl", "urban")
    trajectory = simulate(recipe, keep_state=False)
    assert any(p.name.startswith("traffic_") for p in trajectory.props)
    assert _camera_in_a_vehicle_m(trajectory) < 0.0


def test_traffic_never_starts_on_the_camera():
    """phav-v1, seed 1, v000053 (`push`, middle): the start turned clear of the pushed load
    lay in a lane where a truck was drawn. A vehicle yields to a camera ahead, not to one it
    starts on: it drove through it (7 frames of truck and no protagonist). Planning now
    leaves out a vehicle that starts within reach of a low camera's start."""
    recipe = next(iter(sample_recipes(load_preset("phav-v1"), n=1, seed=1, start=53)))
    assert (recipe.video_id, recipe.action, recipe.environment.name) == ("v000053", "push", "middle")
    assert _camera_in_a_vehicle_m(simulate(recipe, keep_state=False)) < 0.0


def test_a_follower_stops_behind_its_leader():
    wall = footprint_points(np.array([80.0, -2.0, 0.0]), 0.0, (1.0, 2.0, 1.0))
    traffic = _drive((_car("follower", 10.0, 12.0), _car("leader", 30.0)), [wall] * 451)
    half = VEHICLE_HALF_SIZES["car"][0]
    gap = (traffic.s[1] - half) - (traffic.s[0] + half)
    assert _speeds(traffic)[:, -30:].max() == 0.0
    assert STOP_GAP_M - 0.5 < gap[-1] <= STOP_GAP_M + 0.5
    assert gap.min() >= STOP_GAP_M - 1e-6
    assert _decelerations(traffic).max() <= BRAKE_MPS2 + 1e-6


def test_planning_leaves_out_a_vehicle_someone_stands_in():
    """Someone standing where a planned vehicle starts: no speed keeps it clear, so the
    rehearsal against the planned bodies leaves it out and keeps the rest."""
    urban = (r for r in sample_recipes(load_preset("phav-v1"), n=100, seed=0) if r.environment.name == "urban")
    recipe, kept = next((r, k) for r in urban if len(k := plan_traffic(r, np.zeros((r.n_frames + 1, 0, 3)))) >= 2)
    v = kept[0]
    u = np.subtract(v.lane.end, v.lane.start) / np.linalg.norm(np.subtract(v.lane.end, v.lane.start))
    at = np.array(v.lane.start) + u * v.s0 + np.array([0.0, 0.0, 1.0])
    left = plan_traffic(recipe, np.tile(at, (recipe.n_frames + 1, 1, 1)))
    assert [w.name for w in left] == [w.name for w in kept[1:]]


def test_a_lost_body_point_does_not_hide_the_clearance_of_the_rest():
    car = _car("c", 20.0, cruise=0.0)
    beside = np.array([[20.0, -2.0 + VEHICLE_HALF_SIZES["car"][1] + 0.6, 1.0]])  # 0.6 m off its side
    lost = np.vstack([beside, [np.nan, np.nan, np.nan]])
    traffic = _drive((car,), [beside, lost])
    np.testing.assert_allclose(traffic.clearances([beside, lost])[0], [0.6, 0.6])


def test_poses_lie_on_the_lane_facing_its_direction():
    lane = ENVIRONMENT_SCENES["urban"].lanes[1]  # westbound
    bus = Vehicle("b", "bus", lane, 1, VEHICLE_HALF_SIZES["bus"], 20.0, 8.0)
    pos, quat = _drive((bus,), [NONE] * 2).poses()
    np.testing.assert_allclose(pos[0, 0], [lane.start[0] - 20.0, lane.start[1], VEHICLE_HALF_SIZES["bus"][2]])
    np.testing.assert_allclose(pos[0, 1] - pos[0, 0], [-8.0 * DT, 0.0, 0.0], atol=1e-12)
    np.testing.assert_allclose(np.abs(quat[0]), [0.0, 0.0, 0.0, 1.0], atol=1e-12)  # yaw 180°


@pytest.mark.parametrize("environment", ["simple", "urban", "middle"])
def test_traffic_in_simulated_scenes_keeps_clear_of_everyone(environment: str):
    """Vehicles drive forwards along their lane, never braking harder than BRAKE_MPS2, and
    stay at least 0.5 m from every body (people standing on the road, walkers crossing it)
    in every clip."""
    vehicles = 0
    for seed in range(4):
        tr = simulate(recipe_for("clap", environment, seconds=4.0, seed=seed, variation="none"), keep_state=False)
        traffic = [p for p in tr.props if p.name.startswith("traffic_")]
        vehicles += len(traffic)
        assert tr.traffic_clearance_m is not None and tr.traffic_clearance_m.min() > 0.5
        for v in traffic:
            lane = ENVIRONMENT_SCENES[environment].lanes[int(v.name.split("_")[1])]
            direction = np.subtract(lane.end, lane.start)[:2]
            step = np.diff(v.pos[:, :2], axis=0) @ direction
            assert np.all(step >= -1e-9), f"{v.name} reversed"
            speed = step / np.linalg.norm(direction) * tr.fps
            assert np.max(-np.diff(speed)) * tr.fps <= BRAKE_MPS2 + 1e-6, f"{v.name} braked too hard"
            np.testing.assert_allclose(v.pos[:, 1], lane.start[1])
            assert v.object in lane.vehicles and v.pixel_class == v.object
    assert vehicles > 0


def test_no_traffic_without_roads():
    for environment in ("green", "lake", "stadium", "house_interior"):
        tr = simulate(recipe_for("clap", environment, seconds=0.5, variation="none"), keep_state=False)
        assert not any(p.name.startswith("traffic_") for p in tr.props)
        assert tr.traffic_clearance_m is not None and np.all(tr.traffic_clearance_m == 1000.0)


def test_traffic_keeps_out_of_the_action_s_boxes() -> None:
    """phav-v1, seed 0, 201 (`climb_stairs`, urban): the flight is built from the pavement out
    into the eastbound lane, and a car drove through its top treads for 20 frames: traffic
    yielded to people and driven props, not to the action's boxes. It now stops short of
    them as of a body (or, met at once, is left out)."""
    from phav_generator.physics.plan.scene import plan_scene
    from phav_generator.physics.simulate import simulate_plan
    from phav_generator.sampling import RecipeSampler
    from phav_spec.theta import load_theta

    recipe = RecipeSampler(load_theta("phav-v1")).sample(0, 201)
    plan = plan_scene(recipe)
    assert recipe.action == "climb_stairs" and plan.boxes
    tr = simulate_plan(plan, keep_state=False)
    for track in (t for t in tr.props if t.name.startswith("traffic")):
        yaw = float(2.0 * np.arctan2(track.quat[0, 3], track.quat[0, 0]))  # a lane's vehicle keeps its heading
        vehicle = footprint_points(track.pos, yaw, track.size)  # (F, 9, 3)
        for box in plan.boxes:
            tread = footprint_points(np.asarray(box.center), np.radians(box.yaw_deg), box.half_size)  # (9, 3)
            assert not _inside(vehicle, box.center, np.radians(box.yaw_deg), box.half_size).any(), (track.name, box)
            assert not _inside(tread[None], track.pos[:, None], yaw, track.size).any(), (track.name, box)


def _inside(points, centre, yaw, half) -> np.ndarray:
    """Which points lie inside a box's footprint (centre, yaw in radians, half sizes) seen from above."""
    d = np.asarray(points)[..., :2] - np.asarray(centre)[..., :2]
    along = np.abs(d[..., 0] * np.cos(yaw) + d[..., 1] * np.sin(yaw)) <= half[0]
    across = np.abs(-d[..., 0] * np.sin(yaw) + d[..., 1] * np.cos(yaw)) <= half[1]
    return along & across
