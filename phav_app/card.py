"""A release's descriptions: the dataset card (Markdown with SVG histograms) and Croissant.

Both are pure functions of the dataset's manifest, recipes table, θ and release index, so
one dataset always gets the same card and the same ``croissant.json``, byte for byte (no
dates, no host names). Croissant 1.0 (https://mlcommons.org/croissant/) describes every
file the release carries with its sha256 and the record sets a loader can read: the
recipes, and in a full release the cameras, the people and each modality's frames.
"""

from __future__ import annotations

import itertools
import logging
import re
from collections import Counter
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
import yaml

from phav_spec.expectations import duration_cdf
from phav_spec.metadata import CAMERA_COLUMNS, PEOPLE_COLUMNS, MetaColumn
from phav_spec.release import PHAV_CITATION
from phav_validators.checks.distribution import check_distributions
from phav_validators.report import histogram_svg

if TYPE_CHECKING:
    from phav_spec.encoding import ModalityEncoding
    from phav_spec.manifest import DatasetManifest
    from phav_spec.recipe_table import RecipeTable
    from phav_spec.release import ReleaseIndex
    from phav_spec.theta import Theta
    from phav_validators.checks.distribution import DistributionResult

#: Variables whose observed-against-θ histograms the card shows (each one SVG file).
CARD_VARIABLES = ("action", "environment", "weather", "day_phase", "camera", "variation", "human_model")
#: Bins of the clip-length histogram between θ's shortest and longest clip.
DURATION_BINS = 12
CROISSANT_CONFORMS_TO = "http://mlcommons.org/croissant/1.0"
#: The Croissant 1.0 JSON-LD context (the specification's, key for key).
CROISSANT_CONTEXT: dict[str, Any] = {
    "@language": "en",
    "@vocab": "https://schema.org/",
    "citeAs": "cr:citeAs",
    "column": "cr:column",
    "conformsTo": "dct:conformsTo",
    "cr": "http://mlcommons.org/croissant/",
    "rai": "http://mlcommons.org/croissant/RAI/",
    "data": {"@id": "cr:data", "@type": "@json"},
    "dataType": {"@id": "cr:dataType", "@type": "@vocab"},
    "dct": "http://purl.org/dc/terms/",
    "equivalentProperty": "cr:equivalentProperty",
    "examples": {"@id": "cr:examples", "@type": "@json"},
    "extract": "cr:extract",
    "field": "cr:field",
    "fileProperty": "cr:fileProperty",
    "fileObject": "cr:fileObject",
    "fileSet": "cr:fileSet",
    "format": "cr:format",
    "includes": "cr:includes",
    "isLiveDataset": "cr:isLiveDataset",
    "jsonPath": "cr:jsonPath",
    "key": "cr:key",
    "md5": "cr:md5",
    "parentField": "cr:parentField",
    "path": "cr:path",
    "recordSet": "cr:recordSet",
    "references": "cr:references",
    "regex": "cr:regex",
    "repeated": "cr:repeated",
    "replace": "cr:replace",
    "samplingRate": "cr:samplingRate",
    "sc": "https://schema.org/",
    "separator": "cr:separator",
    "source": "cr:source",
    "subField": "cr:subField",
    "transform": "cr:transform",
}
_FORMATS = {".tar": "application/x-tar", ".parquet": "application/x-parquet", ".json": "application/json",
            ".yaml": "application/yaml"}  # fmt: skip
#: Recipe columns a Croissant loader reads, with their schema.org types.
RECIPE_FIELDS = {"video_id": "sc:Text", "action": "sc:Text", "environment": "sc:Text", "human_model": "sc:Text",
                 "weather": "sc:Text", "day_phase": "sc:Text", "variation": "sc:Text", "camera": "sc:Text",
                 "base_motion": "sc:Text", "duration_s": "sc:Float", "n_frames": "sc:Integer",
                 "clock_hour": "sc:Float", "recipe": "sc:Text"}  # fmt: skip
CAMERA_FIELDS = {"video_id": "sc:Text", "frame": "sc:Integer", "time_s": "sc:Float", "fx": "sc:Float",
                 "fy": "sc:Float", "cx": "sc:Float", "cy": "sc:Float"}  # fmt: skip
PEOPLE_FIELDS = {"video_id": "sc:Text", "frame": "sc:Integer", "person_id": "sc:Integer", "role": "sc:Text",
                 "human_model": "sc:Text", "pixels": "sc:Integer", "penetration_m": "sc:Float",
                 "joint_limit_excess": "sc:Float"}  # fmt: skip


def _shares(counts: np.ndarray) -> list[float]:
    total = max(float(counts.sum()), 1.0)
    return [float(c) / total for c in counts]


@dataclass(frozen=True)
class RecipeFit:
    """The recipes table's columns and their fit to θ, read and tested once for the card and
    its histograms (the test reads every recipe)."""

    columns: dict[str, list[Any]]
    result: DistributionResult

    @classmethod
    def of(cls, table: RecipeTable, theta: Theta) -> RecipeFit:

        columns = {name: table.column(name) for name in table.table.column_names}
        return cls(columns, check_distributions(columns, theta))


def histograms(fit: RecipeFit, theta: Theta) -> dict[str, str]:
    """SVG histograms, observed against θ's expectation, by file name (``action.svg``, …)."""

    columns = fit.columns
    out = {}
    for s in fit.result.summaries:
        if s.variable in CARD_VARIABLES:
            title = f"{s.variable} (n = {int(s.observed.sum())}; blue observed, orange θ)"
            out[f"{s.variable}.svg"] = histogram_svg(title, s.values, _shares(s.observed), list(map(float, s.expected)))
    durations = np.asarray(columns["duration_s"], dtype=float)
    edges = np.linspace(theta.durations.t_min, theta.durations.t_max, DURATION_BINS + 1)
    observed, _ = np.histogram(np.clip(durations, edges[0], edges[-1]), bins=edges)
    expected = np.diff(duration_cdf(theta)(edges))
    labels = [f"{a:.2f}–{b:.2f} s" for a, b in itertools.pairwise(edges)]
    title = f"clip length (n = {len(durations)}; blue observed, orange θ)"
    out["duration_s.svg"] = histogram_svg(title, labels, _shares(observed), list(map(float, expected)))
    return out


def _bytes(n: int) -> str:
    for unit in ("B", "KB", "MB", "GB", "TB"):
        if n < 1000 or unit == "TB":
            return f"{n:,} {unit}" if unit == "B" else f"{n:.1f} {unit}"
        n /= 1000  # type: ignore[assignment]
    raise AssertionError


def _hf_dtype(arrow_type: str) -> dict[str, Any]:
    """A metadata column's Arrow type (``phav_spec.metadata``) as a Hugging Face feature:
    ``{"dtype": "float64"}``, ``{"list": "float64"}``, ``{"list": {"list": "float64"}}``."""
    if arrow_type.startswith("list<"):
        inner = arrow_type[len("list<") : arrow_type.rindex(">")]
        item = _hf_dtype(inner)
        return {"list": item.get("dtype", item)}
    return {"dtype": arrow_type}


def _hf_struct(columns: Sequence[MetaColumn]) -> list[dict[str, Any]]:
    return [{"name": c.name, **_hf_dtype(c.arrow_type)} for c in sorted(columns, key=lambda c: c.name)]


def hf_front_matter(manifest: DatasetManifest, index: ReleaseIndex) -> dict[str, Any]:
    """The dataset card's YAML for Hugging Face ``datasets``: ``load_dataset(DIR)`` reads the
    frames from the shards with declared features, so that flow (16-bit RGB, which PIL cannot
    hold) arrives as its PNG's bytes and every other modality as an exact image; a
    recipe-only release reads its recipes table. ``datasets`` serves every config of a card
    with one loader, so the metadata tables are not configs here (docs/loading.md)."""
    if index.recipes_only:
        return {**_hf_license(index.license),
                "configs": [{"config_name": "recipes", "default": True,
                             "data_files": [{"split": "train", "path": "recipes.parquet"}]}]}  # fmt: skip
    frame = [{"name": "camera", "struct": _hf_struct(CAMERA_COLUMNS)},
             {"name": "metadata_version", "dtype": "int64"},
             {"name": "people", "list": _hf_struct(PEOPLE_COLUMNS)}]  # fmt: skip
    features: list[dict[str, Any]] = [
        {"name": m.key, "dtype": "binary" if _pil_cannot_hold(m) else "image"} for m in manifest.modalities
    ]
    features += [{"name": "json", "struct": frame}, {"name": "__key__", "dtype": "string"},
                 {"name": "__url__", "dtype": "string"}]  # fmt: skip
    return {
        **_hf_license(index.license),
        "configs": [{"config_name": "frames", "default": True,
                     "data_files": [{"split": "train", "path": f"{manifest.name}-*.tar"}]}],
        "dataset_info": [{"config_name": "frames", "features": features}],
    }  # fmt: skip


def _hf_license(license: str) -> dict[str, str]:
    """The card's license: the Hub's lower-case id, or ``other`` with a link for a URL (the
    Hub knows licenses by id only)."""
    if re.match(r"https?://", license.strip()):
        return {"license": "other", "license_link": license.strip()}
    return {"license": license.strip().lower()}


def dataset_card(
    manifest: DatasetManifest, recipes: RecipeFit, theta: Theta, index: ReleaseIndex, figures: list[str]
) -> str:
    """The release's README.md: the Hugging Face card's YAML, then what the data is, how to
    load it, get and check its pixels, statistics, histograms against θ, the θ itself, the
    files with their hashes, and how to cite."""
    front = yaml.safe_dump(hf_front_matter(manifest, index), sort_keys=False, allow_unicode=True)
    lines = [
        "---",
        front.rstrip("\n"),
        "---",
        "",
        *_card_summary(manifest, theta, index),
        *(_card_recipe_only(index) if index.recipes_only else _card_check()),
        *([] if index.recipes_only else _card_loading(manifest)),
        *_card_modalities(manifest),
        *_card_statistics(manifest, recipes, index, figures),
        *_card_renderer(manifest),
        *_card_files(index),
        *_card_theta(theta),
        *_card_citation(index),
    ]
    return "\n".join(lines)


def _card_summary(manifest: DatasetManifest, theta: Theta, index: ReleaseIndex) -> list[str]:
    """Title, version and license, and one paragraph saying what the videos are."""
    n_frames = sum(v.n_frames for v in manifest.videos)
    fps = theta.video.fps
    published = f", published {index.date_published}" if index.date_published else ""
    where = f" at <{index.url}>" if index.url else ""
    return [
        f"# {manifest.name}: procedural human action videos",
        "",
        f"Version {index.dataset_version}{published}{where}; license {index.license}.",
        "",
        f"{len(manifest.videos):,} videos, {n_frames:,} frames ({_span(n_frames / fps)} at {fps} fps), "
        f"{theta.video.width}×{theta.video.height}, sampled from θ `{theta.name}` (hash `{theta.hash[:16]}…`) "
        f"with dataset seed {manifest.dataset_seed} and rendered by phav {manifest.phav_version}, following the "
        f"PHAV paper (de Souza et al., CVPR 2017). Every frame has {len(manifest.modalities)} modalities (below) "
        "and per-frame metadata.",
        "",
    ]


def _card_recipe_only(index: ReleaseIndex) -> list[str]:
    """How to rebuild the pixels of a recipe-only release and check them."""
    return [
        "## This is a recipe-only release",
        "",
        f"It carries the recipes, θ and the manifest ({_bytes(index.included_bytes)}), not the pixels "
        f"({_bytes(index.full_bytes)} in the full release). Rebuild them and check every hash:",
        "",
        "```",
        "pip install phav",
        "phav regenerate manifest.json --out DIR --workers N",
        "phav-validate .            # regenerates what its checks need, then validates",
        "```",
        "",
        "Pixels are bit-identical where the renderer fingerprint (below) is equal — the GL strings, the CPU's "
        "SIMD class, numpy's and OpenBLAS's kernels, the versions and the body data, not the CPU's model "
        "(`phav fingerprint` says whether a machine is one). Elsewhere they differ: within tolerances where only "
        "the GL driver differs; where numerics or versions differ, the physics can take some videos another way. "
        "`phav regenerate` says which videos differ.",
        "",
    ]


def _card_check() -> list[str]:
    """How to check a full release."""
    return ["Check it: `phav-validate .` (integrity, schema, encoding, distribution, failure cases, consistency, "
            "reproducibility).", ""]  # fmt: skip


def _card_loading(manifest: DatasetManifest) -> list[str]:
    """How to load the frames with Hugging Face ``datasets``, flow exact."""
    tables = ", ".join(f"`{t}.parquet`" for t in ("recipes", "people", "cameras"))
    return [
        "## Loading",
        "",
        "Flow is a 16-bit RGB PNG, which PIL (and so `datasets`' image decoding) cannot hold: the card declares "
        "`flow.png` as bytes; decode them with OpenCV. The other modalities arrive as exact images (depth as "
        "16-bit `I;16`).",
        "",
        "```python",
        "import cv2, numpy as np",
        "from datasets import load_dataset",
        'frames = load_dataset(".", split="train")        # this directory, or the Hub repository',
        'flow = cv2.imdecode(np.frombuffer(frames[0]["flow.png"], np.uint8), cv2.IMREAD_UNCHANGED)[..., ::-1]',
        'people = load_dataset("parquet", data_files="people.parquet", split="train")',
        "```",
        "",
        f"The tables ({tables}) load as `people` does. `phav_spec.webdataset.phav_decoder` reads the shards "
        "with `webdataset`, every modality exact.",
        "",
    ]


def _card_modalities(manifest: DatasetManifest) -> list[str]:
    """The modalities' table and how a sample is laid out in the shards."""
    return [
        "## Modalities",
        "",
        "| name | file in each sample | type | description |",
        "|---|---|---|---|",
        *(
            f"| {m.name} | `{m.key}` | {m.channels}×{m.dtype}{f' ({m.units})' if m.units else ''} | {m.description} |"
            for m in manifest.modalities
        ),
        "",
        "Shards are WebDataset tars; a sample is one frame keyed `{video_id}/{frame:05d}` with the files above and "
        "its metadata (`.json`). `cameras.parquet` and `people.parquet` hold the per-frame cameras and people.",
        "",
    ]


def _card_statistics(
    manifest: DatasetManifest, recipes: RecipeFit, index: ReleaseIndex, figures: list[str]
) -> list[str]:
    """Clip lengths and the fit to θ, videos and frames per action, and the histograms."""
    columns, fit = recipes.columns, recipes.result
    rejected = sum(t.rejected for t in fit.tests)
    lines = [
        "## Statistics",
        "",
        f"- mean clip length {fit.mean_duration:.2f} s (θ expects {fit.expected_mean_duration:.2f} s)",
        f"- {len(fit.tests)} goodness-of-fit tests of the recipes against θ: {rejected} rejected "
        "(Holm, family-wise α = 0.001)",
        f"- {len(manifest.shards)} shard(s); full release {_bytes(index.full_bytes)}",
        "",
        "| action | videos | frames |",
        "|---|---:|---:|",
    ]
    actions = columns["action"]
    frames_by_action: Counter[str] = Counter()
    for action, n in zip(actions, columns["n_frames"], strict=True):
        frames_by_action[action] += int(n)
    for action, count in sorted(Counter(actions).items()):
        lines.append(f"| {action} | {count} | {frames_by_action[action]:,} |")
    lines += ["", "### Histograms: observed (blue) against θ's expectation (orange)", ""]
    lines += [f"![{name.removesuffix('.svg')}](histograms/{name})" for name in figures]
    return lines


def _card_renderer(manifest: DatasetManifest) -> list[str]:
    """The renderer of record, whose fingerprint decides whether pixels must match bit for bit."""
    r = manifest.renderer
    if r is None:
        return []
    return [
        "",
        "## Renderer of record",
        "",
        f"{r.gl_renderer} ({r.gl_vendor}, OpenGL {r.gl_version}) on {r.cpu_model} (SIMD class {r.simd_class}); "
        + ", ".join(f"{k} {v}" for k, v in sorted(r.versions.items()))
        + f". Fingerprint digest `{r.digest()}`.",
    ]


def _card_files(index: ReleaseIndex) -> list[str]:
    """Every file of the full release with its size and sha256, and whether this release carries it."""
    return [
        "",
        "## Files",
        "",
        "Every file of the full release; `release.json` has the same list, and the manifest each video's "
        "per-modality content hashes.",
        "",
        "| file | bytes | sha256 | in this release |",
        "|---|---:|---|---|",
        *(
            f"| {f.path} | {f.bytes:,} | `{f.sha256}` | {'yes' if f.included else 'no (regenerate)'} |"
            for f in index.files
        ),
    ]


def _card_theta(theta: Theta) -> list[str]:
    """θ as YAML: the generative model's parameters the data were sampled from."""
    return ["", "## θ", "", "```yaml", theta.to_yaml().rstrip(), "```"]


def _card_citation(index: ReleaseIndex) -> list[str]:
    """The data's license and the paper to cite."""
    return [
        "",
        "## License and citation",
        "",
        f"Data license: {index.license}. If you use this dataset, cite the paper whose generative model made it:",
        "",
        "```bibtex",
        _citation(),
        "```",
        "",
    ]


def _span(seconds: float) -> str:
    return f"{seconds / 3600:.1f} h" if seconds >= 3600 else f"{seconds / 60:.1f} min"


def _citation() -> str:

    return PHAV_CITATION


def _file_object(f: Any) -> dict[str, Any]:
    suffix = "." + f.path.rsplit(".", 1)[-1]
    return {"@type": "cr:FileObject", "@id": f.path, "name": f.path, "contentUrl": f.path,
            "contentSize": f"{f.bytes} B", "encodingFormat": _FORMATS[suffix], "sha256": f.sha256}  # fmt: skip


def _fields(record_set: str, file_id: str, columns: dict[str, str]) -> list[dict[str, Any]]:
    return [{"@type": "cr:Field", "@id": f"{record_set}/{col}", "name": col, "dataType": kind,
             "source": {"fileObject": {"@id": file_id}, "extract": {"column": col}}}
            for col, kind in columns.items()]  # fmt: skip


def _pil_cannot_hold(m: ModalityEncoding) -> bool:
    """16-bit RGB (flow): PIL, which Croissant and Hugging Face loaders decode images with,
    reduces it to 8 bits; such a modality is served as its PNG's bytes."""
    return m.dtype == "uint16" and m.channels == 3


def _modality_note(m: ModalityEncoding) -> str:
    """The modality's description, and how to decode it where PIL would lose bits."""
    if _pil_cannot_hold(m):
        return (f"{m.description}. The field holds the 16-bit RGB PNG's bytes (PIL would reduce it to 8 bits): "
                "decode them with cv2.imdecode(..., cv2.IMREAD_UNCHANGED), channels in BGR order")  # fmt: skip
    return m.description


def croissant(manifest: DatasetManifest, table: RecipeTable, index: ReleaseIndex) -> dict[str, Any]:
    """The release as Croissant 1.0 JSON-LD (``mlcroissant validate`` accepts it offline)."""
    n_frames = sum(v.n_frames for v in manifest.videos)
    carried = [f for f in index.files if f.included]
    description = (
        f"{len(manifest.videos)} procedural human action videos ({n_frames} frames) generated by phav "
        f"{manifest.phav_version} from θ {table.theta.name if table.theta else 'unnamed'} with seed "
        f"{manifest.dataset_seed}; modalities: {', '.join(m.name for m in manifest.modalities)}."
    )
    if index.recipes_only:
        description += (
            " This recipe-only release carries recipes, θ and the manifest; "
            "`phav regenerate manifest.json --out DIR` rebuilds the pixels and checks every hash."
        )
    distribution: list[dict[str, Any]] = [_file_object(f) for f in carried]
    record_sets: list[dict[str, Any]] = [{
        "@type": "cr:RecordSet", "@id": "recipes", "name": "recipes",
        "description": "One procedural recipe per video: the sampled variables and the full recipe JSON.",
        "key": {"@id": "recipes/video_id"},
        "field": _fields("recipes", "recipes.parquet", RECIPE_FIELDS),
    }]  # fmt: skip
    if not index.recipes_only:
        shards = [f.path for f in carried if f.kind == "shard"]
        for m in manifest.modalities:
            distribution.append({
                "@type": "cr:FileSet", "@id": f"{m.name}-frames", "name": f"{m.name}-frames",
                "containedIn": [{"@id": s} for s in shards], "encodingFormat": "image/png",
                "includes": f"*/*.{m.key}",
            })  # fmt: skip
            record_sets.append({
                "@type": "cr:RecordSet", "@id": m.name, "name": m.name, "description": _modality_note(m),
                "field": [
                    {"@type": "cr:Field", "@id": f"{m.name}/image", "name": "image",
                     "dataType": "sc:Text" if _pil_cannot_hold(m) else "sc:ImageObject",
                     "source": {"fileSet": {"@id": f"{m.name}-frames"}, "extract": {"fileProperty": "content"}}},
                    {"@type": "cr:Field", "@id": f"{m.name}/key", "name": "key", "dataType": "sc:Text",
                     "source": {"fileSet": {"@id": f"{m.name}-frames"}, "extract": {"fileProperty": "fullpath"},
                                "transform": {"regex": r"^.*(v\d{6,}/\d{5})\.[^/]*$"}}},
                ],
            })  # fmt: skip
        record_sets.append({"@type": "cr:RecordSet", "@id": "cameras", "name": "cameras",
                            "description": "Per frame: the camera's intrinsics (pixels).",
                            "field": _fields("cameras", "cameras.parquet", CAMERA_FIELDS)})  # fmt: skip
        record_sets.append({"@type": "cr:RecordSet", "@id": "people", "name": "people",
                            "description": "Per frame and person: role, human model and visible pixels.",
                            "field": _fields("people", "people.parquet", PEOPLE_FIELDS)})  # fmt: skip
    out: dict[str, Any] = {
        "@context": CROISSANT_CONTEXT,
        "@type": "sc:Dataset",
        "conformsTo": CROISSANT_CONFORMS_TO,
        "name": manifest.name,
        "description": description,
        "license": index.license,
        "version": index.dataset_version,
        "citeAs": _citation(),
        "keywords": ["action recognition", "synthetic data", "procedural generation", "video", "PHAV"],
        "isLiveDataset": False,
        "distribution": distribution,
        "recordSet": record_sets,
    }
    if index.url is not None:
        out["url"] = index.url
    if index.date_published is not None:
        out["datePublished"] = index.date_published
    return out


def check_croissant(path: Path) -> tuple[list[str], list[str]] | None:
    """(errors, warnings) of mlcroissant's offline validation of ``path``, None when
    mlcroissant is not installed (``pip install 'phav[croissant]'``)."""
    try:
        import mlcroissant as mlc  # optional extra phav[croissant]
    except ImportError:
        return None

    logging.getLogger("absl").setLevel(logging.ERROR)  # the issues come back as values
    try:
        ds = mlc.Dataset(str(path))
    except mlc.ValidationError as e:
        return [str(e)], []
    issues = ds.metadata.ctx.issues
    return sorted(issues.errors), sorted(issues.warnings)
