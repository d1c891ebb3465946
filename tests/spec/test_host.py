"""The CPU fields that the renderer fingerprint records and training's precision reads."""

from __future__ import annotations

from phav_spec.host import cpu_fields


def test_the_cpu_fields_are_the_first_processors(tmp_path):
    info = tmp_path / "cpuinfo"
    info.write_text("processor\t: 0\nvendor_id\t: AuthenticAMD\nmodel name\t: AMD EPYC\nflags\t\t: fpu avx512_bf16\n\n"
                    "processor\t: 1\nvendor_id\t: AuthenticAMD\nmodel name\t: other\nflags\t\t: fpu\n")  # fmt: skip
    fields = cpu_fields(info)
    assert fields["vendor_id"] == "AuthenticAMD" and fields["model name"] == "AMD EPYC"
    assert fields["flags"] == "fpu avx512_bf16" and fields["processor"] == "0"


def test_no_cpuinfo_gives_no_fields(tmp_path):
    assert cpu_fields(tmp_path / "missing") == {}
