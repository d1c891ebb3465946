"""θ: every parameter of the paper's generative model (Section "Generative models for world
control"), as a frozen pydantic model loaded from YAML and validated for support.

People are the paper's H (``theta_h`` over the 20 fixed human models) unless a ``people``
section with ``mode: sampled`` draws every person continuously (``PeopleTheta``).

Categorical weights are written either as ``uniform`` or as a mapping value → weight
(unlisted values weigh 0); they are filled out on load to a full mapping in registry order,
so the canonical hash does not depend on the mapping's order or on ``uniform`` against
weights of 1 (weights are not rescaled: weights of 2 are another θ of the same
distribution). Conditional tables
(θ_AE, θ_AV, θ_AC, θ_EC) have a ``default`` row and per-parent ``rows`` overriding it.
"""

from __future__ import annotations

import difflib
import math
import re
from collections.abc import Mapping
from dataclasses import dataclass
from functools import cached_property
from pathlib import Path
from typing import Annotated, Any, Literal

import numpy as np
import yaml
from pydantic import (
    AfterValidator,
    BaseModel,
    BeforeValidator,
    ConfigDict,
    Field,
    PlainSerializer,
    StrictInt,
    model_validator,
)

from phav_spec.canonical import canonical_json, sha256_hex
from phav_spec.distributions import Bernoulli, Continuous, Triangular, Uniform
from phav_spec.errors import PhavUserError, validate_user_data
from phav_spec.files import read_text
from phav_spec.motions import MOTIONS, theta_ab
from phav_spec.people import BOTTOMS, FABRICS, HAIR_STYLES, TOPS
from phav_spec.population import HAIR_COLOURS, MAX_AGE_YEARS, PEOPLE_PARAMETER_BOUNDS
from phav_spec.scene import (
    ACTION_SCENES,
    CAMERA_INFO,
    CAMERA_PLACEMENT_VARIABLES,
    ENVIRONMENT_SCENES,
    HUMAN_MODELS,
    KITE_SPRING_VARIABLES,
    MAX_BACKGROUND_ACTORS,
    MAX_CAMERA_KICK_MPS,
    PARAMETER_BOUNDS,
    SPRING_MIN_DISTANCES_M,
    WEATHER_LEVELS,
    why_not_hosted,
)
from phav_spec.vocab import (
    ACTIONS,
    CAMERAS,
    DAY_PHASES,
    ENVIRONMENTS,
    VARIATIONS,
    WEATHERS,
    Registry,
)

THETA_FORMAT_VERSION = 1
#: A categorical weight is 0 or within these: weights are relative, and a sum of two huge
#: ones overflows to infinity (every draw then the last value) while tiny ones lose their
#: precision (subnormal floats), each a wrong distribution sampled without a word.
MIN_WEIGHT, MAX_WEIGHT = 1e-100, 1e100
_FROZEN = ConfigDict(extra="forbid", frozen=True)
PRESETS_DIR = Path(__file__).parent / "presets"


def unknown_name_message(registry: Registry, name: object) -> str:
    """'unknown action 'walkk' (did you mean 'walk'?)' — the one wording for bad names."""
    close = difflib.get_close_matches(str(name), registry.names, n=1)
    hint = f" (did you mean {close[0]!r}?)" if close else f"; known: {', '.join(registry.names)}"
    return f"unknown {registry.kind} {name!r}{hint}"


def _weights(registry: Registry, value: Any) -> dict[str, float]:
    """Normalise a categorical weight spec to a full mapping in registry order."""
    if value == "uniform":
        return {name: 1.0 for name in registry.names}
    if not isinstance(value, Mapping):
        raise ValueError(f"expected 'uniform' or a mapping {registry.kind} → weight, got {value!r}")
    out = {name: 0.0 for name in registry.names}
    for key, w in value.items():
        if key not in registry:
            raise ValueError(unknown_name_message(registry, key))
        out[key] = _weight(repr(key), w)
    return out


def _weight(name: str, w: Any) -> float:
    """One categorical weight: a number (not a boolean), 0 or within [MIN_WEIGHT, MAX_WEIGHT]."""
    if isinstance(w, bool) or not isinstance(w, int | float):
        raise ValueError(f"weight of {name} must be a number, got {w!r}")
    if not math.isfinite(w) or w < 0:
        raise ValueError(f"weight of {name} must be finite and non-negative, got {w}")
    if w != 0 and not MIN_WEIGHT <= w <= MAX_WEIGHT:  # sums and products of weights stay exact enough
        raise ValueError(f"weight of {name} must be 0 or in [{MIN_WEIGHT:g}, {MAX_WEIGHT:g}], got {w}")
    return float(w) + 0.0  # -0.0 is 0.0: one spelling, one hash


def _weights_field(registry: Registry) -> Any:
    return Annotated[dict[str, float], BeforeValidator(lambda v: _weights(registry, v))]


def _table_field(rows: Registry, cols: Registry) -> Any:
    """A conditional table: ``default`` weights and per-parent ``rows`` overriding them.

    It normalises to one full row per parent value and serialises as ``{rows: ...}`` alone,
    which loads back to the same table.
    """

    def normalise(value: Any) -> dict[str, Any]:
        if not isinstance(value, Mapping):
            raise ValueError("expected a mapping with 'default' and optional 'rows'")
        extra = set(value) - {"default", "rows"}
        if extra:
            raise ValueError(f"unexpected key {sorted(extra, key=str)[0]!r}; a table has 'default' and 'rows'")
        given = value.get("rows") or {}
        if not isinstance(given, Mapping):
            raise ValueError("'rows' must map each parent value to weights")
        for name in given:
            if name not in rows:
                raise ValueError(f"rows: {unknown_name_message(rows, name)}")
        uncovered = [name for name in rows.names if name not in given]
        if uncovered and "default" not in value:
            raise ValueError(f"missing 'default' row (no row given for {uncovered[0]!r})")
        try:  # checked where every row is given too: a wrong default is a mistake all the same
            default = _weights(cols, value["default"]) if "default" in value else {}
        except ValueError as e:
            raise ValueError(f"default: {e}") from None
        table = {}
        for name in rows.names:
            try:
                table[name] = _weights(cols, given[name]) if name in given else dict(default)
            except ValueError as e:
                raise ValueError(f"rows.{name}: {e}") from None
        return table

    return Annotated[
        dict[str, dict[str, float]],
        BeforeValidator(normalise),
        PlainSerializer(lambda table: {"rows": table}),
    ]


ActionWeights = _weights_field(ACTIONS)
EnvironmentWeights = _weights_field(ENVIRONMENTS)
WeatherWeights = _weights_field(WEATHERS)
DayPhaseWeights = _weights_field(DAY_PHASES)
HumanWeights = _weights_field(HUMAN_MODELS)
VariationWeights = _weights_field(VARIATIONS)
CameraWeights = _weights_field(CAMERAS)


def _choices(kind: str, names: tuple[str, ...]) -> Registry:
    return Registry(kind, tuple((n, None) for n in names))


#: The categorical values of θ's people section, as registries (weights like θ_H's).
SEXES: Registry[None] = _choices("sex", ("female", "male"))
TOP_KINDS: Registry[None] = _choices("top", TOPS)
BOTTOM_KINDS: Registry[None] = _choices("bottom", BOTTOMS)
FABRIC_KINDS: Registry[None] = _choices("fabric", FABRICS)
HAIR_STYLE_KINDS: Registry[None] = _choices("hair style", HAIR_STYLES)
HAIR_COLOUR_KINDS: Registry[None] = _choices("hair colour", HAIR_COLOURS)


#: The frame sizes (px) and rates (frames/s) a θ and a recipe may ask for.
MIN_FRAME_SIDE, MAX_FRAME_SIDE, MAX_FPS = 16, 4096, 240


class VideoFormat(BaseModel):
    """Resolution and frame rate (paper: 340×256 at 30 fps)."""

    model_config = _FROZEN
    width: int = Field(340, ge=MIN_FRAME_SIDE, le=MAX_FRAME_SIDE, strict=True)
    height: int = Field(256, ge=MIN_FRAME_SIDE, le=MAX_FRAME_SIDE, strict=True)
    fps: StrictInt = Field(30, ge=1, le=MAX_FPS)  # not `yes`, not 29.97


class Durations(BaseModel):
    """T_min, T_max and T_mod in seconds (Section "Generated video duration")."""

    model_config = _FROZEN
    t_min: float = Field(gt=0.0, allow_inf_nan=False, strict=True)
    t_max: float = Field(gt=0.0, allow_inf_nan=False, strict=True)
    t_mod: float = Field(gt=0.0, allow_inf_nan=False, strict=True)

    @model_validator(mode="after")
    def _ordered(self) -> Durations:
        if self.t_min > self.t_max:
            raise ValueError(f"t_min ({self.t_min}) must not exceed t_max ({self.t_max})")
        if not self.t_min <= self.t_mod <= self.t_max:
            raise ValueError(f"t_mod ({self.t_mod}) must lie in [t_min, t_max] = [{self.t_min}, {self.t_max}]")
        return self

    def clip_length(self, motion_length_s: float) -> tuple[float, float, float]:
        """(a, b, c) of P(L | B = b) = Tr(T_min, min(L_b, T_max), min(T_mod, L_b)) (paper)."""
        return self.t_min, min(motion_length_s, self.t_max), min(self.t_mod, motion_length_s)


class MotionRegex(BaseModel):
    """θ_AB as in the paper: one regular expression per action, matched against motion texts."""

    model_config = _FROZEN
    regex: dict[str, str]

    @model_validator(mode="after")
    def _compile(self) -> MotionRegex:
        for action, pattern in self.regex.items():
            if action not in ACTIONS:
                raise ValueError(f"regex: {unknown_name_message(ACTIONS, action)}")
            try:
                re.compile(pattern)
            except re.error as e:
                raise ValueError(f"regex.{action}: does not compile: {e}") from None
        return self


class ClockHour(BaseModel):
    """Tr(t | min, max, mode) in hours on a 24 h clock; min > max wraps midnight."""

    model_config = _FROZEN
    min: float = Field(ge=0.0, lt=24.0, allow_inf_nan=False, strict=True)
    max: float = Field(ge=0.0, lt=24.0, allow_inf_nan=False, strict=True)
    mode: float = Field(ge=0.0, lt=24.0, allow_inf_nan=False, strict=True)

    @model_validator(mode="after")
    def _valid(self) -> ClockHour:
        self.distribution()
        return self

    def distribution(self) -> Triangular:
        return Triangular(min=self.min, max=self.max, mode=self.mode, period=24.0)


class DependentBernoulli(BaseModel):
    """P(element on | parent on) and P(element on | parent off)."""

    model_config = _FROZEN
    p_if_parent: float = Field(ge=0.0, le=1.0, allow_inf_nan=False, strict=True)
    p_otherwise: float = Field(ge=0.0, le=1.0, allow_inf_nan=False, strict=True)


class WeatherElementsTheta(BaseModel):
    """Θ_w for one weather: light levels, element activations and their intensities."""

    model_config = _FROZEN
    sun_brightness: Continuous
    ambient_luminosity: Continuous
    rain: Bernoulli
    fog: Bernoulli
    clouds: DependentBernoulli
    wet_ground: DependentBernoulli
    cloud_intensity: Continuous
    fog_intensity: Continuous
    rain_intensity: Continuous

    @model_validator(mode="after")
    def _bounds(self) -> WeatherElementsTheta:
        for name, (lo, hi) in WEATHER_LEVELS.items():
            _check_support(getattr(self, name), lo, hi, name)
        return self

    def p_on(self, element: str, parent_on: bool | None = None) -> float:
        """Activation probability of an element, given its parent's state when it has one."""
        spec = getattr(self, element)
        if isinstance(spec, Bernoulli):
            return spec.p
        return spec.p_if_parent if parent_on else spec.p_otherwise


def bounded(key: str, bounds: Mapping[str, tuple[str, float, float]] = PARAMETER_BOUNDS) -> Any:
    """A θ distribution whose support must stay inside ``bounds[key]`` (scene.PARAMETER_BOUNDS)."""
    unit, lo, hi = bounds[key]

    def check(dist: Uniform | Triangular) -> Uniform | Triangular:
        _check_support(dist, lo, hi, unit=unit)
        return dist

    return Annotated[Continuous, AfterValidator(check)]


def _check_support(dist: Uniform | Triangular, lo: float, hi: float, name: str | None = None, unit: str = "") -> None:
    """Refuse a distribution whose support leaves [lo, hi] (the message names ``name`` if given);
    a wrapped interval draws from its whole period, [0, period), and must fit it all."""
    a, b = dist.support
    wraps = isinstance(dist, Triangular) and dist.wraps
    if wraps:
        a, b = 0.0, float(dist.period)
    if a < lo or b > hi:
        what = f"support [{a}, {b}]" if not wraps else f"wrapped support [0, {b})"
        message = f"{what} leaves the allowed range [{lo}, {hi}]" + (f" {unit}" if unit else "")
        raise ValueError(f"{name}: {message}" if name else message)


class IntegerRange(BaseModel):
    """A uniform integer on [min, max]."""

    model_config = _FROZEN
    min: int = Field(ge=0, strict=True)
    max: int = Field(ge=0, strict=True)

    @model_validator(mode="after")
    def _ordered(self) -> IntegerRange:
        if self.min > self.max:
            raise ValueError(f"min ({self.min}) must not exceed max ({self.max})")
        return self


class MuscleCount(IntegerRange):
    """How many muscles a variation acts on: at least one (capped by what the action has)."""

    min: int = Field(ge=1, strict=True)
    max: int = Field(ge=1, strict=True)


class BackgroundActors(BaseModel):
    """Background pedestrians walking between waypoints of B_WG (outdoor scenes only)."""

    model_config = _FROZEN
    count: IntegerRange
    speed_mps: bounded("background_speed_mps")

    @model_validator(mode="after")
    def _not_a_crowd(self) -> BackgroundActors:
        if self.count.max > MAX_BACKGROUND_ACTORS:
            raise ValueError(f"count.max: at most {MAX_BACKGROUND_ACTORS} background actors per scene")
        return self


class SupportingCharacters(BaseModel):
    """Where the supporting character of a two-people action starts, relative to P_xyz."""

    model_config = _FROZEN
    side_distance_m: bounded("supporting_distance_m")
    behind_distance_m: bounded("supporting_distance_m")
    facing_distance_m: bounded("supporting_distance_m")


class MotionParameters(BaseModel):
    """Playback of the base motion: speed factor, mirroring left/right, and where in the
    take the clip starts: ``uniform`` anywhere it fits, or ``active`` among the windows
    where the body moves (``phav_spec.motions.active_start``; for short clips, which a
    held pose would otherwise fill). Either way two people walking into each other on a take
    that stops them start it where they meet as it stops (``meeting_start``)."""

    model_config = _FROZEN
    speed: bounded("motion_speed")
    p_mirror: float = Field(ge=0.0, le=1.0, allow_inf_nan=False, strict=True)
    start: Literal["uniform", "active"] = "uniform"


def _distance_weights(value: Any) -> Any:
    """``min_distance_weights`` as given (its keys as integers), under the rules of every
    categorical's weights (``_weight``): a distance of ``SPRING_MIN_DISTANCES_M``, named once
    (``1`` and ``"1"`` are one key)."""
    if not isinstance(value, Mapping):
        return value  # pydantic says what it expected
    out: dict[int, float] = {}
    for key, w in value.items():
        d = key if isinstance(key, int) and not isinstance(key, bool) else None
        if isinstance(key, str) and key.strip().isdigit():
            d = int(key)
        if d not in SPRING_MIN_DISTANCES_M:
            raise ValueError(f"{key!r} m is not one of {SPRING_MIN_DISTANCES_M}")
        if d in out:
            raise ValueError(f"{d} m is given twice")
        out[d] = _weight(f"{d} m", w)
    return out


class KiteSprings(BaseModel):
    """The kite camera's springs: camera–target (CT) and target–protagonist (TP)."""

    model_config = _FROZEN
    ct_spring_strength: Continuous
    tp_spring_strength: Continuous
    camera_mass: Continuous
    target_mass: Continuous
    camera_drag: Continuous
    target_drag: Continuous
    min_distance_weights: Annotated[dict[int, float], BeforeValidator(_distance_weights)]

    @model_validator(mode="after")
    def _bounds(self) -> KiteSprings:
        for name, (_, lo, hi) in KITE_SPRING_VARIABLES.items():
            _check_support(getattr(self, name), lo, hi, name)
        if sum(self.min_distance_weights.values()) <= 0:
            raise ValueError("min_distance_weights: all zero, no dead zone has support")
        return self

    def dead_zone_weights(self) -> list[float]:
        return [self.min_distance_weights.get(d, 0.0) for d in SPRING_MIN_DISTANCES_M]


class Impulse(BaseModel):
    """The random initial impulse that starts the camera moving (N·s, degrees)."""

    model_config = _FROZEN
    strength: bounded("impulse_strength")
    azimuth_deg: bounded("impulse_azimuth_deg")
    elevation_deg: bounded("impulse_elevation_deg")


class CameraTheta(BaseModel):
    """Θ_c for one camera behaviour: initial placement around the protagonist, springs, impulse."""

    model_config = _FROZEN
    fov_deg: Continuous
    distance_m: Continuous
    height_m: Continuous
    azimuth_deg: Continuous
    springs: KiteSprings | None = None
    impulse: Impulse | None = None

    @model_validator(mode="after")
    def _bounds(self) -> CameraTheta:
        for name, (_, lo, hi) in CAMERA_PLACEMENT_VARIABLES.items():
            _check_support(getattr(self, name), lo, hi, name)
        if self.springs is not None and self.impulse is not None:
            strongest, lightest = self.impulse.strength.support[1], self.springs.camera_mass.support[0]
            if strongest > MAX_CAMERA_KICK_MPS * lightest:
                raise ValueError(
                    f"impulse.strength: up to {strongest:g} N·s on a camera of {lightest:g} kg (springs.camera_mass) "
                    f"throws it at up to {strongest / lightest:.0f} m/s; at most {MAX_CAMERA_KICK_MPS:g}"
                )
        return self


class Perturbation(BaseModel):
    """Random perturbation: orbiting bodies on a subset of complementary muscles."""

    model_config = _FROZEN
    n_muscles: MuscleCount
    radius_m: bounded("perturbation_radius_m")
    period_s: bounded("perturbation_period_s")


class Weakening(BaseModel):
    """Muscle weakening: a subset of any muscles, each at a random strength."""

    model_config = _FROZEN
    n_muscles: MuscleCount
    strength: bounded("weakening_strength")


class Blending(BaseModel):
    """Action blending: complementary muscles follow a second motion at a blend weight."""

    model_config = _FROZEN
    n_muscles: MuscleCount
    weight: bounded("blending_weight")


class VariationsTheta(BaseModel):
    """Θ_v: the parameters of each motion variation."""

    model_config = _FROZEN
    random_perturbation: Perturbation
    muscle_weakening: Weakening
    action_blending: Blending


def _per_sex_field(cols: Registry) -> Any:
    """Weights per sex: ``{female: …, male: …}``, or one set of weights for both."""

    def normalise(value: Any) -> dict[str, dict[str, float]]:
        if isinstance(value, Mapping) and value and set(value) <= set(SEXES.names):
            missing = [s for s in SEXES.names if s not in value]
            if missing:
                raise ValueError(f"{missing[0]}: missing (give weights for both sexes, or one set for both)")
            out = {}
            for sex in SEXES.names:
                try:
                    out[sex] = _weights(cols, value[sex])
                except ValueError as e:
                    raise ValueError(f"{sex}: {e}") from None
            return out
        shared = _weights(cols, value)
        return {sex: dict(shared) for sex in SEXES.names}

    return Annotated[dict[str, dict[str, float]], BeforeValidator(normalise)]


def people_bounded(key: str) -> Any:
    """A θ people distribution whose support must stay inside PEOPLE_PARAMETER_BOUNDS[key]."""
    return bounded(key, PEOPLE_PARAMETER_BOUNDS)


def _has_support(name: str, weights: Mapping[str, float]) -> None:
    if sum(weights.values()) <= 0:
        raise ValueError(f"{name}: all weights are zero, no value has support")


Probability = Annotated[float, Field(ge=0.0, le=1.0, allow_inf_nan=False, strict=True)]


def _a_number(value: Any) -> Any:
    """A value a number must be, not a boolean or a quoted string (YAML's ``yes`` is True)."""
    if isinstance(value, bool | str):
        raise ValueError(f"expected a number, got {value!r}")
    return value


class GreyHair(BaseModel):
    """Hair turns grey with age: P(grey) is 0 before ``start_years``, rises linearly to
    ``p_full`` at ``full_years`` and stays there."""

    model_config = _FROZEN
    start_years: float = Field(ge=0.0, le=MAX_AGE_YEARS, allow_inf_nan=False, strict=True)
    full_years: float = Field(ge=0.0, le=MAX_AGE_YEARS, allow_inf_nan=False, strict=True)
    p_full: Probability

    @model_validator(mode="after")
    def _ordered(self) -> GreyHair:
        if self.start_years > self.full_years:
            raise ValueError(f"start_years ({self.start_years}) must not exceed full_years ({self.full_years})")
        return self


class HairTheta(BaseModel):
    """Hair style per sex, colour (black, brown, blond, red) and greying with age."""

    model_config = _FROZEN
    styles: _per_sex_field(HAIR_STYLE_KINDS)
    colours: _weights_field(HAIR_COLOUR_KINDS)
    grey: GreyHair

    @model_validator(mode="after")
    def _support(self) -> HairTheta:
        _has_support("colours", self.colours)
        return self


class OutfitTheta(BaseModel):
    """Clothes: top kinds, bottom kinds per sex, fabrics, and colours as HSV (the hue is
    uniform on the circle; θ shapes saturation and value). Each garment draws a ground and
    a pattern colour; shoes have their own saturation and value."""

    model_config = _FROZEN
    tops: _weights_field(TOP_KINDS)
    bottoms: _per_sex_field(BOTTOM_KINDS)
    top_fabrics: _weights_field(FABRIC_KINDS)
    bottom_fabrics: _weights_field(FABRIC_KINDS)
    saturation: people_bounded("saturation")
    value: people_bounded("value")
    shoes_saturation: people_bounded("saturation")
    shoes_value: people_bounded("value")
    pattern_scale: people_bounded("pattern_scale")

    @model_validator(mode="after")
    def _support(self) -> OutfitTheta:
        for name in ("tops", "top_fabrics", "bottom_fabrics"):
            _has_support(name, getattr(self, name))
        return self


class PeopleTheta(BaseModel):
    """People drawn continuously (``mode: sampled``) instead of from the 20 models of H.

    Each person: a sex (``p_female``), a child with probability ``p_child`` where the action
    allows children (``ActionScene.children``; background pedestrians always may), an age in
    years from the child or adult range, a stature of ``stature_z`` reference standard
    deviations about the WHO median of that sex and age, anny's gender offset, weight,
    muscle and proportions, a skin tone and undertone, hair and an outfit. How years,
    metres and tones become anny's phenotype and sRGB: ``phav_spec.population``.
    """

    model_config = _FROZEN
    mode: Literal["models", "sampled"]
    p_female: Probability
    p_child: Probability
    adult_age_years: people_bounded("adult_age_years")
    child_age_years: people_bounded("child_age_years")
    stature_z: people_bounded("stature_z")
    gender_offset: people_bounded("gender_offset")
    weight: people_bounded("weight")
    muscle: people_bounded("muscle")
    proportions: people_bounded("proportions")
    skin_tone: people_bounded("skin_tone")
    skin_undertone: people_bounded("skin_undertone")
    hair: HairTheta
    outfit: OutfitTheta

    @model_validator(mode="after")
    def _support(self) -> PeopleTheta:
        if self.mode != "sampled":  # pragma: no cover - Theta drops a "models" section before this
            raise ValueError("mode: a people section with distributions needs mode 'sampled'")
        for sex, p in (("female", self.p_female), ("male", 1.0 - self.p_female)):
            if p > 0:
                _has_support(f"hair.styles.{sex}", self.hair.styles[sex])
                _has_support(f"outfit.bottoms.{sex}", self.outfit.bottoms[sex])
        return self

    def p_sex(self) -> dict[str, float]:
        """P(female), P(male)."""
        return {"female": self.p_female, "male": 1.0 - self.p_female}


class RenderSettings(BaseModel):
    """The RGB stream's supersampling and post-processing (paper Section "Rendered RGB
    Frames"), and the PNGs' zlib level; labels, depth and flow are always one sample a pixel."""

    model_config = _FROZEN
    supersampling: Annotated[Literal[1, 2, 4], BeforeValidator(_a_number)] = 2
    motion_blur: bool = True
    bloom: bool = True
    ambient_occlusion: bool = True
    screen_space_reflection: bool = True
    color_grading: bool = True
    vignette: bool = True
    png_compression: int = Field(1, ge=0, le=9, strict=True)


@dataclass(frozen=True)
class ThetaArrays:
    """θ's categorical parameters as numpy arrays in registry order (rows = parents)."""

    a: np.ndarray
    e: np.ndarray
    w: np.ndarray
    d: np.ndarray
    h: np.ndarray
    v: np.ndarray
    c: np.ndarray
    ae: np.ndarray
    av: np.ndarray
    ac: np.ndarray
    ec: np.ndarray
    ab: np.ndarray  # θ_AB from the regexes, before the T_min mask
    motion_long_enough: np.ndarray  # length(b) >= T_min

    def p_e_given_a(self) -> np.ndarray:
        """Unnormalised P(E | A) ∝ θ_E · θ_AE, shape (A, E)."""
        return self.e[None, :] * self.ae

    def p_v_given_a(self) -> np.ndarray:
        """Unnormalised P(V | A) ∝ θ_V · θ_AV, shape (A, V)."""
        return self.v[None, :] * self.av

    def p_c_given_ae(self) -> np.ndarray:
        """Unnormalised P(C | A, E) ∝ θ_C · θ_AC · θ_EC, shape (A, E, C)."""
        return self.c[None, None, :] * self.ac[:, None, :] * self.ec[None, :, :]

    def p_b_given_a(self) -> np.ndarray:
        """Unnormalised P(B | A) ∝ θ_AB · 1[length(b) ≥ T_min], shape (A, B)."""
        return self.ab * self.motion_long_enough[None, :]


class Theta(BaseModel):
    """All parameters θ of the generative model; one file, one canonical hash."""

    model_config = _FROZEN
    format_version: Literal[1] = THETA_FORMAT_VERSION  # this phav reads format 1 only, written so
    name: str = Field(min_length=1, pattern=r"^[A-Za-z0-9_.-]+$")
    description: str = ""
    video: VideoFormat = VideoFormat()
    durations: Durations
    theta_a: ActionWeights
    theta_e: EnvironmentWeights
    theta_w: WeatherWeights
    theta_d: DayPhaseWeights
    theta_h: HumanWeights = Field(default_factory=lambda: {name: 1.0 for name in HUMAN_MODELS.names})
    theta_v: VariationWeights
    theta_c: CameraWeights
    theta_ae: _table_field(ACTIONS, ENVIRONMENTS)
    theta_av: _table_field(ACTIONS, VARIATIONS)
    theta_ac: _table_field(ACTIONS, CAMERAS)
    theta_ec: _table_field(ENVIRONMENTS, CAMERAS)
    theta_ab: MotionRegex
    clock_hours: dict[str, ClockHour]
    weather_elements: dict[str, WeatherElementsTheta]
    background_actors: BackgroundActors
    supporting_characters: SupportingCharacters
    motion: MotionParameters
    protagonist_heading_deg: bounded("heading_deg")
    cameras: dict[str, CameraTheta]
    variations: VariationsTheta
    people: PeopleTheta | None = None
    render: RenderSettings = RenderSettings()
    #: Which looks the environments' objects and places take (facades, tree species, parked
    #: cars' models and paints, furniture's woods and fabrics): ``environment``, one fixed look
    #: per environment as in the paper's scenes, or ``video``, a look of its own per video
    #: (its seed in the recipe). The layouts, and so physics and placement, stay the same.
    world_variety: Literal["environment", "video"] = "environment"

    @model_validator(mode="before")
    @classmethod
    def _version_first(cls, data: Any) -> Any:
        if isinstance(data, Mapping):
            v = data.get("format_version", THETA_FORMAT_VERSION)
            if isinstance(v, bool) or not isinstance(v, int):  # 2.0 or "7" would pass as a number
                raise ValueError(f"format_version: must be a whole number, got {v!r}")
            if v > THETA_FORMAT_VERSION:
                raise ValueError(
                    f"format_version: {v} is newer than this phav reads ({THETA_FORMAT_VERSION}); upgrade phav"
                )
        return data

    @model_validator(mode="before")
    @classmethod
    def _people_models(cls, data: Any) -> Any:
        """``people: {mode: models}`` is the paper's H, the same θ as no people section."""
        if isinstance(data, Mapping) and isinstance(data.get("people"), Mapping):
            people = data["people"]
            if people.get("mode") == "models":
                extra = [key for key in people if key != "mode"]
                if extra:
                    raise ValueError(
                        f"people.{extra[0]}: mode 'models' takes no distributions (H comes from theta_h); "
                        "remove it or set mode: sampled"
                    )
                data = {k: v for k, v in data.items() if k != "people"}
        return data

    @model_validator(mode="after")
    def _support(self) -> Theta:
        _require_keys("clock_hours", self.clock_hours, DAY_PHASES)
        _require_keys("weather_elements", self.weather_elements, WEATHERS)
        _require_keys("cameras", self.cameras, CAMERAS)
        for name, cam in self.cameras.items():
            tracking = CAMERA_INFO[name].tracking
            if tracking == "springs" and (cam.springs is None or cam.impulse is None):
                raise ValueError(f"cameras.{name}: a spring camera needs 'springs' and 'impulse'")
            if tracking != "springs" and (cam.springs is not None or cam.impulse is not None):
                raise ValueError(f"cameras.{name}: only spring cameras take 'springs'/'impulse'")
        for fieldname in (
            "theta_a",
            "theta_w",
            "theta_d",
            *(("theta_h",) if self.people is None else ()),
            "theta_v",
            "theta_c",
            "theta_e",
        ):
            if sum(getattr(self, fieldname).values()) <= 0:
                raise ValueError(f"{fieldname}: all weights are zero, no value has support")
        self._check_reachable_rows()
        return self

    def _check_reachable_rows(self) -> None:
        arr = self.arrays
        t_min = self.durations.t_min
        for ai, action in enumerate(ACTIONS.names):
            if arr.a[ai] <= 0:
                continue
            scene = ACTION_SCENES[action]
            pe = arr.p_e_given_a()[ai]
            if pe.sum() <= 0:
                raise ValueError(f"theta_ae.rows.{action}: no environment with positive θ_E·θ_AE (all-zero row)")
            pv = arr.p_v_given_a()[ai]
            if pv.sum() <= 0:
                raise ValueError(f"theta_av.rows.{action}: no variation with positive θ_V·θ_AV (all-zero row)")
            if pv[VARIATIONS.index("objects")] > 0 and not scene.variation_objects:
                raise ValueError(f"theta_av.rows.{action}.objects: {action} declares no objects to add")
            for needs_muscles in ("random_perturbation", "action_blending"):
                if pv[VARIATIONS.index(needs_muscles)] > 0 and not scene.complementary_muscles:
                    raise ValueError(f"theta_av.rows.{action}.{needs_muscles}: {action} has no complementary muscles")
            if arr.ab[ai].sum() <= 0:
                raise ValueError(f"theta_ab.regex.{action}: matches no motion description")
            if arr.p_b_given_a()[ai].sum() <= 0:
                longest = max(MOTIONS[m].length_s for m, hit in zip(MOTIONS.names, arr.ab[ai], strict=True) if hit)
                raise ValueError(
                    f"durations.t_min: {t_min} s is longer than every motion of {action} (longest {longest} s)"
                )
            if ACTIONS[action].n_people > 1 and self.people is None and np.count_nonzero(arr.h) < 2:
                raise ValueError(f"theta_h: {action} needs a supporting character but only one human model has weight")
            for ei, env in enumerate(ENVIRONMENTS.names):
                if pe[ei] <= 0:
                    continue
                env_scene = ENVIRONMENT_SCENES[env]
                reason = why_not_hosted(action, env)
                if reason is not None:
                    raise ValueError(f"theta_ae.rows.{action}.{env}: {reason}")
                pc = arr.p_c_given_ae()[ai, ei]
                if pc.sum() <= 0:
                    raise ValueError(
                        f"theta_ec.rows.{env}: no camera with positive θ_C·θ_AC·θ_EC for action {action} in {env}"
                    )
                for ci, cam in enumerate(CAMERAS.names):
                    if pc[ci] > 0 and CAMERA_INFO[cam].indoor_only and not env_scene.indoor:
                        raise ValueError(f"theta_ec.rows.{env}.{cam}: the {cam} camera needs an indoor environment")

    @cached_property
    def arrays(self) -> ThetaArrays:
        """θ's categorical parameters as arrays in registry order (computed once)."""

        def vec(d: dict[str, float]) -> np.ndarray:
            return np.array(list(d.values()), dtype=np.float64)

        def table(t: dict[str, dict[str, float]]) -> np.ndarray:
            return np.array([list(row.values()) for row in t.values()], dtype=np.float64)

        lengths = np.array([MOTIONS[m].length_s for m in MOTIONS.names])
        return ThetaArrays(
            a=vec(self.theta_a), e=vec(self.theta_e), w=vec(self.theta_w), d=vec(self.theta_d),
            h=vec(self.theta_h), v=vec(self.theta_v), c=vec(self.theta_c),
            ae=table(self.theta_ae), av=table(self.theta_av), ac=table(self.theta_ac),
            ec=table(self.theta_ec), ab=theta_ab(self.theta_ab.regex),
            motion_long_enough=lengths >= self.durations.t_min,
        )  # fmt: skip

    @cached_property
    def hash(self) -> str:
        """sha256 of θ's canonical JSON: the identity of a θ.

        ``name`` and ``description`` are labels, not parameters: renaming a θ or editing its
        description leaves its hash, and every recipe sampled from it, unchanged.
        """
        return sha256_hex(
            canonical_json(self.model_dump(mode="json", exclude={"name": True, "description": True} | self._absent()))
        )

    def _absent(self) -> dict[str, Any]:
        """Optional parts left out: a θ without ``people``, with the uniform clip start or
        with one look per environment is written (and hashed) as before the part existed."""
        absent: dict[str, Any] = {"people": True} if self.people is None else {}
        if self.motion.start == "uniform":
            absent["motion"] = {"start"}
        if self.world_variety == "environment":
            absent["world_variety"] = True
        return absent

    @property
    def people_sampled(self) -> bool:
        """Whether θ draws people continuously (``people.mode: sampled``) rather than from H."""
        return self.people is not None

    def __eq__(self, other: object) -> bool:
        # Same canonical form, same θ; the cached arrays must not take part in comparison.
        return isinstance(other, Theta) and self.hash == other.hash

    __hash__ = None  # type: ignore[assignment]  # mutable-looking dict fields: not hashable

    def to_yaml(self) -> str:
        """YAML that loads back to an equal θ (the normalised, explicit form)."""
        return yaml.safe_dump(self.model_dump(mode="json", exclude=self._absent()), sort_keys=False, allow_unicode=True)


def _require_keys(fieldname: str, mapping: Mapping[str, Any], registry: Registry) -> None:
    for key in mapping:
        if key not in registry:
            raise ValueError(f"{fieldname}: {unknown_name_message(registry, key)}")
    for name in registry.names:
        if name not in mapping:
            raise ValueError(f"{fieldname}.{name}: missing")


def parse_theta(data: Any, *, source: str = "<theta>") -> Theta:
    """Validate a θ mapping; a problem raises PhavUserError naming ``source`` and the field."""
    if not isinstance(data, Mapping):
        raise PhavUserError("a θ file must hold a mapping at the top level", source=source)
    return validate_user_data(Theta, data, source=source)


def load_theta(path: str | Path) -> Theta:
    """Load θ from a YAML file (``yaml.safe_load``), or a preset by name (``phav-v1``)."""
    given = str(path)
    path = Path(path)
    is_bare_name = "/" not in given and "\\" not in given and path.suffix not in (".yaml", ".yml")
    # A preset's name, unless a file of that name is here (a folder named after the preset,
    # such as a dataset made from it, does not hide it).
    if is_bare_name and not path.is_file() and (PRESETS_DIR / f"{given}.yaml").exists():
        path = PRESETS_DIR / f"{given}.yaml"
    presets = ", ".join(p.stem for p in sorted(PRESETS_DIR.glob("*.yaml")))
    text = read_text(path, hint=f"give a θ file or a preset name ({presets})")
    try:
        data = _load_yaml(text, source=str(path))
    except yaml.YAMLError as e:
        mark = getattr(e, "problem_mark", None)
        where = f"line {mark.line + 1}" if mark is not None else "yaml"
        problem = getattr(e, "problem", None) or str(e).splitlines()[0]
        raise PhavUserError(f"invalid YAML: {problem}", source=str(path), field=where) from None
    except RecursionError:
        raise PhavUserError("invalid YAML: nested too deeply", source=str(path)) from None
    except ValueError as e:  # Python's limit on an integer's digits
        raise PhavUserError(f"invalid YAML: {str(e).splitlines()[0]}", source=str(path)) from None
    return parse_theta(data, source=str(path))


#: libyaml's parser where PyYAML was built with it (about ten times as fast as the pure-Python
#: one, which took most of a second over phav-v1); the values are the same either way.
_LOADER = getattr(yaml, "CSafeLoader", yaml.SafeLoader)


def _load_yaml(text: str, *, source: str) -> Any:
    """The YAML document ``text`` as Python values, parsed once: its node graph is checked
    for keys written twice, then constructed."""
    loader = _LOADER(text)
    try:
        node = loader.get_single_node()
        _refuse_duplicate_keys(node, source=source)
        return loader.construct_document(node) if node is not None else None
    finally:
        loader.dispose()


def _refuse_duplicate_keys(node: yaml.Node | None, *, source: str, visited: set[int] | None = None) -> None:
    """A key written twice in one mapping is an error (YAML would keep the last silently), so
    is one that reads as the same number (``2`` and ``2.0``). Each node is looked at once: an
    alias shares its node, and walking it again at every use grows exponentially."""
    visited = set() if visited is None else visited
    if id(node) in visited:
        return
    visited.add(id(node))
    if isinstance(node, yaml.MappingNode):
        seen: set[object] = set()
        for key, value in node.value:
            name = str(key.value)
            same = _key_value(key)
            if same in seen:
                raise PhavUserError(
                    "key written twice in one mapping; keep one",
                    source=source,
                    field=f"line {key.start_mark.line + 1}: {name}",
                )
            seen.add(same)
            _refuse_duplicate_keys(value, source=source, visited=visited)
    elif isinstance(node, yaml.SequenceNode):
        for item in node.value:
            _refuse_duplicate_keys(item, source=source, visited=visited)


def _key_value(key: yaml.Node) -> object:
    """What a mapping key means: a number as its value (``2`` and ``2.0`` alike), else its text."""
    if isinstance(key, yaml.ScalarNode) and key.tag in ("tag:yaml.org,2002:int", "tag:yaml.org,2002:float"):
        try:
            return float(yaml.safe_load(key.value))
        except (ValueError, TypeError, OverflowError):
            return key.value
    return str(key.value)


def load_preset(name: str = "phav-v1") -> Theta:
    """A θ shipped with the package (``phav-v1`` is the paper's θ)."""
    return load_theta(PRESETS_DIR / f"{name}.yaml")


__all__ = [
    "THETA_FORMAT_VERSION",
    "PeopleTheta",
    "Theta",
    "ThetaArrays",
    "load_preset",
    "load_theta",
    "parse_theta",
]
