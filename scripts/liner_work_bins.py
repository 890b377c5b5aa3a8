#!/usr/bin/env python3
"""Shear work along one lifter, from `millwear charge` outputs, averaged over seeds.

Each argument is a glob of charge output folders (one per seed) forming one group:
    scripts/liner_work_bins.py 'out/c200_s*' 'out/c1000_s*'
For each group it prints the total lifter and shell shear work (W per metre of mill
length, summed over the rows) and the shear work per lifter in bins of the unit's
surface coordinate (s_local_mm of liner_work.csv), mean +- standard error over the
folders. A bin whose error is a large part of its mean holds rare events (jams).
"""
import csv
import glob
import math
import sys

BIN_MM = 40.0


def load(folder):
    bins, total = {}, {"lifter": 0.0, "shell": 0.0}
    rows = set()
    with open(folder + "/liner_work.csv") as f:
        for r in csv.DictReader(f):
            length = math.hypot(float(r["x2_m"]) - float(r["x1_m"]),
                                float(r["y2_m"]) - float(r["y1_m"]))
            w = float(r["shear_work_W_per_m2"]) * length  # W per metre of mill length
            total[r["owner"]] += w
            if r["owner"] == "lifter":
                rows.add(r["owner_index"])
                b = BIN_MM * math.floor(float(r["s_local_mm"]) / BIN_MM)
                bins[b] = bins.get(b, 0.0) + w
    return {b: w / max(1, len(rows)) for b, w in bins.items()}, total


def mean_se(values):
    m = sum(values) / len(values)
    if len(values) < 2:
        return m, float("nan")
    var = sum((v - m) ** 2 for v in values) / (len(values) - 1)
    return m, math.sqrt(var / len(values))


def main(patterns):
    if not patterns:
        sys.exit(__doc__)
    for pattern in patterns:
        folders = sorted(glob.glob(pattern))
        if not folders:
            sys.exit(f"liner_work_bins: no folder matches {pattern}")
        data = [load(f) for f in folders]
        lifter = mean_se([t["lifter"] for _, t in data])
        shell = mean_se([t["shell"] for _, t in data])
        print(f"{pattern} ({len(folders)} runs): lifters {lifter[0]:.0f} +- {lifter[1]:.0f} W/m, "
              f"shell {shell[0]:.0f} +- {shell[1]:.0f} W/m")
        keys = sorted(set().union(*(b.keys() for b, _ in data)))
        cells = []
        for k in keys:
            m, se = mean_se([b.get(k, 0.0) for b, _ in data])
            cells.append(f"{k:.0f}:{m:.0f}+-{se:.0f}")
        print("  per lifter, W/m by s (mm): " + " ".join(cells))


if __name__ == "__main__":
    main(sys.argv[1:])
