#!/usr/bin/env python3
"""The chapter 6 tables of sweeps/thesis/README.md, generated from run databases (issue 23).

For every database given it runs `armfarm table DB --against thesis_results.json --format json`
(the verdicts are armfarm's, by the README's rule "Verdicts"; nothing here judges), takes each
thesis table or figure from the database that compared most of its cells, and prints markdown:

  - per spec: jobs done / total, seeds, the wall time of its runs (the `runs` table of its
    database: finished_at - started_at, summed over the runs of every stage) and, when
    --times names the run log (lines of key=value: spec=, user_s=, load_start=, load_end=),
    the CPU time and the load; then the total;
  - per thesis table: thesis | armfarm mean [95 % CI] (n) | verdict, per cell, with the sweep,
    the database and the spec's wall time;
  - the "holds?" sentence of each table (tools/holds_sentences.py's `sentence`) and the count
    of each verdict.

With --readme FILE the output replaces what lies between the lines
`<!-- thesis_tables.py: begin -->` and `<!-- thesis_tables.py: end -->` of FILE (exit 2, nothing
written, when they are missing); otherwise it goes to standard output.

Usage: python3 sweeps/thesis/tools/thesis_tables.py --armfarm build/runner/armfarm
         [--thesis sweeps/thesis/thesis_results.json] [--times /work/runs/times.txt]
         [--readme sweeps/thesis/README.md] DB [DB ...]
Python 3 standard library only.
"""
import argparse
import datetime
import json
import os
import sqlite3
import subprocess
import sys

from holds_sentences import sentence, title

HERE = os.path.dirname(os.path.abspath(__file__))
BEGIN = "<!-- thesis_tables.py: begin -->"
END = "<!-- thesis_tables.py: end -->"
VERDICTS = ("matches", "same direction", "differs", "one seed")


def fail(message):
    print(message, file=sys.stderr)
    sys.exit(2)


def number(value):
    return f"{value:.4g}"


def against(armfarm, database, thesis):
    """The tables of `armfarm table DB --against THESIS --format json`."""
    try:
        done = subprocess.run([armfarm, "table", database, "--against", thesis, "--format", "json"],
                              capture_output=True, text=True, check=False)
    except OSError as error:
        fail(f"{armfarm}: {error}")
    if done.returncode != 0:
        fail(f"{database}: armfarm table --against exited {done.returncode}: {done.stderr.strip()}")
    try:
        return json.loads(done.stdout)
    except ValueError as error:
        fail(f"{database}: armfarm table --against printed no JSON: {error}")


def parse_time(text):
    return datetime.datetime.fromisoformat(text.replace("Z", "+00:00"))


def spec_runs(database):
    """{spec: {"wall": seconds, "done": n, "total": n, "seeds": set, "complete": bool}} from the
    database's runs and jobs (a spec's stages `spec.stage` add up)."""
    try:
        connection = sqlite3.connect("file:" + database + "?mode=ro", uri=True)
        runs = connection.execute("SELECT s.name, r.started_at, r.finished_at, r.status FROM runs r "
                                  "JOIN sweeps s ON s.id = r.sweep_id").fetchall()
        jobs = connection.execute("SELECT sweep, status, seed FROM sweep_job_status").fetchall()
    except sqlite3.Error as error:
        fail(f"{database}: {error}")
    specs = {}
    for sweep, started, finished, status in runs:
        entry = specs.setdefault(sweep.split(".")[0], {"wall": 0.0, "done": 0, "total": 0, "seeds": set(), "complete": True})
        if finished is None:
            entry["complete"] = False
            continue
        entry["wall"] += (parse_time(finished) - parse_time(started)).total_seconds()
        entry["complete"] = entry["complete"] and status == "complete"
    for sweep, status, seed in jobs:
        entry = specs.setdefault(sweep.split(".")[0], {"wall": 0.0, "done": 0, "total": 0, "seeds": set(), "complete": False})
        entry["total"] += 1
        if status == "done":
            entry["done"] += 1
            entry["seeds"].add(seed)
    return specs


def read_times(path):
    """{spec: {"cpu": seconds, "loads": [load, ...], "runs": n}} from the run log's key=value lines
    (one line per run of a spec: the CPU times add up, the loads at each start and end are kept)."""
    times = {}
    try:
        with open(path) as log:
            for line in log:
                fields = dict(item.split("=", 1) for item in line.split() if "=" in item)
                if "spec" not in fields:
                    continue
                entry = times.setdefault(fields["spec"], {"cpu": 0.0, "loads": [], "runs": 0})
                entry["runs"] += 1
                for key in ("user_s", "sys_s"):
                    try:
                        entry["cpu"] += float(fields.get(key, ""))
                    except ValueError:
                        pass
                for key in ("load_start", "load_end"):
                    try:
                        entry["loads"].append(float(fields.get(key, "")))
                    except ValueError:
                        pass
    except OSError as error:
        fail(f"{path}: {error}")
    return times


def duration(seconds):
    seconds = int(round(seconds))
    hours, rest = divmod(seconds, 3600)
    return (f"{hours} h " if hours else "") + f"{rest // 60} min {rest % 60:02d} s"


def compared_count(table):
    return sum(1 for c in table.get("cells", []) if c.get("state") == "compared")


def rank(table):
    """More compared cells first; among tables of none, the database that holds the sweep."""
    absent = sum(1 for c in table.get("cells", []) if "absent" in (c.get("reason") or ""))
    return compared_count(table), -absent


def pick_tables(per_database):
    """[(table, database)]: each thesis table from the database that compared most of its cells
    (else the one holding its sweep; the first database on a tie), in thesis_results.json's order."""
    order, best = [], {}
    for database, tables in per_database:
        for table in tables:
            key = table["id"]
            if key not in best:
                order.append(key)
                best[key] = (table, database)
            elif rank(table) > rank(best[key][0]):
                best[key] = (table, database)
    return [best[key] for key in order]


def armfarm_cell(cell):
    if cell.get("state") != "compared":
        return cell.get("reason") and f"not run ({cell['reason']})" or cell.get("state", "—")
    text = number(cell["mean"])
    if cell.get("ci95"):
        text += f" [{number(cell['ci95'][0])}, {number(cell['ci95'][1])}]"
    return text + f" ({cell['n']})"


def verdict_cell(cell):
    if not cell.get("verdict"):
        return "—"
    return cell["verdict"] + (f" ({cell['verdict_note']})" if cell.get("verdict_note") else "")


def render(per_database, specs, times):
    lines = [BEGIN, "", "Generated by `sweeps/thesis/tools/thesis_tables.py` from "
             + ", ".join(f"`{os.path.basename(d)}`" for d, _ in per_database) + "; do not edit by hand.", ""]
    lines += ["| spec | jobs done / total | seeds | wall time (runs table) | CPU user + sys (run log) | load average (runs' starts and ends) |",
              "|---|---|---|---|---|---|"]
    total_wall = total_cpu = 0.0
    for spec in sorted(specs):
        entry = specs[spec]
        log = times.get(spec)
        cpu = load = ""
        if log:
            total_cpu += log["cpu"]
            cpu = duration(log["cpu"]) + (f" ({log['runs']} runs)" if log["runs"] > 1 else "")
            if log["loads"]:
                load = f"{min(log['loads']):.1f}–{max(log['loads']):.1f}"
        seeds = f"{len(entry['seeds'])}" if entry["seeds"] else "0"
        wall = duration(entry["wall"]) + ("" if entry["complete"] else " (incomplete)")
        total_wall += entry["wall"]
        lines.append(f"| `{spec}` | {entry['done']} / {entry['total']} | {seeds} | {wall} | {cpu} | {load} |")
    lines += [f"| **all** | {sum(e['done'] for e in specs.values())} / {sum(e['total'] for e in specs.values())} | "
              f"| **{duration(total_wall)}** | {duration(total_cpu) if total_cpu else ''} | |", ""]
    counts = {}
    sentences = []
    absent = []
    for table, database in pick_tables(per_database):
        if not compared_count(table):
            if table.get("cells"):
                reasons = sorted({armfarm_cell(c) for c in table["cells"]})
                absent.append(f"{title(table)} ({len(table['cells'])} cells: {'; '.join(reasons)})")
                counts["not compared"] = counts.get("not compared", 0) + len(table["cells"])
            continue
        spec_walls = [duration(specs[s.split('.')[0]]["wall"]) for s in table.get("sweeps", []) if s.split(".")[0] in specs]
        caption = table.get("caption", "")
        heading = caption if caption.startswith(title(table)) else f"{title(table)}: {caption}"
        lines += [f"#### {heading}", "",
                  f"armfarm: sweep {', '.join(table.get('sweeps', []))} (`{os.path.basename(database)}`, wall time "
                  f"{', '.join(spec_walls) or 'unknown'}), mean [95 % Student-t interval] (n seeds) over done jobs; "
                  "verdicts by the rule under \"Verdicts\"", "",
                  "| row | column | thesis | armfarm mean [95 % CI] (n) | verdict |", "|---|---|---|---|---|"]
        for cell in table["cells"]:
            lines.append(f"| {cell['row']} | {cell['column']} | {cell['printed']} | {armfarm_cell(cell)} | {verdict_cell(cell)} |")
            key = cell.get("verdict") or "not compared"
            counts[key] = counts.get(key, 0) + 1
        lines.append("")
        paragraph = sentence(table, numbers=False)
        if paragraph:
            sentences.append(paragraph)
    if absent:
        lines += ["#### Not compared in these databases", ""] + [f"- {entry}" for entry in absent] + [""]
    lines += ["#### Holds? (from the verdicts)", ""]
    for paragraph in sentences:
        lines += [paragraph, ""]
    lines.append("Verdicts over " + str(sum(counts.values())) + " cells of chapter 6: "
                 + ", ".join(f"{counts.get(word, 0)} {word}" for word in VERDICTS + ("not compared",)) + ".")
    lines += ["", END]
    return "\n".join(lines) + "\n"


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("databases", nargs="+")
    parser.add_argument("--armfarm", required=True, help="the armfarm executable")
    parser.add_argument("--thesis", default=os.path.join(HERE, "..", "thesis_results.json"))
    parser.add_argument("--times", help="the run log of key=value lines (CPU time and load per spec)")
    parser.add_argument("--readme", help="replace the generated section of this file instead of printing")
    args = parser.parse_args()
    per_database, specs = [], {}
    for database in args.databases:
        if not os.path.isfile(database):
            fail(f"{database}: no such database")
        per_database.append((database, against(args.armfarm, database, args.thesis)))
        specs.update(spec_runs(database))
    text = render(per_database, specs, read_times(args.times) if args.times else {})
    if not args.readme:
        sys.stdout.write(text)
        return
    try:
        readme = open(args.readme).read()
    except OSError as error:
        fail(f"{args.readme}: {error}")
    if readme.count(BEGIN) != 1 or readme.count(END) != 1 or readme.index(BEGIN) > readme.index(END):
        fail(f"{args.readme}: needs one line {BEGIN} and after it one line {END}")
    head, rest = readme.split(BEGIN, 1)
    tail = rest.split(END, 1)[1]
    with open(args.readme + ".tmp", "w") as out:
        out.write(head + text.rstrip("\n") + tail)
    os.replace(args.readme + ".tmp", args.readme)


if __name__ == "__main__":
    main()
