"""What a manifest's fingerprint records: phav's version even when it runs from a source checkout,
the CPU's model and SIMD class."""

from __future__ import annotations

import contextlib
import errno
import tomllib
from importlib.metadata import PackageNotFoundError
from pathlib import Path

import pytest

from phav_generator.dataset import fingerprint
from phav_generator.dataset.fingerprint import package_version
from phav_spec.files import WriteError

ROOT = Path(__file__).resolve().parents[3]


def _not_installed(name: str) -> str:
    raise PackageNotFoundError(name)


def test_phav_run_from_a_checkout_reports_its_pyproject_version(monkeypatch):
    monkeypatch.setattr(fingerprint, "version", _not_installed)
    declared = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))["project"]["version"]
    assert package_version("phav") == declared != "unknown"
    assert package_version("numpy") == "unknown"  # only phav has a source tree to read


def test_a_missing_pyproject_leaves_phav_unknown(monkeypatch, tmp_path):
    monkeypatch.setattr(fingerprint, "version", _not_installed)
    monkeypatch.setattr(fingerprint, "_PYPROJECT", tmp_path / "pyproject.toml")
    assert package_version("phav") == "unknown"


def test_the_fingerprint_records_the_first_processors_model_and_simd_class(monkeypatch):
    monkeypatch.setattr(fingerprint.platform, "machine", lambda: "x86_64")
    flags = "sse2 avx avx2 fma avx512_bf16"
    monkeypatch.setattr(fingerprint, "cpu_fields", lambda: {"model name": "AMD EPYC", "flags": flags})
    assert fingerprint._cpu() == ("AMD EPYC", "x86-64-avx")
    monkeypatch.setattr(fingerprint.platform, "machine", lambda: "aarch64")
    monkeypatch.setattr(fingerprint, "cpu_fields", lambda: {"Features": "neon fp"})  # ARM names its flags so
    model = fingerprint.platform.processor() or "aarch64"
    assert fingerprint._cpu() == (model, f"aarch64: {model}")  # not measured: its model decides


def test_the_drivers_settings_from_the_environment_are_recorded():
    """llvmpipe's GALLIVM_* and LP_* variables change its code, not its GL strings (GALLIVM_PERF
    changes rgb): recorded, sorted; the thread count, the CPU caps and the driver's choice not."""
    env = {"LP_DEBUG": "fs", "GALLIVM_PERF": "no_quad_lerp", "LP_NUM_THREADS": "2", "GALLIUM_DRIVER": "llvmpipe",
           "GALLIUM_OVERRIDE_CPU_CAPS": "avx", "HOME": "/root"}  # fmt: skip
    assert fingerprint.gl_settings(env) == "GALLIVM_PERF=no_quad_lerp;LP_DEBUG=fs"
    assert fingerprint.gl_settings({"PATH": "/bin"}) == ""


def test_the_files_encoders_are_recorded():
    import cv2

    found = fingerprint.file_versions()
    assert found["opencv"] == cv2.__version__ and found["pyarrow"] == package_version("pyarrow") != "unknown"
    assert set(found) == {"opencv", "pyarrow", "zlib", "libpng"} and "unknown" not in (found["zlib"], found["libpng"])


@pytest.fixture
def uncached_world_sha256():
    """``world_sha256`` without its in-process cache, before and after (a fake never stays)."""
    fingerprint.world_sha256.cache_clear()
    yield fingerprint.world_sha256
    fingerprint.world_sha256.cache_clear()


def test_the_world_librarys_hash_is_built_once_per_machine_and_code(tmp_path, monkeypatch, uncached_world_sha256):
    from phav_generator.world.library import world_library_sha256

    monkeypatch.setenv("PHAV_CACHE_DIR", str(tmp_path))
    built = fingerprint.world_sha256()
    assert built == world_library_sha256()
    [kept] = (tmp_path / "world").glob("*.sha256")
    assert kept.read_text().strip() == built

    def unbuildable() -> str:
        raise AssertionError("built again")

    monkeypatch.setattr(fingerprint, "world_library_sha256", unbuildable)
    fingerprint.world_sha256.cache_clear()
    assert fingerprint.world_sha256() == built  # read back, not built
    # a corrupt file, or other code (another key), builds it again
    monkeypatch.setattr(fingerprint, "world_library_sha256", lambda: "ab" * 32)
    for damaged in (b"not a hash\n", b"\xff\xfe garbage"):  # not a hash, not even text
        kept.write_bytes(damaged)
        fingerprint.world_sha256.cache_clear()
        assert fingerprint.world_sha256() == "ab" * 32 and kept.read_text().strip() == "ab" * 32
    monkeypatch.setattr(fingerprint, "source_sha256", lambda: "0" * 64)
    monkeypatch.setattr(fingerprint, "world_library_sha256", lambda: "cd" * 32)
    fingerprint.world_sha256.cache_clear()
    assert fingerprint.world_sha256() == "cd" * 32
    assert len(list((tmp_path / "world").glob("*.sha256"))) == 2


def test_a_read_only_cache_builds_the_worlds_hash_again_without_an_error(tmp_path, monkeypatch,
                                                                        uncached_world_sha256):  # fmt: skip
    monkeypatch.setenv("PHAV_CACHE_DIR", str(tmp_path))
    monkeypatch.setattr(fingerprint, "world_library_sha256", lambda: "ef" * 32)

    @contextlib.contextmanager
    def read_only(path):  # what atomic_write raises on a read-only place
        raise WriteError(OSError(errno.EROFS, "Read-only file system", str(path)), str(path))
        yield

    monkeypatch.setattr(fingerprint, "atomic_write", read_only)
    assert fingerprint.world_sha256() == "ef" * 32
    assert not list((tmp_path / "world").glob("*.sha256"))
