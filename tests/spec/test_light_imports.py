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
