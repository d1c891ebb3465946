"""All recipes of a dataset in one Parquet table: stable columns plus the full recipe JSON.

A table of an older recipe schema is read upgraded: its recipes through the migrations,
its stable columns recomputed (``RecipeTable.schema_version`` says what the file holds).

The stable columns are a documented contract (README): one row per video, categorical
variables as strings/booleans/integers, and ``recipe`` holding the recipe's JSON, which is
the source of truth. The table's key-value metadata carries θ (canonical JSON), its hash,
the dataset seed and the recipe schema version, so ``phav stats`` needs nothing else.
pyarrow is imported inside the functions: reading θ or a recipe never needs it.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

from phav_spec.canonical import canonical_json
from phav_spec.errors import PhavUserError
from phav_spec.files import atomic_write, parse_json_object, read_parquet
from phav_spec.population import age_years, estimated_stature
from phav_spec.recipe import RECIPE_SCHEMA_VERSION, HumanSpec, Recipe, parse_recipe
from phav_spec.theta import Theta, parse_theta

if TYPE_CHECKING:
    import pyarrow as pa


@dataclass(frozen=True)
class Column:
    """A stable column: its name, Arrow type name and how it is read off a recipe."""

    name: str
    arrow_type: str  # string, int64, float64, bool_, list<string>, list<int64>
    extract: Callable[[Recipe], Any]
    doc: str


def _springs(r: Recipe, attr: str) -> int | None:
    return getattr(r.camera.springs, attr) if r.camera.springs is not None else None


def _variation_attr(r: Recipe, kind: str, attr: str) -> Any:
    """A variation's field when the video has that variation (None otherwise, or if absent)."""
    if r.variation.kind != kind:
        return None
    value = getattr(r.variation, attr, None)
    return list(value) if isinstance(value, tuple) else value


def _sex(human: HumanSpec) -> str:
    """``female`` or ``male``: the end of anny's gender scale the phenotype is nearer."""
    return "female" if human.phenotype.gender > 0.5 else "male"


def _draw(human: HumanSpec, attr: str) -> Any:
    """A θ draw of a sampled person (None for a fixed model of H)."""
    return getattr(human.sampled, attr) if human.sampled is not None else None


#: The stable columns, in table order (the ``recipe`` JSON column follows them).
COLUMNS: tuple[Column, ...] = (
    Column("video_id", "string", lambda r: r.video_id, "v000123: dataset-wide id"),
    Column("index", "int64", lambda r: r.index, "video index i in the dataset"),
    Column("action", "string", lambda r: r.action, "A"),
    Column("human_model", "string", lambda r: r.protagonist.human.model, "H (protagonist)"),
    Column("environment", "string", lambda r: r.environment.name, "E"),
    Column("weather", "string", lambda r: r.world.weather, "W"),
    Column("day_phase", "string", lambda r: r.world.day_phase, "D"),
    Column("variation", "string", lambda r: r.variation.kind, "V"),
    Column("camera", "string", lambda r: r.camera.kind, "C"),
    Column("base_motion", "string", lambda r: r.motion.base_motion, "B"),
    Column("duration_s", "float64", lambda r: r.duration_s, "L in seconds"),
    Column("n_frames", "int64", lambda r: r.n_frames, "frames at the video's fps"),
    Column("clock_hour", "float64", lambda r: r.world.clock_hour, "T, hours in [0, 24)"),
    Column("rain", "bool_", lambda r: r.world.rain, "weather element"),
    Column("fog", "bool_", lambda r: r.world.fog, "weather element"),
    Column("clouds", "bool_", lambda r: r.world.clouds, "weather element"),
    Column("wet_ground", "bool_", lambda r: r.world.wet_ground, "weather element"),
    Column("ct_min_distance_m", "int64", lambda r: _springs(r, "ct_min_distance_m"), "camera–target dead zone"),
    Column("tp_min_distance_m", "int64", lambda r: _springs(r, "tp_min_distance_m"), "target–protagonist dead zone"),
    Column("supporting_human_model", "string",
           lambda r: r.supporting_characters[0].human.model if r.supporting_characters else None,
           "H of the supporting character (two-people actions)"),
    Column("variation_object", "string", lambda r: _variation_attr(r, "objects", "object"), "objects variation's prop"),
    Column("blend_motion", "string", lambda r: _variation_attr(r, "action_blending", "blend_motion"), "blended motion"),
    Column("n_background_actors", "int64", lambda r: len(r.background_actors), "background pedestrians"),
    Column("waypoint_index", "int64", lambda r: r.environment.waypoint_index, "P_W in the environment's graph"),
    Column("mirror", "bool_", lambda r: r.motion.mirror, "base motion played mirrored"),
    Column("varied_muscles", "list<string>", lambda r: _variation_attr(r, r.variation.kind, "muscles"), "the muscles"),
    Column("background_human_models", "list<string>", lambda r: [a.human.model for a in r.background_actors],
           "H of each background actor"),
    Column("background_start_waypoints", "list<int64>",
           lambda r: [a.start_waypoint for a in r.background_actors], "starts on B_WG"),
    Column("background_destination_waypoints", "list<int64>",
           lambda r: [a.destination_waypoint for a in r.background_actors], "destinations on B_WG"),
    Column("n_varied_muscles", "int64", lambda r: len(getattr(r.variation, "muscles", ())) or None, "how many"),
    Column("sex", "string", lambda r: _sex(r.protagonist.human), "protagonist: female or male (anny's gender)"),
    Column("age_years", "float64", lambda r: age_years(r.protagonist.human.phenotype.age), "protagonist's age"),
    Column("stature_m", "float64", lambda r: estimated_stature(r.protagonist.human.phenotype),
           "protagonist's standing height"),
    Column("child", "bool_", lambda r: _draw(r.protagonist.human, "child"), "protagonist drawn as a child (sampled)"),
    Column("skin_tone", "float64", lambda r: _draw(r.protagonist.human, "skin_tone"), "0 lightest … 1 (sampled)"),
    Column("hair_style", "string", lambda r: r.protagonist.human.hair.style, "protagonist's hair"),
    Column("hair_colour", "string", lambda r: _draw(r.protagonist.human, "hair_colour"), "named colour (sampled)"),
    Column("top", "string", lambda r: r.protagonist.human.outfit.top.kind, "protagonist's top"),
    Column("top_fabric", "string", lambda r: r.protagonist.human.outfit.top.fabric, "its fabric"),
    Column("bottom", "string", lambda r: r.protagonist.human.outfit.bottom.kind, "protagonist's bottom"),
    Column("bottom_fabric", "string", lambda r: r.protagonist.human.outfit.bottom.fabric, "its fabric"),
    Column("look_seed", "int64", lambda r: r.environment.look_seed,
           "the video's own look of its environment (null: the environment's fixed look)"),
)  # fmt: skip
COLUMN_NAMES: tuple[str, ...] = tuple(c.name for c in COLUMNS)
RECIPE_COLUMN = "recipe"
#: Schema-1 tables end their stable columns after ``n_varied_muscles``, schema-2 tables
#: after ``bottom_fabric``.
_COLUMNS_OF_VERSION = {1: COLUMN_NAMES.index("n_varied_muscles") + 1, 2: COLUMN_NAMES.index("bottom_fabric") + 1}


class RecipeRows:
    """Column lists accumulated recipe by recipe, so millions of Recipe objects need not live."""

    def __init__(self) -> None:
        self.columns: dict[str, list[Any]] = {c.name: [] for c in COLUMNS}
        self.columns[RECIPE_COLUMN] = []

    def __len__(self) -> int:
        return len(self.columns[RECIPE_COLUMN])

    def add(self, recipe: Recipe) -> None:
        """Append one recipe's stable columns and JSON."""
        for c in COLUMNS:
            self.columns[c.name].append(c.extract(recipe))
        self.columns[RECIPE_COLUMN].append(recipe.model_dump_json())

    def extend(self, recipes: Iterable[Recipe]) -> RecipeRows:
        """Append every recipe; returns self for chaining."""
        for r in recipes:
            self.add(r)
        return self

    def to_arrow(self, *, theta: Theta | None = None, dataset_seed: int | None = None) -> pa.Table:
        """The Arrow table, with θ, its hash, the seed and the schema version as metadata."""
        import pyarrow as pa  # phav_spec imports light (DESIGN.md): pyarrow only when a table is read or written

        arrays = {c.name: pa.array(self.columns[c.name], type=arrow_type(c.arrow_type)) for c in COLUMNS}
        arrays[RECIPE_COLUMN] = pa.array(self.columns[RECIPE_COLUMN], type=pa.string())
        meta = {"phav.recipe_schema_version": str(RECIPE_SCHEMA_VERSION)}
        if theta is not None:
            meta["phav.theta"] = canonical_json(theta.model_dump(mode="json"))
            meta["phav.theta_hash"] = theta.hash
        if dataset_seed is not None:
            meta["phav.dataset_seed"] = str(dataset_seed)
        return pa.table(arrays).replace_schema_metadata(meta)


#: The tables' compression, streamed or whole: the same rows give the same bytes either way.
_COMPRESSION = "zstd"
#: Rows per row group when recipes are written as they are drawn: memory holds one batch of
#: rows, however many recipes the table gets.
STREAM_BATCH_ROWS = 10_000


def write_recipe_stream(
    recipes: Iterable[Recipe],
    path: str | Path,
    *,
    theta: Theta | None = None,
    dataset_seed: int | None = None,
    batch_rows: int = STREAM_BATCH_ROWS,
) -> tuple[int, int]:
    """Write recipes as they come, a row group per ``batch_rows``, atomically (nothing at
    ``path`` until the last row is written, and a killed writer's temporary removed first);
    returns (rows, the file's bytes). The table reads back as
    ``RecipeRows().extend(recipes).to_arrow(...)`` would, in a bounded memory."""
    import pyarrow.parquet as pq  # phav_spec imports light (DESIGN.md): pyarrow only when a table is read or written

    if batch_rows < 1:
        raise ValueError(f"batch_rows must be at least 1, got {batch_rows}")

    def table(rows: RecipeRows) -> pa.Table:
        return rows.to_arrow(theta=theta, dataset_seed=dataset_seed)

    written = 0
    with atomic_write(path, sweep=True) as tmp:
        # Opened before the first recipe is drawn: a place that cannot be written fails now.
        with pq.ParquetWriter(tmp, table(RecipeRows()).schema, compression=_COMPRESSION) as writer:
            rows = RecipeRows()
            for recipe in recipes:
                rows.add(recipe)
                if len(rows) == batch_rows:
                    writer.write_table(table(rows))
                    written, rows = written + len(rows), RecipeRows()
            if len(rows) or not written:  # the rest, or an empty table's one (empty) row group
                writer.write_table(table(rows))
                written += len(rows)
    return written, Path(path).stat().st_size


def write_recipe_table(table: pa.Table, path: str | Path) -> int:
    """Write atomically (temp file in the same folder, then rename); returns the file's bytes."""
    import pyarrow.parquet as pq  # phav_spec imports light (DESIGN.md): pyarrow only when a table is read or written

    with atomic_write(path) as tmp:
        pq.write_table(table, tmp, compression=_COMPRESSION)
    return Path(path).stat().st_size


@dataclass(frozen=True)
class RecipeTable:
    """A recipes.parquet as read back: the Arrow table and what its metadata says."""

    path: Path
    table: pa.Table
    theta: Theta | None
    dataset_seed: int | None
    schema_version: int

    def column(self, name: str) -> list[Any]:
        """One column as a Python list."""
        return self.table.column(name).to_pylist()

    def recipes(self) -> Iterable[Recipe]:
        """Every row's recipe, validated; a bad row raises PhavUserError naming its video."""
        ids = self.table.column("video_id").to_pylist()
        for vid, text in zip(ids, self.table.column(RECIPE_COLUMN).to_pylist(), strict=True):
            yield parse_recipe(text, source=f"{self.path}[{vid}]")


def _metadata_int(meta: dict[str, str], key: str, path: Path, *, default: int | None) -> int | None:
    if key not in meta:
        return default
    try:
        value = int(meta[key])
    except ValueError:
        raise PhavUserError(f"not an integer: {meta[key][:40]!r}", source=str(path), field=key) from None
    if value < 0:
        raise PhavUserError(f"must be non-negative, got {value}", source=str(path), field=key)
    return value


def _upgraded(table: pa.Table, path: Path) -> pa.Table:
    """An older table in the current schema: every recipe upgraded (migrations) and the
    stable columns recomputed from it, the metadata kept. If a row does not parse, the
    table is kept as it is and the columns it lacks are null (the checks report the row)."""
    import pyarrow as pa  # phav_spec imports light (DESIGN.md): pyarrow only when a table is read or written

    rows = RecipeRows()
    try:
        ids, texts = table.column("video_id").to_pylist(), table.column(RECIPE_COLUMN).to_pylist()
        for vid, text in zip(ids, texts, strict=True):
            rows.add(parse_recipe(text, source=f"{path}[{vid}]"))
    except PhavUserError:
        for name in COLUMN_NAMES:
            if name not in table.column_names:
                table = table.append_column(name, pa.nulls(table.num_rows))
        return table
    return rows.to_arrow().replace_schema_metadata(table.schema.metadata)


def arrow_type(name: str) -> pa.DataType:
    """The Arrow type a column's ``arrow_type`` names (``int64``, ``list<string>``, …)."""
    import pyarrow as pa  # phav_spec imports light (DESIGN.md): pyarrow only when a table is read or written

    if name.startswith("list<"):
        return pa.list_(arrow_type(name[5:-1]))
    return getattr(pa, name)()


def read_recipe_table(path: str | Path) -> RecipeTable:
    """Read recipes.parquet; a missing, truncated or foreign file raises PhavUserError."""
    import pyarrow as pa  # phav_spec imports light (DESIGN.md): pyarrow only when a table is read or written

    path = Path(path)
    if not path.exists():
        raise PhavUserError("no such file", source=str(path))
    try:
        table = read_parquet(path)
    except (pa.ArrowException, OSError) as e:
        first = str(e).splitlines()[0] if str(e) else type(e).__name__
        raise PhavUserError(f"not a readable Parquet file ({first})", source=str(path)) from None
    meta = {k.decode(errors="replace"): v.decode(errors="replace") for k, v in (table.schema.metadata or {}).items()}
    version = _metadata_int(meta, "phav.recipe_schema_version", path, default=RECIPE_SCHEMA_VERSION)
    if version > RECIPE_SCHEMA_VERSION:
        raise PhavUserError(
            f"recipe schema version {version} is newer than this phav supports ({RECIPE_SCHEMA_VERSION}); upgrade phav",
            source=str(path),
            field="phav.recipe_schema_version",
        )
    required = COLUMN_NAMES[: _COLUMNS_OF_VERSION.get(version, len(COLUMN_NAMES))]
    missing = [name for name in (*required, RECIPE_COLUMN) if name not in table.column_names]
    if missing:
        raise PhavUserError("missing column (not a phav recipes table?)", source=str(path), field=missing[0])
    expected = {c.name: arrow_type(c.arrow_type) for c in COLUMNS if c.name in required}
    expected[RECIPE_COLUMN] = pa.string()
    for name, kind in expected.items():
        found = table.schema.field(name).type
        if not found.equals(kind):
            raise PhavUserError(f"column is {found}, a recipes table's is {kind}", source=str(path), field=name)
    if version < RECIPE_SCHEMA_VERSION:
        table = _upgraded(table, path)
    theta = None
    if "phav.theta" in meta:
        source = f"{path} (metadata phav.theta)"
        theta = parse_theta(parse_json_object(meta["phav.theta"], source=source), source=source)
    seed = _metadata_int(meta, "phav.dataset_seed", path, default=None)
    return RecipeTable(path=path, table=table, theta=theta, dataset_seed=seed, schema_version=version)
