#!/usr/bin/env python3
"""Conclusion (d) of issue 23: does the IK noise model (trajectory.ik_noise) move joints 1, 5 and 6
toward table 6.1's ratios? The rule is sweeps/thesis/README.md's ("(d) The thesis's IK noise"),
written before the run:

  r_j(sigma, s) = ff_fb_ratio_avg of joint j at ik_noise sigma and seed s, t_j = table 6.1's
  avg(ff/fb); each sigma > 0 is paired by seed with sigma = 0.
  - joint j in {1, 5, 6} moves toward the thesis when |r_j(sigma, s) - t_j| < |r_j(0, s) - t_j|
    in every paired seed (at least 2) or by the one-sided sign test (p < 0.05);
  - the pattern moves toward it when G = mean(r_2, r_3, r_4) - mean(r_1, r_5, r_6) is larger at
    sigma than at 0 by the same test;
  - verdict: "moves toward" (all three joints and the pattern), "moves toward, partly" (some),
    "does not move toward" (none); a joint whose t_j lies in the 95 % Student-t interval of
    r_j(sigma) also "reaches" the thesis.

Usage: python3 sweeps/thesis/tools/ik_noise_verdict.py DB [--sweep ik_noise_figure_eight]
       [--param trajectory.ik_noise] [--thesis sweeps/thesis/thesis_results.json]
Prints a markdown table (mean [95 % interval] (n) per joint and noise level) and the verdicts.
Python 3 standard library only.
"""
import argparse
import json
import os
import sqlite3
import sys

from seed_statistics import format_mean_interval, holds_in_seeds, mean_interval

WEAK = (1, 5, 6)
MAJOR = (2, 3, 4)
HERE = os.path.dirname(os.path.abspath(__file__))


def read_thesis_ratios(path):
    """{joint: table 6.1's avg(ff/fb)}, from thesis_results.json."""
    try:
        document = json.load(open(path))
        table = next(t for t in document["tables"] if t["id"] == "table6_1")
        return {int(c["row"].split()[-1]): c["value"] for c in table["cells"] if c["column"] == "avg(ff/fb)"}
    except (OSError, ValueError, KeyError, StopIteration) as error:
        sys.exit(f"{path}: cannot read table6_1's avg(ff/fb): {error}")


def read_ratios(path, sweep, param):
    """{sigma: {seed: {joint: ratio}}} over the done jobs of `sweep`, sigma the swept `param`."""
    try:
        connection = sqlite3.connect("file:" + path + "?mode=ro", uri=True)
        rows = connection.execute(
            "SELECT seed, params, joint, value FROM job_metrics WHERE sweep = ? AND status = 'done' "
            "AND name = 'ff_fb_ratio_avg' AND checkpoint IS NULL AND joint IS NOT NULL AND value IS NOT NULL",
            (sweep,)).fetchall()
    except sqlite3.Error as error:
        sys.exit(f"{path}: {error}")
    ratios = {}
    for seed, params, joint, value in rows:
        try:
            sigma = float(json.loads(params)[param])
        except (ValueError, KeyError, TypeError):
            sys.exit(f"{path}: sweep {sweep}: a job's params have no {param}")
        ratios.setdefault(sigma, {}).setdefault(seed, {})[joint] = value
    if 0.0 not in ratios:
        sys.exit(f"{path}: sweep {sweep}: no done job at {param} 0")
    return ratios


def gap(joints):
    return sum(joints[j] for j in MAJOR) / len(MAJOR) - sum(joints[j] for j in WEAK) / len(WEAK)


def judge(ratios, thesis):
    """[(sigma, {joint: bool toward}, pattern bool, verdict text, {joint: bool reaches})] for sigma > 0."""
    exact = ratios[0.0]
    results = []
    for sigma in sorted(s for s in ratios if s > 0.0):
        seeds = [s for s in sorted(ratios[sigma]) if s in exact
                 and all(j in ratios[sigma][s] and j in exact[s] for j in WEAK + MAJOR)]
        toward = {j: holds_in_seeds([abs(exact[s][j] - thesis[j]) - abs(ratios[sigma][s][j] - thesis[j]) for s in seeds])
                  for j in WEAK}
        pattern = holds_in_seeds([gap(ratios[sigma][s]) - gap(exact[s]) for s in seeds])
        count = sum(toward.values()) + pattern
        verdict = "moves toward" if count == len(WEAK) + 1 else ("moves toward, partly" if count else "does not move toward")
        reaches = {}
        for j in WEAK:
            _, low, high = mean_interval([ratios[sigma][s][j] for s in seeds])
            reaches[j] = low is not None and low <= thesis[j] <= high
        results.append((sigma, toward, pattern, verdict, reaches, len(seeds)))
    return results


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("database")
    parser.add_argument("--sweep", default="ik_noise_figure_eight")
    parser.add_argument("--param", default="trajectory.ik_noise", help="the swept noise parameter")
    parser.add_argument("--thesis", default=os.path.join(HERE, "..", "thesis_results.json"))
    args = parser.parse_args()
    thesis = read_thesis_ratios(args.thesis)
    ratios = read_ratios(args.database, args.sweep, args.param)
    joints = sorted({j for by_seed in ratios.values() for joint_values in by_seed.values() for j in joint_values})
    print("| ik_noise (mrad) | " + " | ".join(f"joint {j}" for j in joints) + " | gap G |")
    print("|---|" + "---|" * (len(joints) + 1))
    for sigma in sorted(ratios):
        by_seed = ratios[sigma]
        cells = [format_mean_interval([v[j] for v in by_seed.values() if j in v]) for j in joints]
        gaps = [gap(v) for v in by_seed.values() if all(j in v for j in WEAK + MAJOR)]
        print(f"| {sigma * 1000:g} | " + " | ".join(cells) + f" | {format_mean_interval(gaps) if gaps else '—'} |")
    print("| thesis (table 6.1) | " + " | ".join(f"{thesis[j]:.3f}" if j in thesis else "—" for j in joints)
          + f" | {gap(thesis):.3f} |")
    print()
    for sigma, toward, pattern, verdict, reaches, n in judge(ratios, thesis):
        moved = [str(j) for j in WEAK if toward[j]]
        reached = [str(j) for j in WEAK if reaches[j]]
        print(f"ik_noise {sigma * 1000:g} mrad ({n} paired seeds): **{verdict}** — joints moving toward table 6.1: "
              f"{', '.join(moved) if moved else 'none'} of 1, 5, 6; gap widens: {'yes' if pattern else 'no'}; "
              f"reaching the thesis's ratio: {', '.join(reached) if reached else 'none'}.")


if __name__ == "__main__":
    main()
