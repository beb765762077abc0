#!/usr/bin/env python3
"""Conclusion (b) of issue 23: negative interference, by the rule of sweeps/thesis/README.md
("(b) Negative interference"), written before the run: it holds when task A's held-out nMSE
after learning task B is at most 10 % above before, in every seed.

Reads the database of interference_two_task.json: in stage score_a, per seed, the job whose
learning.initial_model names stage train_a (before B) and the one naming train_b (after B);
heldout_test_nmse, the mean over joints (joint NULL).

Usage: python3 sweeps/thesis/tools/interference_verdict.py DB [--sweep interference_two_task.score_a]
       [--tolerance 0.10]
Python 3 standard library only.
"""
import argparse
import json
import math
import sqlite3
import sys

from seed_statistics import mean_interval


def read_scores(path, sweep):
    """{seed: {"before": nmse, "after": nmse}} of the done jobs of `sweep`."""
    try:
        connection = sqlite3.connect("file:" + path + "?mode=ro", uri=True)
        rows = connection.execute(
            "SELECT seed, params, value FROM job_metrics WHERE sweep = ? AND status = 'done' AND name = 'heldout_test_nmse' "
            "AND joint IS NULL AND value IS NOT NULL", (sweep,)).fetchall()
    except sqlite3.Error as error:
        sys.exit(f"{path}: {error}")
    scores = {}
    for seed, params, value in rows:
        try:
            source = json.loads(params)["learning.initial_model"]["sweep"]
        except (ValueError, KeyError, TypeError):
            sys.exit(f"{path}: sweep {sweep}: a job's params name no learning.initial_model sweep")
        stage = source.rsplit(".", 1)[-1]
        if stage not in ("train_a", "train_b"):
            sys.exit(f"{path}: sweep {sweep}: learning.initial_model names {source}, not a train_a or train_b stage")
        scores.setdefault(seed, {})["before" if stage == "train_a" else "after"] = value
    return {seed: pair for seed, pair in scores.items() if len(pair) == 2}


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("database")
    parser.add_argument("--sweep", default="interference_two_task.score_a")
    parser.add_argument("--tolerance", type=float, default=0.10)
    args = parser.parse_args()
    scores = read_scores(args.database, args.sweep)
    if not scores:
        sys.exit(f"{args.database}: sweep {args.sweep}: no seed with both a before and an after score")
    seeds = sorted(scores)
    ratios = [scores[s]["after"] / scores[s]["before"] for s in seeds]
    print("| seed | " + " | ".join(str(s) for s in seeds) + " |")
    print("|---|" + "---|" * len(seeds))
    print("| A's held-out nMSE before B | " + " | ".join(f"{scores[s]['before']:.4f}" for s in seeds) + " |")
    print("| after B | " + " | ".join(f"{scores[s]['after']:.4f}" for s in seeds) + " |")
    print("| after / before | " + " | ".join(f"{r:.3f}" for r in ratios) + " |")
    print()
    mean, low, high = mean_interval(ratios)
    geometric = math.exp(sum(math.log(r) for r in ratios) / len(ratios))
    interval = f" [{low:.3f}, {high:.3f}]" if low is not None else ""
    worse = [str(s) for s, r in zip(seeds, ratios) if r > 1.0 + args.tolerance]
    verdict = "holds" if not worse and len(seeds) >= 2 else "does not hold"
    print(f"after / before: mean {mean:.3f}{interval} ({len(seeds)}), geometric mean {geometric:.3f}. "
          f"Verdict (at most {args.tolerance:.0%} worse in every seed): **{verdict}**"
          + (f" (seeds {', '.join(worse)} above)" if worse else "") + ".")


if __name__ == "__main__":
    main()
