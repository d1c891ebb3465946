"""Power of phav-validate's distribution check against a skewed θ_W, on recipe tables.

For each skew s (percentage points moved onto ``clear``, taken evenly from the other three
weathers) and each replicate r: sample 2,000 recipes from the skewed θ with seed 1000 + r,
check them against phav-v1 and record whether the weather test (or any test) rejected.
Skew 0 measures the false-alarm rate. No rendering is needed.

    .venv/bin/python docs/measure/distribution_power.py 0,1,2,3,4,5,6 100
"""

from __future__ import annotations

import copy
import sys
import time
from concurrent.futures import ProcessPoolExecutor

import yaml

from phav_generator.sampling import sample_recipes
from phav_spec.recipe_table import RecipeRows
from phav_spec.theta import PRESETS_DIR, load_theta, parse_theta
from phav_validators.checks.distribution import check_distributions
from phav_validators.findings import Reason

N_VIDEOS = 2000


def run(args: tuple[float, int]) -> tuple[float, int, bool, bool]:
    skew, rep = args
    data = copy.deepcopy(yaml.safe_load((PRESETS_DIR / "phav-v1.yaml").read_text(encoding="utf-8")))
    if skew:
        rest = 25 - skew / 3
        data["theta_w"] = {"clear": 25 + skew, "overcast": rest, "rain": rest, "fog": rest}
    theta = parse_theta(data, source=f"skew {skew}")
    rows = RecipeRows().extend(sample_recipes(theta, n=N_VIDEOS, seed=1000 + rep))
    table = rows.to_arrow(theta=theta, dataset_seed=1000 + rep)
    columns = {name: table.column(name).to_pylist() for name in table.column_names}
    result = check_distributions(columns, load_theta("phav-v1"))
    mismatches = [f for f in result.report.findings if f.reason == Reason.DISTRIBUTION_MISMATCH]
    return skew, rep, any(f.message.startswith("weather") for f in mismatches), bool(mismatches)


def main() -> None:
    skews = [float(s) for s in sys.argv[1].split(",")]
    reps = int(sys.argv[2])
    start = time.time()
    with ProcessPoolExecutor(2) as pool:
        out = list(pool.map(run, [(s, r) for s in skews for r in range(reps)]))
    print("| skew of θ_W (pp) | weather rejected | any test rejected |")
    print("| ---: | ---: | ---: |")
    for s in skews:
        rows = [o for o in out if o[0] == s]
        print(f"| {s:g} | {sum(o[2] for o in rows)}/{len(rows)} | {sum(o[3] for o in rows)}/{len(rows)} |")
    print(f"\n{len(out)} runs of {N_VIDEOS} recipes in {time.time() - start:.0f} s")


if __name__ == "__main__":
    main()
