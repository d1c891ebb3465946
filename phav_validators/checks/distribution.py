"""Observed recipes against θ's exact expectations: chi-square per variable and per
conditional row, Kolmogorov–Smirnov for durations and clock times, Holm-corrected.

A value θ gives probability zero is never a matter of p-values: one occurrence is an
IMPOSSIBLE_VALUE finding. Expected cells below five counts are pooled before the test.
"""

from __future__ import annotations

import io
import math
from collections import Counter
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
import pyarrow as pa
import pyarrow.compute as pc
import pyarrow.json as pj

from phav_spec.errors import PhavUserError
from phav_spec.expectations import (
    CONTINUOUS_PARAMETERS,
    ContinuousParameter,
    ExactTable,
    clock_hour_cdf,
    duration_cdf,
    exact_expectations,
    mean_duration,
)
from phav_spec.recipe import parse_recipe
from phav_spec.theta import Theta
from phav_spec.vocab import ACTIONS, DAY_PHASES
from phav_validators.findings import Finding, Reason, Report

if TYPE_CHECKING:
    import pyarrow as pa

DEFAULT_ALPHA = 1e-3
MIN_EXPECTED = 5.0


@dataclass(frozen=True)
class FitTest:
    """One goodness-of-fit test: which distribution, on how many videos, with what result."""

    variable: str
    condition: str  # "marginal" or "action=walk, environment=urban"
    kind: str  # chi2 or ks
    n: int
    statistic: float
    dof: int
    p_value: float
    impossible: int = 0
    rejected: bool = False  # set after the Holm correction
    unit: str = "videos"  # what ``n`` counts: a list column's elements (background actors, muscles)

    @property
    def tested(self) -> bool:
        """Whether the data could test anything: a chi-square left with two cells or more
        once its small cells are pooled, a KS test with a sample. Rows too small to test
        are reported, never counted in the Holm family as passed tests."""
        return self.n > 0 and (self.kind != "chi2" or self.dof > 0 or math.isnan(self.p_value))


@dataclass
class VariableSummary:
    """Observed against expected for one variable's marginal, for printing as a histogram."""

    variable: str
    values: tuple[Any, ...]
    observed: np.ndarray
    expected: np.ndarray  # probabilities
    applies_to: str


@dataclass
class DistributionResult:
    tests: list[FitTest]
    summaries: list[VariableSummary]
    report: Report
    n_videos: int
    mean_duration: float
    expected_mean_duration: float

    @property
    def ok(self) -> bool:
        """No finding: every test passed and no impossible value was seen."""
        return self.report.ok


def chi_square(observed: np.ndarray, probs: np.ndarray) -> tuple[float, int, float, int]:
    """(statistic, dof, p, impossible count) with small expected cells joined into groups of
    at least ``MIN_EXPECTED``; where two cells are left, p is the exact binomial test's (the
    chi-square's is up to 40× too small in the tails Holm's thresholds reach)."""
    n = observed.sum()
    impossible = int(observed[probs <= 0].sum())
    support = probs > 0
    obs, exp = observed[support].astype(float), probs[support] * n
    if n == 0 or len(obs) < 2 or obs.sum() == 0:  # nothing on the support: only impossible values to report
        return 0.0, 0, 1.0, impossible
    small = exp < MIN_EXPECTED
    if small.any():
        grouped_obs, grouped_exp = _group_small(obs[small], exp[small])
        obs, exp = np.append(obs[~small], grouped_obs), np.append(exp[~small], grouped_exp)
    if len(obs) < 2:
        return 0.0, 0, 1.0, impossible
    from scipy import stats  # 0.4 s to import: only the tests need it, not every phav process

    stat, p = stats.chisquare(obs, exp * (obs.sum() / exp.sum()))
    if len(obs) == 2:  # one cell against the rest: the exact binomial p, where the chi-square's tail is too thin
        p = stats.binomtest(int(obs[0]), int(obs.sum()), float(exp[0] / exp.sum())).pvalue
    return float(stat), len(obs) - 1, float(p), impossible


def _group_small(obs: np.ndarray, exp: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Small cells, in value order, joined into groups of at least ``MIN_EXPECTED`` expected
    each (the last few into the group before them). Any fixed grouping is a valid test; one
    group of them all left a row of many small cells untested (128 blend motions at 3.7
    expected each) and gave a pooled cell the chi-square read too optimistically."""
    out_obs, out_exp = [], []
    o_sum = e_sum = 0.0
    for o, e in zip(obs, exp, strict=True):
        o_sum, e_sum = o_sum + o, e_sum + e
        if e_sum >= MIN_EXPECTED:
            out_obs.append(o_sum)
            out_exp.append(e_sum)
            o_sum = e_sum = 0.0
    if e_sum > 0:
        if out_exp:
            out_obs[-1] += o_sum
            out_exp[-1] += e_sum
        else:
            out_obs.append(o_sum)
            out_exp.append(e_sum)
    return np.array(out_obs), np.array(out_exp)


def _codes(column: Sequence[Any], values: tuple[Any, ...]) -> tuple[np.ndarray, int]:
    """Index of each entry in ``values`` (−1 when unknown) and how many are unknown."""
    index = {v: i for i, v in enumerate(values)}
    codes = np.fromiter((index.get(x, -1) for x in column), dtype=np.int64, count=len(column))
    return codes, int((codes < 0).sum())


def _support_sizes(table: ExactTable, keys: Sequence[tuple[Any, ...]], n: int) -> np.ndarray:
    """Per element (``keys``: its video's parent values; none without parents), how many
    values its row allows (its subset is drawn from them)."""
    sizes = {key: int((row > 0).sum()) for key, row in table.rows.items()}
    return np.array([sizes.get(k, 0) for k in keys] if keys else [sizes.get((), 0)] * n, dtype=np.int64)


def _subset_corrected(stat: float, dof: int, p: float, video: np.ndarray, support: np.ndarray) -> tuple[float, float]:
    """A chi-square of elements that are subsets drawn without replacement (k of m in each
    video), scaled to its null spread: the counts vary by Σ k(m − k)/(m − 1) / Σ k of what
    independent draws' would, so the plain statistic is too small (a test without power).
    Each video's k is its elements' count; a video with k = m tells nothing."""
    if dof < 1 or len(video) == 0:
        return stat, p
    _, first, k = np.unique(video, return_index=True, return_counts=True)
    m = support[first].astype(float)
    spread = float(np.sum(np.where(m > 1, k * (m - k) / np.maximum(m - 1.0, 1.0), 0.0))) / float(k.sum())
    if spread <= 0.0:
        return stat, p
    from scipy import stats  # 0.4 s to import: only the tests need it, not every phav process

    corrected = stat / spread
    return corrected, float(stats.chi2.sf(corrected, dof))


def _unit(table: ExactTable) -> str:
    """What one observation of ``table`` is: a video, or one element of a list column."""
    return table.applies_to if table.multi else "videos"


def _fmt(parents: tuple[str, ...], key: tuple[Any, ...]) -> str:
    return ", ".join(f"{p}={k}" for p, k in zip(parents, key, strict=True)) or "marginal"


def check_table(
    table: ExactTable, columns: Mapping[str, Sequence[Any]], source: str | None = None
) -> tuple[list[FitTest], VariableSummary, list[Finding]]:
    """Test one variable: its marginal and each conditional row that has observations."""
    column = columns[table.variable]
    if table.multi:  # one observation per list element, with its video's parent values
        idx = np.array([i for i, xs in enumerate(column) if xs is not None for _ in xs], dtype=np.int64)
        values = [x for xs in column if xs is not None for x in xs]
    else:
        idx = np.flatnonzero(np.array([x is not None for x in column], dtype=bool))
        values = [column[i] for i in idx]
    codes, unknown = _codes(values, table.values)
    # Each observation's parent values (its video's), in the order of ``values``.
    keys = list(zip(*(([columns[p][i] for i in idx]) for p in table.parents), strict=True)) if table.parents else []
    findings: list[Finding] = []
    probs = table.marginal()
    if table.multi and table.parents:
        # A video's elements share its parents and their number varies: mixed by θ's parent
        # probabilities, the marginal's counts spread more than a chi-square allows (false
        # alarms with many background actors). Mixed by the elements each parent holds.
        held = Counter(keys)
        mixed = sum((n * table.rows[key] for key, n in held.items() if key in table.rows), np.zeros(len(table.values)))
        if mixed.sum() > 0:
            probs = mixed / mixed.sum()
    observed = np.bincount(codes[codes >= 0], minlength=len(table.values))
    stat, dof, p, impossible = chi_square(observed, probs)
    if table.subset:
        stat, p = _subset_corrected(stat, dof, p, idx, _support_sizes(table, keys, len(idx)))
    impossible += unknown
    tests = [FitTest(table.variable, "marginal", "chi2", len(values), stat, dof, p, impossible, unit=_unit(table))]
    if impossible:
        hit = [j for j, c in enumerate(codes) if c < 0 or probs[c] <= 0]
        bad = sorted({str(values[j]) for j in hit})
        ids = columns.get("video_id")
        videos = sorted({str(ids[idx[j]]) for j in hit}) if ids is not None else []
        findings.append(Finding(
            Reason.IMPOSSIBLE_VALUE,
            f"{table.variable}: {impossible} {_unit(table)} have values θ gives probability zero ({', '.join(bad[:5])})"
            + (f": {', '.join(videos[:5])}" if videos else ""),
            file=source, video_id=videos[0] if len(videos) == 1 else None,
            numbers={"count": impossible, "values": bad[:20], "videos": videos[:50]},
        ))  # fmt: skip
    if table.parents:
        groups: dict[tuple[Any, ...], list[int]] = {}
        for j, key in enumerate(keys):
            groups.setdefault(key, []).append(j)
        for key in sorted(groups, key=str):
            members = np.array(groups[key])
            if key not in table.rows:
                findings.append(Finding(
                    Reason.IMPOSSIBLE_VALUE,
                    f"{table.variable}: {len(members)} {_unit(table)} have {_fmt(table.parents, key)}, "
                    "which θ gives probability zero",
                    file=source, numbers={"count": len(members)},
                ))  # fmt: skip
                continue
            row = table.rows[key]
            sub = codes[members]
            obs = np.bincount(sub[sub >= 0], minlength=len(table.values))
            stat, dof, p, imp = chi_square(obs, row)
            if table.subset:
                stat, p = _subset_corrected(stat, dof, p, idx[members], np.full(len(members), int((row > 0).sum())))
            imp += int((sub < 0).sum())
            tests.append(
                FitTest(
                    table.variable,
                    _fmt(table.parents, key),
                    "chi2",
                    len(members),
                    stat,
                    dof,
                    p,
                    imp,
                    unit=_unit(table),
                )
            )
            if imp:
                bad = sorted({str(table.values[c]) if c >= 0 else "?" for c in sub if c < 0 or row[c] <= 0})
                findings.append(Finding(
                    Reason.IMPOSSIBLE_VALUE,
                    f"{table.variable} given {_fmt(table.parents, key)}: {imp} {_unit(table)} with "
                    f"probability-zero values ({', '.join(bad[:5])})",
                    file=source, numbers={"count": imp, "values": bad[:20]},
                ))  # fmt: skip
    summary = VariableSummary(table.variable, table.values, observed, probs, table.applies_to)
    return tests, summary, findings


def ks(variable: str, condition: str, x: np.ndarray, cdf: Callable[[np.ndarray], np.ndarray]) -> FitTest:
    """Kolmogorov–Smirnov test of the finite values of ``x`` against ``cdf``.

    θ may put an atom where the data are (fixed-length clips: T_min = T_max). scipy's test
    assumes a continuous CDF and then finds the largest possible distance at the atom, so
    there the statistic takes the CDF's left limits (D⁻ = max F(x₍ᵢ₎⁻) − (i−1)/n) and the
    p-value the continuous null distribution, which is conservative for a discrete F.
    """
    from scipy import stats  # 0.4 s to import: only the tests need it, not every phav process

    x = x[np.isfinite(x)]
    n = len(x)
    if n == 0:
        return FitTest(variable, condition, "ks", 0, 0.0, 0, 1.0)
    xs = np.sort(x)
    at, left = np.asarray(cdf(xs), dtype=float), np.asarray(cdf(np.nextafter(xs, -np.inf)), dtype=float)
    if not np.any(at - left > 1e-12):
        res = stats.kstest(x, cdf)
        return FitTest(variable, condition, "ks", n, float(res.statistic), 0, float(res.pvalue))
    d = max(float(np.max(np.arange(1, n + 1) / n - at)), float(np.max(left - np.arange(n) / n)), 0.0)
    return FitTest(variable, condition, "ks", n, d, 0, float(stats.kstwo.sf(d, n)))


def _finite_column(columns: Mapping[str, Sequence[Any]], name: str, report: Report, source: str | None) -> np.ndarray:
    """A float column as an array, with NaN in place of nulls; non-finite entries are findings."""
    x = np.array([np.nan if v is None else v for v in columns[name]], dtype=float)
    bad = int((~np.isfinite(x)).sum())
    if bad:
        report.add(
            Finding(Reason.IMPOSSIBLE_VALUE, f"{name}: {bad} videos with a null or non-finite value", file=source)
        )
    return x


def holm(tests: list[FitTest], alpha: float) -> list[FitTest]:
    """Mark rejections with the Holm–Bonferroni step-down procedure at family-wise ``alpha``,
    over the tests that could test anything (``FitTest.tested``)."""
    # A NaN p-value (a test that could not be computed) sorts first and is rejected.
    family = [i for i, t in enumerate(tests) if t.tested]
    order = sorted(family, key=lambda i: -1.0 if math.isnan(tests[i].p_value) else tests[i].p_value)
    rejected = [False] * len(tests)
    m = len(family)
    for rank, i in enumerate(order):
        if math.isnan(tests[i].p_value) or tests[i].p_value <= alpha / (m - rank):
            rejected[i] = True
        else:
            break
    return [FitTest(**{**t.__dict__, "rejected": r or t.impossible > 0}) for t, r in zip(tests, rejected, strict=True)]


def check_alpha(alpha: float) -> float:
    """``alpha`` if it is a significance level, in (0, 1) (NaN is not); else a user error
    naming ``--alpha``."""
    if not 0.0 < alpha < 1.0:
        raise PhavUserError(f"must be in (0, 1), got {alpha}", field="--alpha")
    return alpha


def check_distributions(
    columns: Mapping[str, Sequence[Any]],
    theta: Theta,
    *,
    alpha: float = DEFAULT_ALPHA,
    source: str | None = None,
) -> DistributionResult:
    """Every categorical variable (marginal and conditional rows) and the continuous ones,
    Holm-corrected to the family-wise level ``alpha``."""
    check_alpha(alpha)
    report = Report()
    tests: list[FitTest] = []
    summaries: list[VariableSummary] = []
    for table in exact_expectations(theta).values():
        t, s, f = check_table(table, columns, source)
        tests += t
        summaries.append(s)
        for finding in f:
            report.add(finding)

    durations = _finite_column(columns, "duration_s", report, source)
    tests.append(ks("duration_s", "marginal", durations, duration_cdf(theta)))
    actions = np.asarray(columns["action"], dtype=object)
    for action in ACTIONS.names:
        if theta.arrays.a[ACTIONS.index(action)] > 0:
            x = durations[actions == action]
            tests.append(ks("duration_s", f"action={action}", x, duration_cdf(theta, action)))
    hours = _finite_column(columns, "clock_hour", report, source)
    tests.append(ks("clock_hour", "marginal", hours, clock_hour_cdf(theta)))
    phases = np.asarray(columns["day_phase"], dtype=object)
    for phase in DAY_PHASES.names:
        if theta.arrays.d[DAY_PHASES.index(phase)] > 0:
            tests.append(
                ks(
                    "clock_hour",
                    f"day_phase={phase}",
                    hours[phases == phase],
                    clock_hour_cdf(theta, phase),
                )
            )

    if "recipe" in columns:
        more, outside = check_continuous(columns["recipe"], theta)
        tests += more
        for name, group, count in outside:
            report.add(Finding(
                Reason.IMPOSSIBLE_VALUE,
                f"{name} ({group}): {count} draws outside the support θ gives",
                file=source, numbers={"count": count},
            ))  # fmt: skip

    tests = holm(tests, alpha)
    for t in tests:
        if t.rejected and t.impossible == 0:
            report.add(Finding(
                Reason.DISTRIBUTION_MISMATCH,
                f"{t.variable} ({t.condition}): {t.kind} = {t.statistic:.4g}, p = {t.p_value:.3g} on {t.n} {t.unit} "
                f"(Holm-corrected family-wise α = {alpha:g})",
                file=source, numbers={"statistic": t.statistic, "p_value": t.p_value, "n": t.n, "dof": t.dof},
            ))  # fmt: skip
    n = len(durations)
    return DistributionResult(
        tests=tests,
        summaries=summaries,
        report=report,
        n_videos=n,
        mean_duration=float(np.nanmean(durations)) if n and np.isfinite(durations).any() else float("nan"),
        expected_mean_duration=mean_duration(theta),
    )


def parse_recipes_arrow(recipes_json: Sequence[str | None]) -> pa.Table:
    """Parse recipe JSON texts into one Arrow table (C++ parser: ~15× Python's json).

    Where the texts do not parse as one table (a null, a text that is not a JSON object, a
    value of another type than the rest's, such as a number written as text), each text is
    read as a recipe and written back in the schema's own types, and those that are not
    recipes are left out (the schema check reports them): a damaged row cannot hide the
    distribution of the others.
    """

    def read(texts: Sequence[str]) -> pa.Table:
        if not texts:
            return pa.table({})
        blob = "\n".join(texts).encode("utf-8")
        # One block, one thread: the types are inferred from every row at once. In blocks read
        # in parallel, a block without any supporting person typed that list as null, and the
        # blocks then failed to join, on some runs and not others.
        options = pj.ReadOptions(use_threads=False, block_size=min(len(blob) + 1, 2**31 - 1))
        return pj.read_json(io.BytesIO(blob), read_options=options)

    try:
        return read(recipes_json)  # type: ignore[arg-type]  # a null row fails the join: sorted out below
    except (pa.ArrowException, ValueError, TypeError):
        good = []
        for text in recipes_json:
            try:
                good.append(parse_recipe(text).model_dump_json())  # type: ignore[arg-type]
            except (PhavUserError, ValueError, TypeError):
                continue
        try:
            return read(good)
        except pa.ArrowException:  # structurally foreign recipes: nothing to test here
            return pa.table({})


def _path(table: pa.Table, path: str) -> tuple[np.ndarray, np.ndarray]:
    """(row index, values) at a recipe path such as ``background_actors[].speed_mps``."""

    rows = np.arange(table.num_rows)
    head, *rest = path.split(".")
    if head.removesuffix("[]") not in table.column_names:
        return rows[:0], np.array([], dtype=object)
    node = table.column(head.removesuffix("[]")).combine_chunks()
    steps = ([head[-2:]] if head.endswith("[]") else []) + [
        part for seg in rest for part in ([seg.removesuffix("[]"), "[]"] if seg.endswith("[]") else [seg])
    ]
    for step in steps:
        if step == "[]":
            rows = rows[pc.list_parent_indices(node).to_numpy()]
            node = pc.list_flatten(node)
        else:
            if not pa.types.is_struct(node.type) or node.type.get_field_index(step) < 0:
                return rows[:0], np.array([], dtype=object)
            node = pc.struct_field(node, step)
    return rows, np.asarray(node.to_pylist(), dtype=object)


def parameter_draws(table: pa.Table, param: ContinuousParameter) -> tuple[np.ndarray, np.ndarray]:
    """(group, value) of every draw of a continuous parameter in parsed recipes."""
    rows, values = _path(table, param.value)
    keep = np.array([v is not None for v in values], dtype=bool)
    if param.when is not None:
        when_rows, flags = _path(table, param.when)
        on = dict(zip(when_rows.tolist(), flags.tolist(), strict=True))
        keep &= np.array([bool(on.get(r)) for r in rows.tolist()], dtype=bool)
    if param.group is None:
        groups = np.full(len(values), "all", dtype=object)
    else:
        # By recipe row, never by position: a list parameter (``strengths[]``) yields several
        # draws per recipe, and their count may equal the number of recipes by chance.
        group_rows, group_values = _path(table, param.group)
        by_row = dict(zip(group_rows.tolist(), group_values.tolist(), strict=True))
        groups = np.array([by_row.get(r) for r in rows.tolist()], dtype=object)
    keep &= np.array([g is not None for g in groups], dtype=bool)
    return groups[keep], values[keep].astype(float)


def check_continuous(recipes_json: Sequence[str], theta: Theta) -> tuple[list[FitTest], list[tuple[str, str, int]]]:
    """KS test of every continuous θ parameter per group; point masses need only the support.

    Returns the tests and (parameter, group, count) of draws outside θ's support.
    """
    table = parse_recipes_arrow(recipes_json)
    tests: list[FitTest] = []
    outside: list[tuple[str, str, int]] = []
    for param in CONTINUOUS_PARAMETERS:
        groups, values = parameter_draws(table, param)
        for group in sorted(set(groups.tolist())):
            x = values[groups == group]
            try:
                dist = param.distribution(theta, group)
            except (KeyError, AttributeError):  # a group θ does not know (e.g. weather "snow")
                outside.append((param.name, str(group), len(x)))
                continue
            if dist is None:  # θ draws nothing here (people of H: the human-model check covers them)
                continue
            lo, hi = dist.support
            if getattr(dist, "wraps", False):
                bad = int(((x > hi) & (x < lo)).sum())
            else:
                bad = int(((x < lo) | (x > hi)).sum())
            if bad:
                outside.append((param.name, group, bad))
            if lo == hi:
                continue  # a point mass: nothing to fit beyond the support check
            tests.append(ks(param.name, f"group={group}", x, dist.cdf))
    return tests, outside
