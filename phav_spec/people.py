"""A person's body and look, as a recipe stores them: anny's phenotype, skin, hair, outfit.

The body model (``phav_generator.body``) turns the phenotype into a mesh and a ragdoll;
the renderer paints skin, clothes and hair from the rest. Every field is realised (sampled
values, never distributions), so a recipe alone gives the same person anywhere.
"""

from __future__ import annotations

from typing import Annotated, Literal

from pydantic import BaseModel, ConfigDict, Field

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
    model_config = _FROZEN
    style: HairStyle
    rgb: RGB


__all__ = [
    "BOTTOMS",
    "FABRICS",
    "HAIR_STYLES",
    "TOPS",
    "Bottom",
    "Garment",
    "Hair",
    "Outfit",
    "Phenotype",
    "Top",
]
