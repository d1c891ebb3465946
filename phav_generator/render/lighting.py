"""Light and weather of a recipe's world: sun from the clock, sky, ambient, fog, rain, lamps.

Everything is a pure function of the recipe's ``WorldSpec`` (and indoor or not): the sun
stands where the clock puts it at a fixed latitude and date, overcast and rain dim and
flatten it, fog thickens with ``fog_intensity``, dusk and night switch the street lamps on.
Colours are linear RGB in [0, 1] before the renderer's tone curve.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from phav_spec.recipe import WorldSpec

#: Where and when the sun is computed: latitude 45° N, solar declination −10° (an autumn
#: day), on a clock whose solar noon is 13:30 (summer time west in its zone). θ's dawn and
#: dusk hours (7–10 h, mode 9; 17–20 h, mode 18) mirror each other about 13:30, so on this
#: clock they are the same light: sunrise ≈ 8:10 and sunset ≈ 18:50, each phase low sun and
#: twilight down to 12° below the horizon, and night (20–7 h) dark.
LATITUDE_DEG = 45.0
DECLINATION_DEG = -10.0
SOLAR_NOON_H = 13.5
#: Fog extinction per metre: a light haze always (a dark object fades out 2 km away), plus
#: fog. Fog is what keeps one from seeing a kilometre (the meteorologists' definition); θ's
#: fog intensity runs evenly in the logarithm of that visibility from light fog at 0 to dense
#: fog at 1, in which a dark object is lost 40 m away.
HAZE_PER_M = 0.0015
FOG_VISIBILITY_M = (1000.0, 40.0)
#: Koschmieder's law: a dark object's contrast falls to 5 % at ``VISIBILITY_CONTRAST / β``.
VISIBILITY_CONTRAST = 3.0
#: Most lamps the shader takes (the nearest to the action are kept).
MAX_LAMPS = 16
#: The tone curve's exposure (1 − exp(−exposure·c)) in good light.
EXPOSURE = 1.6
#: The camera meters the light, as a real one does: where the light on a white horizontal
#: surface (the luminance of the sky's ambient and the direct sun) falls below ``METER_KEY``
#: (an overcast day's), it opens up to bring it there, by at most ``MAX_GAIN`` (three stops).
#: Its reserve runs out as the sun sinks from 8° to 18° below the horizon: night stays dark.
METER_KEY = 0.4
MAX_GAIN = 8.0
#: In fog the camera sees the fog's own light as much as the lit scene: the meter weighs the
#: fog colour by how much of it lies between the camera and a subject this far away (m).
METER_DISTANCE_M = 15.0
_LUMINANCE = (0.2126, 0.7152, 0.0722)
#: An overcast deck's colour through the camera's daylight balance, in linear RGB: the light
#: of a sky under cloud (6500–7000 K) is bluer than the sun's the camera is balanced for
#: (about 5500 K), so an overcast sky reads a cool grey, not a neutral one. This is CIE
#: daylight of about 6300 K seen so (6500 K's would be 0.89, 1, 1.20): the warm end. It
#: multiplies the sky and its clouds, also where water and gloss mirror them, and the fog and
#: haze under them, as cloud closes over it (with the clouds' cover squared, as the grey does).
OVERCAST_SKY_TINT = (0.88, 1.0, 1.12)


def _smoothstep(e0: float, e1: float, x: float) -> float:
    t = min(max((x - e0) / (e1 - e0), 0.0), 1.0)
    return t * t * (3.0 - 2.0 * t)


def _mix(a, b, t: float) -> np.ndarray:
    return np.asarray(a, dtype=np.float64) * (1.0 - t) + np.asarray(b, dtype=np.float64) * t


def sun_direction(clock_hour: float) -> np.ndarray:
    """Unit vector towards the sun in the world frame (+X east, +Y north, +Z up)."""
    phi, delta = math.radians(LATITUDE_DEG), math.radians(DECLINATION_DEG)
    h = math.radians(15.0 * (clock_hour - SOLAR_NOON_H))
    v = np.array([
        -math.cos(delta) * math.sin(h),
        math.sin(delta) * math.cos(phi) - math.cos(delta) * math.sin(phi) * math.cos(h),
        math.sin(delta) * math.sin(phi) + math.cos(delta) * math.cos(phi) * math.cos(h),
    ])  # fmt: skip
    return v / np.linalg.norm(v)


@dataclass(frozen=True)
class Lighting:
    """Uniforms of the scene shader and the post-processing pass for one video."""

    sun_dir: np.ndarray  # (3,) towards the sun
    sun_colour: np.ndarray  # (3,) irradiance colour × intensity (0 below the horizon)
    sky_ambient: np.ndarray  # (3,) light from the upper hemisphere
    ground_ambient: np.ndarray  # (3,) light bounced from below
    sky_zenith: np.ndarray  # (3,)
    sky_horizon: np.ndarray  # (3,) away from the sun
    fog_colour: np.ndarray  # (3,)
    fog_per_m: float  # extinction coefficient
    wetness: float  # 0 dry … 1 soaked ground (darker, reflecting as water does)
    rain: float  # 0 … 1: streak density
    lamp_intensity: float  # street/indoor lamps, 0 off
    daylight: float  # 0 night … 1 full day
    cloud_cover: float = 0.0  # 0 clear … 1 overcast: how much of the sky the clouds drawn in it cover
    sky_glow: np.ndarray = field(default_factory=lambda: np.zeros(3))  # (3,) added low towards the sun
    sky_tint: np.ndarray = field(default_factory=lambda: np.ones(3))  # (3,) the sky's and its clouds' colour balance
    exposure: float = EXPOSURE  # the tone curve's, as the camera metered the light

    @property
    def shadows(self) -> bool:
        return float(self.sun_colour.max()) > 0.02


def lighting_for(world: WorldSpec, *, indoor: bool) -> Lighting:
    """The light and weather the renderer uses for a recipe's world."""
    sun = sun_direction(world.clock_hour)
    elevation = math.degrees(math.asin(float(sun[2])))
    daylight = 0.02 + 0.98 * _smoothstep(-12.0, 12.0, elevation)  # civil twilight to day
    clouds = world.cloud_intensity if world.clouds else 0.0
    fog = world.fog_intensity if world.fog else 0.0
    rain = world.rain_intensity if world.rain else 0.0
    # Direct sun: up above the horizon, warm when low, dimmed by clouds, fog and rain.
    above = _smoothstep(-1.0, 6.0, elevation)
    warm = _mix((1.0, 0.55, 0.3), (1.0, 0.96, 0.9), _smoothstep(0.0, 25.0, elevation))
    veil = (1.0 - 0.85 * clouds) * (1.0 - 0.6 * fog) * (1.0 - 0.5 * rain)
    sun_colour = warm * (1.1 * world.sun_brightness * above * veil)
    # Sky: blue by day, dark blue at night; near sunrise and sunset an orange glow low in the
    # sun's quarter (the sky shader spreads it by azimuth) and a faint pink band opposite, the
    # sky above both still blue. Clouds grey it.
    twilight = _smoothstep(-10.0, 3.0, elevation) * (1.0 - _smoothstep(3.0, 20.0, elevation))
    zenith = _mix((0.02, 0.03, 0.07), (0.22, 0.42, 0.85), daylight)
    clear_horizon = _mix((0.03, 0.04, 0.08), (0.68, 0.78, 0.92), daylight)
    glowing = _mix(clear_horizon, (0.95, 0.55, 0.3), 0.7 * twilight)
    horizon = _mix(clear_horizon, (0.9, 0.72, 0.75), 0.2 * twilight)
    grey = np.array([0.62, 0.64, 0.67]) * daylight
    # Broken cloud leaves the sky between the clouds blue (the sky shader draws the clouds);
    # only an overcast sky turns grey.
    overcast = clouds**2
    zenith, horizon = _mix(zenith, grey, overcast), _mix(horizon, grey * 1.05, overcast)
    glowing = _mix(glowing, grey * 1.05, overcast)
    glow = (glowing - horizon) * 1.3  # straight towards the sun, more than the haze's average
    # Ambient: the sky's light, flatter and stronger under cloud: an overcast sky lights the
    # ground from its whole dome, brightest overhead, so a white surface on the ground
    # outshines the sky at the horizon (2.3× under the CIE's overcast sky).
    level = world.ambient_luminosity * (0.04 + 0.5 * daylight) * (1.0 + 0.8 * clouds)
    sky_ambient = _mix(zenith / max(float(zenith.max()), 1e-6), np.ones(3), 0.5 + 0.5 * clouds) * level
    ground_ambient = np.array([0.45, 0.42, 0.38]) * level * 0.5
    # Fog scatters the whole sky's light: the glow fills a quarter of the horizon, the fog
    # takes the colour of the rest. Without fog, the haze keeps the glow's.
    fog_colour = _mix(horizon, grey + 0.05 * daylight, 0.6) if fog else glowing
    # Under cloud, fog and haze scatter the deck's light: they take its balance, as the sky
    # they veil does.
    fog_colour = fog_colour * _mix(np.ones(3), OVERCAST_SKY_TINT, overcast)
    lamps = 1.0 - _smoothstep(-4.0, 8.0, elevation)  # on from dusk, full at night
    if indoor:
        lamps = 1.0
        sky_ambient = sky_ambient * 0.4 + np.array([0.22, 0.2, 0.17])
        ground_ambient = ground_ambient * 0.4 + np.array([0.08, 0.075, 0.07])
    wetness = 0.0 if indoor else (1.0 if world.wet_ground else 0.0) * (0.6 + 0.4 * max(rain, 0.5))
    sun_colour = sun_colour if not indoor else sun_colour * 0.35
    foggy = world.fog and not indoor  # no fog or rain inside a house
    fog_per_m = HAZE_PER_M + (fog_extinction(world.fog_intensity) if foggy else 0.0)
    return Lighting(
        sun_dir=sun,
        sun_colour=sun_colour,
        sky_ambient=sky_ambient,
        ground_ambient=ground_ambient,
        sky_zenith=zenith,
        sky_horizon=horizon,
        fog_colour=fog_colour,
        fog_per_m=fog_per_m,
        wetness=wetness,
        rain=0.0 if indoor else rain,
        lamp_intensity=lamps,
        daylight=daylight,
        cloud_cover=clouds,
        sky_glow=glow,
        sky_tint=_mix(np.ones(3), OVERCAST_SKY_TINT, overcast),
        exposure=metered_exposure(sky_ambient, sun_colour, sun, elevation, fog_colour, fog_per_m),
    )


def fog_extinction(intensity: float) -> float:
    """Extinction per metre (β) of fog of θ's ``intensity`` in [0, 1], from its visibility."""
    light, dense = FOG_VISIBILITY_M
    return VISIBILITY_CONTRAST / (light * (dense / light) ** intensity)


def metered_exposure(sky_ambient: np.ndarray, sun_colour: np.ndarray, sun: np.ndarray, elevation_deg: float,
                     fog_colour: np.ndarray, fog_per_m: float) -> float:  # fmt: skip
    """The tone curve's exposure the camera sets for a scene lit by ``sky_ambient`` and the
    sun (``sun_colour`` from direction ``sun``, ``elevation_deg`` above the horizon), seen
    through fog of ``fog_colour`` and extinction ``fog_per_m``: constant over a video, as its
    light is."""
    up = max(float(sun[2]), 0.0)
    # scalar products in a fixed order: no BLAS or SIMD summation decides the exposure's bits
    key = sum(w * (float(a) + float(s) * up) for w, a, s in zip(_LUMINANCE, sky_ambient, sun_colour, strict=True))
    seen = math.exp(-fog_per_m * METER_DISTANCE_M)
    key = key * seen + sum(w * float(c) for w, c in zip(_LUMINANCE, fog_colour, strict=True)) * (1.0 - seen)
    reserve = 1.0 + (MAX_GAIN - 1.0) * _smoothstep(-18.0, -8.0, elevation_deg)
    return EXPOSURE * min(max(METER_KEY / max(key, 1e-6), 1.0), reserve)
