"""phav_spec imports with pydantic, numpy and PyYAML only (a consumer installs nothing heavy)."""

import subprocess
import sys

HEAVY = ("pyarrow", "scipy", "hypothesis", "typer", "rich", "torch", "moderngl", "mujoco", "phav_generator")


def test_spec_modules_import_light():
    code = (
        "import sys\n"
        "import phav_spec.vocab, phav_spec.scene, phav_spec.motions, phav_spec.distributions, phav_spec.theta\n"
        "import phav_spec.recipe, phav_spec.expectations, phav_spec.encoding, phav_spec.manifest\n"
        "import phav_spec.recipe_table, phav_spec.clips\n"
        "print(' '.join(sorted({m.split('.')[0] for m in sys.modules})))\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout.split()
    assert not set(HEAVY) & set(out), set(HEAVY) & set(out)
    assert {"pydantic", "numpy", "yaml"} <= set(out)


def test_tables_read_without_pyarrow_dataset(tmp_path):
    # pq.read_table imports pyarrow.dataset (a noticeable share of a short command's time):
    # phav's readers read a file's columns, metadata kept, without it.
    import pyarrow as pa
    import pyarrow.parquet as pq

    path = tmp_path / "t.parquet"
    pq.write_table(pa.table({"a": [1, 2], "b": ["x", "y"]}).replace_schema_metadata({"k": "v"}), path)
    code = (
        "import sys\n"
        "from phav_spec.errors import PhavUserError\n"
        "from phav_spec.files import read_parquet\n"
        "from phav_spec.recipe_table import read_recipe_table\n"
        f"t = read_parquet({str(path)!r}, ['b'])\n"
        "try:\n"
        f"    read_recipe_table({str(path)!r})\n"
        "except PhavUserError as e:\n"
        "    print(e.field or e.detail.split()[0])\n"
        "print(t.column_names, t.column('b').to_pylist(), t.schema.metadata[b'k'].decode())\n"
        "print('pyarrow.dataset' in sys.modules, 'pyarrow.parquet' in sys.modules)\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout.splitlines()
    assert out[1:] == ["['b'] ['x', 'y'] v", "False True"], out
