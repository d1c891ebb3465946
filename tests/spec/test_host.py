"""The CPU fields that the renderer fingerprint records and training's precision reads."""

from __future__ import annotations

import pytest

from phav_spec.host import cpu_fields, simd_class


def test_the_cpu_fields_are_the_first_processors(tmp_path):
    info = tmp_path / "cpuinfo"
    info.write_text("processor\t: 0\nvendor_id\t: AuthenticAMD\nmodel name\t: AMD EPYC\nflags\t\t: fpu avx512_bf16\n\n"
                    "processor\t: 1\nvendor_id\t: AuthenticAMD\nmodel name\t: other\nflags\t\t: fpu\n")  # fmt: skip
    fields = cpu_fields(info)
    assert fields["vendor_id"] == "AuthenticAMD" and fields["model name"] == "AMD EPYC"
    assert fields["flags"] == "fpu avx512_bf16" and fields["processor"] == "0"


def test_no_cpuinfo_gives_no_fields(tmp_path):
    assert cpu_fields(tmp_path / "missing") == {}


@pytest.mark.parametrize(
    ("flags", "override", "expected"),
    [
        ("fpu sse2 ssse3 sse4_1 avx avx2 fma avx512f", None, "x86-64-avx"),
        ("fpu sse2 ssse3 sse4_1 avx avx2 fma", None, "x86-64-avx"),
        ("fpu sse2 ssse3 sse4_1 avx", None, "x86-64-avx1"),  # Sandy Bridge: no AVX2, no FMA (not measured)
        ("fpu sse2 sse3 ssse3 sse4_1 sse4_2", None, "x86-64-ssse3"),
        ("fpu sse sse2 sse3", None, "x86-64-sse2"),
        ("fpu", None, "x86-64"),
        ("fpu sse2 ssse3 avx avx2 fma", "sse4.1", "x86-64-ssse3"),
        ("fpu sse2 ssse3 avx avx2 fma", "sse3", "x86-64-sse2"),
        ("fpu sse2 ssse3 avx avx2 fma", "nosse", "x86-64"),
        ("fpu sse2 ssse3 avx avx2 fma avx512f", "avx", "x86-64-avx"),  # Mesa's avx turns off AVX-512 alone
        ("fpu sse2 ssse3", "avx", "x86-64-ssse3"),  # an override never adds what the CPU lacks
        ("fpu sse2 ssse3 avx avx2 fma", "not-a-level", "x86-64-avx"),  # Mesa ignores what it does not know
    ],
)
def test_the_simd_class_is_llvmpipes_code_path(flags, override, expected):
    assert simd_class(flags, "x86_64", "Some CPU", override) == expected


def test_other_architectures_are_classed_by_their_model():
    assert simd_class("fp asimd", "aarch64", "Neoverse-N1") == "aarch64: Neoverse-N1"
    assert simd_class("", "riscv64") == "riscv64"
