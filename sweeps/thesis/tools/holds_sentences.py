#!/usr/bin/env python3
"""The "holds?" sentences of sweeps/thesis/README.md, generated from the verdicts of
`armfarm table DB --against sweeps/thesis/thesis_results.json --format json` (issue 23, item 5).

Per thesis table or figure with compared cells it prints one markdown paragraph: how many cells
"match" (the thesis value inside armfarm's 95 % interval) or go the "same direction" (every
comparison the thesis draws on the cell holds), i.e. hold, and which "differ", each with the
thesis value and armfarm's mean [interval] (n); cells that were not run or have no metric are
counted apart. The rule of each verdict is the README's ("Verdicts"); nothing here judges.

Usage: armfarm table DB --against sweeps/thesis/thesis_results.json --format json \\
         | python3 sweeps/thesis/tools/holds_sentences.py [--table ID ...]
       python3 sweeps/thesis/tools/holds_sentences.py FILE.json [--table ID ...]
Python 3 standard library only.
"""
import argparse
import json
import sys

HOLDS = ("matches", "same direction")


def format_number(value):
    return f"{value:.3g}"


def describe(cell):
    text = f"{cell['row']} {cell['column']}: thesis {cell['printed']}, armfarm {format_number(cell['mean'])}"
    if cell.get("ci95"):
        low, high = cell["ci95"]
        text += f" [{format_number(low)}, {format_number(high)}]"
    return text + f" ({cell['n']})"


def title(table):
    if table.get("number"):
        return f"Table {table['number']}" if table["id"].startswith("table") else f"Figure {table['number']}"
    caption = table.get("caption", table["id"])
    return caption.split(":")[0] if caption.startswith("Figure") else caption.rstrip(".")


def sentence(table, numbers=True):
    """The paragraph of one table; `numbers` False names the differing cells without their values
    (for a page that prints them in a table beside it)."""
    cells = table.get("cells", [])
    compared = [c for c in cells if c.get("state") == "compared" and c.get("verdict") in HOLDS + ("differs",)]
    one_seed = [c for c in cells if c.get("state") == "compared" and c.get("verdict") not in HOLDS + ("differs",)]
    skipped = len(cells) - len(compared) - len(one_seed)
    if not compared:
        return None
    holds = [c for c in compared if c["verdict"] in HOLDS]
    matches = sum(1 for c in holds if c["verdict"] == "matches")
    differs = [c for c in compared if c["verdict"] == "differs"]
    seeds = sorted({c["n"] for c in compared})
    n_text = f"n = {seeds[0]}–{seeds[-1]}" if len(seeds) > 1 else f"n = {seeds[0]}"
    text = (f"**{title(table)}** ({', '.join(table.get('sweeps', []))}, {n_text} seeds): holds on {len(holds)} of "
            f"{len(compared)} compared cells ({matches} matches, {len(holds) - matches} same direction)")
    if differs:
        if numbers:
            text += "; does not hold on " + "; ".join(describe(c) for c in differs)
        else:
            text += "; does not hold on " + ", ".join(f"{c['row']} {c['column']}" for c in differs)
    text += "."
    if one_seed or skipped:
        text += f" Not judged: {len(one_seed)} cells of one seed, {skipped} not run or without a metric."
    return text


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("file", nargs="?", help="the JSON of armfarm table --against (default: standard input)")
    parser.add_argument("--table", action="append", default=[], help="only this table id (table6_5, fig6_7, ...)")
    args = parser.parse_args()
    try:
        text = open(args.file).read() if args.file else sys.stdin.read()
        tables = json.loads(text)
    except (OSError, ValueError) as error:
        sys.exit(f"{args.file or 'standard input'}: {error}")
    if not isinstance(tables, list):
        sys.exit(f"{args.file or 'standard input'}: expected the list armfarm table --against --format json prints")
    for table in tables:
        if args.table and table.get("id") not in args.table:
            continue
        paragraph = sentence(table)
        if paragraph:
            print(paragraph + "\n")


if __name__ == "__main__":
    main()
