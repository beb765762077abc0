#!/usr/bin/env python3
"""Conclusion (a) of issue 23: is the feed-forward to feedback ratio a task-independent indicator
of learning success (thesis, section 6.2: "a good indicator of the learning success")?

Reads armfarm results databases (SQLite, the job_metrics view of results/README.md) and, pooled
over every done job of the named sweeps, prints Spearman's rank correlation with a percentile
bootstrap 95 % interval of
  - ff_fb_ratio_avg of a joint against id_nmse of the same joint (one pair per job and joint
    where both are defined), and
  - the mean over joints of ff_fb_ratio_avg against tracking_nmse (mean row; one pair per job),
and a verdict: "holds" when the interval lies below 0 (a higher ratio goes with a smaller error),
"differs" when it lies above 0, "undecided" otherwise.

Usage: python3 sweeps/thesis/tools/ff_fb_indicator.py DB [DB ...] [--sweep NAME ...]
       [--resamples 2000] [--seed 0]
Python 3 standard library only; the bootstrap is seeded, so the same databases print the same
numbers.
"""
import argparse
import random
import sqlite3
import sys


def ranks(values):
    """1-based ranks, ties given their mean rank."""
    order = sorted(range(len(values)), key=lambda i: values[i])
    result = [0.0] * len(values)
    i = 0
    while i < len(order):
        j = i
        while j + 1 < len(order) and values[order[j + 1]] == values[order[i]]:
            j += 1
        for k in range(i, j + 1):
            result[order[k]] = (i + j) / 2.0 + 1.0
        i = j + 1
    return result


def pearson(x, y):
    n = len(x)
    mx, my = sum(x) / n, sum(y) / n
    sxy = sum((a - mx) * (b - my) for a, b in zip(x, y))
    sxx = sum((a - mx) ** 2 for a in x)
    syy = sum((b - my) ** 2 for b in y)
    if sxx == 0.0 or syy == 0.0:
        return float("nan")
    return sxy / (sxx * syy) ** 0.5


def spearman(pairs):
    return pearson(ranks([p[0] for p in pairs]), ranks([p[1] for p in pairs]))


def bootstrap_interval(pairs, resamples, seed):
    generator = random.Random(seed)
    values = []
    for _ in range(resamples):
        sample = [pairs[generator.randrange(len(pairs))] for _ in pairs]
        rho = spearman(sample)
        if rho == rho:  # a resample of tied values has no correlation; left out
            values.append(rho)
    values.sort()
    if not values:
        return float("nan"), float("nan")
    return values[int(0.025 * (len(values) - 1))], values[int(0.975 * (len(values) - 1))]


def read_jobs(path, sweeps):
    """{(db, job_id): {(name, joint): value}} of the done jobs of `sweeps` (all when empty)."""
    try:
        connection = sqlite3.connect("file:" + path + "?mode=ro", uri=True)
        rows = connection.execute(
            "SELECT sweep, job_id, name, joint, value FROM job_metrics WHERE status = 'done' AND checkpoint IS NULL "
            "AND name IN ('ff_fb_ratio_avg', 'id_nmse', 'tracking_nmse') AND value IS NOT NULL").fetchall()
    except sqlite3.Error as error:
        sys.exit(f"{path}: {error}")
    jobs = {}
    for sweep, job, name, joint, value in rows:
        if sweeps and sweep not in sweeps:
            continue
        jobs.setdefault((path, job), {})[(name, joint)] = value
    return jobs


def verdict(low, high):
    if high < 0.0:
        return "holds"
    if low > 0.0:
        return "differs"
    return "undecided"


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("databases", nargs="+")
    parser.add_argument("--sweep", action="append", default=[])
    parser.add_argument("--resamples", type=int, default=2000)
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args()
    jobs = {}
    for path in args.databases:
        jobs.update(read_jobs(path, set(args.sweep)))
    joint_pairs, job_pairs = [], []
    for metrics in jobs.values():
        ratios = {joint: value for (name, joint), value in metrics.items() if name == "ff_fb_ratio_avg" and joint is not None}
        for joint, ratio in ratios.items():
            if ("id_nmse", joint) in metrics:
                joint_pairs.append((ratio, metrics[("id_nmse", joint)]))
        if ratios and ("tracking_nmse", None) in metrics:
            job_pairs.append((sum(ratios.values()) / len(ratios), metrics[("tracking_nmse", None)]))
    print(f"{len(jobs)} done jobs; bootstrap {args.resamples} resamples, seed {args.seed}")
    print("| pairs | n | Spearman rho | 95 % bootstrap interval | verdict (thesis: rho < 0) |")
    print("|---|---|---|---|---|")
    for label, pairs in (("ff/fb of a joint vs id_nmse of that joint", joint_pairs),
                         ("mean ff/fb vs tracking_nmse", job_pairs)):
        if len(pairs) < 3:
            print(f"| {label} | {len(pairs)} | — | — | too few pairs |")
            continue
        rho = spearman(pairs)
        low, high = bootstrap_interval(pairs, args.resamples, args.seed)
        print(f"| {label} | {len(pairs)} | {rho:.3f} | [{low:.3f}, {high:.3f}] | {verdict(low, high)} |")


if __name__ == "__main__":
    main()
