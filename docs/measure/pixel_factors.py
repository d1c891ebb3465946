"""Which factors of a machine change a video's bytes: the reference recipes rendered under
each factor, every stage's hash compared with the run without any (docs/reproducibility.md).

Each factor is an environment that makes this machine behave like another one: llvmpipe held
to a lower SIMD level, another vector width or thread count, LLVM tuning for another CPU,
numpy without its newer SIMD kernels, OpenBLAS on another CPU's kernels, torch's other
kernels for the body data. A row says, per stage (recipe, trajectory, body data, scene, then
each modality), ``=`` when the bytes equal the plain run's and ``≠`` when not.

    python docs/measure/pixel_factors.py --out factors.md --json factors.json
    python docs/measure/pixel_factors.py --body --workers     # also rebuild the body data, and generate twice
    python docs/measure/pixel_factors.py --videos 16          # also full phav-v1 videos under the numerics

Run it on every machine you can; the header records the machine. ``--body`` rebuilds the
body data under each of torch's kernel levels (~1.5 min each); ``--workers`` generates two
videos with one worker and with two; ``--videos N`` generates the first N phav-v1 videos of
``--seed`` and regenerates them under each factor of numpy's and OpenBLAS's kernels (the
reference clips are 6 frames: too short for the physics to carry a last bit into the
motion), counting the videos whose pixels differ (~1.5 min per factor for 16).
"""

from __future__ import annotations

import argparse
import ctypes
import json
import os
import platform
import shutil
import subprocess
import sys
import tempfile
from importlib.metadata import version
from pathlib import Path

from phav_generator.dataset.reference import STAGES, load_reference
from phav_spec.host import cpu_fields

#: (factor, setting, environment): each a way this machine can stand in for another.
FACTORS: list[tuple[str, str, dict[str, str]]] = [
    ("llvmpipe SIMD level", f"held to {level}", {"GALLIUM_OVERRIDE_CPU_CAPS": level})
    for level in ("avx", "sse4.1", "ssse3", "sse3", "sse2", "sse", "nosse")
] + [
    ("llvmpipe vector width", f"{w} bits", {"LP_NATIVE_VECTOR_WIDTH": str(w)}) for w in (256, 128)
] + [
    ("llvmpipe threads", str(n), {"LP_NUM_THREADS": str(n)}) for n in (0, 1, 4)
] + [
    ("numpy SIMD", "baseline only", {"NPY_DISABLE_CPU_FEATURES": "__ABOVE_BASELINE__"}),
    ("numpy / OpenBLAS threads", "1", {"OMP_NUM_THREADS": "1", "OPENBLAS_NUM_THREADS": "1"}),
] + [
    ("OpenBLAS kernels", core, {"OPENBLAS_CORETYPE": core})
    for core in ("Prescott", "Sandybridge", "Haswell", "SkylakeX", "Zen")
]  # fmt: skip
#: CPUs LLVM 15 knows, for llvmpipe's tuning (``llvm::sys::getHostCPUName``, interposed).
LLVM_CPUS = ("x86-64", "haswell", "skylake-avx512", "icelake-server", "znver2", "znver3")
#: torch's kernel levels for the body data build.
ATEN_LEVELS = ("default", "avx2", "avx512")

_INTERPOSER = r"""
#include <stdlib.h>
#include <string.h>
struct StringRef { const char *data; unsigned long size; };
/* llvm::sys::getHostCPUName(): the CPU llvmpipe asks LLVM to tune its shaders for. */
struct StringRef _ZN4llvm3sys14getHostCPUNameEv(void) {
    const char *s = getenv("PHAV_FAKE_LLVM_CPU");
    struct StringRef r = { s ? s : "generic", s ? strlen(s) : 7 };
    return r;
}
"""


def _llvm_host_cpu(gl_renderer: str) -> str:
    """The CPU name the machine's LLVM gives this host (what llvmpipe compiles for)."""
    major = gl_renderer.split("LLVM ")[-1].split(".")[0] if "LLVM " in gl_renderer else ""
    try:
        lib = ctypes.CDLL(f"libLLVM-{major}.so.1")
    except OSError:
        return "unknown"
    lib.LLVMGetHostCPUName.restype = ctypes.c_char_p
    return lib.LLVMGetHostCPUName().decode()


def _numpy_above_baseline() -> str:
    """numpy's dispatched SIMD targets this CPU has: disabling them leaves the baseline."""
    from numpy._core._multiarray_umath import __cpu_dispatch__, __cpu_features__

    return " ".join(f for f in __cpu_dispatch__ if __cpu_features__.get(f))


def _trace(env: dict[str, str], work: Path, name: str) -> dict:
    """Run ``phav fingerprint --json`` under ``env``; its traced stages, or why it failed."""
    out = work / f"{name}.json"
    run = subprocess.run(
        [sys.executable, "-m", "phav_app.cli", "fingerprint", "--json", str(out)],
        env=os.environ | env, capture_output=True, text=True, timeout=600,
    )  # fmt: skip
    if not out.exists():
        tail = (run.stderr.strip().splitlines() or [f"exit {run.returncode}"])[-1]
        return {"error": tail[:80]}
    data = json.loads(out.read_text(encoding="utf-8"))
    return {"fingerprint": data["fingerprint"], "stages": {k: v["stages"] for k, v in data["videos"].items()}}


def _cells(base: dict, got: dict) -> list[str]:
    if "error" in got:
        return [f"failed: {got['error']}"] + [""] * (len(STAGES) - 1)
    return ["=" if all(base["stages"][v][s] == got["stages"][v][s] for v in base["stages"]) else "≠" for s in STAGES]


def _body_rows(work: Path) -> list[tuple[str, str, str]]:
    """The body data built under each of torch's kernel levels, one thread: its sha256."""
    rows = []
    for level in ATEN_LEVELS:
        cache = work / f"body-{level}"
        env = os.environ | {"PHAV_CACHE_DIR": str(cache), "ATEN_CPU_CAPABILITY": level, "OMP_NUM_THREADS": "1"}
        run = subprocess.run([sys.executable, "-m", "phav_app.cli", "body", "build"], env=env, capture_output=True,
                             text=True, timeout=900)  # fmt: skip
        files = sorted(cache.glob("body/*/*.npz"))
        rows.append(("torch kernels (body data)", level, files[0].stem if files and run.returncode == 0 else "failed"))
    return rows


def _worker_rows(work: Path) -> list[tuple[str, str, str]]:
    """Two phav-v1-short videos generated with one worker and with two: their content hashes."""
    rows = []
    for workers in (1, 2):
        out = work / f"workers-{workers}"
        command = ["generate", "--theta", "phav-v1-short", "--videos", "2", "--seed", "4", "--workers", str(workers)]
        subprocess.run(
            [sys.executable, "-m", "phav_app.cli", *command, "--out", str(out)], capture_output=True, check=True
        )
        manifest = json.loads((out / "manifest.json").read_text(encoding="utf-8"))
        digest = ",".join(v["content_hash"][:12] for v in manifest["videos"])
        rows.append(("generate workers", str(workers), digest))
    return rows


def _video_rows(work: Path, n: int, seed: int) -> list[tuple[str, str, str]]:
    """The first ``n`` phav-v1 videos of ``seed`` generated plain, then regenerated under each
    factor of numpy's and OpenBLAS's kernels: per factor, the videos whose content hash
    differs and the modalities that do."""
    plain = work / "videos"
    command = ["generate", "--theta", "phav-v1", "--videos", str(n), "--seed", str(seed), "--workers", "2"]
    subprocess.run([sys.executable, "-m", "phav_app.cli", *command, "--out", str(plain)], capture_output=True,
                   check=True)  # fmt: skip
    base = {v["video_id"]: v for v in json.loads((plain / "manifest.json").read_text(encoding="utf-8"))["videos"]}
    rows = []
    for factor, setting, env in FACTORS:
        if not any(k in env for k in ("NPY_DISABLE_CPU_FEATURES", "OPENBLAS_CORETYPE")):
            continue
        if env.get("NPY_DISABLE_CPU_FEATURES") == "__ABOVE_BASELINE__":
            env = {"NPY_DISABLE_CPU_FEATURES": _numpy_above_baseline()}
        out = work / f"videos-{len(rows)}"
        subprocess.run([sys.executable, "-m", "phav_app.cli", "regenerate", str(plain), "--out", str(out),
                        "--workers", "2"], env=os.environ | env, capture_output=True)  # fmt: skip
        made = json.loads((out / "manifest.json").read_text(encoding="utf-8"))["videos"]
        differ = [v for v in made if v["content_hash"] != base[v["video_id"]]["content_hash"]]
        modalities = sorted({m for v in differ for m, h in v["modality_hashes"].items()
                             if h != base[v["video_id"]]["modality_hashes"][m]})  # fmt: skip
        which = f": {' '.join(v['video_id'] for v in differ)} in {', '.join(modalities)}" if differ else ""
        rows.append((f"{factor} ({n} phav-v1 videos, seed {seed})", setting, f"{len(differ)} differ{which}"))
        print(f"{factor}: {setting}: {rows[-1][2]}", file=sys.stderr)
    return rows


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", type=Path, help="Markdown table (default: print)")
    parser.add_argument("--json", type=Path, help="every run's fingerprint and stage hashes")
    parser.add_argument("--body", action="store_true", help="also rebuild the body data under torch's kernel levels")
    parser.add_argument("--workers", action="store_true", help="also generate two videos with 1 and 2 workers")
    parser.add_argument("--videos", type=int, default=0, help="also N full phav-v1 videos under the numerics")
    parser.add_argument("--seed", type=int, default=52, help="the dataset seed of --videos")
    parser.add_argument("--only-videos", action="store_true", help="skip the reference recipes' factors")
    args = parser.parse_args()

    work = Path(tempfile.mkdtemp(prefix="phav-factors-"))
    try:
        base = _trace({}, work, "base")
        if "error" in base:
            sys.exit(f"phav fingerprint failed here: {base['error']}")
        reference = load_reference()
        runs: dict[str, dict] = {"none": base}
        rows: list[list[str]] = []
        factors = list(FACTORS)
        compiler = shutil.which("cc") or shutil.which("gcc")
        if compiler:
            (work / "llvmcpu.c").write_text(_INTERPOSER, encoding="utf-8")
            lib = work / "libllvmcpu.so"
            subprocess.run([compiler, "-shared", "-fPIC", "-O2", "-o", str(lib), str(work / "llvmcpu.c")], check=True)
            factors += [
                ("LLVM tuning CPU", cpu, {"LD_PRELOAD": str(lib), "PHAV_FAKE_LLVM_CPU": cpu}) for cpu in LLVM_CPUS
            ]
        for i, (factor, setting, env) in enumerate(factors if not args.only_videos else []):
            if env.get("NPY_DISABLE_CPU_FEATURES") == "__ABOVE_BASELINE__":
                env = {"NPY_DISABLE_CPU_FEATURES": _numpy_above_baseline()}
            got = _trace(env, work, f"run{i}")
            runs[f"{factor}: {setting}"] = got
            renderer = got.get("fingerprint", {})
            described = ", ".join(renderer.get(k, "") for k in ("cpu_class", "numeric_class", "gl_renderer"))
            rows.append([factor, setting, *_cells(base, got), described.strip(", ")])
            print(f"{factor}: {setting}: {' '.join(rows[-1][2 : 2 + len(STAGES)])}", file=sys.stderr)
        fp = base["fingerprint"]
        fields = cpu_fields()
        flags = set(fields.get("flags", "").split())
        simd = [f for f in ("sse4_2", "avx", "avx2", "fma", "avx512f", "avx512_bf16", "amx_bf16") if f in flags]
        libc = " ".join(platform.libc_ver())
        llvm_cpu = _llvm_host_cpu(fp["gl_renderer"])
        lines = [
            f"Machine: {fp['cpu_model']} ({fields.get('vendor_id', '?')}, family {fields.get('cpu family', '?')} "
            f"model {fields.get('model', '?')}; {' '.join(simd)}), LLVM host CPU `{llvm_cpu}`, "
            f"{os.cpu_count()} cores; {fp['gl_renderer']}, {fp['gl_version']}; Python {platform.python_version()}, "
            f"{libc}, numpy {version('numpy')}, MuJoCo {version('mujoco')}, torch {version('torch')}; "
            f"SIMD class `{fp['cpu_class']}`, numerics `{fp['numeric_class']}`.",
            "",
            "Plain run against the shipped reference (recorded on "
            f"{reference.fingerprint.cpu_model}, class {reference.fingerprint.simd_class}): "
            + " ".join(
                "=" if all(base["stages"][v][s] == reference.stages[v][s] for v in reference.stages) else "≠"
                for s in STAGES
            ),
        ]
        if rows:
            lines += ["", "| factor | setting | " + " | ".join(STAGES) + " | SIMD class, numerics, GL renderer |",
                      "| --- | --- | " + " | ".join(":-:" for _ in STAGES) + " | --- |"]  # fmt: skip
            lines += ["| " + " | ".join(r) + " |" for r in rows]
        extra = (_body_rows(work) if args.body else []) + (_worker_rows(work) if args.workers else [])
        extra += _video_rows(work, args.videos, args.seed) if args.videos else []
        if extra:
            lines += ["", "| factor | setting | result |", "| --- | --- | --- |"]
            lines += [f"| {f} | {s} | `{r}` |" for f, s, r in extra]
        text = "\n".join(lines) + "\n"
        if args.out:
            args.out.write_text(text, encoding="utf-8")
        print(text)
        if args.json:
            args.json.write_text(json.dumps({"runs": runs, "extra": extra}, indent=1, sort_keys=True), encoding="utf-8")
    finally:
        shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    main()
