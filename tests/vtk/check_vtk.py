"""Reads millwear's ParaView files back with meshio (a VTK XML reader independent of
millwear) and checks the counts and fields against the run's own CSV files.

usage: check_vtk.py CHARGE_OUT RUN_OUT DESIGN
  CHARGE_OUT  a `millwear charge --vtk` folder (vtk/NAME.pvd, snapshot_NAME.csv, liner_work.csv)
  RUN_OUT     a `millwear run --vtk` folder (vtk/DESIGN_stageK.pvd, snapshot_DESIGN.csv, ...)
"""
import csv
import json
import math
import os
import sys
import xml.etree.ElementTree as ET

import meshio

PARTICLE_FIELDS = {"id": 1, "radius_m": 1, "species": 1, "velocity_m_per_s": 3, "speed_m_per_s": 1,
                   "spin_rad_per_s": 1}
LINER_FIELDS = {"shear_power_W_per_m2", "impact_power_W_per_m2", "wear_rate_mm_per_1000h", "lifter"}
failures = []


def check(cond, what):
    if not cond:
        failures.append(what)


def rows(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def series(pvd):
    """(time, part, path) of every DataSet of a .pvd, in file order."""
    root = ET.parse(pvd).getroot()
    check(root.get("type") == "Collection", pvd + ": not a Collection")
    base = os.path.dirname(pvd)
    return [(float(d.get("timestep")), int(d.get("part")), os.path.join(base, d.get("file")))
            for d in root.iter("DataSet")]


def check_particles(path):
    m = meshio.read(path)
    n = len(m.points)
    check(n > 0, path + ": no particles")
    check(len(m.cells) == 1 and m.cells[0].type == "vertex" and len(m.cells[0].data) == n,
          path + ": expected one vertex per particle")
    for name, comps in PARTICLE_FIELDS.items():
        check(name in m.point_data, path + ": no point array " + name)
        if name in m.point_data:
            a = m.point_data[name]
            check(len(a) == n, path + ": " + name + " has %d values for %d points" % (len(a), n))
            check((a.shape[1] if a.ndim > 1 else 1) == comps, path + ": " + name + " components")
    v, s = m.point_data["velocity_m_per_s"], m.point_data["speed_m_per_s"]
    check(all(abs(math.hypot(v[i][0], v[i][1]) - s[i]) <= 1e-6 * (1 + s[i]) for i in range(n)),
          path + ": speed is not |velocity|")
    check(all(abs(p[2]) == 0.0 for p in m.points), path + ": a 2D slice lies in z = 0")
    return m


def check_liner(path, edges=None):
    m = meshio.read(path)
    check(len(m.cells) == 1 and m.cells[0].type == "line", path + ": expected line cells")
    nc = len(m.cells[0].data)
    check(nc == len(m.points), path + ": a closed liner has as many edges as vertices")
    if edges is not None:
        check(nc == edges, path + ": %d edges, the run's liner file has %d" % (nc, edges))
    for name in LINER_FIELDS:
        check(name in m.cell_data and len(m.cell_data[name][0]) == nc, path + ": no cell array " + name)
    check(min(m.cell_data["shear_power_W_per_m2"][0]) >= 0.0, path + ": negative shear power")
    check(max(m.cell_data["wear_rate_mm_per_1000h"][0]) > 0.0, path + ": the liner does not wear")
    return m


def check_series(pvd, frames):
    s = series(pvd)
    parts = [p for _, p, _ in s]
    check(parts.count(0) == frames and parts.count(1) == frames,
          pvd + ": %d particle and %d liner files, expected %d each" % (parts.count(0), parts.count(1), frames))
    times = [t for t, p, _ in s if p == 0]
    check(all(b > a for a, b in zip(times, times[1:])), pvd + ": times not increasing")
    check(all(os.path.isfile(f) for _, _, f in s), pvd + ": a listed file is missing")
    return s


def main(charge_out, run_out, design):
    # `millwear charge --vtk`: 8 frames over the window, the last one the snapshot.
    name = os.path.splitext([f for f in os.listdir(os.path.join(charge_out, "vtk")) if f.endswith(".pvd")][0])[0]
    s = check_series(os.path.join(charge_out, "vtk", name + ".pvd"), 8)
    last_p = [f for t, p, f in s if p == 0][-1]
    m = check_particles(last_p)
    snap = rows(os.path.join(charge_out, "snapshot_%s.csv" % name))
    check(len(m.points) == len(snap), "charge: %d particles, snapshot.csv has %d" % (len(m.points), len(snap)))
    check(all(abs(float(r["x_m"]) - p[0]) < 1e-6 and abs(float(r["radius_m"]) - rad) < 1e-9
              for r, p, rad in zip(snap, m.points, m.point_data["radius_m"])),
          "charge: the last frame is not the snapshot")
    liner = rows(os.path.join(charge_out, "liner_work.csv"))
    lm = check_liner([f for t, p, f in s if p == 1][-1], len(liner))
    shear = lm.cell_data["shear_power_W_per_m2"][0]
    check(all(abs(float(r["shear_work_W_per_m2"]) - shear[i]) <= 1e-6 * (1 + shear[i]) for i, r in enumerate(liner)),
          "charge: shear power differs from liner_work.csv")
    for f in [f for _, p, f in s if p == 0]:
        check_particles(f)

    # `millwear run --vtk`: one series per finished stage, 4 frames each.
    manifest = json.load(open(os.path.join(run_out, "manifest.json")))
    d = manifest["designs"][0]
    check(d["set"] == ["wear.stages=1", "outputs.vtk_frames=4", "outputs.vtk=true"], "run: manifest set " + str(d["set"]))
    stages = [st["stage"] for st in d["stages"]]
    check(stages == [0, 1], "run: stages " + str(stages))
    for k in stages:
        pvd = os.path.join(run_out, "vtk", "%s_stage%d.pvd" % (design, k))
        s = check_series(pvd, 4)
        check(all(os.path.relpath(f, run_out) in manifest["files"] for _, _, f in s), pvd + ": files not in the manifest")
        for f in [f for _, p, f in s if p == 0]:
            check_particles(f)
    # The latest stage's last frame is the run's snapshot; its liner is the run's liner file.
    pm = check_particles([f for t, p, f in s if p == 0][-1])
    snap = rows(os.path.join(run_out, "snapshot_%s.csv" % design))
    check(len(pm.points) == len(snap), "run: %d particles, snapshot has %d" % (len(pm.points), len(snap)))
    liner = rows(os.path.join(run_out, "liner_%s.csv" % design))
    lm = check_liner([f for t, p, f in s if p == 1][-1], len(liner))
    wear = lm.cell_data["wear_rate_mm_per_1000h"][0]
    check(all(abs(float(r["wear_rate_mm_per_1000h"]) - wear[i]) <= 1e-6 * (1 + abs(wear[i]))
              for i, r in enumerate(liner)), "run: wear rate differs from the liner file")
    check(all(abs(float(r["x1_m"]) - lm.points[i][0]) < 1e-6 for i, r in enumerate(liner)),
          "run: the liner is not where the liner file has it")

    for f in failures:
        print("FAIL:", f)
    print("checked %s and %s: %s" % (charge_out, run_out, "ok" if not failures else "%d failures" % len(failures)))
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main(*sys.argv[1:4]))
