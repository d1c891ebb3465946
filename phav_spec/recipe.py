"""The recipe: everything one video depends on, frozen before any physics or pixels.

Schema version 2: people are anny phenotypes with skin, hair and outfit (version 1 gave
them metric shapes and flat colours; its recipes upgrade to version 2). A recipe names
every variable of the paper's model and every parameter a later stage needs, including
integer seeds for anything decided at run time, so a renderer given the recipe alone
reproduces the video. Older schema versions are upgraded by the migration registry; a
newer one is refused with a clear message.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from pathlib import Path
from typing import Annotated, Any, Literal

from pydantic import AfterValidator, BaseModel, ConfigDict, Field, StrictInt, model_validator

from phav_spec.encoding import MAX_PERSON_ID
from phav_spec.errors import PhavUserError, validate_user_data
from phav_spec.files import parse_json_object, read_text
from phav_spec.motions import MOTIONS
from phav_spec.people import Hair, Outfit, PersonDraws, Phenotype
from phav_spec.scene import (
    CAMERA_INFO,
    CAMERA_PLACEMENT_VARIABLES,
    ENVIRONMENT_SCENES,
    HUMAN_MODELS,
    KITE_SPRING_VARIABLES,
    MAX_CAMERA_KICK_MPS,
    PARAMETER_BOUNDS,
    WEATHER_LEVELS,
)
from phav_spec.theta import MAX_FPS, MAX_FRAME_SIDE, MIN_FRAME_SIDE, RenderSettings
from phav_spec.vocab import (
    ACTIONS,
    CAMERAS,
    DAY_PHASES,
    ENVIRONMENTS,
    MUSCLES,
    OBJECTS,
    WEATHERS,
    Registry,
)

RECIPE_SCHEMA_VERSION = 3
_FROZEN = ConfigDict(extra="forbid", frozen=True)
Finite = Annotated[float, Field(allow_inf_nan=False)]
Vec3 = tuple[Finite, Finite, Finite]
RGB = tuple[
    Annotated[int, Field(ge=0, le=255)],
    Annotated[int, Field(ge=0, le=255)],
    Annotated[int, Field(ge=0, le=255)],
]
Seed = Annotated[StrictInt, Field(ge=0, lt=2**32)]  # `true` is no seed
#: A spring's dead zone (m): `true` is no distance.
DeadZone = Annotated[StrictInt, Field(ge=0, le=2)]
#: A count or index the recipe table stores as int64.
Int64 = Annotated[StrictInt, Field(ge=0, lt=2**63)]
#: A person's id: its instance colour exists for 1 … ``MAX_PERSON_ID`` (0 is the protagonist).
PersonId = Annotated[int, Field(ge=1, le=MAX_PERSON_ID)]


def _within(bounds: tuple[float, float] | tuple[str, float, float]) -> Any:
    """A finite number inside the bounds θ keeps the parameter's distribution in (a recipe
    outside them is not one θ can give, and the renderer or physics could not honour it)."""
    lo, hi = bounds[-2:]
    return Annotated[float, Field(ge=lo, le=hi, allow_inf_nan=False)]


def _one_of(registry: Registry) -> Any:
    """A Literal over a registry's names: validated in pydantic-core, listed in JSON Schema."""
    return Literal[registry.names]


ActionName = _one_of(ACTIONS)
CameraName = _one_of(CAMERAS)
DayPhaseName = _one_of(DAY_PHASES)
EnvironmentName = _one_of(ENVIRONMENTS)
#: A person is one of the 20 fixed models of H, or drawn from θ's ``people`` section.
SAMPLED_PERSON = "sampled"
HumanModelName = Literal[(*HUMAN_MODELS.names, SAMPLED_PERSON)]
MotionName = _one_of(MOTIONS)
MuscleName = _one_of(MUSCLES)
ObjectName = _one_of(OBJECTS)
WeatherName = _one_of(WEATHERS)


def _distinct(values: tuple[str, ...]) -> tuple[str, ...]:
    if len(set(values)) != len(values):
        raise ValueError(f"duplicate muscle in {list(values)}")
    return values


Muscles = Annotated[tuple[MuscleName, ...], Field(min_length=1), AfterValidator(_distinct)]


class HumanSpec(BaseModel):
    """A person's body and look, realised: everything the body model and the renderer need.

    ``model`` names the fixed human model of H the person is (its phenotype and appearance
    copied in, so the recipe is complete), or is ``"sampled"`` for a person θ drew
    continuously; then ``sampled`` holds the draws in θ's units. The metric shape (stature,
    limb lengths, masses) comes from the phenotype through the body model.
    """

    model_config = _FROZEN
    model: HumanModelName
    phenotype: Phenotype
    skin_rgb: RGB
    hair: Hair
    outfit: Outfit
    sampled: PersonDraws | None = None

    @model_validator(mode="after")
    def _draws_iff_sampled(self) -> HumanSpec:
        if (self.model == SAMPLED_PERSON) != (self.sampled is not None):
            raise ValueError(f"sampled: set exactly when model is {SAMPLED_PERSON!r}")
        return self


class Protagonist(BaseModel):
    """The main human model performing the action, at waypoint P_W."""

    model_config = _FROZEN
    person_id: Literal[0] = 0
    human: HumanSpec
    position: Vec3
    heading_deg: Finite


class SupportingCharacter(BaseModel):
    """An actor whose part completes the action (hold hands, hug, bump into)."""

    model_config = _FROZEN
    person_id: PersonId
    human: HumanSpec
    placement: Literal["side_by_side", "behind", "facing"]
    distance_m: Finite
    position: Vec3
    heading_deg: Finite


class BackgroundActor(BaseModel):
    """A pedestrian walking from one background waypoint to another."""

    model_config = _FROZEN
    person_id: PersonId
    human: HumanSpec
    start_waypoint: Int64
    destination_waypoint: Int64
    start: Vec3
    destination: Vec3
    speed_mps: _within(PARAMETER_BOUNDS["background_speed_mps"])


class MotionSpec(BaseModel):
    """The base motion B and how it is played back.

    The clip plays ``duration_s · speed`` seconds of the motion from ``start_s``. The clip
    length L never exceeds the motion's length, but a speed above 1 can ask for more motion
    than remains; playback then wraps to the motion's start (catalogue motions are cycles
    or end at rest), which the animation stage implements.
    """

    model_config = _FROZEN
    base_motion: MotionName
    base_motion_length_s: Finite = Field(gt=0.0)
    start_s: Finite = Field(ge=0.0)
    speed: _within(PARAMETER_BOUNDS["motion_speed"])
    mirror: bool

    @model_validator(mode="after")
    def _starts_within_the_take(self) -> MotionSpec:
        length = MOTIONS[self.base_motion].length_s
        if self.base_motion_length_s != length:  # the start and the clip are checked against it
            raise ValueError(
                f"base_motion_length_s: {self.base_motion} is {length} s long, not {self.base_motion_length_s}"
            )
        if self.start_s > self.base_motion_length_s:
            raise ValueError(f"start_s: {self.start_s} s is past the take's end ({self.base_motion_length_s} s)")
        return self


class NoVariation(BaseModel):
    model_config = _FROZEN
    kind: Literal["none"] = "none"


class RandomPerturbation(BaseModel):
    """Orbiting bodies pull a subset of complementary muscles (paper "Random perturbations")."""

    model_config = _FROZEN
    kind: Literal["random_perturbation"] = "random_perturbation"
    muscles: Muscles
    radius_m: _within(PARAMETER_BOUNDS["perturbation_radius_m"])
    period_s: _within(PARAMETER_BOUNDS["perturbation_period_s"])


class MuscleWeakening(BaseModel):
    """A subset of muscles at reduced strength, one strength per muscle."""

    model_config = _FROZEN
    kind: Literal["muscle_weakening"] = "muscle_weakening"
    muscles: Muscles
    strengths: tuple[_within(PARAMETER_BOUNDS["weakening_strength"]), ...]

    @model_validator(mode="after")
    def _one_strength_each(self) -> MuscleWeakening:
        if len(self.strengths) != len(self.muscles):
            raise ValueError("strengths: one strength per weakened muscle")
        return self


class ActionBlending(BaseModel):
    """Complementary muscles follow a second motion (at most two blended sequences)."""

    model_config = _FROZEN
    kind: Literal["action_blending"] = "action_blending"
    muscles: Muscles
    blend_motion: MotionName
    blend_start_s: Finite = Field(ge=0.0)
    weight: _within(PARAMETER_BOUNDS["blending_weight"])


class ObjectsVariation(BaseModel):
    """An extra prop the protagonist carries or uses."""

    model_config = _FROZEN
    kind: Literal["objects"] = "objects"
    object: ObjectName


Variation = Annotated[
    NoVariation | RandomPerturbation | MuscleWeakening | ActionBlending | ObjectsVariation,
    Field(discriminator="kind"),
]


class SpringsSpec(BaseModel):
    """Kite springs: camera–target and target–protagonist, with dead zones of 0, 1 or 2 m."""

    model_config = _FROZEN
    ct_spring_strength: _within(KITE_SPRING_VARIABLES["ct_spring_strength"])
    tp_spring_strength: _within(KITE_SPRING_VARIABLES["tp_spring_strength"])
    camera_mass: _within(KITE_SPRING_VARIABLES["camera_mass"])
    target_mass: _within(KITE_SPRING_VARIABLES["target_mass"])
    camera_drag: _within(KITE_SPRING_VARIABLES["camera_drag"])
    target_drag: _within(KITE_SPRING_VARIABLES["target_drag"])
    ct_min_distance_m: DeadZone
    tp_min_distance_m: DeadZone


class ImpulseSpec(BaseModel):
    model_config = _FROZEN
    strength: _within(PARAMETER_BOUNDS["impulse_strength"])
    azimuth_deg: _within(PARAMETER_BOUNDS["impulse_azimuth_deg"])
    elevation_deg: _within(PARAMETER_BOUNDS["impulse_elevation_deg"])


class CameraSpec(BaseModel):
    """Camera behaviour C, its initial position C_xyz, target T_xyz and parameters Θ_c."""

    model_config = _FROZEN
    kind: CameraName
    fov_deg: _within(CAMERA_PLACEMENT_VARIABLES["fov_deg"])
    distance_m: _within(CAMERA_PLACEMENT_VARIABLES["distance_m"])
    height_m: _within(CAMERA_PLACEMENT_VARIABLES["height_m"])
    azimuth_deg: _within(CAMERA_PLACEMENT_VARIABLES["azimuth_deg"])
    position: Vec3
    target: Vec3
    springs: SpringsSpec | None
    impulse: ImpulseSpec | None

    @model_validator(mode="after")
    def _springs_of_a_spring_camera(self) -> CameraSpec:
        tracked = CAMERA_INFO[self.kind].tracking == "springs"
        for name in ("springs", "impulse"):
            if (getattr(self, name) is not None) != tracked:  # the physics would read them, or find none
                need = "needs" if tracked else "takes no"
                raise ValueError(f"{name}: a {self.kind} camera {need} {name}")
        if self.springs is not None and self.impulse is not None:
            strength, mass = self.impulse.strength, self.springs.camera_mass
            if strength > MAX_CAMERA_KICK_MPS * mass:  # as θ and the strategies bound it: no division's rounding
                raise ValueError(
                    f"impulse.strength: {strength:g} N·s on a camera of {mass:g} kg throws it at "
                    f"{strength / mass:.4g} m/s; at most {MAX_CAMERA_KICK_MPS:g}"
                )
        return self


class EnvironmentSpec(BaseModel):
    model_config = _FROZEN
    name: EnvironmentName
    indoor: bool
    waypoint_index: Int64
    waypoint: Vec3
    #: The seed of this video's own look of the environment (θ's ``world_variety: video``);
    #: None: the environment's one fixed look.
    look_seed: Seed | None = None


class WorldSpec(BaseModel):
    """Day phase D, clock time T, weather W and the weather elements Θ_w."""

    model_config = _FROZEN
    day_phase: DayPhaseName
    clock_hour: Finite = Field(ge=0.0, lt=24.0)
    weather: WeatherName
    sun_brightness: _within(WEATHER_LEVELS["sun_brightness"])
    ambient_luminosity: _within(WEATHER_LEVELS["ambient_luminosity"])
    rain: bool
    fog: bool
    clouds: bool
    wet_ground: bool
    cloud_intensity: _within(WEATHER_LEVELS["cloud_intensity"])
    fog_intensity: _within(WEATHER_LEVELS["fog_intensity"])
    rain_intensity: _within(WEATHER_LEVELS["rain_intensity"])


class Seeds(BaseModel):
    """Seeds for everything decided at run time, each from its own named stream."""

    model_config = _FROZEN
    physics: Seed
    perturbation: Seed
    render: Seed
    background: Seed


class VideoSpec(BaseModel):
    model_config = _FROZEN
    width: int = Field(ge=MIN_FRAME_SIDE, le=MAX_FRAME_SIDE)
    height: int = Field(ge=MIN_FRAME_SIDE, le=MAX_FRAME_SIDE)
    fps: int = Field(ge=1, le=MAX_FPS)


class Recipe(BaseModel):
    """A procedural recipe for one video (schema version 3)."""

    model_config = _FROZEN
    schema_version: Literal[3] = RECIPE_SCHEMA_VERSION
    video_id: str = Field(pattern=r"^v\d{6,}$")
    index: Int64
    dataset_seed: StrictInt = Field(ge=0)  # `true` is no seed; kept as text in the table's metadata
    theta_hash: str = Field(pattern=r"^[0-9a-f]{64}$")
    action: ActionName
    n_people: int = Field(ge=1)
    duration_s: Finite = Field(gt=0.0)
    n_frames: int = Field(ge=1)
    video: VideoSpec
    motion: MotionSpec
    variation: Variation
    protagonist: Protagonist
    supporting_characters: tuple[SupportingCharacter, ...]
    environment: EnvironmentSpec
    background_actors: tuple[BackgroundActor, ...]
    camera: CameraSpec
    world: WorldSpec
    render: RenderSettings
    seeds: Seeds

    @model_validator(mode="after")
    def _consistent(self) -> Recipe:
        if not math.isfinite(self.duration_s * self.video.fps):
            raise ValueError(f"duration_s {self.duration_s} is too long to count its frames")
        if self.n_frames != frames_for(self.duration_s, self.video.fps):
            raise ValueError(
                f"n_frames ({self.n_frames}) does not match duration_s {self.duration_s} at {self.video.fps} fps"
            )
        if self.video_id != video_id(self.index):
            raise ValueError(f"video_id {self.video_id!r} does not match index {self.index}")
        if self.n_people != 1 + len(self.supporting_characters):
            raise ValueError("n_people must count the protagonist and the supporting characters")
        if self.n_people != ACTIONS[self.action].n_people:
            raise ValueError(f"n_people: {self.action} is done by {ACTIONS[self.action].n_people}, not {self.n_people}")
        if self.duration_s > self.motion.base_motion_length_s:  # θ's clip length is at most the take's
            raise ValueError(
                f"duration_s: {self.duration_s} s is longer than {self.motion.base_motion} "
                f"({self.motion.base_motion_length_s} s)"
            )
        self._in_its_environment()
        ids = [0] + [p.person_id for p in self.supporting_characters] + [p.person_id for p in self.background_actors]
        if len(set(ids)) != len(ids):
            raise ValueError("person_id values must be unique within a recipe")
        return self

    def _in_its_environment(self) -> None:
        """The environment's facts the recipe repeats or indexes (indoor, its waypoint
        graphs) and the cameras it allows, as θ and ``phav vary`` hold them."""
        env = self.environment
        scene = ENVIRONMENT_SCENES[env.name]
        if env.indoor != scene.indoor:
            raise ValueError(f"environment.indoor: {env.name} is {'' if scene.indoor else 'not '}indoors")
        if env.waypoint_index >= len(scene.protagonist_waypoints):
            raise ValueError(
                f"environment.waypoint_index: {env.name} has {len(scene.protagonist_waypoints)} protagonist waypoints"
            )
        if self.background_actors and not scene.background_waypoints:
            raise ValueError(f"background_actors: {env.name} has no background actors' waypoints (an indoor scene)")
        for k, actor in enumerate(self.background_actors):
            for field in ("start_waypoint", "destination_waypoint"):
                if getattr(actor, field) >= len(scene.background_waypoints):
                    raise ValueError(
                        f"background_actors.{k}.{field}: {env.name} has "
                        f"{len(scene.background_waypoints)} background waypoints"
                    )
        if CAMERA_INFO[self.camera.kind].indoor_only and not scene.indoor:
            raise ValueError(f"camera.kind: the {self.camera.kind} camera films indoors only, not in {env.name}")


def frames_for(duration_s: float, fps: int) -> int:
    """Number of frames of a clip of ``duration_s`` seconds: round half up, at least one."""
    return max(1, int(duration_s * fps + 0.5))


def video_id(index: int) -> str:
    """``v000123``: the dataset-wide video id (never contains a dot, WebDataset keys)."""
    return f"v{index:06d}"


def _human_v1_to_v2(human: Any) -> Any:
    """A version-1 person (a model name with metric shape and flat colours) as the same
    model in version 2; anything malformed is left for validation to report."""
    if isinstance(human, Mapping) and human.get("model") in HUMAN_MODELS:
        return HUMAN_MODELS[human["model"]].human(human["model"])
    return human


def _people_v1_to_v2(data: dict[str, Any]) -> dict[str, Any]:
    """Schema 1 → 2: every person becomes the version-2 fixed model of the same name (its
    phenotype, skin, hair and outfit); everything else is kept as it was."""
    out = dict(data)
    if isinstance(out.get("protagonist"), Mapping):
        out["protagonist"] = {**out["protagonist"], "human": _human_v1_to_v2(out["protagonist"].get("human"))}
    for role in ("supporting_characters", "background_actors"):
        people = out.get(role)
        if isinstance(people, list | tuple):
            out[role] = [
                {**p, "human": _human_v1_to_v2(p.get("human"))} if isinstance(p, Mapping) else p for p in people
            ]
    out["schema_version"] = 2
    return out


def _looks_v2_to_v3(data: dict[str, Any]) -> dict[str, Any]:
    """Schema 2 → 3: the environment gains ``look_seed``; a version-2 recipe had the
    environment's one fixed look (None), so it renders as it did."""
    out = dict(data)
    if isinstance(out.get("environment"), Mapping):
        out["environment"] = {**out["environment"], "look_seed": None}
    out["schema_version"] = 3
    return out


#: Upgrades from schema version v to v + 1, keyed by v. Version 1 is the first release.
RECIPE_MIGRATIONS: dict[int, Callable[[dict[str, Any]], dict[str, Any]]] = {1: _people_v1_to_v2, 2: _looks_v2_to_v3}


def upgrade_recipe(
    data: Mapping[str, Any],
    *,
    migrations: Mapping[int, Callable[[dict[str, Any]], dict[str, Any]]] = RECIPE_MIGRATIONS,
    current: int = RECIPE_SCHEMA_VERSION,
    source: str = "<recipe>",
) -> dict[str, Any]:
    """Bring a recipe mapping up to the ``current`` schema version through ``migrations``."""
    version = data.get("schema_version")
    if version is None:
        raise PhavUserError("missing required field", source=source, field="schema_version")
    if isinstance(version, bool) or not isinstance(version, int) or version < 0:
        raise PhavUserError(
            f"must be a non-negative integer, got {version!r}",
            source=source,
            field="schema_version",
        )
    if version > current:
        raise PhavUserError(
            f"version {version} is newer than this phav supports ({current}); upgrade phav",
            source=source,
            field="schema_version",
        )
    out = dict(data)
    while out["schema_version"] < current:
        v = out["schema_version"]
        if v not in migrations:
            raise PhavUserError(f"no migration from version {v}", source=source, field="schema_version")
        out = migrations[v](dict(out))
        if out.get("schema_version") != v + 1:
            raise RuntimeError(f"migration from schema version {v} did not produce version {v + 1}")
    return out


def parse_recipe(data: Mapping[str, Any] | str | bytes, *, source: str = "<recipe>") -> Recipe:
    """Validate (and upgrade) a recipe from a mapping or JSON text; errors name source and field."""
    if isinstance(data, str | bytes):
        data = parse_json_object(data, source=source)
    if not isinstance(data, Mapping):
        raise PhavUserError("a recipe must be a JSON object", source=source)
    return validate_user_data(Recipe, upgrade_recipe(data, source=source), source=source, strict=True)


def load_recipe(path: str | Path) -> Recipe:
    """Read one recipe JSON file."""
    return parse_recipe(read_text(path), source=str(path))


def recipe_json_schema() -> dict[str, Any]:
    """JSON Schema of the current recipe version (``phav spec schema``)."""
    schema = Recipe.model_json_schema()
    schema["$id"] = f"https://phav.invalid/schema/recipe/v{RECIPE_SCHEMA_VERSION}.json"
    schema["$schema"] = "https://json-schema.org/draft/2020-12/schema"
    return schema
