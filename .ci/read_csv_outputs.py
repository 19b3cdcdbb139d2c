#!/usr/bin/env python3
"""Every CSV output kind of helixreach reads with the defaults users type.

Runs the binary given as the first argument to write one output of each kind into a temporary
directory, then reads every CSV there with `pandas.read_csv(f)` (defaults) and
`numpy.genfromtxt(f, names=True, delimiter=',')`: both must see the header row as the column
names and every data row as a row. Sweep outputs must have their settings record `F.meta.json`
beside them, naming the same columns with units.
"""

import csv
import json
import os
import subprocess
import sys
import tempfile

import numpy
import pandas


def run(binary, *args):
    subprocess.run([binary, *args], check=True, stdout=subprocess.DEVNULL)


def write_outputs(binary, d):
    p = lambda name: os.path.join(d, name)
    run(binary, "boundary", "--fibonacci", "20", "--out", p("boundary.csv"))
    for i in range(2):
        run(binary, "boundary", "--fibonacci", "20", "--shard", f"{i}/2", "--out", p(f"shard{i}.csv"))
    run(binary, "merge", "--out", p("merged.csv"), p("shard0.csv"), p("shard1.csv"))
    run(binary, "boundary", "--fibonacci", "20", "--speed-report", p("speed_error.csv"))
    run(binary, "reach", "--rig", "sawyer-seed", "--fibonacci", "2", "--quarter", "--out", p("reach.csv"))
    run(binary, "bifurcation", "--fibonacci", "2", "--n-edges", "20", "--out", p("bifurcation.csv"))
    run(binary, "layout", "--rig", "sawyer-seed", "--fibonacci", "2", "--quarter",
        "--region", "0.70:0.90,-0.35:0.05,-0.145:-0.145", "--spacing", "0.2",
        "--placements", "1", "--out", p("layout"))
    run(binary, "plan", "--direction", "0.6,0.8,0", "--waypoints", "20", "--allow-partial", "--out", p("trajectory.csv"))
    run(binary, "simulate", "--direction", "1,0,0", "--s-max", "0.3", "--out", p("series.csv"))
    with open(p("measured.csv"), "w") as f:
        f.write("dir_kappa,dir_tau,dir_omega,s_measured\n1,0,0,6.3\n0.6,0.8,0,7.1\n")
    run(binary, "compare", "--measured", p("measured.csv"), "--method", "continuum",
        "--out", p("compare.csv"))
    run(binary, "check", "--trajectory", p("trajectory.csv"), "--report-only", "--out", p("check.csv"))


def check(path):
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    header, body = rows[0], rows[1:]
    assert header and not header[0].startswith("#"), f"{path}: first line is not a header"
    df = pandas.read_csv(path)
    assert list(df.columns) == header, f"{path}: pandas columns {list(df.columns)} != {header}"
    assert len(df) == len(body), f"{path}: pandas read {len(df)} rows, the file has {len(body)}"
    a = numpy.atleast_1d(numpy.genfromtxt(path, names=True, delimiter=",", dtype=None, encoding="utf-8"))
    assert list(a.dtype.names) == header, f"{path}: numpy names {a.dtype.names} != {header}"
    assert len(a) == len(body), f"{path}: numpy read {len(a)} rows, the file has {len(body)}"
    meta = path + ".meta.json"
    if os.path.exists(meta):
        with open(meta) as f:
            m = json.load(f)
        if m.get("format") == "helixreach trajectory":
            # A trajectory's sidecar: its points are the file's rows.
            assert m["points"] == len(body), f"{meta}: {m['points']} points, the file has {len(body)} rows"
        else:
            assert m["columns"] == header, f"{meta}: columns {m['columns']} != {header}"
            assert [c["name"] for c in m["column_units"]] == header, f"{meta}: units do not name the columns"
    return len(body)


def main():
    binary = os.path.abspath(sys.argv[1])
    with tempfile.TemporaryDirectory() as d:
        write_outputs(binary, d)
        files = sorted(
            os.path.join(root, n) for root, _, names in os.walk(d) for n in names if n.endswith(".csv")
        )
        sweeps = ["boundary.csv", "merged.csv", "reach.csv", "bifurcation.csv", os.path.join("layout", "rays.csv")]
        for s in sweeps:
            assert os.path.exists(os.path.join(d, s + ".meta.json")), f"{s}: no settings record"
        for f in files:
            n = check(f)
            print(f"read {os.path.relpath(f, d)}: {n} rows (pandas, numpy)")


if __name__ == "__main__":
    main()
