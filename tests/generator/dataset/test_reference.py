"""The reference renders: stage hashes that locate where two machines' bytes part, the
fingerprint's rule (the CPU's SIMD class, not its name) and a manifest of fingerprint
version 1 verifying with today's code."""

from __future__ import annotations

import json
import shutil
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pytest

from phav_generator.dataset import fingerprint
from phav_generator.dataset.fingerprint import renderer_fingerprint
from phav_generator.dataset.reference import (
    PIXEL_STAGES,
    REFERENCE_FILE,
    STAGES,
    compare,
    first_difference,
    load_reference,
    promised_stages,
    structure_hash,
    without_code,
)
from phav_generator.regenerate import compare_hashes, plan_regeneration
from phav_generator.render.context import gl_context, gl_strings
from phav_spec.errors import PhavUserError
from phav_spec.manifest import FINGERPRINT_VERSION, load_manifest
from tests.helpers import invoke_cli, run_cli

V1 = Path(__file__).parents[2] / "golden" / "v1-fingerprint"
GL = {"GL_VENDOR": "Mesa/X.org", "GL_RENDERER": "llvmpipe (LLVM 15.0.6, 256 bits)", "GL_VERSION": "4.5 Mesa 22.3.6"}


@dataclass(frozen=True)
class _Pair:
    a: np.ndarray
    b: tuple[int, ...]


def test_structure_hashes_see_dtype_shape_values_and_nesting_but_not_key_order():
    base = {"x": _Pair(np.zeros((2, 3), np.float32), (1, 2)), "y": [1.5, None, "s"]}
    same = {"y": [1.5, None, "s"], "x": _Pair(np.zeros((2, 3), np.float32), (1, 2))}
    assert structure_hash(base) == structure_hash(same)
    changed = [
        {"x": _Pair(np.zeros((2, 3), np.float64), (1, 2)), "y": [1.5, None, "s"]},
        {"x": _Pair(np.zeros((3, 2), np.float32), (1, 2)), "y": [1.5, None, "s"]},
        {"x": _Pair(np.full((2, 3), 1e-30, np.float32), (1, 2)), "y": [1.5, None, "s"]},
        {"x": _Pair(np.zeros((2, 3), np.float32), (1, 2)), "y": [[1.5, None], "s"]},
        {"x": _Pair(np.zeros((2, 3), np.float32), (1, 2)), "y": [1.5, None, "s"], "z": 0},
    ]
    assert len({structure_hash(c) for c in changed} | {structure_hash(base)}) == len(changed) + 1
    with pytest.raises(TypeError):
        structure_hash(object())


def test_the_first_differing_stage_follows_the_data_flow():
    recorded = {"a": dict.fromkeys(STAGES, "0"), "b": dict.fromkeys(STAGES, "0")}
    traced = {
        "a": dict.fromkeys(STAGES, "0") | {"rgb": "1"},
        "b": dict.fromkeys(STAGES, "0") | {"depth": "1", "rgb": "1"},
    }
    differing = compare(recorded, traced)
    assert differing == {"a": ["rgb"], "b": ["depth", "rgb"]}
    assert first_difference(differing) == "depth"
    assert first_difference(compare(recorded, recorded)) is None


def test_the_shipped_reference_loads_and_a_malformed_one_is_one_error(tmp_path):
    ref = load_reference()
    assert sorted(ref.recipes) == sorted(ref.stages) and len(ref.recipes) >= 2
    assert ref.fingerprint.fingerprint_version == FINGERPRINT_VERSION and ref.fingerprint.cpu_class
    data = json.loads(REFERENCE_FILE.read_text(encoding="utf-8"))
    name = sorted(data["videos"])[0]
    del data["videos"][name]["stages"]["flow"]
    bad = tmp_path / "reference.json"
    bad.write_text(json.dumps(data), encoding="utf-8")
    with pytest.raises(PhavUserError) as e:
        load_reference(bad)
    assert str(bad) in str(e.value) and f"videos.{name}.stages" in str(e.value) and "flow" in str(e.value)


def _fingerprint_on(monkeypatch, model: str, flags: str):
    monkeypatch.setattr(fingerprint, "cpu_fields", lambda: {"model name": model, "flags": flags})
    monkeypatch.setattr(fingerprint.platform, "machine", lambda: "x86_64")
    return renderer_fingerprint(GL)


def test_another_cpu_model_of_the_same_class_is_the_same_renderer(monkeypatch):
    """/proc/cpuinfo faked: the model name is recorded, not compared; the SIMD class is."""
    intel = _fingerprint_on(monkeypatch, "Intel(R) Xeon(R) Platinum 8480+", "fpu sse2 avx avx2 fma avx512f amx_bf16")
    amd = _fingerprint_on(monkeypatch, "AMD EPYC 7B13", "fpu sse2 ssse3 avx avx2 fma")
    old = _fingerprint_on(monkeypatch, "Intel(R) Core(TM)2 Duo", "fpu sse2 ssse3 sse4_1")
    avx_only = _fingerprint_on(monkeypatch, "Intel(R) Core(TM) i7-2600", "fpu sse2 ssse3 sse4_1 avx")  # not measured
    assert intel.cpu_model != amd.cpu_model and intel.differences(amd) == [] and intel.digest() == amd.digest()
    assert intel.differences(old) == ["cpu_class"] and old.cpu_class == "x86-64-ssse3"
    assert intel.differences(avx_only) == ["cpu_class"] and avx_only.cpu_class == "x86-64-avx1"
    monkeypatch.setenv("GALLIUM_OVERRIDE_CPU_CAPS", "sse2")  # llvmpipe told to use SSE2 only
    assert _fingerprint_on(monkeypatch, "AMD EPYC 7B13", "fpu sse2 ssse3 avx avx2").cpu_class == "x86-64-sse2"


def test_a_manifest_of_fingerprint_version_1_verifies_by_todays_rule(tmp_path):
    """Written by 1afb1c9 (CPU model and flags in its fingerprint): it loads, compares by the
    class its flags give, and its video regenerates bit for bit where the rule says so."""
    manifest = load_manifest(V1 / "manifest.json")
    old = manifest.renderer
    assert old is not None and old.fingerprint_version == 1 and old.cpu_flags and old.simd_class == "x86-64-avx"
    assert "cpu_model" not in old.key() and "cpu_flags" not in old.key()
    source = tmp_path / "v1"
    shutil.copytree(V1, source)
    plan = plan_regeneration(source / "manifest.json", videos=None)
    result = invoke_cli("regenerate", str(source / "manifest.json"), "--out", str(tmp_path / "rebuilt"))
    assert result.returncode in (0, 1), result.stderr
    rebuilt = load_manifest(tmp_path / "rebuilt" / "manifest.json")
    report = compare_hashes(plan.expected, rebuilt)
    ctx = gl_context()
    try:
        here = renderer_fingerprint(gl_strings(ctx))
    finally:
        ctx.release()
    assert report.exact == (old.differences(here) == [])
    if report.exact:
        assert report.matched == report.compared == 1 and result.returncode == 0
    else:
        assert report.renderer_differs == old.differences(here) and "equal pixels not promised" in report.summary()


def test_phav_fingerprint_checks_the_reference_and_names_a_broken_promise(tmp_path):
    mine = tmp_path / "mine.json"
    result = invoke_cli("fingerprint", "--json", str(mine))
    assert result.returncode == 0, result.stdout
    assert "class" in result.stdout and "reference: recorded on" in result.stdout
    assert load_reference(mine).stages  # another machine's --json is a reference
    again = invoke_cli("fingerprint", "--reference", str(mine))
    assert again.returncode == 0 and "every stage of 2 reference videos is identical" in again.stdout
    data = json.loads(mine.read_text(encoding="utf-8"))
    name = sorted(data["videos"])[0]
    data["videos"][name]["stages"]["raw_rgb"] = "0" * 64
    tampered = tmp_path / "tampered.json"
    tampered.write_text(json.dumps(data), encoding="utf-8")
    broken = invoke_cli("fingerprint", "--reference", str(tampered))
    assert broken.returncode == 1 and "first stage that differs (≠) is raw_rgb" in broken.stdout
    assert "the fingerprint promises identical raw_rgb, and the bytes differ" in broken.stdout


def test_a_cpu_held_to_avx_renders_the_reference_bytes():
    """Mesa's capability override stands in for a CPU without AVX2, FMA or AVX-512: llvmpipe
    compiles for AVX only, the fingerprint keeps its class, and every stage is identical;
    held to SSE4.1 it is another class, and says so."""
    avx = run_cli("fingerprint", env={"GALLIUM_OVERRIDE_CPU_CAPS": "avx"})
    if "same renderer" not in avx.stdout:
        pytest.skip(f"this machine is not the reference's renderer: {avx.stdout.splitlines()[-1:]}")
    assert avx.returncode == 0 and "every stage of 2 reference videos is identical" in avx.stdout
    sse = run_cli("fingerprint", "--no-check", env={"GALLIUM_OVERRIDE_CPU_CAPS": "sse4.1"})
    assert sse.returncode == 0 and "differs in cpu_class, gl_renderer" in sse.stdout


def test_the_source_hash_moves_with_any_code_or_shader_edit_and_nothing_else(tmp_path):
    """A shader edit within one phav version changes pixels: the fingerprint must see it."""
    shaders = Path(fingerprint.__file__).parents[1] / "render" / "shaders"
    copy = tmp_path / "phav_generator" / "render"
    shutil.copytree(shaders, copy / "shaders", ignore=shutil.ignore_patterns("__pycache__"))
    root = tmp_path / "phav_generator"
    before = fingerprint.tree_sha256([root])
    (copy / "shaders" / "__pycache__").mkdir()
    (copy / "shaders" / "__pycache__" / "x.cpython-311.pyc").write_bytes(b"compiled")
    (copy / "notes.txt").write_text("not code", encoding="utf-8")
    assert fingerprint.tree_sha256([root]) == before
    tone = copy / "shaders" / "tone.glsl"
    tone.write_text(tone.read_text(encoding="utf-8") + "\n", encoding="utf-8")
    edited = fingerprint.tree_sha256([root])
    tone.rename(copy / "shaders" / "tone2.glsl")  # the same bytes under another name
    assert len({before, edited, fingerprint.tree_sha256([root])}) == 3
    versions = renderer_fingerprint(GL).versions
    assert versions[fingerprint.SOURCE_KEY] == fingerprint.source_sha256()


def test_code_keys_are_compared_where_a_reference_records_them():
    """The package's reference records the machine only, so an edit to phav's code is tested
    by its bytes (the golden render test fails) instead of skipped; another machine's
    ``--json`` records the code too, and a different code promises nothing."""
    shipped = load_reference().fingerprint
    assert not set(shipped.versions) & set(fingerprint.CODE_KEYS)
    here = renderer_fingerprint(GL)
    edited = here.model_copy(update={"versions": here.versions | {fingerprint.SOURCE_KEY: "0" * 64}})
    assert promised_stages(shipped, edited) == promised_stages(shipped, here)
    assert promised_stages(here, here) == STAGES and promised_stages(here, edited) == ()
    assert here.differences(edited) == [f"versions.{fingerprint.SOURCE_KEY}"]
    assert without_code(here).differences(without_code(edited)) == []


def test_the_reference_clips_owe_their_pixels_across_numerics_and_a_dataset_does_not():
    """numpy's and OpenBLAS's kernels count for a dataset's pixels (the physics carries their
    last bits into a whole clip's motion), but the 0.2 s reference clips are too short for
    that (measured): a machine differing in the numerics alone still owes their pixels, not
    their trajectory; one differing in anything else owes nothing."""
    here = renderer_fingerprint(GL)
    other_blas = here.model_copy(update={"numeric_class": "numpy baseline; OpenBLAS Prescott"})
    assert here.differences(other_blas) == ["numeric_class"]
    assert promised_stages(here, other_blas) == ("recipe", "body", *PIXEL_STAGES)
    both = other_blas.model_copy(update={"gl_renderer": "llvmpipe (LLVM 19.1.7, 256 bits)"})
    assert promised_stages(here, both) == ()
