"""Power of phav-validate's distribution check against a skewed θ_W, on recipe tables.

For each skew s (percentage points moved onto ``clear``, taken evenly from the other three
weathers) and each replicate r: sample 2,000 recipes from the skewed θ with seed 1000 + r,
check them against phav-v1 and record whether the weather test (or any test) rejected.
Skew 0 measures the false-alarm rate. No rendering is needed.

    .venv/bin/python docs/measure/distribution_power.py 0,1,2,3,4,5,6 100
"""

from __future__ import annotations

import argparse
import copy
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


def skew_list(text: str) -> list[float]:
    """``0,1,2``: the skews in percentage points, each in [0, 75)."""
    try:
        skews = [float(s) for s in text.split(",") if s.strip()]
    except ValueError:
        raise argparse.ArgumentTypeError(f"comma-separated numbers, as in 0,1,2; got {text!r}") from None
    if not skews or not all(0.0 <= s < 75.0 for s in skews):
        raise argparse.ArgumentTypeError(f"skews in [0, 75) percentage points; got {text!r}")
    return skews


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("skews", type=skew_list, help="comma-separated skews of θ_W onto clear (pp), e.g. 0,1,2")
    parser.add_argument("replicates", type=int, help="seeded recipe tables per skew")
    args = parser.parse_args()
    if args.replicates < 1:
        parser.error("replicates: at least 1")
    start = time.time()
    with ProcessPoolExecutor(2) as pool:
        out = list(pool.map(run, [(s, r) for s in args.skews for r in range(args.replicates)]))
    share = {s: [o for o in out if o[0] == s] for s in args.skews}
    print("| skew of θ_W (pp) | " + " | ".join(f"{s:g}" for s in args.skews) + " |")
    print("| --- |" + " ---: |" * len(args.skews))
    for label, column in (("weather test rejects", 2), ("any test rejects", 3)):
        cells = " | ".join(f"{100 * sum(o[column] for o in rows) / len(rows):.0f} %" for rows in share.values())
        print(f"| {label} | {cells} |")
    print(f"\n{len(out)} runs of {N_VIDEOS} recipes in {time.time() - start:.0f} s")


if __name__ == "__main__":
    main()
