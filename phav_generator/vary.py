"""``phav vary``: a counterfactual recipe that changes only the named variables.

The recipe is re-sampled from its own (θ, dataset seed, index) with the named variables
forced (``RecipeSampler.sample(force=…)``): every random draw is the same, so seeds, the
action, people, motion and everything not downstream of a forced variable stay as they
were, while what θ makes depend on it (the clock on the day phase, weather elements on the
weather, a camera's parameters on its kind) follows from the same uniforms.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from pydantic import ValidationError

from phav_generator.sampling import VARIABLES, RecipeSampler
from phav_spec.errors import PhavUserError, format_validation_error
from phav_spec.recipe import Recipe
from phav_spec.scene import CAMERA_INFO
from phav_spec.theta import Theta
from phav_spec.vocab import CAMERAS, DAY_PHASES, WEATHERS

_CHOICES = {"weather": WEATHERS, "day_phase": DAY_PHASES, "camera": CAMERAS}
_BOOLEANS = ("rain", "fog", "clouds", "wet_ground")
#: Each weather element with an intensity, and that intensity's variable.
_INTENSITIES = {"clouds": "cloud_intensity", "fog": "fog_intensity", "rain": "rain_intensity"}


def parse_settings(items: list[str]) -> dict[str, Any]:
    """``["weather=fog", "clock_hour=21.5"]`` → typed values, with one-line errors."""
    out: dict[str, Any] = {}
    for item in items:
        key, sep, text = item.partition("=")
        key, text = key.strip(), text.strip()
        if not sep or not key:
            raise PhavUserError(f"expected NAME=VALUE, got {item!r}", field="--set")
        if key in out:  # the last would silently win
            raise PhavUserError(f"{key} is set twice; set it once", field="--set")
        if key not in VARIABLES:
            raise PhavUserError(f"unknown variable {key!r}; choose from {', '.join(VARIABLES)}", field="--set")
        if key in _CHOICES:
            if text not in _CHOICES[key]:
                raise PhavUserError(f"{key} must be one of {', '.join(_CHOICES[key].names)}", field=f"--set {key}")
            out[key] = text
        elif key in _BOOLEANS:
            if text.lower() not in ("true", "false", "1", "0", "on", "off"):
                raise PhavUserError(f"{key} must be true or false, got {text!r}", field=f"--set {key}")
            out[key] = text.lower() in ("true", "1", "on")
        else:
            try:
                value = float(text)
            except ValueError:
                raise PhavUserError(f"{key} must be a number, got {text!r}", field=f"--set {key}") from None
            if key == "clock_hour" and not 0.0 <= value < 24.0:
                raise PhavUserError("clock_hour must be in [0, 24)", field="--set clock_hour")
            out[key] = value
    return out


def drawn_sampler(recipe: Recipe, theta: Theta) -> RecipeSampler:
    """The sampler of θ, the one ``recipe`` records (a user error naming ``theta_hash``
    otherwise): ``.sample(recipe.dataset_seed, recipe.index)`` is what it gives."""
    if theta.hash != recipe.theta_hash:
        raise PhavUserError(
            f"the recipe was sampled from θ {recipe.theta_hash[:12]}…, not {theta.hash[:12]}…; "
            "pass that θ with --theta",
            field="theta_hash",
        )
    return RecipeSampler(theta)


def vary(recipe: Recipe, theta: Theta, settings: Mapping[str, Any]) -> Recipe:
    """The counterfactual of ``recipe`` with ``settings`` forced (see the module doc)."""
    sampler = drawn_sampler(recipe, theta)
    if sampler.sample(recipe.dataset_seed, recipe.index) != recipe:
        raise PhavUserError(
            "this recipe is not what θ and its seed give (edited by hand, or from another phav version); "
            "it cannot be varied consistently",
            field=recipe.video_id,
        )
    camera = settings.get("camera")
    if camera is not None and CAMERA_INFO[camera].indoor_only and not recipe.environment.indoor:
        raise PhavUserError(f"camera {camera} films indoors only; {recipe.video_id} is in {recipe.environment.name}",
                            field="--set camera")  # fmt: skip
    try:
        varied = sampler.sample(recipe.dataset_seed, recipe.index, force=settings)
    except ValidationError as e:  # a value out of its range: name the recipe field it would set
        where, message = format_validation_error(e)
        raise PhavUserError(f"the varied recipe is invalid: {where}: {message}", field="--set") from None
    except ValueError as e:
        raise PhavUserError(f"the varied recipe is invalid: {str(e).splitlines()[0]}", field="--set") from None
    _check_intensities(varied, settings)
    return varied


def _check_intensities(varied: Recipe, settings: Mapping[str, Any]) -> None:
    """Refuse a weather element forced on where θ's weather draws it at intensity 0 (fog in
    clear weather): the recipe would be drawn with next to none (fog as a 1 km haze)."""
    world = varied.world
    for element, key in _INTENSITIES.items():
        if settings.get(element) is True and key not in settings and getattr(world, key) == 0.0:
            raise PhavUserError(
                f"{element}=true in {world.weather} weather: θ draws its {key} as 0 there, which would show "
                f"next to no {element}; set {key} too, or a weather in which θ draws {element}",
                field=f"--set {element}",
            )
