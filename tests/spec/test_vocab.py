"""The registries: counts, groups and colours exactly as the paper and DESIGN.md say."""

from collections import Counter

import pytest

from phav_spec.scene import (
    ACTION_SCENES,
    CAMERA_INFO,
    ENVIRONMENT_SCENES,
    HUMAN_MODELS,
    WEATHER_ELEMENTS,
)
from phav_spec.vocab import (
    ACTIONS,
    CAMERAS,
    DAY_PHASES,
    ENVIRONMENTS,
    MUSCLES,
    OBJECTS,
    PIXEL_CLASSES,
    VARIATIONS,
    WEATHERS,
    ActionGroup,
    PixelGroup,
)


def test_counts_match_the_paper():
    assert len(ACTIONS) == 35
    groups = Counter(info.group for _, info in ACTIONS.items())
    assert groups == {
        ActionGroup.SUB_HMDB: 21,
        ActionGroup.ONE_PERSON_SYNTHETIC: 10,
        ActionGroup.TWO_PEOPLE_SYNTHETIC: 4,
    }
    assert all(
        info.n_people == (2 if info.group is ActionGroup.TWO_PEOPLE_SYNTHETIC else 1) for _, info in ACTIONS.items()
    )
    assert ENVIRONMENTS.names == (
        "simple",
        "urban",
        "green",
        "middle",
        "lake",
        "stadium",
        "house_interior",
    )
    assert WEATHERS.names == ("clear", "overcast", "rain", "fog")
    assert DAY_PHASES.names == ("dawn", "day", "dusk", "night")
    assert CAMERAS.names == ("kite", "indoors", "closeup", "static")
    assert VARIATIONS.names == (
        "none",
        "random_perturbation",
        "muscle_weakening",
        "action_blending",
        "objects",
    )
    assert len(MUSCLES) == 15
    assert len(HUMAN_MODELS) == 20


def test_sixty_three_pixel_classes_plus_unlabeled_with_unique_colours():
    assert len(PIXEL_CLASSES) == 64
    assert PIXEL_CLASSES["unlabeled"].rgb == (0, 0, 0) and PIXEL_CLASSES["unlabeled"].class_id == 0
    colours = [pc.rgb for _, pc in PIXEL_CLASSES.items()]
    assert len(set(colours)) == len(colours), [c for c, k in Counter(colours).items() if k > 1]
    assert [pc.class_id for _, pc in PIXEL_CLASSES.items()] == list(range(64))
    groups = Counter(pc.group for _, pc in PIXEL_CLASSES.items())
    assert groups[PixelGroup.VIRTUAL_KITTI] == 14  # vKITTI's 14 incl. GuardRail
    assert groups[PixelGroup.HUMAN_PARTS] == 14 and groups[PixelGroup.HUMAN_JOINTS] == 13
    assert groups[PixelGroup.INDOORS] == 16


@pytest.mark.parametrize(
    ("name", "rgb"),
    [
        ("guard_rail", (250, 100, 255)),  # DESIGN.md: vKITTI's GuardRail
        ("table", (255, 250, 205)),  # the RGB column wins over the LaTeX swatch
        ("left_foot", (255, 239, 213)),  # likewise
        ("bus", (0, 139, 139)),
        ("sky", (90, 200, 255)),
        ("right_ankle", (255, 105, 180)),
    ],
)
def test_colour_table_entries(name, rgb):
    assert PIXEL_CLASSES[name].rgb == rgb


def test_every_prop_renders_with_a_pixel_class():
    for name, pixel_class in OBJECTS.items():
        assert pixel_class in PIXEL_CLASSES, name


def test_unknown_names_raise_with_the_known_ones():
    with pytest.raises(KeyError, match="unknown action 'fly'"):
        ACTIONS.index("fly")


@pytest.mark.parametrize("action", ACTIONS.names)
def test_action_scene_splits_the_fifteen_muscles(action):
    scene = ACTION_SCENES[action]
    assert set(scene.necessary_muscles).isdisjoint(scene.complementary_muscles)
    assert set(scene.necessary_muscles) | set(scene.complementary_muscles) == set(MUSCLES.names)
    assert scene.necessary_muscles, "every action needs some muscles"
    assert (scene.supporting_placement is not None) == (ACTIONS[action].n_people == 2)
    for cls in scene.requires_classes:
        assert any(cls in env.pixel_classes for _, env in ENVIRONMENT_SCENES.items())


@pytest.mark.parametrize("env", ENVIRONMENTS.names)
def test_environment_scene(env):
    scene = ENVIRONMENT_SCENES[env]
    assert scene.indoor == (env == "house_interior")
    assert scene.protagonist_waypoints
    assert bool(scene.background_waypoints) == (not scene.indoor)  # paper: indoor scenes have none
    for cls in scene.pixel_classes:
        assert PIXEL_CLASSES[cls].group not in (PixelGroup.HUMAN_PARTS, PixelGroup.HUMAN_JOINTS)


def test_weather_dependencies_point_backwards_and_cameras_align():
    seen = set()
    for name, element in WEATHER_ELEMENTS.items():
        assert element.parent is None or element.parent in seen
        seen.add(name)
    assert CAMERA_INFO["indoors"].indoor_only and not CAMERA_INFO["kite"].indoor_only
    assert [CAMERA_INFO[c].tracking for c in CAMERAS.names] == [
        "springs",
        "pan",
        "springs",
        "fixed",
    ]
