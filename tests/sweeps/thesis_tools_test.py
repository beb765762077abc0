#!/usr/bin/env python3
"""Tests of the Python tools of sweeps/thesis/tools/ on small generated databases (issue 23).

Each database is made by the test executable armfarm_fakejobs ($ARMFARM_FAKEJOBS: armfarm's command
line running the fake job, the real schema and runner, cheap deterministic jobs); the metrics the tools
read are then set to known values with sqlite3, the way a user's script would write them. The
expected numbers are computed by hand in the comments.

Run: ARMFARM=build/runner/armfarm ARMFARM_FAKEJOBS=build/runner/armfarm_fakejobs \
       python3 tests/sweeps/thesis_tools_test.py (ctest does this).
"""
import io
import json
import math
import os
import shutil
import sqlite3
import subprocess
import sys
import tempfile
import unittest
from contextlib import redirect_stdout

SOURCE = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
TOOLS = os.path.join(SOURCE, "sweeps", "thesis", "tools")
sys.path.insert(0, TOOLS)

import ff_fb_indicator  # noqa: E402
import holds_sentences  # noqa: E402
import seed_statistics  # noqa: E402

ARMFARM = os.environ.get("ARMFARM", "")
ARMFARM_FAKEJOBS = os.environ.get("ARMFARM_FAKEJOBS", "")


def run_tool(script, *arguments):
    done = subprocess.run([sys.executable, os.path.join(TOOLS, script), *arguments], capture_output=True, text=True)
    return done.returncode, done.stdout, done.stderr


class GeneratedDatabase:
    """A results database of fake jobs, made by armfarm, whose metrics a test then writes."""

    def __init__(self, directory, name, sweep):
        self.path = os.path.join(directory, name + ".db")
        spec = os.path.join(directory, name + ".json")
        with open(spec, "w") as out:
            json.dump({"name": name, "base": {"fake": {"sleep_ms": 0}}, "sweep": sweep}, out)
        done = subprocess.run([ARMFARM_FAKEJOBS, "run", spec, "--db", self.path, "-j1"], capture_output=True, text=True)
        if done.returncode != 0:
            raise RuntimeError(f"armfarm run {spec}: exit {done.returncode}: {done.stderr}")
        self.connection = sqlite3.connect(self.path)

    def jobs(self):
        """[(job id, seed, params dict)] in seed order."""
        rows = self.connection.execute("SELECT j.id, j.seed, sj.params FROM jobs j JOIN sweep_jobs sj ON sj.job_id = j.id "
                                       "ORDER BY j.seed, j.id").fetchall()
        return [(job, seed, json.loads(params)) for job, seed, params in rows]

    def set_metric(self, job, name, joint, value, checkpoint=None):
        self.connection.execute("DELETE FROM metrics WHERE job_id = ? AND name = ? AND joint IS ? AND checkpoint IS ?",
                                (job, name, joint, checkpoint))
        self.connection.execute("INSERT INTO metrics (job_id, name, joint, checkpoint, value) VALUES (?, ?, ?, ?, ?)",
                                (job, name, joint, checkpoint, float(value)))

    def set_params(self, job, params):
        """The job's swept values as `params` (what a spec of those axes would have stored)."""
        self.connection.execute("UPDATE sweep_jobs SET params = ? WHERE job_id = ?", (json.dumps(params), job))

    def commit(self):
        self.connection.commit()
        self.connection.close()


class SeedStatistics(unittest.TestCase):
    def test_t_quantile_equals_the_closed_forms_and_printed_tables(self):
        # df 1 (Cauchy): tan(pi (0.975 - 1/2)); df 2: sqrt(2 / (p (2 - p)) - 2) with p = 2 * 0.025.
        self.assertAlmostEqual(seed_statistics.t_quantile_975(1), math.tan(math.pi * 0.475), places=9)
        self.assertAlmostEqual(seed_statistics.t_quantile_975(2), math.sqrt(2 / (0.05 * 1.95) - 2), places=9)
        # Printed tables (3 decimals): 2.776 at 4, 2.228 at 10, 2.042 at 30.
        self.assertAlmostEqual(seed_statistics.t_quantile_975(4), 2.776, places=3)
        self.assertAlmostEqual(seed_statistics.t_quantile_975(10), 2.228, places=3)
        self.assertAlmostEqual(seed_statistics.t_quantile_975(30), 2.042, places=3)

    def test_interval_of_known_samples_equals_a_hand_computation(self):
        # 1, 2, 3: mean 2, s = 1, half width t(0.975, 2) / sqrt(3) = 4.302653 / 1.732051 = 2.484138.
        mean, low, high = seed_statistics.mean_interval([1.0, 2.0, 3.0])
        self.assertEqual(mean, 2.0)
        self.assertAlmostEqual(low, 2.0 - 2.484138, places=5)
        self.assertAlmostEqual(high, 2.0 + 2.484138, places=5)
        self.assertEqual(seed_statistics.mean_interval([4.0]), (4.0, None, None))

    def test_sign_test_and_paired_comparison(self):
        self.assertEqual(seed_statistics.sign_test_p(5, 5), 1 / 32)
        self.assertEqual(seed_statistics.sign_test_p(4, 5), 6 / 32)  # 0.1875: does not hold
        self.assertEqual(seed_statistics.sign_test_p(9, 10), 11 / 1024)
        self.assertTrue(seed_statistics.holds_in_seeds([0.1, 0.2]))
        self.assertFalse(seed_statistics.holds_in_seeds([0.1, 0.2, 0.3, 0.4, -0.1]))
        self.assertTrue(seed_statistics.holds_in_seeds([0.1] * 9 + [-0.1]))
        self.assertFalse(seed_statistics.holds_in_seeds([0.1]))


class Spearman(unittest.TestCase):
    def test_known_orderings(self):
        # x 1..5 against y 2, 1, 4, 3, 5: d = -1, 1, -1, 1, 0, sum d^2 = 4, rho = 1 - 6*4/(5*24) = 0.8.
        pairs = list(zip([1, 2, 3, 4, 5], [2, 1, 4, 3, 5]))
        self.assertAlmostEqual(ff_fb_indicator.spearman(pairs), 0.8, places=12)
        self.assertAlmostEqual(ff_fb_indicator.spearman([(x, -y) for x, y in pairs]), -0.8, places=12)
        # Ties take their mean rank: ranks of 1, 2, 2, 3 are 1, 2.5, 2.5, 4.
        self.assertEqual(ff_fb_indicator.ranks([1, 2, 2, 3]), [1.0, 2.5, 2.5, 4.0])

    def test_bootstrap_interval_contains_the_estimate(self):
        generator_pairs = [(i, i + ((-1) ** i) * 1.5) for i in range(20)]
        rho = ff_fb_indicator.spearman(generator_pairs)
        low, high = ff_fb_indicator.bootstrap_interval(generator_pairs, 500, 0)
        self.assertLess(low, rho)
        self.assertLess(rho, high)
        self.assertLessEqual(high, 1.0)
        self.assertEqual((low, high), ff_fb_indicator.bootstrap_interval(generator_pairs, 500, 0))  # seeded


@unittest.skipUnless(ARMFARM and os.access(ARMFARM, os.X_OK) and ARMFARM_FAKEJOBS and os.access(ARMFARM_FAKEJOBS, os.X_OK),
                     "ARMFARM and ARMFARM_FAKEJOBS do not name the armfarm and armfarm_fakejobs executables")
class OnGeneratedDatabases(unittest.TestCase):
    def setUp(self):
        self.directory = tempfile.mkdtemp(prefix="thesis_tools_test_")

    def tearDown(self):
        shutil.rmtree(self.directory)

    def test_ff_fb_indicator_reads_a_known_ordering(self):
        database = GeneratedDatabase(self.directory, "indicator", {"repeat": 6})
        # Six jobs: ff/fb of joint 1 rises 0.1 ... 0.6 while id_nmse falls: rho = -1 exactly; the
        # job's mean ff/fb (joint 1 only) against tracking_nmse follows 2, 1, 4, 3, 6, 5 reversed in
        # sign: ranks of y are 5, 6, 3, 4, 1, 2, d = -4, -4, 0, 0, 4, 4, sum d^2 = 64,
        # rho = 1 - 6*64/(6*35) = -0.8286.
        tracking = [5.0, 6.0, 3.0, 4.0, 1.0, 2.0]
        for index, (job, _, _) in enumerate(database.jobs()):
            database.connection.execute("DELETE FROM metrics WHERE job_id = ?", (job,))
            database.set_metric(job, "ff_fb_ratio_avg", 1, 0.1 * (index + 1))
            database.set_metric(job, "id_nmse", 1, 1.0 / (index + 1))
            database.set_metric(job, "tracking_nmse", None, tracking[index])
        database.commit()
        code, out, err = run_tool("ff_fb_indicator.py", database.path, "--resamples", "400")
        self.assertEqual(code, 0, err)
        rows = [line.split("|") for line in out.splitlines() if line.startswith("| ff/fb") or line.startswith("| mean")]
        self.assertEqual(len(rows), 2, out)
        self.assertEqual(rows[0][2].strip(), "6")
        self.assertEqual(rows[0][3].strip(), "-1.000")
        self.assertEqual(rows[0][4].strip(), "[-1.000, -1.000]")
        self.assertEqual(rows[0][5].strip(), "holds")
        self.assertEqual(rows[1][3].strip(), "-0.829")
        low, high = (float(x) for x in rows[1][4].strip(" []").split(","))
        self.assertLessEqual(low, -0.829)
        self.assertGreaterEqual(high, -0.829)

    def test_ik_noise_verdicts_on_constructed_cases(self):
        database = GeneratedDatabase(self.directory, "ik", {"grid": {"trajectory.amplitude": [0.0, 1.0, 2.0, 3.0]}, "repeat": 3})
        # Table 6.1: joints 1, 5, 6 at 0.433, 0.401, 0.496; 2-4 at 0.890, 0.834, 0.749.
        exact = [0.80, 0.97, 0.98, 0.97, 0.95, 0.90]
        cases = {
            0.0: exact,
            1.0: [0.43, 0.97, 0.98, 0.97, 0.70, 0.70],  # all three fall toward the thesis, the gap widens
            2.0: [0.60, 0.97, 0.98, 0.97, 0.99, 0.99],  # joint 1 falls, 5 and 6 rise away: partly
            3.0: [0.95, 0.90, 0.90, 0.90, 0.99, 0.99],  # all rise away, the gap narrows: does not move
        }
        for job, seed, params in database.jobs():
            database.connection.execute("DELETE FROM metrics WHERE job_id = ?", (job,))
            for joint, value in enumerate(cases[params["trajectory.amplitude"]], start=1):
                database.set_metric(job, "ff_fb_ratio_avg", joint, value + 0.001 * (seed - 1) * (3 if joint == 1 else 0.5))
        database.commit()
        code, out, err = run_tool("ik_noise_verdict.py", database.path, "--sweep", "ik", "--param", "trajectory.amplitude")
        self.assertEqual(code, 0, err)
        verdicts = [line for line in out.splitlines() if line.startswith("ik_noise")]
        self.assertEqual(len(verdicts), 3, out)
        self.assertIn("1000 mrad (3 paired seeds): **moves toward** — joints moving toward table 6.1: 1, 5, 6", verdicts[0])
        self.assertIn("gap widens: yes; reaching the thesis's ratio: 1.", verdicts[0])  # 0.43 [0.4225, 0.4375] holds 0.433344
        self.assertIn("**moves toward, partly** — joints moving toward table 6.1: 1 of", verdicts[1])
        self.assertIn("**does not move toward** — joints moving toward table 6.1: none", verdicts[2])
        self.assertIn("gap widens: no", verdicts[2])

    def test_interference_verdict_pairs_before_and_after_by_seed(self):
        database = GeneratedDatabase(self.directory, "interference", {"repeat": 6})
        # Seeds 0-2 score A before B (train_a's model), seeds 3-5 stand for the after jobs of
        # seeds 0-2 (train_b's model). Ratios 1.05, 1.05, 1.2: seed 2 is 20 % worse, so the rule
        # (at most 10 % worse in every seed) does not hold; mean 1.1.
        before, after = [0.1, 0.2, 0.3], [0.105, 0.21, 0.36]
        for index, (job, _, _) in enumerate(database.jobs()):
            seed, stage = index % 3, ("train_a" if index < 3 else "train_b")
            database.connection.execute("UPDATE jobs SET seed = ? WHERE id = ?", (seed, job))
            database.set_params(job, {"seed": seed, "learning.initial_model": {"sweep": "interference." + stage, "params": {"seed": seed}}})
            database.set_metric(job, "heldout_test_nmse", None, (before if index < 3 else after)[seed])
        database.commit()
        code, out, err = run_tool("interference_verdict.py", database.path, "--sweep", "interference")
        self.assertEqual(code, 0, err)
        self.assertIn("| after / before | 1.050 | 1.050 | 1.200 |", out)
        self.assertIn("mean 1.100", out)
        self.assertIn("**does not hold** (seeds 2 above)", out)
        code, out, err = run_tool("interference_verdict.py", database.path, "--sweep", "interference", "--tolerance", "0.25")
        self.assertEqual(code, 0, err)
        self.assertIn("**holds**.", out)

    def test_realtime_verdict_per_number_of_joints(self):
        database = GeneratedDatabase(self.directory, "realtime", {"repeat": 4})
        # 1 joint: 2.0 and 1.5 simulated seconds per wall second, both >= 1: holds; mean 1.75,
        # s = 0.35355, half width 12.706 * 0.35355 / sqrt(2) = 3.177: [-1.43, 4.93]. 2 joints: 1.2
        # and 0.9, one below real time: does not hold.
        speeds = {1: [2.0, 1.5], 2: [1.2, 0.9]}
        for index, (job, _, _) in enumerate(database.jobs()):
            joints, seed = 1 + index // 2, index % 2
            database.connection.execute("UPDATE jobs SET seed = ? WHERE id = ?", (seed, job))
            database.set_params(job, {"active_joints": list(range(1, joints + 1)), "learning.lwpr.init_D": 0.05, "seed": seed})
            database.set_metric(job, "sim_seconds_per_wall_second", None, speeds[joints][seed])
            database.set_metric(job, "learner_us_per_update", None, 10.0 * joints)
            database.set_metric(job, "n_receptive_fields", None, 3.0 * joints)
        database.commit()
        code, out, err = run_tool("realtime_verdict.py", database.path, "--sweep", "realtime")
        self.assertEqual(code, 0, err)
        self.assertIn("| 1 | 3 [3, 3] (2) | 10 [10, 10] (2) | 1.75 [-1.43, 4.93] (2) | holds |", out)
        self.assertIn("| 2 | 6 [6, 6] (2) | 20 [20, 20] (2) | 1.05 [-0.856, 2.96] (2) | does not hold |", out)

    def write_thesis_file(self, sweep):
        path = os.path.join(self.directory, "thesis.json")
        document = {
            "format": "armfarm-thesis-results-1",
            "tables": [{
                "id": "table9_1", "number": "9.1", "caption": "Constructed table.", "page": None,
                "armfarm": {"sweep": sweep},
                "columns": [{"label": "nMSE", "armfarm": {"metric": "tracking_nmse"}},
                            {"label": "test", "armfarm": {"metric": "same_run_test_nmse"}}],
                "rows": [{"label": "Joint 1", "armfarm": {"active_joint": 1}}, {"label": "Joint 2", "armfarm": {"active_joint": 2}},
                         {"label": "All", "armfarm": {}}],
                "cells": [{"row": "Joint 1", "column": "nMSE", "value": 3, "printed": "3"},
                          {"row": "Joint 2", "column": "nMSE", "value": 10, "printed": "10"},
                          {"row": "All", "column": "test", "value": 5, "printed": "5"}]}],
            "comparisons": [{"claim": "constructed: joint 2 above joint 1",
                             "greater": {"table": "table9_1", "row": "Joint 2", "column": "nMSE"},
                             "less": {"table": "table9_1", "row": "Joint 1", "column": "nMSE"}}],
        }
        with open(path, "w") as out:
            json.dump(document, out)
        return path

    def test_tables_and_sentences_carry_the_three_verdicts(self):
        database = GeneratedDatabase(self.directory, "generated", {"repeat": 3})
        # Joint 1: 1, 2, 3 -> 2 [-0.4841, 4.484] (3), thesis 3 inside: matches.
        # Joint 2: 5, 6, 7 -> 6 [3.516, 8.484] (3), thesis 10 outside, above joint 1 in every seed: same direction.
        # All: 0.9, 1.0, 1.1 -> 1 [0.7516, 1.248] (3), thesis 5 outside, no comparison: differs.
        for job, seed, _ in database.jobs():
            database.set_metric(job, "tracking_nmse", 1, 1.0 + seed)
            database.set_metric(job, "tracking_nmse", 2, 5.0 + seed)
            database.set_metric(job, "same_run_test_nmse", None, 0.9 + 0.1 * seed)
        database.commit()
        thesis = self.write_thesis_file("generated")
        times = os.path.join(self.directory, "times.txt")
        with open(times, "w") as out:
            out.write("spec=generated rc=0 wall=0:01.00 user_s=1.50 sys_s=0.25 load_start=2.00 load_end=3.00\n"
                      "spec=other rc=0 user_s=9 sys_s=9 load_start=9 load_end=9\n"
                      "spec=generated rc=0 wall=0:01.00 user_s=0.75 sys_s=0.50 load_start=4.50 load_end=1.50\n")
        code, out, err = run_tool("thesis_tables.py", "--armfarm", ARMFARM, "--thesis", thesis, "--times", times, database.path)
        self.assertEqual(code, 0, err)
        self.assertIn("| Joint 1 | nMSE | 3 | 2 [-0.4841, 4.484] (3) | matches |", out)
        self.assertRegex(out, r"\| Joint 2 \| nMSE \| 10 \| 6 \[3\.516, 8\.484\] \(3\) \| same direction \(.*3 of 3 seeds.*\) \|")
        self.assertIn("| All | test | 5 | 1 [0.7516, 1.248] (3) | differs |", out)
        # Two runs in the log: CPU 1.5 + 0.25 + 0.75 + 0.5 = 3 s, loads 1.5 to 4.5.
        self.assertRegex(out, r"\| `generated` \| 3 / 3 \| 3 \| 0 min \d\d s \| 0 min 03 s \(2 runs\) \| 1\.5–4\.5 \|")
        self.assertIn("holds on 2 of 3 compared cells (1 matches, 1 same direction); does not hold on All test.", out)
        self.assertIn("1 matches, 1 same direction, 1 differs, 0 one seed, 0 not compared.", out)

    def test_readme_section_is_replaced_between_the_markers_only(self):
        database = GeneratedDatabase(self.directory, "generated", {"repeat": 2})
        database.commit()
        thesis = self.write_thesis_file("generated")
        readme = os.path.join(self.directory, "README.md")
        with open(readme, "w") as out:
            out.write("before\n<!-- thesis_tables.py: begin -->\nold\n<!-- thesis_tables.py: end -->\nafter\n")
        code, _, err = run_tool("thesis_tables.py", "--armfarm", ARMFARM, "--thesis", thesis, "--readme", readme, database.path)
        self.assertEqual(code, 0, err)
        with open(readme) as handle:
            text = handle.read()
        self.assertTrue(text.startswith("before\n<!-- thesis_tables.py: begin -->\n"))
        self.assertTrue(text.endswith("<!-- thesis_tables.py: end -->\nafter\n"))
        self.assertNotIn("\nold\n", text)
        self.assertIn("| Joint 1 | nMSE | 3 |", text)
        # Without the markers: exit 2, one line naming the file, the file untouched.
        with open(readme, "w") as out:
            out.write("no markers\n")
        code, _, err = run_tool("thesis_tables.py", "--armfarm", ARMFARM, "--thesis", thesis, "--readme", readme, database.path)
        self.assertEqual(code, 2)
        self.assertEqual(len(err.strip().splitlines()), 1)
        self.assertIn(readme, err)
        with open(readme) as handle:
            self.assertEqual(handle.read(), "no markers\n")


class HoldsSentences(unittest.TestCase):
    def test_sentence_counts_and_names_the_differing_cells(self):
        table = {"id": "table6_9", "number": "6.9", "sweeps": ["s"], "cells": [
            {"row": "Joint 1", "column": "a", "printed": "1", "state": "compared", "mean": 1.0, "ci95": [0.5, 1.5], "n": 5, "verdict": "matches"},
            {"row": "Joint 2", "column": "a", "printed": "2", "state": "compared", "mean": 3.0, "ci95": [2.5, 3.5], "n": 5, "verdict": "same direction"},
            {"row": "Joint 3", "column": "a", "printed": "3", "state": "compared", "mean": 9.0, "ci95": [8.0, 10.0], "n": 4, "verdict": "differs"},
            {"row": "Joint 4", "column": "a", "printed": "4", "state": "not_run", "n": 0, "verdict": None}]}
        text = holds_sentences.sentence(table)
        self.assertEqual(text, "**Table 6.9** (s, n = 4–5 seeds): holds on 2 of 3 compared cells (1 matches, 1 same direction); "
                               "does not hold on Joint 3 a: thesis 3, armfarm 9 [8, 10] (4). Not judged: 0 cells of one seed, "
                               "1 not run or without a metric.")
        self.assertIn("; does not hold on Joint 3 a. Not judged", holds_sentences.sentence(table, numbers=False))


if __name__ == "__main__":
    unittest.main(verbosity=2)
