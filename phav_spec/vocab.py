"""Vocabularies of the PHAV generative model, declared once.

Every categorical value is one snake_case string. The sampler, the CLI, the validators and
the parameterised tests all read these registries; nothing else lists actions, environments
or pixel classes. Order is significant: it fixes the column order of every θ table and the
class ids of the semantic label maps.
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import StrEnum
from types import MappingProxyType
from typing import Generic, TypeVar

T = TypeVar("T")


class Registry(Generic[T]):
    """An ordered, immutable name → entry table with index lookup and helpful errors."""

    def __init__(self, kind: str, entries: tuple[tuple[str, T], ...]):
        names = [name for name, _ in entries]
        if len(set(names)) != len(names):
            raise ValueError(f"duplicate {kind} names in registry")
        for name in names:
            if not name.isidentifier() or name != name.lower():
                raise ValueError(f"{kind} name {name!r} is not snake_case")
        self.kind = kind
        self.names: tuple[str, ...] = tuple(names)
        self._entries = MappingProxyType(dict(entries))
        self._index = MappingProxyType({name: i for i, name in enumerate(names)})

    def __len__(self) -> int:
        return len(self.names)

    def __iter__(self):
        return iter(self.names)

    def __contains__(self, name: object) -> bool:
        try:
            return name in self._index
        except TypeError:  # unhashable (a list or a mapping from a malformed file): no name
            return False

    def __getitem__(self, name: str) -> T:
        self.check(name)
        return self._entries[name]

    def index(self, name: str) -> int:
        """Position of ``name`` in the registry (column index in θ tables)."""
        self.check(name)
        return self._index[name]

    def items(self) -> tuple[tuple[str, T], ...]:
        """(name, entry) pairs in registry order."""
        return tuple((name, self._entries[name]) for name in self.names)

    def check(self, name: str) -> str:
        """Return ``name`` if it is known, else raise ``KeyError`` listing close names."""
        if name not in self._index:
            raise KeyError(f"unknown {self.kind} {name!r}; expected one of: {', '.join(self.names)}")
        return name


class ActionGroup(StrEnum):
    """The three groups of the paper's action table."""

    SUB_HMDB = "sub_hmdb"
    ONE_PERSON_SYNTHETIC = "one_person_synthetic"
    TWO_PEOPLE_SYNTHETIC = "two_people_synthetic"


@dataclass(frozen=True)
class ActionInfo:
    group: ActionGroup
    n_people: int


def _actions() -> tuple[tuple[str, ActionInfo], ...]:
    sub_hmdb = (
        "brush_hair", "catch", "clap", "climb_stairs", "golf", "jump", "kick_ball", "push",
        "pick", "pour", "pull_up", "run", "shoot_ball", "shoot_bow", "shoot_gun", "sit",
        "stand", "swing_baseball", "throw", "walk", "wave",
    )  # fmt: skip
    one_person = (
        "car_hit", "crawl", "dive_floor", "flee", "hop", "leg_split", "limp", "moonwalk",
        "stagger", "surrender",
    )  # fmt: skip
    two_people = ("walking_hug", "walk_holding_hands", "walk_the_line", "bump_into_each_other")
    return (
        tuple((a, ActionInfo(ActionGroup.SUB_HMDB, 1)) for a in sub_hmdb)
        + tuple((a, ActionInfo(ActionGroup.ONE_PERSON_SYNTHETIC, 1)) for a in one_person)
        + tuple((a, ActionInfo(ActionGroup.TWO_PEOPLE_SYNTHETIC, 2)) for a in two_people)
    )


#: The 35 action categories of the paper's Table "Action categories included in PHAV".
ACTIONS: Registry[ActionInfo] = Registry("action", _actions())

#: Environments (paper Table "key random variables"); `simple` is a plain ground plane.
ENVIRONMENTS: Registry[None] = Registry(
    "environment",
    tuple((e, None) for e in ("simple", "urban", "green", "middle", "lake", "stadium", "house_interior")),
)
WEATHERS: Registry[None] = Registry("weather", tuple((w, None) for w in ("clear", "overcast", "rain", "fog")))
DAY_PHASES: Registry[None] = Registry("day_phase", tuple((d, None) for d in ("dawn", "day", "dusk", "night")))
CAMERAS: Registry[None] = Registry("camera", tuple((c, None) for c in ("kite", "indoors", "closeup", "static")))
VARIATIONS: Registry[None] = Registry(
    "variation",
    tuple((v, None) for v in ("none", "random_perturbation", "muscle_weakening", "action_blending", "objects")),
)

#: The 15 ragdoll bodies ("muscles") of the paper's Figure "Ragdoll configuration".
MUSCLES: Registry[None] = Registry(
    "muscle",
    tuple(
        (m, None)
        for m in (
            "pelvis", "chest", "head",
            "left_upper_arm", "left_lower_arm", "left_hand",
            "right_upper_arm", "right_lower_arm", "right_hand",
            "left_upper_leg", "left_lower_leg", "left_foot",
            "right_upper_leg", "right_lower_leg", "right_foot",
        )
    ),
)  # fmt: skip


class PixelGroup(StrEnum):
    """Groups of the paper's pixel-class table (appendix)."""

    VOID = "void"
    VIRTUAL_KITTI = "virtual_kitti"
    INDOORS = "indoors"
    INTERACTION_OBJECTS = "interaction_objects"
    PHAV_ONLY = "phav_only"
    HUMAN_PARTS = "human_parts"
    HUMAN_JOINTS = "human_joints"


@dataclass(frozen=True)
class PixelClass:
    class_id: int
    rgb: tuple[int, int, int]
    group: PixelGroup


def _pixel_classes() -> tuple[tuple[str, PixelClass], ...]:
    g = PixelGroup
    rows: list[tuple[str, tuple[int, int, int], PixelGroup]] = [
        ("unlabeled", (0, 0, 0), g.VOID),
        # Virtual KITTI / CityScapes. GuardRail is vKITTI's 14th class, missing from the
        # paper's table although the text promises all 14 (DESIGN.md).
        ("road", (100, 60, 100), g.VIRTUAL_KITTI),
        ("building", (140, 140, 140), g.VIRTUAL_KITTI),
        ("pole", (255, 130, 0), g.VIRTUAL_KITTI),
        ("traffic_light", (200, 200, 0), g.VIRTUAL_KITTI),
        ("traffic_sign", (255, 255, 0), g.VIRTUAL_KITTI),
        ("vegetation", (90, 240, 0), g.VIRTUAL_KITTI),
        ("terrain", (210, 0, 200), g.VIRTUAL_KITTI),
        ("sky", (90, 200, 255), g.VIRTUAL_KITTI),
        ("car", (255, 127, 80), g.VIRTUAL_KITTI),
        ("truck", (160, 60, 60), g.VIRTUAL_KITTI),
        ("bus", (0, 139, 139), g.VIRTUAL_KITTI),
        ("misc", (80, 80, 80), g.VIRTUAL_KITTI),
        ("tree", (0, 199, 0), g.VIRTUAL_KITTI),
        ("guard_rail", (250, 100, 255), g.VIRTUAL_KITTI),
        # ADE20k indoors. Table: the RGB columns (255, 250, 205) win over the LaTeX swatch.
        ("ceiling", (240, 230, 140), g.INDOORS),
        ("floor", (0, 191, 255), g.INDOORS),
        ("chair", (72, 61, 139), g.INDOORS),
        ("table", (255, 250, 205), g.INDOORS),
        ("bed", (205, 92, 92), g.INDOORS),
        ("lamp", (160, 82, 45), g.INDOORS),
        ("sofa", (128, 0, 128), g.INDOORS),
        ("window", (0, 128, 0), g.INDOORS),
        ("door", (127, 255, 212), g.INDOORS),
        ("stairs", (219, 112, 147), g.INDOORS),
        ("curtain", (230, 230, 250), g.INDOORS),
        ("fireplace", (233, 150, 122), g.INDOORS),
        ("shelf", (153, 50, 204), g.INDOORS),
        ("bench", (245, 222, 179), g.INDOORS),
        ("screen", (218, 165, 32), g.INDOORS),
        ("fridge", (255, 255, 240), g.INDOORS),
        # Interaction objects.
        ("ball", (178, 34, 34), g.INTERACTION_OBJECTS),
        ("baseball_bat", (210, 105, 30), g.INTERACTION_OBJECTS),
        ("gun", (255, 248, 220), g.INTERACTION_OBJECTS),
        ("golf_club", (173, 255, 47), g.INTERACTION_OBJECTS),
        ("hair_brush", (224, 255, 255), g.INTERACTION_OBJECTS),
        ("bow", (95, 158, 160), g.PHAV_ONLY),
        # Human parts. LeftFoot: the RGB columns (255, 239, 213) win over the swatch.
        ("head", (220, 20, 60), g.HUMAN_PARTS),
        ("right_upper_arm", (255, 255, 26), g.HUMAN_PARTS),
        ("right_lower_arm", (255, 215, 0), g.HUMAN_PARTS),
        ("right_hand", (255, 140, 0), g.HUMAN_PARTS),
        ("left_upper_arm", (60, 179, 113), g.HUMAN_PARTS),
        ("left_lower_arm", (135, 206, 235), g.HUMAN_PARTS),
        ("left_hand", (100, 149, 237), g.HUMAN_PARTS),
        ("chest", (248, 248, 255), g.HUMAN_PARTS),
        ("right_upper_leg", (102, 51, 153), g.HUMAN_PARTS),
        ("right_lower_leg", (164, 89, 58), g.HUMAN_PARTS),
        ("right_foot", (220, 173, 116), g.HUMAN_PARTS),
        ("left_upper_leg", (0, 0, 139), g.HUMAN_PARTS),
        ("left_lower_leg", (255, 182, 193), g.HUMAN_PARTS),
        ("left_foot", (255, 239, 213), g.HUMAN_PARTS),
        # Human joints.
        ("neck", (152, 251, 152), g.HUMAN_JOINTS),
        ("left_shoulder", (47, 79, 79), g.HUMAN_JOINTS),
        ("right_shoulder", (85, 107, 47), g.HUMAN_JOINTS),
        ("left_elbow", (25, 25, 112), g.HUMAN_JOINTS),
        ("right_elbow", (128, 0, 0), g.HUMAN_JOINTS),
        ("left_wrist", (0, 255, 255), g.HUMAN_JOINTS),
        ("right_wrist", (238, 130, 238), g.HUMAN_JOINTS),
        ("left_hip", (147, 112, 219), g.HUMAN_JOINTS),
        ("right_hip", (143, 188, 139), g.HUMAN_JOINTS),
        ("left_knee", (102, 0, 102), g.HUMAN_JOINTS),
        ("right_knee", (69, 33, 84), g.HUMAN_JOINTS),
        ("left_ankle", (50, 205, 50), g.HUMAN_JOINTS),
        ("right_ankle", (255, 105, 180), g.HUMAN_JOINTS),
    ]
    return tuple((name, PixelClass(i, rgb, group)) for i, (name, rgb, group) in enumerate(rows))


#: The 63 pixel classes of the appendix table plus GuardRail, and `unlabeled` (id 0) as void.
PIXEL_CLASSES: Registry[PixelClass] = Registry("pixel class", _pixel_classes())

#: Props an action can use. Each renders with a pixel class; props without a class of their
#: own (cup, pull-up bar) use `misc` (DESIGN.md).
OBJECTS: Registry[str] = Registry(
    "object",
    (
        ("ball", "ball"),
        ("baseball_bat", "baseball_bat"),
        ("gun", "gun"),
        ("golf_club", "golf_club"),
        ("hair_brush", "hair_brush"),
        ("bow", "bow"),
        ("cup", "misc"),
        ("bottle", "misc"),
        ("pull_up_bar", "misc"),
        ("chair", "chair"),
        ("bench", "bench"),
        ("car", "car"),
        ("truck", "truck"),
        ("bus", "bus"),
        ("box", "misc"),
        ("shopping_cart", "misc"),
        ("door", "door"),
    ),
)

#: Every vocabulary, by name (``phav spec vocab``).
VOCABULARIES: dict[str, Registry] = {
    "action": ACTIONS,
    "environment": ENVIRONMENTS,
    "weather": WEATHERS,
    "day_phase": DAY_PHASES,
    "camera": CAMERAS,
    "variation": VARIATIONS,
    "muscle": MUSCLES,
    "pixel_class": PIXEL_CLASSES,
    "object": OBJECTS,
}
