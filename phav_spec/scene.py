"""Scene data the later stages must honour, declared as data.

Per action: necessary and complementary muscles, the props it needs, the props the
``objects`` variation may add, the pixel classes its environment must contain. Per
environment: indoor or not, its static pixel classes, the protagonist's waypoints and the
background actors' waypoints (indoor scenes have none, as in the paper). The 20 human models.
The weather elements and their Bernoulli dependencies. The kite camera's spring variables
with their physical bounds. θ chooses distributions inside these declarations; it cannot
change them.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from phav_spec.vocab import (
    ACTIONS,
    CAMERAS,
    ENVIRONMENTS,
    MUSCLES,
    OBJECTS,
    PIXEL_CLASSES,
    Registry,
)

Vec3 = tuple[float, float, float]
RGB = tuple[int, int, int]

#: Where a supporting character starts relative to the protagonist.
SUPPORTING_PLACEMENTS: tuple[str, ...] = ("side_by_side", "behind", "facing")

_CORE = ("pelvis", "chest")
_HEAD = ("head",)
_LEGS = (
    "left_upper_leg", "left_lower_leg", "left_foot",
    "right_upper_leg", "right_lower_leg", "right_foot",
)  # fmt: skip
_LEFT_ARM = ("left_upper_arm", "left_lower_arm", "left_hand")
_RIGHT_ARM = ("right_upper_arm", "right_lower_arm", "right_hand")
_ARMS = _LEFT_ARM + _RIGHT_ARM


@dataclass(frozen=True)
class ActionScene:
    """What an action needs from the scene (paper Sections "Actions", "Ragdoll physics")."""

    necessary_muscles: tuple[str, ...]
    objects: tuple[str, ...] = ()
    variation_objects: tuple[str, ...] = ()
    requires_classes: tuple[str, ...] = ()
    supporting_placement: str | None = None  # side_by_side, behind or facing (two people)
    complementary_muscles: tuple[str, ...] = field(init=False)

    def __post_init__(self) -> None:
        necessary = set(self.necessary_muscles)
        for m in necessary:
            MUSCLES.check(m)
        for o in self.objects + self.variation_objects:
            OBJECTS.check(o)
        for c in self.requires_classes:
            PIXEL_CLASSES.check(c)
        if self.supporting_placement not in (None, *SUPPORTING_PLACEMENTS):
            raise ValueError(f"unknown supporting placement {self.supporting_placement!r}")
        # Complementary = the rest of the 15, in registry order: the two groups are disjoint
        # and cover the ragdoll (paper: "two disjoint groups").
        rest = tuple(m for m in MUSCLES.names if m not in necessary)
        object.__setattr__(self, "necessary_muscles", tuple(m for m in MUSCLES.names if m in necessary))
        object.__setattr__(self, "complementary_muscles", rest)


_HANDHELD = ("cup", "bottle", "ball")


def _action_scenes() -> tuple[tuple[str, ActionScene], ...]:
    s = ActionScene
    scenes = {
        "brush_hair": s(_RIGHT_ARM + _HEAD + ("chest",), objects=("hair_brush",), variation_objects=("cup", "bottle")),
        "catch": s(_ARMS + _HEAD + ("chest",), objects=("ball",)),
        "clap": s(_ARMS + ("chest",)),
        "climb_stairs": s(_LEGS + _CORE, variation_objects=_HANDHELD, requires_classes=("stairs",)),
        "golf": s(_ARMS + _CORE + _HEAD, objects=("golf_club",)),
        "jump": s(_LEGS + _CORE, variation_objects=_HANDHELD),
        "kick_ball": s(_LEGS + ("pelvis",), objects=("ball",), variation_objects=("cup", "bottle")),
        "push": s(_ARMS + _CORE + _LEGS),
        "pick": s(_RIGHT_ARM + _CORE + _LEGS, objects=("bottle",), variation_objects=("cup", "ball")),
        "pour": s(_ARMS + ("chest",), objects=("bottle", "cup")),
        "pull_up": s(_ARMS + ("chest",), objects=("pull_up_bar",)),
        "run": s(_LEGS + ("pelvis",), variation_objects=_HANDHELD),
        "shoot_ball": s(_ARMS + _LEGS + ("chest",), objects=("ball",)),
        "shoot_bow": s(_ARMS + _HEAD + ("chest",), objects=("bow",)),
        "shoot_gun": s(_ARMS + _HEAD + ("chest",), objects=("gun",)),
        "sit": s(_LEGS + _CORE, objects=("chair",), variation_objects=("cup", "bottle")),
        "stand": s(_LEGS + _CORE, objects=("chair",), variation_objects=("cup", "bottle")),
        "swing_baseball": s(_ARMS + _CORE, objects=("baseball_bat",)),
        "throw": s(_RIGHT_ARM + _CORE, objects=("ball",)),
        "walk": s(_LEGS + ("pelvis",), variation_objects=_HANDHELD),
        "wave": s(_RIGHT_ARM, variation_objects=("cup", "bottle")),
        "car_hit": s(_LEGS + _CORE, objects=("car",), variation_objects=_HANDHELD, requires_classes=("road",)),
        "crawl": s(_ARMS + _LEGS + _CORE),
        "dive_floor": s(_ARMS + _CORE, variation_objects=("ball",)),
        "flee": s(_LEGS + _CORE + _HEAD, variation_objects=_HANDHELD),
        "hop": s(_LEGS + ("pelvis",), variation_objects=_HANDHELD),
        "leg_split": s(_LEGS + ("pelvis",), variation_objects=("cup", "bottle")),
        "limp": s(_LEGS + ("pelvis",), variation_objects=_HANDHELD),
        "moonwalk": s(_LEGS + ("pelvis",), variation_objects=("cup", "bottle")),
        "stagger": s(_LEGS + _CORE + _HEAD, variation_objects=("bottle",)),
        "surrender": s(_ARMS + ("chest",), variation_objects=("bottle",)),
        "walking_hug": s(_ARMS + _LEGS + _CORE, supporting_placement="side_by_side"),
        "walk_holding_hands": s(_RIGHT_ARM + _LEGS + ("pelvis",), variation_objects=("cup", "bottle"), supporting_placement="side_by_side"),
        "walk_the_line": s(_LEGS + ("pelvis",), variation_objects=_HANDHELD, supporting_placement="behind"),
        "bump_into_each_other": s(_LEGS + _CORE, variation_objects=_HANDHELD, supporting_placement="facing"),
    }  # fmt: skip
    for name, scene in scenes.items():
        if (ACTIONS[name].n_people > 1) != (scene.supporting_placement is not None):
            raise ValueError(f"{name}: a supporting placement is declared exactly for two-people actions")
    return tuple((name, scenes[name]) for name in ACTIONS.names)


#: Per-action scene data, in ACTIONS order.
ACTION_SCENES: Registry[ActionScene] = Registry("action", _action_scenes())


@dataclass(frozen=True)
class EnvironmentScene:
    """An environment: indoor or not, its static pixel classes and its two waypoint graphs."""

    indoor: bool
    pixel_classes: tuple[str, ...]
    protagonist_waypoints: tuple[Vec3, ...]
    background_waypoints: tuple[Vec3, ...]

    def __post_init__(self) -> None:
        for c in self.pixel_classes:
            PIXEL_CLASSES.check(c)
        if not self.protagonist_waypoints:
            raise ValueError("an environment needs at least one protagonist waypoint")
        if self.indoor and self.background_waypoints:
            raise ValueError("indoor scenes have no background-actor waypoint graph")
        if not self.indoor and len(self.background_waypoints) < 2:
            raise ValueError("an outdoor background graph needs a start and a destination")


_OUTDOOR_BASE = ("sky", "terrain", "misc")


def _grid(xs: tuple[float, ...], ys: tuple[float, ...], z: float = 0.0) -> tuple[Vec3, ...]:
    return tuple((x, y, z) for x in xs for y in ys)


#: Environments in ENVIRONMENTS order; coordinates in metres, MuJoCo world frame (+Z up).
ENVIRONMENT_SCENES: Registry[EnvironmentScene] = Registry(
    "environment",
    (
        (
            "simple",
            EnvironmentScene(
                indoor=False,
                pixel_classes=(*_OUTDOOR_BASE, "road"),
                protagonist_waypoints=_grid((-4.0, 0.0, 4.0), (-3.0, 3.0)),
                background_waypoints=_grid((-20.0, 20.0), (-15.0, 0.0, 15.0)),
            ),
        ),
        (
            "urban",
            EnvironmentScene(
                indoor=False,
                pixel_classes=(
                    *_OUTDOOR_BASE,
                    "road",
                    "building",
                    "pole",
                    "traffic_light",
                    "traffic_sign",
                    "vegetation",
                    "tree",
                    "car",
                    "truck",
                    "bus",
                    "guard_rail",
                    "stairs",
                    "bench",
                ),
                protagonist_waypoints=(
                    (2.0, 6.0, 0.0),
                    (12.0, 6.0, 0.0),
                    (22.0, 6.5, 0.0),
                    (-8.0, 6.0, 0.0),
                    (5.0, -6.0, 0.0),
                    (15.0, -6.5, 0.0),
                    (30.0, 10.0, 0.6),
                ),
                background_waypoints=(
                    (-30.0, 7.0, 0.0),
                    (-10.0, 7.5, 0.0),
                    (10.0, 7.0, 0.0),
                    (35.0, 7.0, 0.0),
                    (-30.0, -7.0, 0.0),
                    (0.0, -7.5, 0.0),
                    (35.0, -7.0, 0.0),
                    (40.0, 12.0, 0.6),
                ),
            ),
        ),
        (
            "green",
            EnvironmentScene(
                indoor=False,
                pixel_classes=(*_OUTDOOR_BASE, "vegetation", "tree", "bench", "pole"),
                protagonist_waypoints=(
                    (0.0, 0.0, 0.0),
                    (8.0, 3.0, 0.1),
                    (-6.0, 5.0, 0.0),
                    (3.0, -8.0, -0.1),
                    (-9.0, -4.0, 0.0),
                    (12.0, -2.0, 0.2),
                ),
                background_waypoints=(
                    (-25.0, 0.0, 0.0),
                    (25.0, 0.0, 0.2),
                    (0.0, 25.0, 0.0),
                    (0.0, -25.0, -0.2),
                    (18.0, 18.0, 0.1),
                    (-18.0, -18.0, 0.0),
                ),
            ),
        ),
        (
            "middle",
            EnvironmentScene(
                indoor=False,
                pixel_classes=(
                    *_OUTDOOR_BASE,
                    "road",
                    "vegetation",
                    "tree",
                    "pole",
                    "traffic_sign",
                    "guard_rail",
                    "car",
                    "building",
                ),
                protagonist_waypoints=(
                    (0.0, 5.0, 0.0),
                    (10.0, 5.5, 0.0),
                    (-10.0, 5.0, 0.0),
                    (20.0, -5.0, 0.0),
                    (-20.0, -5.5, 0.0),
                ),
                background_waypoints=(
                    (-40.0, 6.0, 0.0),
                    (40.0, 6.0, 0.0),
                    (-40.0, -6.0, 0.0),
                    (40.0, -6.0, 0.0),
                    (0.0, 30.0, 0.5),
                ),
            ),
        ),
        (
            "lake",
            EnvironmentScene(
                indoor=False,
                pixel_classes=(*_OUTDOOR_BASE, "vegetation", "tree", "bench"),
                protagonist_waypoints=(
                    (0.0, -12.0, 0.2),
                    (10.0, -10.0, 0.2),
                    (-10.0, -11.0, 0.2),
                    (16.0, 0.0, 0.3),
                    (-16.0, 2.0, 0.3),
                ),
                background_waypoints=(
                    (-30.0, -14.0, 0.2),
                    (30.0, -14.0, 0.2),
                    (22.0, 14.0, 0.3),
                    (-22.0, 14.0, 0.3),
                    (0.0, 20.0, 0.4),
                ),
            ),
        ),
        (
            "stadium",
            EnvironmentScene(
                indoor=False,
                pixel_classes=(*_OUTDOOR_BASE, "building", "pole", "stairs", "bench", "guard_rail"),
                protagonist_waypoints=_grid((-20.0, 0.0, 20.0), (-8.0, 8.0)) + ((0.0, 32.0, 1.5),),
                background_waypoints=(
                    (-45.0, 0.0, 0.0),
                    (45.0, 0.0, 0.0),
                    (0.0, -30.0, 0.0),
                    (0.0, 30.0, 0.0),
                    (-30.0, 20.0, 0.0),
                    (30.0, -20.0, 0.0),
                ),
            ),
        ),
        (
            "house_interior",
            EnvironmentScene(
                indoor=True,
                pixel_classes=(
                    "ceiling",
                    "floor",
                    "chair",
                    "table",
                    "bed",
                    "lamp",
                    "sofa",
                    "window",
                    "door",
                    "stairs",
                    "curtain",
                    "fireplace",
                    "shelf",
                    "bench",
                    "screen",
                    "fridge",
                    "misc",
                ),
                protagonist_waypoints=(
                    (0.0, 0.0, 0.0),
                    (2.5, 1.0, 0.0),
                    (-2.0, 1.5, 0.0),
                    (1.0, -2.0, 0.0),
                    (-2.5, -1.5, 0.0),
                    (4.0, 3.0, 0.0),
                ),
                background_waypoints=(),
            ),
        ),
    ),
)


@dataclass(frozen=True)
class HumanModel:
    """A protagonist / actor body: shape (ragdoll proportions, mass) and appearance."""

    height_m: float
    mass_kg: float
    shoulder_width_m: float
    hip_width_m: float
    limb_girth: float  # scale on the default capsule radii
    skin_rgb: RGB
    hair_rgb: RGB
    hair_style: str  # short, long, bald, ponytail
    top_rgb: RGB
    bottom_rgb: RGB
    shoes_rgb: RGB


def _human_models() -> tuple[tuple[str, HumanModel], ...]:
    h = HumanModel
    rows = [
        h(1.78, 76.0, 0.41, 0.33, 1.00, (224, 172, 105), (60, 40, 20), "short", (30, 60, 140), (40, 40, 50), (20, 20, 20)),
        h(1.65, 58.0, 0.36, 0.35, 0.92, (241, 194, 125), (170, 120, 60), "long", (200, 40, 60), (30, 30, 90), (240, 240, 240)),
        h(1.83, 88.0, 0.45, 0.35, 1.12, (141, 85, 36), (20, 15, 10), "short", (240, 240, 240), (60, 70, 60), (80, 50, 30)),
        h(1.58, 52.0, 0.35, 0.34, 0.88, (255, 219, 172), (230, 200, 120), "ponytail", (120, 200, 120), (90, 60, 40), (200, 30, 30)),
        h(1.90, 95.0, 0.47, 0.36, 1.15, (198, 134, 66), (40, 30, 25), "bald", (90, 90, 90), (20, 30, 60), (30, 30, 30)),
        h(1.72, 66.0, 0.39, 0.34, 0.97, (92, 51, 23), (10, 10, 10), "short", (250, 200, 40), (50, 50, 50), (250, 250, 250)),
        h(1.69, 62.0, 0.37, 0.36, 0.95, (224, 172, 105), (120, 60, 30), "long", (60, 20, 80), (20, 20, 20), (120, 80, 40)),
        h(1.76, 80.0, 0.42, 0.35, 1.05, (255, 224, 189), (200, 170, 100), "short", (180, 30, 30), (200, 190, 150), (60, 40, 20)),
        h(1.62, 70.0, 0.37, 0.38, 1.08, (141, 85, 36), (30, 20, 15), "ponytail", (30, 140, 140), (70, 70, 110), (30, 30, 30)),
        h(1.86, 84.0, 0.44, 0.35, 1.06, (241, 194, 125), (90, 60, 30), "short", (20, 20, 20), (20, 20, 20), (220, 220, 220)),
        h(1.55, 49.0, 0.34, 0.33, 0.85, (198, 134, 66), (15, 10, 5), "long", (255, 150, 180), (240, 240, 240), (200, 160, 120)),
        h(1.80, 73.0, 0.42, 0.33, 0.98, (92, 51, 23), (5, 5, 5), "bald", (0, 90, 160), (150, 120, 80), (40, 40, 40)),
        h(1.70, 90.0, 0.43, 0.39, 1.20, (255, 219, 172), (140, 140, 140), "short", (100, 120, 60), (40, 40, 60), (90, 60, 30)),
        h(1.67, 60.0, 0.36, 0.35, 0.93, (224, 172, 105), (60, 30, 10), "ponytail", (240, 120, 20), (30, 50, 100), (250, 250, 250)),
        h(1.93, 100.0, 0.48, 0.37, 1.18, (141, 85, 36), (25, 20, 15), "short", (160, 0, 40), (50, 50, 50), (20, 20, 20)),
        h(1.60, 55.0, 0.35, 0.34, 0.90, (255, 224, 189), (210, 180, 110), "long", (170, 210, 240), (60, 40, 30), (140, 30, 30)),
        h(1.74, 71.0, 0.40, 0.34, 0.99, (198, 134, 66), (50, 35, 20), "short", (70, 70, 70), (120, 100, 70), (50, 50, 50)),
        h(1.82, 82.0, 0.44, 0.35, 1.04, (255, 219, 172), (180, 80, 30), "short", (40, 110, 40), (30, 30, 40), (200, 200, 200)),
        h(1.64, 64.0, 0.37, 0.37, 1.00, (92, 51, 23), (15, 10, 10), "long", (230, 230, 200), (110, 30, 60), (30, 30, 30)),
        h(1.77, 78.0, 0.42, 0.34, 1.02, (241, 194, 125), (100, 100, 100), "bald", (20, 40, 80), (80, 80, 80), (120, 90, 60)),
    ]  # fmt: skip
    return tuple((f"model_{i + 1:02d}", row) for i, row in enumerate(rows))


#: The 20 human models (paper Table "key random variables": H, 20 artist-designed models).
HUMAN_MODELS: Registry[HumanModel] = Registry("human model", _human_models())


@dataclass(frozen=True)
class WeatherElement:
    """A boolean weather element; its activation may depend on one earlier element."""

    parent: str | None
    description: str


#: Boolean weather elements in sampling order (parents first). The paper's example: fog
#: visibility influences cloud activation through a Bernoulli (Section "Weather elements").
WEATHER_ELEMENTS: Registry[WeatherElement] = Registry(
    "weather element",
    (
        ("rain", WeatherElement(None, "rain particles visible")),
        ("fog", WeatherElement(None, "volumetric fog visible")),
        ("clouds", WeatherElement("fog", "cloud layer visible")),
        ("wet_ground", WeatherElement("rain", "ground material wet and reflective")),
    ),
)

#: Continuous weather parameters: name → (lower bound, upper bound) a θ range must respect.
WEATHER_LEVELS: dict[str, tuple[float, float]] = {
    "sun_brightness": (0.0, 2.0),
    "ambient_luminosity": (0.0, 2.0),
    "cloud_intensity": (0.0, 1.0),
    "fog_intensity": (0.0, 1.0),
    "rain_intensity": (0.0, 1.0),
}


@dataclass(frozen=True)
class CameraInfo:
    """How a camera behaves: spring-tracked (kite), panning on a fixed mount, or fixed."""

    tracking: str  # "springs" | "pan" | "fixed"
    indoor_only: bool


CAMERA_INFO: Registry[CameraInfo] = Registry(
    "camera",
    (
        ("kite", CameraInfo("springs", indoor_only=False)),
        ("indoors", CameraInfo("pan", indoor_only=True)),
        ("closeup", CameraInfo("springs", indoor_only=False)),
        ("static", CameraInfo("fixed", indoor_only=False)),
    ),
)
assert CAMERA_INFO.names == CAMERAS.names and ENVIRONMENT_SCENES.names == ENVIRONMENTS.names

#: Kite camera spring variables (paper Section "Camera placement and parameters": CT_s,
#: CT_m, TP_s, ...): name → (unit, lower bound, upper bound) a θ range must respect. Spring
#: strengths beyond 1e5 N/m need the implicit integrator and are refused here.
KITE_SPRING_VARIABLES: dict[str, tuple[str, float, float]] = {
    "ct_spring_strength": ("N/m", 0.1, 1.0e5),
    "tp_spring_strength": ("N/m", 0.1, 1.0e5),
    "camera_mass": ("kg", 0.01, 100.0),
    "target_mass": ("kg", 0.01, 100.0),
    "camera_drag": ("1/s", 0.0, 50.0),
    "target_drag": ("1/s", 0.0, 50.0),
}

#: The spring dead zone (minimum distance at which a spring starts pulling), metres.
SPRING_MIN_DISTANCES_M: tuple[int, ...] = (0, 1, 2)

#: Camera placement variables: name → (unit, lower bound, upper bound).
CAMERA_PLACEMENT_VARIABLES: dict[str, tuple[str, float, float]] = {
    "fov_deg": ("deg", 10.0, 120.0),
    "distance_m": ("m", 0.3, 60.0),
    "height_m": ("m", -2.0, 30.0),
    "azimuth_deg": ("deg", -360.0, 360.0),
}

#: Bounds of the other continuous parameters θ may set: name → (unit, lower, upper). A
#: recipe outside them would be physically meaningless (negative speeds, periods of zero).
PARAMETER_BOUNDS: dict[str, tuple[str, float, float]] = {
    "motion_speed": ("×", 0.1, 5.0),
    "heading_deg": ("deg", -360.0, 720.0),
    "background_speed_mps": ("m/s", 0.1, 5.0),
    "supporting_distance_m": ("m", 0.2, 50.0),
    "perturbation_radius_m": ("m", 0.0, 2.0),
    "perturbation_period_s": ("s", 0.05, 60.0),
    "weakening_strength": ("fraction", 0.0, 1.0),
    "blending_weight": ("fraction", 0.0, 1.0),
    "impulse_strength": ("N·s", 0.0, 1000.0),
    "impulse_azimuth_deg": ("deg", -360.0, 360.0),
    "impulse_elevation_deg": ("deg", -90.0, 90.0),
}

#: Most background pedestrians one scene may hold.
MAX_BACKGROUND_ACTORS = 50
