#!/usr/bin/env python3
"""Makes the example inputs of this folder (see README.md). No file is a measurement.

  lab-mill-surveys.csv    SIMULATED surveys: the lifter profiles of a `millwear run` of
                          scenarios/lab-mill.toml (its own draft fidelity, C = 1e-10 m^3/J) at
                          0, 100 and 200 h, with Gaussian "measurement" noise (sd 0.1 mm in x
                          and y, seed 7) added.
  lab-mill-areas.csv      SYNTHETIC area-only surveys from the same run: the lifter area of its
                          OUT/summary.csv at 0 h (one row) and at 100 and 200 h (three rows each,
                          three lifters surveyed), each plus Gaussian noise of sd 2 mm^2 (seed 13).
  hardness-synthetic.csv  SYNTHETIC periods: wear rate = R0 * a * H^b with R0 = 20 mm^2/day,
                          b = 2.0, a = 14^-2 (CT = 1 at hardness 14), times exp(N(0, 0.02^2))
                          noise (seed 11); period lengths as in the paper's Fig. 1.

Usage: millwear run scenarios/lab-mill.toml -o out/lab-mill
       python3 validation/make_examples.py out/lab-mill
"""
import csv
import math
import random
import sys
from pathlib import Path

here = Path(__file__).resolve().parent


def surveys(run_dir: Path):
    rng = random.Random(7)
    rows = []
    for stage, hours in [(0, 0), (1, 100), (2, 200)]:
        with open(run_dir / "profiles" / f"lab-mill_stage{stage}.csv") as f:
            for r in csv.DictReader(f):
                x = float(r["x_mm"]) + rng.gauss(0.0, 0.1)
                y = float(r["y_mm"]) + rng.gauss(0.0, 0.1)
                rows.append(f"{hours},{x:.2f},{y:.2f}")
    text = (
        "# SIMULATED, NOT MEASURED: example surveys for `millwear validate` and `millwear calibrate`.\n"
        "# Made by validation/make_examples.py from `millwear run scenarios/lab-mill.toml` (draft fidelity,\n"
        "# wear_rate = 1e-10 m^3/J, bidirectional, 100 h stages): the lifter profiles at 0, 100 and 200 h\n"
        "# with Gaussian noise of sd 0.1 mm added to x and y (seed 7).\n"
        "# Format: hours,x_mm,y_mm; one block of rows per survey (lifter-local mm: x along the shell,\n"
        "# +x the leading face; y up from the original shell line), points in order along the profile.\n"
        "hours,x_mm,y_mm\n" + "\n".join(rows) + "\n")
    (here / "lab-mill-surveys.csv").write_text(text)


def areas(run_dir: Path):
    rng = random.Random(13)
    rows = []
    with open(run_dir / "summary.csv") as f:
        for r in csv.DictReader(f):
            if r["design"] != "lab-mill":
                continue
            hours, area = float(r["hours"]), float(r["area_mm2"])
            for _ in range(3 if hours > 0 else 1):
                rows.append(f"{hours:g},{area + rng.gauss(0.0, 2.0):.1f}")
    text = (
        "# SYNTHETIC, NOT MEASURED: example area-only surveys for `millwear validate` and `millwear calibrate`.\n"
        "# Made by validation/make_examples.py from the run that made lab-mill-surveys.csv (`millwear run\n"
        "# scenarios/lab-mill.toml`, draft fidelity, wear_rate = 1e-10 m^3/J, bidirectional, 100 h stages).\n"
        "# Model: every lifter wears like the simulated one; a survey measures its area with Gaussian error\n"
        "# of sd 2 mm^2 (0.5% of the 419 mm^2 new lifter), seed 13. One row at 0 h (the new lifter: the\n"
        "# reference of the area loss), three rows (three lifters) at each of 100 and 200 h.\n"
        "# Format: hours,area_mm2; one row per lifter surveyed; area = the lifter's metal cross-section\n"
        "# above the original shell line (as OUT/summary.csv reports it, on the mill's curved shell).\n"
        "hours,area_mm2\n" + "\n".join(rows) + "\n")
    (here / "lab-mill-areas.csv").write_text(text)


def hardness():
    rng = random.Random(11)
    r0, b = 20.0, 2.0
    a = 14.0 ** -b
    days = [54, 55, 29, 63, 20, 41, 36, 58]
    hard = [13.2, 15.8, 11.9, 16.9, 14.5, 12.6, 17.4, 14.0]
    rows = []
    for i, (t, h) in enumerate(zip(days, hard), 1):
        rate = r0 * a * h ** b * math.exp(rng.gauss(0.0, 0.02))
        rows.append(f"{i},{t},{rate * t:.1f},{h}")
    text = (
        "# SYNTHETIC, NOT MEASURED: example input for `millwear hardness`.\n"
        "# Model: area loss rate = R0 * CT, CT = a * H^b with R0 = 20 mm^2/day, b = 2.0 and\n"
        f"# a = 14^-2 = {a:.6g} (CT = 1 at hardness 14), times exp(N(0, 0.02^2)) noise (seed 11).\n"
        "# Periods 1-5 have the lengths of the paper's Fig. 1 (54, 55, 29, 63, 20 days); 6-8 are extra.\n"
        "# Recover a and b with: millwear hardness validation/hardness-synthetic.csv -o OUT --reference-hardness 14\n"
        "period,days,area_loss_mm2,hardness\n" + "\n".join(rows) + "\n")
    (here / "hardness-synthetic.csv").write_text(text)


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    surveys(Path(sys.argv[1]))
    areas(Path(sys.argv[1]))
    hardness()
