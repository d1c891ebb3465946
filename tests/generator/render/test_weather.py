"""Scenes are what they claim, measured: counterfactual pairs from `phav vary` differ as they
should (fog, night, rain, each weather element) and each environment shows its classes."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from phav_generator.motion.rotations import look_at
from phav_generator.physics.simulate import simulate
from phav_generator.render.gl import FrameRenderer
from phav_generator.render.lighting import (
    EXPOSURE,
    MAX_GAIN,
    METER_DISTANCE_M,
    METER_KEY,
    OVERCAST_SKY_TINT,
    fog_extinction,
    lighting_for,
    sun_direction,
)
from phav_generator.render.scene import build_drawables, class_id
from phav_generator.vary import parse_settings, vary
from phav_spec.errors import PhavUserError
from phav_spec.scene import ENVIRONMENT_SCENES
from phav_spec.vocab import OBJECTS, PIXEL_CLASSES
from tests.generator.physics.support import recipe_for, theta_for
from tests.generator.render.support import render_recipe
from tests.helpers import luma

SECONDS = 0.2
LABELS = ("semantic", "instance", "depth", "flow")


def _pair(action: str, env: str, base: dict, changed: dict):
    theta = theta_for(action, env, seconds=SECONDS, variation="none")
    recipe = recipe_for(action, env, seconds=SECONDS, variation="none")
    return vary(recipe, theta, base), vary(recipe, theta, {**base, **changed})


def _frames(recipe, ctx) -> list[dict[str, np.ndarray]]:
    return [rf.modalities for rf in render_recipe(recipe, ctx)]


def test_vary_changes_only_the_named_variables_and_what_follows_from_them():
    a, b = _pair("walk", "urban", {"weather": "clear", "rain": False}, {"weather": "rain", "rain": True})
    da, db = a.model_dump(), b.model_dump()
    assert {k for k in da if da[k] != db[k]} == {"world"}
    assert a.seeds == b.seeds and b.world.rain and b.world.weather == "rain"
    with pytest.raises(PhavUserError, match="unknown variable"):
        parse_settings(["colour=red"])
    with pytest.raises(PhavUserError, match="weather must be one of"):
        parse_settings(["weather=snow"])
    with pytest.raises(PhavUserError, match="sampled from"):
        vary(a, theta_for("run", "urban", seconds=SECONDS, variation="none"), {"weather": "fog"})
    with pytest.raises(PhavUserError, match="--set: weather is set twice; set it once"):
        parse_settings(["weather=fog", "weather=rain"])
    with pytest.raises(PhavUserError, match=r"--set camera: camera indoors films indoors only; .* is in urban"):
        vary(
            recipe_for("walk", "urban", seconds=SECONDS, variation="none"),
            theta_for("walk", "urban", seconds=SECONDS, variation="none"),
            {"camera": "indoors"},
        )
    # Fog forced on where θ's clear weather draws its intensity as 0: a 1 km haze, not fog.
    recipe, theta = (f("walk", "urban", seconds=SECONDS, variation="none") for f in (recipe_for, theta_for))
    with pytest.raises(PhavUserError, match=r"fog=true in clear weather: θ draws its fog_intensity as 0") as e:
        vary(recipe, theta, {"weather": "clear", "fog": True})
    assert e.value.field == "--set fog"
    foggy = vary(recipe, theta, {"weather": "clear", "fog": True, "fog_intensity": 0.6})
    assert foggy.world.fog and foggy.world.fog_intensity == 0.6


def _first_frame(ctx, recipe, trajectory, lighting):
    """The first frame of ``recipe``'s ``trajectory`` at a small size, under ``lighting``."""
    drawables = build_drawables(recipe, trajectory, lighting)
    with FrameRenderer(ctx, 170, 128, drawables, sky_class=class_id("sky"), lighting=lighting) as renderer:
        return renderer.render(0, trajectory.cam_to_world[0], trajectory.cam_to_world[1], trajectory.intrinsics)


def _linear(rgb: np.ndarray, exposure: float) -> np.ndarray:
    """Undo the renderer's tone curve at the camera's ``exposure``: display values → linear light."""
    v = (rgb.astype(np.float64) / 255.0) ** 2.2
    return -np.log(np.clip(1.0 - v, 1e-4, 1.0)) / exposure


@pytest.mark.parametrize("env", ["simple", "urban"])
def test_fog_lowers_contrast_more_at_greater_depth(ctx, env):
    """Contrast of each pixel against the fog's colour (linear light), fog over clear, per
    depth band: it falls with depth in raw RGB (monotonically) and in the final RGB."""
    clear, fog = _pair("walk", env, {"weather": "fog", "fog": False}, {"weather": "fog", "fog": True,
                                                                     "fog_intensity": 0.8})  # fmt: skip
    fog_colour = lighting_for(fog.world, indoor=False).fog_colour
    ea, eb = (lighting_for(r.world, indoor=False).exposure for r in (clear, fog))
    a, b = _frames(clear, ctx)[0], _frames(fog, ctx)[0]
    depth = a["depth"].astype(np.float64) / 100.0
    for key in ("raw_rgb", "rgb"):
        ca = np.abs(_linear(a[key], ea) - fog_colour).sum(axis=-1)
        cb = np.abs(_linear(b[key], eb) - fog_colour).sum(axis=-1)
        ratios = []
        for lo, hi in ((0.5, 6.0), (6.0, 12.0), (12.0, 30.0)):
            band = (depth >= lo) & (depth < hi) & (ca > 0.02)
            assert band.sum() > 200
            ratios.append(float(np.median(cb[band] / ca[band])))
        assert ratios[0] < 1.0 and ratios[2] < 0.8 * ratios[0], (key, ratios)
        if key == "raw_rgb":
            assert ratios[0] > ratios[1] > ratios[2], ratios


def test_night_is_darker_than_day(ctx):
    day, night = _pair("walk", "simple", {"day_phase": "day", "clock_hour": 13.0},
                       {"day_phase": "night", "clock_hour": 23.0})  # fmt: skip
    d, n = _frames(day, ctx)[0], _frames(night, ctx)[0]
    assert luma(n["rgb"]).mean() < 0.4 * luma(d["rgb"]).mean()
    assert luma(n["raw_rgb"]).mean() < 0.4 * luma(d["raw_rgb"]).mean()


def test_rain_changes_rgb_but_not_labels_depth_or_flow(ctx):
    dry, wet = _pair("walk", "urban", {"weather": "overcast", "rain": False, "wet_ground": False},
                     {"weather": "overcast", "rain": True, "rain_intensity": 1.0, "wet_ground": True})  # fmt: skip
    for a, b in zip(_frames(dry, ctx), _frames(wet, ctx), strict=True):
        for name in LABELS:
            assert np.array_equal(a[name], b[name]), name
        assert np.abs(a["rgb"].astype(int) - b["rgb"].astype(int)).mean() > 2.0


def test_fog_intensity_runs_evenly_in_visibility_from_light_to_dense_fog():
    """Visibility (where a dark object's contrast falls to 5 %): 1 km at θ's fog intensity 0,
    the meteorologists' bound of fog, 40 m at 1, their geometric mean halfway; no fog flag,
    or indoors, leaves only the haze."""

    def visibility(intensity: float) -> float:
        return math.log(20.0) / fog_extinction(intensity)

    assert visibility(0.0) == pytest.approx(1000.0, rel=0.01)
    assert visibility(0.5) == pytest.approx(200.0, rel=0.01)
    assert visibility(1.0) == pytest.approx(40.0, rel=0.01)
    seen = [visibility(i) for i in np.linspace(0.0, 1.0, 11)]
    assert np.all(np.diff(seen) < 0.0)
    base = recipe_for("walk", "urban", seconds=SECONDS, variation="none")
    theta = theta_for("walk", "urban", seconds=SECONDS, variation="none")
    foggy = vary(base, theta, {"weather": "fog", "fog": True, "fog_intensity": 0.5})
    clear = vary(base, theta, {"weather": "fog", "fog": False, "fog_intensity": 0.5})
    haze = lighting_for(clear.world, indoor=False).fog_per_m
    assert lighting_for(foggy.world, indoor=False).fog_per_m == pytest.approx(haze + fog_extinction(0.5))
    assert lighting_for(foggy.world, indoor=True).fog_per_m == haze


def test_a_wet_road_is_dark_below_the_camera_and_shines_towards_the_horizon(ctx):
    """Water reflects 2 % head-on and most at grazing angles (Fresnel): wet, the road seen
    steeply from above is darker than dry, and the road seen at a grazing angle brighter;
    a lawn, which water does not soak, darkens less."""
    dry, wet = _pair("walk", "simple", {"weather": "overcast", "rain": False, "wet_ground": False},
                     {"wet_ground": True})  # fmt: skip
    tr = simulate(dry, keep_state=False)
    eye = np.array([0.0, 4.0, 1.6])  # over the simple road's edge (y ∈ [-4, 4], its top at z = 0), lawn beyond
    pose = np.eye(4)
    pose[:3, :3], pose[:3, 3] = look_at(eye, np.array([2.0, 4.0, 0.0])), eye
    fx, fy, cx, cy = intrinsics = (120.0, 120.0, 170.0, 128.0)
    frames = {}
    for name, recipe in (("dry", dry), ("wet", wet)):
        lighting = lighting_for(recipe.world, indoor=False)
        world = [d for d in build_drawables(recipe, tr, lighting) if d.instance_id == 0]  # no people
        with FrameRenderer(ctx, 340, 256, world, sky_class=class_id("sky"), lighting=lighting,
                           supersample=1) as renderer:  # fmt: skip
            frames[name] = renderer.render(0, pose, pose, intrinsics)
    v, u = np.mgrid[0:256, 0:340] + 0.5
    distance = frames["dry"].depth_m * np.sqrt(1.0 + ((u - cx) / fx) ** 2 + ((v - cy) / fy) ** 2)
    elevation = np.degrees(np.arcsin(np.clip(eye[2] / distance, 0.0, 1.0)))  # of the eye, from the road
    road = frames["dry"].class_id == class_id("road")
    steep, grazing = road & (elevation > 45.0), road & (elevation < 10.0)
    assert steep.sum() > 1000 and grazing.sum() > 1000
    lum = {name: luma(f.colour) for name, f in frames.items()}
    assert lum["wet"][steep].mean() < 0.93 * lum["dry"][steep].mean()
    assert lum["wet"][grazing].mean() > lum["dry"][grazing].mean()
    # Water beads on grass: a wet lawn seen steeply darkens less than the road.
    lawn = (frames["dry"].class_id == class_id("terrain")) & (elevation > 30.0)
    assert lawn.sum() > 1000
    ratio = {name: lum["wet"][m].mean() / lum["dry"][m].mean() for name, m in (("road", steep), ("lawn", lawn))}
    assert ratio["lawn"] > ratio["road"] + 0.05
    # Its blades, facing every way, scatter the water's reflection: no sheen at grazing angles.
    far_lawn = (frames["dry"].class_id == class_id("terrain")) & (elevation < 10.0)
    assert far_lawn.sum() > 1000
    assert lum["wet"][far_lawn].mean() < lum["dry"][far_lawn].mean()
    # Puddles mirror the sky, the damp asphalt between them a third as much: at one grazing
    # angle the road's shine is patchy (a film over all of it varies only with the angle).
    band = road & (elevation > 5.0) & (elevation < 10.0)
    assert band.sum() > 1000
    shine = lum["wet"][band] - lum["dry"][band]
    low, high = np.percentile(shine, [10, 90])
    assert 0.0 < low and high > 3.0 * low


@pytest.mark.parametrize("element", ["rain", "fog", "clouds", "wet_ground"])
def test_every_weather_element_is_visible(ctx, element):
    off, on = _pair("walk", "urban", {"weather": "rain", element: False}, {"weather": "rain", element: True})
    a, b = _frames(off, ctx)[0], _frames(on, ctx)[0]
    for name in LABELS:
        assert np.array_equal(a[name], b[name]), name
    assert np.abs(a["rgb"].astype(int) - b["rgb"].astype(int)).mean() > 1.0


def test_the_sun_follows_the_clock():
    assert sun_direction(12.0)[2] > 0.5 and sun_direction(0.0)[2] < -0.5
    assert sun_direction(8.0)[0] > 0 > sun_direction(16.0)[0]  # east in the morning, west in the afternoon
    assert sun_direction(12.0)[1] < 0  # south at noon, 45° N


def _elevation(clock_hour: float) -> float:
    return math.degrees(math.asin(float(sun_direction(clock_hour)[2])))


def test_dawn_and_dusk_hours_are_the_same_light():
    """θ's dawn (7–10 h, mode 9) and dusk (17–20 h, mode 18) mirror each other about the
    clock's solar noon: the sun stands as high at each pair of mirrored hours, low at the
    modes, and neither phase reaches night's darkness (the sun 12° down at most)."""
    for dawn, dusk in ((7.0, 20.0), (9.0, 18.0), (10.0, 17.0)):
        assert _elevation(dawn) == pytest.approx(_elevation(dusk), abs=1e-9)
    assert 0.0 < _elevation(9.0) < 15.0
    assert _elevation(7.0) > -13.0
    assert _elevation(0.0) < -30.0 and _elevation(13.5) > 30.0


@pytest.mark.parametrize("env", sorted(ENVIRONMENT_SCENES))
def test_each_environment_shows_its_declared_classes(ctx, env):
    """Looking around from the protagonist's waypoint (and down on it) shows every class
    the environment declares, and nothing outside its classes and props."""
    recipe = recipe_for("walk", env, seconds=SECONDS, variation="none")
    tr = simulate(recipe, keep_state=False)
    scene = ENVIRONMENT_SCENES[env]
    lighting = lighting_for(recipe.world, indoor=scene.indoor)
    # The camera stands where the protagonist does: people are left out of this look around.
    world = [d for d in build_drawables(recipe, tr, lighting) if d.instance_id == 0]
    renderer = FrameRenderer(ctx, 340, 256, world, sky_class=class_id("sky"), supersample=1)
    x, y, z = recipe.environment.waypoint
    seen: set[int] = set()
    around = np.linspace(0, 2 * np.pi, 12)
    views = [((x, y, z + 1.6), (x + np.cos(a) * 10, y + np.sin(a) * 10, z + 1.0)) for a in around]
    views.append(((x + 0.1, y, z + (2.4 if scene.indoor else 40.0)), (x, y, z)))
    try:
        for eye, target in views:
            pose = np.eye(4)
            pose[:3, :3] = look_at(np.array(eye), np.array(target))
            pose[:3, 3] = eye
            frame = renderer.render(0, pose, pose, (120.0, 120.0, 170.0, 128.0))
            seen |= set(np.unique(frame.class_id).tolist())
    finally:
        renderer.release()
    names = {n for n in PIXEL_CLASSES.names if PIXEL_CLASSES[n].class_id in seen}
    # Props and vehicles come with actions and traffic, not with the static world.
    dynamic = {OBJECTS[name] for name in OBJECTS.names}
    missing = set(scene.pixel_classes) - names - dynamic
    assert not missing, missing
    assert names <= set(scene.pixel_classes) | dynamic


def _seen_key(light) -> float:
    """The light on a white horizontal surface, seen through the fog at the meter's distance."""
    lit = float(luma(light.sky_ambient + light.sun_colour * max(light.sun_dir[2], 0.0)))
    seen = math.exp(-light.fog_per_m * METER_DISTANCE_M)
    return lit * seen + float(luma(light.fog_colour)) * (1.0 - seen)


def test_an_overcast_sky_lights_the_ground_brighter_than_it_looks_at_the_horizon():
    """Under full cloud the whole dome lights the ground, brightest overhead: the light on a
    white horizontal surface outshines the sky at the horizon (2.3× for the CIE's overcast
    sky), as it does not under a clear sky, whose light is mostly the sun's."""
    base = recipe_for("walk", "simple", seconds=SECONDS, variation="none")
    theta = theta_for("walk", "simple", seconds=SECONDS, variation="none")
    settings = {"weather": "overcast", "day_phase": "day", "clock_hour": 13.0, "cloud_intensity": 1.0,
                "ambient_luminosity": 1.0}  # fmt: skip
    overcast = lighting_for(vary(base, theta, settings).world, indoor=False)
    assert luma(overcast.sky_ambient) > 1.3 * luma(overcast.sky_horizon)
    clear = lighting_for(vary(base, theta, {**settings, "weather": "clear", "clouds": False}).world, indoor=False)
    assert luma(clear.sky_ambient) < luma(clear.sky_horizon)


def test_an_overcast_sky_is_a_cool_grey_and_only_the_sky_takes_its_tint(ctx):
    """Under full cloud the sky and its clouds take OVERCAST_SKY_TINT (the deck's light is
    bluer than the sun's the camera is balanced for); the dry ground keeps the light it had
    (it mirrors no sky; glossy materials and wet ground do), and labels, depth and flow stay
    as they were."""
    base = recipe_for("walk", "simple", seconds=SECONDS, variation="none")
    theta = theta_for("walk", "simple", seconds=SECONDS, variation="none")
    settings = {"weather": "overcast", "day_phase": "day", "clock_hour": 13.0, "clouds": True, "cloud_intensity": 1.0,
                "fog": False, "rain": False, "wet_ground": False}  # fmt: skip
    recipe = vary(base, theta, settings)
    tinted = lighting_for(recipe.world, indoor=False)
    assert np.allclose(tinted.sky_tint, OVERCAST_SKY_TINT)
    assert np.array_equal(lighting_for(vary(base, theta, {**settings, "clouds": False}).world, indoor=False).sky_tint,
                          np.ones(3))  # fmt: skip
    tr = simulate(recipe, keep_state=False)
    t = _first_frame(ctx, recipe, tr, tinted)
    n = _first_frame(ctx, recipe, tr, dataclasses.replace(tinted, sky_tint=np.ones(3)))
    frames = {"tinted": t, "neutral": n}
    assert np.array_equal(t.class_id, n.class_id) and np.array_equal(t.depth_m, n.depth_m)
    assert np.array_equal(t.flow, n.flow)
    sky = t.class_id == class_id("sky")
    assert sky.mean() > 0.2
    light = {k: _linear(f.colour, tinted.exposure)[sky].mean(axis=0) for k, f in frames.items()}
    bluer = (light["tinted"][2] / light["tinted"][0]) / (light["neutral"][2] / light["neutral"][0])
    assert bluer == pytest.approx(OVERCAST_SKY_TINT[2] / OVERCAST_SKY_TINT[0], rel=0.05)  # the sun's haze on top
    changed = (t.colour != n.colour).any(axis=-1) & ~sky
    ground = t.class_id == class_id("terrain")
    assert ground.sum() > 500 and not changed[ground].any()
    assert changed.sum() < 0.02 * (~sky).sum()  # glossy materials mirror the sky, a few pixels


def test_fog_under_cloud_takes_the_decks_cool_grey(ctx):
    """Fog under a full overcast scatters the deck's light, so it takes the deck's balance
    (OVERCAST_SKY_TINT) as the sky does: the sky seen through dense fog is the same cool grey
    as the overcast sky in clear air."""
    base = recipe_for("walk", "simple", seconds=SECONDS, variation="none")
    theta = theta_for("walk", "simple", seconds=SECONDS, variation="none")
    settings = {"weather": "fog", "day_phase": "day", "clock_hour": 13.0, "clouds": True, "cloud_intensity": 1.0,
                "fog": True, "fog_intensity": 1.0, "rain": False, "wet_ground": False}  # fmt: skip

    def sky_blue_over_red(changes: dict) -> float:
        recipe = vary(base, theta, {**settings, **changes})
        light = lighting_for(recipe.world, indoor=False)
        frame = _first_frame(ctx, recipe, simulate(recipe, keep_state=False), light)
        sky = frame.class_id == class_id("sky")
        assert sky.mean() > 0.2
        mean = _linear(frame.colour, light.exposure)[sky].mean(axis=0)
        return float(mean[2] / mean[0])

    overcast, foggy = sky_blue_over_red({"fog": False}), sky_blue_over_red({})
    assert foggy == pytest.approx(overcast, rel=0.05)


def test_in_fog_the_camera_meters_the_fogs_light_too():
    """Fog between the camera and its subject is bright (it scatters the sky's light): the
    camera that meters it opens up less than in clear air at the same hour, and by day it
    keeps the base exposure. At dusk it takes the colour of the sky away from the sunset."""
    base = recipe_for("walk", "simple", seconds=SECONDS, variation="none")
    theta = theta_for("walk", "simple", seconds=SECONDS, variation="none")

    def light(weather: str, phase: str, hour: float):
        settings = {"weather": weather, "day_phase": phase, "clock_hour": hour, "rain": False, "wet_ground": False}
        return lighting_for(vary(base, theta, settings).world, indoor=False)

    clear, foggy = light("clear", "dusk", 19.2), light("fog", "dusk", 19.2)
    assert foggy.fog_per_m > 10 * clear.fog_per_m
    assert EXPOSURE < foggy.exposure < 0.8 * clear.exposure
    assert _seen_key(foggy) * foggy.exposure / EXPOSURE == pytest.approx(METER_KEY)
    assert light("fog", "day", 13.0).exposure == EXPOSURE
    # The sunset's glow fills only the sun's quarter of the sky: the fog scattering the whole
    # sky's light is no warmer than it is blue, and the clear air's haze keeps the glow.
    assert foggy.fog_colour[0] <= foggy.fog_colour[2] and clear.fog_colour[0] > clear.fog_colour[2]


def test_the_camera_meters_dim_light_and_keeps_night_dark(ctx):
    """Day keeps the base exposure; at dusk the camera opens up until the light on a white
    horizontal surface reaches METER_KEY (three stops at most); at night it has nothing left.
    Metering changes RGB only: labels, depth and flow stay as they were."""
    base = recipe_for("walk", "simple", seconds=SECONDS, variation="none")
    theta = theta_for("walk", "simple", seconds=SECONDS, variation="none")
    settings = {"weather": "clear", "clouds": False, "fog": False, "rain": False, "wet_ground": False}
    at = {hour: vary(base, theta, {**settings, "day_phase": phase, "clock_hour": hour})
          for phase, hour in (("day", 13.0), ("dusk", 19.2), ("night", 23.0))}  # fmt: skip
    light = {hour: lighting_for(r.world, indoor=False) for hour, r in at.items()}
    assert light[13.0].exposure == EXPOSURE and light[23.0].exposure == EXPOSURE
    dusk = light[19.2]
    assert 2.0 < dusk.exposure / EXPOSURE <= MAX_GAIN
    assert _seen_key(dusk) * dusk.exposure / EXPOSURE == pytest.approx(METER_KEY)
    tr = simulate(at[19.2], keep_state=False)
    m = _first_frame(ctx, at[19.2], tr, dusk)
    f = _first_frame(ctx, at[19.2], tr, dataclasses.replace(dusk, exposure=EXPOSURE))
    assert np.array_equal(m.class_id, f.class_id) and np.array_equal(m.depth_m, f.depth_m)
    assert np.array_equal(m.flow, f.flow)
    ground = m.class_id != class_id("sky")
    assert luma(m.colour)[ground].mean() > 1.5 * luma(f.colour)[ground].mean()


def test_rain_falls_by_the_clips_time_whatever_its_frame_rate():
    """Frame 2k of a 60 fps clip shows the streaks where frame k of a 30 fps clip does, each
    half a frame of motion long: rain falls at its speed in metres per second."""
    origin = np.random.default_rng(0).random((50, 3)) * 10.0
    eye = np.array([1.0, 2.0, 1.5])

    def lines(fps: float, frame: int) -> np.ndarray:
        renderer = type("Renderer", (), {"rain_origin": origin, "fps": fps})()
        return FrameRenderer._rain_lines(renderer, frame, eye).reshape(-1, 2, 3)

    for k in (0, 3, 17):
        slow, fast = lines(30, k), lines(60, 2 * k)
        assert np.allclose(slow[:, 0], fast[:, 0], atol=1e-5)
        assert np.allclose(slow[:, 1] - slow[:, 0], 2.0 * (fast[:, 1] - fast[:, 0]), atol=1e-5)
