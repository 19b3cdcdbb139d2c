#!/usr/bin/env python3
"""Read a helixreach ROS 2 bag (MCAP) with independent readers and compare it with the plan's CSV.

Usage: check_bag.py BAG.mcap PLAN.csv

The container is read by the `mcap` package, every message is decoded by `rosbags`' own ROS 2
(Humble) type store (its CDR deserializer and message definitions, not the bag's schema text),
and the arm's and the motor's trajectories must equal the CSV columns to 1e-12 (times to the
nanosecond the message carries). Exits 1 naming the first mismatch.
"""
import csv
import json
import sys

from mcap.reader import make_reader
from rosbags.typesys import Stores, get_typestore

TOL = 1e-12


def fail(msg):
    print(f"check_bag: {msg}", file=sys.stderr)
    sys.exit(1)


def main():
    bag, plan = sys.argv[1], sys.argv[2]
    rows = list(csv.DictReader(open(plan, newline="")))
    if not rows:
        fail(f"{plan}: no rows")
    meta = json.load(open(plan + ".meta.json"))
    store = get_typestore(Stores.ROS2_HUMBLE)
    msgs = {}
    with open(bag, "rb") as f:
        reader = make_reader(f)
        header = reader.get_header()
        if header.profile != "ros2":
            fail(f"{bag}: profile {header.profile!r}, expected 'ros2'")
        for schema, channel, message in reader.iter_messages():
            if channel.message_encoding != "cdr":
                fail(f"{channel.topic}: encoding {channel.message_encoding}")
            msgs[channel.topic] = (schema.name, store.deserialize_cdr(message.data, schema.name))
    want = {
        "/helixreach/arm/joint_trajectory": "trajectory_msgs/msg/JointTrajectory",
        "/helixreach/rod_motor/joint_trajectory": "trajectory_msgs/msg/JointTrajectory",
        "/helixreach/trajectory_meta": "std_msgs/msg/String",
    }
    for topic, kind in want.items():
        if topic not in msgs or msgs[topic][0] != kind:
            fail(f"{bag}: topic {topic} of type {kind} missing (have {sorted(msgs)})")
    dof = len(meta["joint_names"])
    arm = msgs["/helixreach/arm/joint_trajectory"][1]
    motor = msgs["/helixreach/rod_motor/joint_trajectory"][1]
    if list(arm.joint_names) != meta["joint_names"]:
        fail(f"arm joint names {list(arm.joint_names)} != {meta['joint_names']}")
    if list(motor.joint_names) != [meta["motor_name"]]:
        fail(f"motor joint names {list(motor.joint_names)}")
    if arm.header.frame_id != meta["frame_id"]:
        fail(f"frame {arm.header.frame_id!r} != {meta['frame_id']!r}")
    annotation = json.loads(msgs["/helixreach/trajectory_meta"][1].data)
    if annotation != meta:
        fail("the annotation topic differs from the sidecar")
    if len(arm.points) != len(rows) or len(motor.points) != len(rows):
        fail(f"{len(arm.points)} arm / {len(motor.points)} motor points, CSV has {len(rows)} rows")
    worst = 0.0
    for k, row in enumerate(rows):
        # The CSV names its joint columns by the URDF joints (the earlier header: q0..).
        names = meta["joint_names"] if meta["joint_names"][0] in row else [f"q{j}" for j in range(dof)]
        cols = {
            "positions": list(names),
            "velocities": [f"v_{n}" for n in names],
            "accelerations": [f"a_{n}" for n in names],
        }
        for msg, names in ((arm, None), (motor, "motor")):
            p = msg.points[k]
            t = p.time_from_start.sec + p.time_from_start.nanosec * 1e-9
            if abs(t - float(row["t"])) > 0.5e-9 + 1e-15 * float(row["t"]):
                fail(f"point {k}: time {t} vs CSV {row['t']}")
            for field, arm_cols in cols.items():
                got = list(getattr(p, field))
                if names is None:
                    ref = [float(row[c]) for c in arm_cols]
                else:
                    prefix = {"positions": "", "velocities": "v_", "accelerations": "a_"}[field]
                    ref = [float(row[prefix + "motor"])]
                if len(got) != len(ref):
                    fail(f"point {k} {field}: {len(got)} values, expected {len(ref)}")
                for g, r in zip(got, ref):
                    d = abs(g - r)
                    worst = max(worst, d)
                    if d > TOL:
                        fail(f"point {k} {field}: {g!r} vs CSV {r!r}")
            if len(p.effort) != 0:
                fail(f"point {k}: effort not empty")
    print(f"check_bag: {bag}: {len(rows)} points on 2 trajectory topics + annotation, "
          f"largest difference from the CSV {worst:.3g}")


if __name__ == "__main__":
    main()
