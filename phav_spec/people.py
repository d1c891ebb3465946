"""A person's body and look, as a recipe stores them: anny's phenotype, skin, hair, outfit.

The body model (``phav_generator.body``) turns the phenotype into a mesh and a ragdoll;
the renderer paints skin, clothes and hair from the rest. Every field is realised (sampled
values, never distributions), so a recipe alone gives the same person anywhere.
"""

from __future__ import annotations

from typing import Annotated, Literal

from pydantic import BaseModel, ConfigDict, Field, model_validator

_FROZEN = ConfigDict(extra="forbid", frozen=True)
Unit = Annotated[float, Field(ge=0.0, le=1.0, allow_inf_nan=False)]
RGB = tuple[
    Annotated[int, Field(ge=0, le=255)],
    Annotated[int, Field(ge=0, le=255)],
    Annotated[int, Field(ge=0, le=255)],
]

#: Tops, bottoms, fabrics and hair styles the renderer draws.
TOPS: tuple[str, ...] = ("sleeveless", "short_sleeves", "long_sleeves")
BOTTOMS: tuple[str, ...] = ("shorts", "skirt", "trousers")
FABRICS: tuple[str, ...] = ("solid", "stripes", "checks", "denim", "print")
HAIR_STYLES: tuple[str, ...] = ("bald", "short", "long", "tied")

TopKind = Literal["sleeveless", "short_sleeves", "long_sleeves"]
BottomKind = Literal["shorts", "skirt", "trousers"]
FabricKind = Literal["solid", "stripes", "checks", "denim", "print"]
HairStyle = Literal["bald", "short", "long", "tied"]


class Phenotype(BaseModel):
    """anny's phenotype parameters, each in [0, 1] (anny's meaning: gender 0 male … 1
    female; age 0 baby, 1/3 child, 2/3 young adult, 1 old; 0.5 is anny's average)."""

    model_config = _FROZEN
    gender: Unit
    age: Unit
    muscle: Unit
    weight: Unit
    height: Unit
    proportions: Unit

    def as_dict(self) -> dict[str, float]:
        return {k: float(v) for k, v in self.model_dump().items()}


class Garment(BaseModel):
    """One piece of clothing: its cut, fabric and two colours (ground and pattern)."""

    model_config = _FROZEN
    kind: str
    fabric: FabricKind
    rgb: RGB
    pattern_rgb: RGB
    scale: Annotated[float, Field(gt=0.0, le=10.0, allow_inf_nan=False)] = 1.0  # pattern size factor


class Top(Garment):
    kind: TopKind


class Bottom(Garment):
    kind: BottomKind


class Outfit(BaseModel):
    """What a person wears: a top, a bottom and shoes."""

    model_config = _FROZEN
    top: Top
    bottom: Bottom
    shoes_rgb: RGB


class Hair(BaseModel):
    """A hair style (drawn as a mesh fitted to the scalp; ``bald`` draws none) and its colour."""

    model_config = _FROZEN
    style: HairStyle
    rgb: RGB


Finite = Annotated[float, Field(allow_inf_nan=False)]
HairColour = Literal["black", "brown", "blond", "red", "grey"]


class HSV(BaseModel):
    """A colour as drawn from θ: hue in degrees, saturation and value in [0, 1]."""

    model_config = _FROZEN
    hue_deg: Annotated[float, Field(ge=0.0, lt=360.0, allow_inf_nan=False)]
    saturation: Unit
    value: Unit


class PersonDraws(BaseModel):
    """What θ's ``people`` section drew for one sampled person, in θ's own units.

    The body and look (phenotype, skin, hair, outfit) are made from these; the recipe keeps
    them so that the validators can test every draw against θ and a reader can see who the
    person is (a 7-year-old girl, a 1.84 m man). Exactly one of the two ages is set: a
    child's age comes from θ's ``child_age_years``, an adult's from ``adult_age_years``.
    """

    model_config = _FROZEN
    female: bool
    adult_age_years: Finite | None
    child_age_years: Finite | None
    stature_z: Finite
    stature_m: Annotated[float, Field(gt=0.0, allow_inf_nan=False)]  # the target the height was solved for
    gender_offset: Unit
    skin_tone: Unit
    skin_undertone: Annotated[float, Field(ge=-1.0, le=1.0, allow_inf_nan=False)]
    hair_colour: HairColour
    hair_shade: Unit
    garment_colours: tuple[HSV, HSV, HSV, HSV]  # top, top pattern, bottom, bottom pattern
    shoes_colour: HSV

    @model_validator(mode="after")
    def _one_age(self) -> PersonDraws:
        if (self.adult_age_years is None) == (self.child_age_years is None):
            raise ValueError("exactly one of adult_age_years and child_age_years is set")
        return self

    @property
    def child(self) -> bool:
        return self.child_age_years is not None

    @property
    def age_years(self) -> float:
        return self.child_age_years if self.child_age_years is not None else self.adult_age_years  # type: ignore[return-value]


__all__ = [
    "BOTTOMS",
    "FABRICS",
    "HAIR_STYLES",
    "HSV",
    "TOPS",
    "Bottom",
    "Garment",
    "Hair",
    "Outfit",
    "PersonDraws",
    "Phenotype",
    "Top",
]
