#!/usr/bin/env python3
"""Conclusion (c) of issue 23: online learning in real time against the number of joints, by the
rule of sweeps/thesis/README.md ("(c) Real time against the number of joints"), written before the
run: real time holds at n joints when sim_seconds_per_wall_second >= 1 in every seed.

Reads the database of realtime_dof.json and prints, per number of active joints and init_D, the
fields after the pass, learner_us_per_update and sim_seconds_per_wall_second as mean [95 %
Student-t interval] (n seeds), and the verdict per number of joints.

Usage: python3 sweeps/thesis/tools/realtime_verdict.py DB [--sweep realtime_dof]
Python 3 standard library only. The timings are wall-clock: report them with the load.
"""
import argparse
import json
import sqlite3
import sys

from seed_statistics import format_mean_interval

METRICS = ("n_receptive_fields", "learner_us_per_update", "sim_seconds_per_wall_second")


def read_jobs(path, sweep):
    """{(n_joints, init_D): {seed: {metric: value}}} of the done jobs of `sweep`."""
    try:
        connection = sqlite3.connect("file:" + path + "?mode=ro", uri=True)
        rows = connection.execute(
            "SELECT seed, params, name, value FROM job_metrics WHERE sweep = ? AND status = 'done' AND joint IS NULL "
            "AND checkpoint IS NULL AND value IS NOT NULL AND name IN (?, ?, ?)", (sweep,) + METRICS).fetchall()
    except sqlite3.Error as error:
        sys.exit(f"{path}: {error}")
    jobs = {}
    for seed, params, name, value in rows:
        try:
            swept = json.loads(params)
            key = (len(swept["active_joints"]), float(swept["learning.lwpr.init_D"]))
        except (ValueError, KeyError, TypeError):
            sys.exit(f"{path}: sweep {sweep}: a job's params lack active_joints or learning.lwpr.init_D")
        jobs.setdefault(key, {}).setdefault(seed, {})[name] = value
    return jobs


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("database")
    parser.add_argument("--sweep", default="realtime_dof")
    args = parser.parse_args()
    jobs = read_jobs(args.database, args.sweep)
    if not jobs:
        sys.exit(f"{args.database}: sweep {args.sweep}: no done job")
    widths = sorted({d for _, d in jobs})
    header = "| joints | " + " | ".join(f"fields ({d:g}) | µs/update ({d:g}) | sim s per wall s ({d:g})" for d in widths) + " | real time |"
    print(header)
    print("|---|" + "---|" * (3 * len(widths) + 1))
    for joints in sorted({n for n, _ in jobs}):
        cells, real_time = [], True
        for width in widths:
            by_seed = jobs.get((joints, width), {})
            for metric, digits in zip(METRICS, (4, 3, 3)):
                values = [m[metric] for m in by_seed.values() if metric in m]
                cells.append(format_mean_interval(values, f".{digits}g") if values else "—")
            speeds = [m["sim_seconds_per_wall_second"] for m in by_seed.values() if "sim_seconds_per_wall_second" in m]
            real_time = real_time and bool(speeds) and min(speeds) >= 1.0
        print(f"| {joints} | " + " | ".join(cells) + f" | {'holds' if real_time else 'does not hold'} |")


if __name__ == "__main__":
    main()
