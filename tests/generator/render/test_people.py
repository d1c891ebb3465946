"""A person as drawn: anny's mesh skinned to the ragdoll in the shader, its labels, levels of
detail and hair; forward flow on a bending limb against the next frame."""

from __future__ import annotations

import numpy as np
import pytest

from phav_generator.body.model import rest_body
from phav_generator.motion.rotations import look_at
from phav_generator.motion.skeleton import DOF_INDEX, N_DOFS, forward_kinematics
from phav_generator.render.clothes import ATLAS, STRIP
from phav_generator.render.gl import Drawable, FrameRenderer
from phav_generator.render.meshes import box
from phav_generator.render.people import level_of_detail, person_drawables, person_mesh
from phav_spec.people import Bottom, Outfit, Phenotype, Top
from phav_spec.vocab import PIXEL_CLASSES

W, H = 340, 256
INTRINSICS = (520.0, 520.0, 170.0, 128.0)
PHENOTYPE = Phenotype(gender=0.2, age=0.75, muscle=0.5, weight=0.5, height=0.3, proportions=0.5)
OUTFIT = Outfit(
    top=Top(kind="short_sleeves", fabric="stripes", rgb=(30, 60, 140), pattern_rgb=(220, 220, 220)),
    bottom=Bottom(kind="trousers", fabric="denim", rgb=(40, 50, 80), pattern_rgb=(60, 70, 110)),
    shoes_rgb=(20, 20, 20),
)
PARTS = ("head", "chest", "left_upper_arm", "left_lower_arm", "left_hand", "right_upper_arm", "right_lower_arm",
         "right_hand", "left_upper_leg", "left_lower_leg", "left_foot", "right_upper_leg", "right_lower_leg",
         "right_foot")  # fmt: skip
JOINTS = ("neck", "left_shoulder", "right_shoulder", "left_elbow", "right_elbow", "left_wrist", "right_wrist",
          "left_hip", "right_hip", "left_knee", "right_knee", "left_ankle", "right_ankle")  # fmt: skip


def _pose(q: np.ndarray):
    dims = rest_body(PHENOTYPE).dims
    n = len(q)
    root = np.tile([0.0, 0.0, dims.standing_pelvis_height], (n, 1))
    return forward_kinematics(dims, root, np.tile([1.0, 0.0, 0.0, 0.0], (n, 1)), q)


def _camera(eye, target) -> np.ndarray:
    m = np.eye(4)
    m[:3, :3] = look_at(np.asarray(eye, float), np.asarray(target, float))
    m[:3, 3] = eye
    return m


def _render(ctx, drawables, cam, frame=0):
    with FrameRenderer(ctx, W, H, drawables, sky_class=8) as r:
        return r.render(frame, cam, cam, INTRINSICS)


@pytest.mark.parametrize("level", [0, 1, 2, 3])
def test_every_part_and_joint_class_is_on_the_mesh(level):
    pm = person_mesh(PHENOTYPE, OUTFIT, level)
    present = set(pm.class_ids.tolist())
    for name in PARTS[:1] + PARTS[1:] + JOINTS:
        if level >= 2 and name.endswith(("wrist", "ankle", "elbow")):
            continue  # coarse meshes may have no vertex within a thin joint's reach
        assert PIXEL_CLASSES[name].class_id in present, name
    assert pm.mesh.n_triangles == (27420, 2454, 1226, 734)[level]
    np.testing.assert_allclose(pm.mesh.weights.sum(axis=1), 1.0, atol=1e-6)


def test_levels_of_detail_go_coarser_as_people_get_smaller():
    levels = [level_of_detail(px) for px in (500, 400, 399, 120, 119, 40, 39, 0)]
    assert levels == [0, 0, 1, 1, 2, 2, 3, 3]


def test_forward_flow_of_a_bending_elbow_lands_on_the_same_part_in_the_next_frame(ctx):
    """The shader skins each vertex at t and t + 1: following a pixel of the bending arm by
    its flow lands on the same body part in the next frame, where zero flow does not."""
    q = np.zeros((2, N_DOFS))
    q[:, DOF_INDEX["left_shoulder_abd"]] = 1.4  # the arm out to the side, seen from the front
    q[1, DOF_INDEX["left_elbow_flex"]] = 0.8
    pos, rot = _pose(q)
    person = person_drawables(PHENOTYPE, (224, 172, 105), OUTFIT, "short", (60, 40, 20), pos, rot, 1)
    ground = np.eye(4)
    scene = [Drawable(box((5, 5, 0.01)), np.stack([ground, ground]), 2), *person]
    cam = _camera([2.6, 0.45, 1.3], [0.0, 0.45, 1.3])
    with FrameRenderer(ctx, W, H, scene, sky_class=8) as r:
        f0 = r.render(0, cam, cam, INTRINSICS)
        f1 = r.render(1, cam, cam, INTRINSICS)
    forearm = PIXEL_CLASSES["left_lower_arm"].class_id
    v, u = np.nonzero((f0.class_id == forearm) & f0.flow_valid)
    assert len(u) > 200
    moved = np.hypot(f0.flow[v, u, 0], f0.flow[v, u, 1])
    assert np.median(moved) > 4.0, "the forearm swings by several pixels"
    tu = np.clip(np.rint(u + 0.5 + f0.flow[v, u, 0] - 0.5).astype(int), 0, W - 1)
    tv = np.clip(np.rint(v + 0.5 + f0.flow[v, u, 1] - 0.5).astype(int), 0, H - 1)
    followed = np.mean(f1.class_id[tv, tu] == forearm)
    stayed = np.mean(f1.class_id[v, u] == forearm)
    assert followed > 0.95 and followed > stayed + 0.2


@pytest.mark.parametrize("style", ["bald", "short", "long", "tied"])
def test_hair_styles_cover_the_head_with_the_hair_colour(ctx, style):
    pos, rot = _pose(np.zeros((1, N_DOFS)))
    person = person_drawables(PHENOTYPE, (224, 172, 105), OUTFIT, style, (200, 30, 30), pos, rot, 1)
    assert len(person) == (1 if style == "bald" else 2)
    head_top = pos[0, 2] + np.array([0.0, 0.0, 0.2])
    frame = _render(ctx, person, _camera(head_top + np.array([-1.0, 0.0, 0.4]), head_top))
    red = (frame.colour[..., 0] > 1.6 * frame.colour[..., 1]) & (frame.instance == 1)
    assert (red.sum() > 200) == (style != "bald")


def test_a_skirt_is_a_flared_tube_from_the_waist_over_the_thighs():
    shorts = person_mesh(
        PHENOTYPE, OUTFIT.model_copy(update={"bottom": OUTFIT.bottom.model_copy(update={"kind": "shorts"})})
    )
    skirt = person_mesh(
        PHENOTYPE, OUTFIT.model_copy(update={"bottom": OUTFIT.bottom.model_copy(update={"kind": "skirt"})})
    )
    extra = len(skirt.mesh.positions) - len(shorts.mesh.positions)
    assert extra > 100 and skirt.mesh.n_triangles > shorts.mesh.n_triangles
    tube = skirt.mesh.positions[-extra:]
    strip_top = STRIP / (ATLAS + STRIP)
    assert np.all(skirt.uvs[-extra:, 1] < strip_top), "the skirt's texels: the strip below the atlas"
    assert np.all(skirt.uvs[:-extra, 1] >= strip_top)
    body = rest_body(PHENOTYPE)
    trunk = body.vertices[np.argmax(body.weights, axis=1) <= 1]  # pelvis and chest (the arms hang beside)
    hips = trunk[np.abs(trunk[:, 2] - tube[:, 2].max()) < 0.01]
    width = np.ptp(tube[tube[:, 2] > tube[:, 2].max() - 1e-6][:, 1])
    assert width >= np.ptp(hips[:, 1]) * 0.95, "the waist ring wraps the hips"
    hem = tube[tube[:, 2] < tube[:, 2].min() + 1e-6]
    assert np.ptp(hem[:, 1]) > width, "flared at the hem"


def test_a_garments_pattern_scale_sets_the_size_of_its_stripes(ctx):
    """Stripes twice the size: fewer changes between ground and pattern down the chest."""
    pos, rot = _pose(np.zeros((1, N_DOFS)))
    chest = pos[0, 1] + np.array([0.0, 0.0, 0.15])
    cam = _camera(chest + np.array([1.2, 0.0, 0.0]), chest)
    changes = []
    for scale in (1.0, 2.0):
        top = OUTFIT.top.model_copy(update={"scale": scale, "rgb": (250, 250, 250), "pattern_rgb": (10, 10, 10)})
        person = person_drawables(PHENOTYPE, (224, 172, 105), OUTFIT.model_copy(update={"top": top}), "bald",
                                  (0, 0, 0), pos, rot, 1)  # fmt: skip
        frame = _render(ctx, person, cam)
        column = frame.colour[:, W // 2, 0].astype(int)
        on_chest = frame.class_id[:, W // 2] == PIXEL_CLASSES["chest"].class_id
        bright = column[on_chest] > 128
        changes.append(int(np.count_nonzero(np.diff(bright))))
    assert changes[0] >= 4 and changes[1] < changes[0], changes


def test_meshes_hair_and_clothes_are_kept_per_body_data(monkeypatch):
    """The per-process memos are kept per body data: body data of another build (another
    PHAV_CACHE_DIR, or rebuilt) never gets a mesh or texture made from the one before."""
    import dataclasses

    from phav_generator.body.data import load_body_data
    from phav_generator.render import clothes, people

    mesh, hair = person_mesh(PHENOTYPE, OUTFIT, 3), people.hair_mesh(PHENOTYPE, "short", 3)
    texture = clothes.outfit_texture(OUTFIT, (224, 172, 105))
    assert person_mesh(PHENOTYPE, OUTFIT, 3) is mesh and people.hair_mesh(PHENOTYPE, "short", 3) is hair
    other = dataclasses.replace(load_body_data())  # another instance: other data, as far as a memo can tell
    monkeypatch.setattr(people, "load_body_data", lambda: other)
    monkeypatch.setattr(clothes, "load_body_data", lambda: other)
    assert person_mesh(PHENOTYPE, OUTFIT, 3) is not mesh and people.hair_mesh(PHENOTYPE, "short", 3) is not hair
    assert clothes.outfit_texture(OUTFIT, (224, 172, 105)) is not texture
