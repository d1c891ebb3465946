"""``phav fingerprint``: this machine's renderer fingerprint and, by rendering the reference
recipes, whether it makes the bytes the renderer of record made — and where it first does not.

Registered on the ``phav`` app by ``phav_app.cli``.
"""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer
from rich.markup import escape
from rich.table import Table

from phav_app.console import EXIT_FINDINGS, console
from phav_generator.dataset.fingerprint import renderer_fingerprint
from phav_generator.dataset.reference import (
    REFERENCE_FILE,
    STAGES,
    Reference,
    as_recorded,
    broken_promise,
    compare,
    first_difference,
    load_reference,
    promised_stages,
    stage_table,
    trace_all,
)
from phav_generator.render.context import gl_context, gl_strings
from phav_spec.canonical import pretty_json
from phav_spec.files import atomic_write, check_output_file
from phav_spec.manifest import RendererFingerprint


def _describe(fp: RendererFingerprint) -> Table:
    table = Table(show_header=False, box=None, pad_edge=False)
    table.add_row("GL", escape(f"{fp.gl_renderer}; {fp.gl_vendor}; {fp.gl_version}"))
    table.add_row("CPU", escape(f"{fp.cpu_model} (class {fp.simd_class})"))
    table.add_row("numerics", escape(fp.numeric_class or "not recorded"))
    table.add_row("versions", escape(", ".join(f"{k} {v}" for k, v in sorted(fp.versions.items()))))
    table.add_row("digest", fp.digest())
    return table


def fingerprint_command(
    check: Annotated[
        bool,
        typer.Option("--check/--no-check", help="Render the reference recipes (a few seconds) and compare."),
    ] = True,
    reference: Annotated[
        Path | None,
        typer.Option("--reference", help="Compare with this file (another machine's --json) instead of the package's."),
    ] = None,
    json_out: Annotated[
        Path | None,
        typer.Option("--json", help="Write this machine's fingerprint, the reference recipes and their stage hashes."),
    ] = None,
) -> None:
    """This machine's renderer fingerprint, and whether it renders the reference recipes bit
    for bit as the renderer of record did. Exit 1 when the fingerprints promise identical
    bytes of a stage and they differ; 0 otherwise, the report saying what differs."""
    if json_out is not None:
        check_output_file(json_out, field="--json", kind="JSON")
    ref = load_reference(reference if reference is not None else REFERENCE_FILE)
    ctx = gl_context()
    try:
        here = renderer_fingerprint(gl_strings(ctx))
        traced = trace_all(ref.recipes, ctx) if check or json_out is not None else None
    finally:
        ctx.release()
    console.print(_describe(here))
    promised = promised_stages(ref.fingerprint, here)
    recorded_on = f"{ref.fingerprint.cpu_model} (class {ref.fingerprint.simd_class})"
    comparable = as_recorded(ref.fingerprint, here)
    pixels, files = ref.fingerprint.differences(comparable, "pixels"), ref.fingerprint.differences(comparable, "files")
    if not files:
        verdict = "same renderer: bit-identical pixels and metadata promised"
    elif not pixels:
        verdict = (f"same renderer for pixels: bit-identical pixels and trajectories promised; {', '.join(files)} "
                   "differ, so the encoded files may differ")  # fmt: skip
    elif promised:
        verdict = (f"this renderer differs in {', '.join(pixels)}: the reference clips' pixels are promised (too "
                   "short for the physics to carry the numerics into them), a whole clip's are not")  # fmt: skip
    else:
        verdict = f"this renderer differs in {', '.join(pixels)}: bit-identical pixels are not promised"
    console.print(f"reference: recorded on {escape(recorded_on)}; {escape(verdict)}")
    if json_out is not None and traced is not None:
        with atomic_write(json_out) as tmp:
            tmp.write_text(pretty_json(Reference(here, ref.recipes, traced).to_json()), encoding="utf-8")
        console.print(f"wrote {escape(str(json_out))}")
    if not check or traced is None:
        return
    differing = compare(ref.stages, traced)
    table = Table("video", *STAGES)
    for row in stage_table(sorted(differing), differing):
        table.add_row(*row)
    console.print(table)
    first = first_difference(differing)
    if first is None:
        console.print(f"every stage of {len(differing)} reference videos is identical (=)")
        return
    console.print(f"the first stage that differs (≠) is {first}")
    broken = broken_promise(differing, promised)
    if broken:
        console.print(f"[red]the fingerprint promises identical {', '.join(broken)}, and the bytes differ[/red]: "
                      "report it with this output")  # fmt: skip
        raise typer.Exit(EXIT_FINDINGS)
