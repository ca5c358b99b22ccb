#!/usr/bin/env python3
"""A CARMEN log driven N times over: a robot that keeps driving the same building.

    bench/repeat_log.py LOG.clf[.gz] N OUT.clf[.gz] [--restart-odometry]
                        [--relations R.relations OUT_PREFIX]

Pass p (0-based) is the log again with every timestamp shifted by p * (duration + 1 s) and
its odometry re-based so that it continues from where pass p-1's odometry ended:
    O'_p(t) = E_{p-1} (+) (O(t_0)^-1 (+) O(t))
with E_{p-1} the last odometry pose of pass p-1 (pass 0 is the log itself) and O(t_0) the
first. The robot is taken to start each pass where the log starts; the log's own offset
between its end and its start (Intel: 0.28 m, 0.3 deg by the loop-closed trajectory) is what
the odometry gets wrong at each seam, as a real robot's would.

With --restart-odometry the odometry is not re-based: every pass reads O'_p(t) = O(t), so at
each seam it jumps back from the log's last odometry pose to its first (Intel: by 62 m and
146 deg), as a robot's odometry does when it is rebooted where the log starts.

With --relations, the log's relations (`t1 t2 x y z roll pitch yaw`, Kuemmerle et al. 2009)
are written once per pass, times shifted as the log's: OUT_PREFIX.pass<p+1>.relations, so each
pass of the repeated run is scored against the same ground truth.

Lines handled: ODOM (x y theta), FLASER/RLASER (laser pose and robot pose), each with
`timestamp hostname logger_timestamp` at the end. Comment (#) and PARAM lines are written once;
any other message type is refused with its line number, since its poses or times would be
left behind.
"""
import argparse
import gzip
import math
import sys


def open_text(path, mode):
    return gzip.open(path, mode + "t") if path.endswith(".gz") else open(path, mode)


def compose(a, b):
    c, s = math.cos(a[2]), math.sin(a[2])
    return (a[0] + c * b[0] - s * b[1], a[1] + s * b[0] + c * b[1],
            math.atan2(math.sin(a[2] + b[2]), math.cos(a[2] + b[2])))


def inverse(a):
    c, s = math.cos(a[2]), math.sin(a[2])
    return (-c * a[0] - s * a[1], s * a[0] - c * a[1], -a[2])


def pose_fields(fields):
    """Indices of the (x, y, theta) triples in a message, and of its two timestamps."""
    kind = fields[0]
    if kind == "ODOM":
        return [1], [len(fields) - 3, len(fields) - 1]
    if kind in ("FLASER", "RLASER"):
        n = int(fields[1])
        return [2 + n, 5 + n], [len(fields) - 3, len(fields) - 1]
    return None, None


def write_relations(relations, n_passes, period, prefix):
    """One relations file per pass, t1 and t2 shifted by p * period [s]."""
    try:
        with open(relations) as f:
            rows = [l.split() for l in f if l.strip() and not l.startswith("#")]
    except OSError as e:
        sys.exit(f"repeat_log: {relations}: cannot read the relations ({e.strerror})")
    for number, row in enumerate(rows, 1):
        if len(row) != 8:
            sys.exit(f"repeat_log: {relations}:{number}: {len(row)} fields, expected 8 "
                     "(t1 t2 x y z roll pitch yaw)")
    for p in range(n_passes):
        with open(f"{prefix}.pass{p + 1}.relations", "w") as f:
            for row in rows:
                t1, t2 = float(row[0]) + p * period, float(row[1]) + p * period
                f.write(" ".join([f"{t1:.6f}", f"{t2:.6f}"] + row[2:]) + "\n")


def parse_args(argv):
    ap = argparse.ArgumentParser(prog="bench/repeat_log.py",
                                 description="A CARMEN log driven N times over.")
    ap.add_argument("log", help="LOG.clf[.gz]")
    ap.add_argument("passes", type=int, help="N, the number of passes (>= 1)")
    ap.add_argument("out", help="OUT.clf[.gz]")
    ap.add_argument("--restart-odometry", action="store_true",
                    help="each pass's odometry starts again at the log's first pose")
    ap.add_argument("--relations", nargs=2, metavar=("R.relations", "OUT_PREFIX"),
                    help="write the relations once per pass: OUT_PREFIX.pass<p>.relations")
    a = ap.parse_args(argv[1:])
    if a.passes < 1:
        sys.exit(f"repeat_log: N = {a.passes} must be >= 1")
    return a


def main(argv):
    a = parse_args(argv)
    src, n_passes, out = a.log, a.passes, a.out
    with open_text(src, "r") as f:
        lines = f.read().splitlines()
    times, first_odom, last_odom = [], None, None
    for number, line in enumerate(lines, 1):
        fields = line.split()
        if not fields or fields[0].startswith("#") or fields[0] == "PARAM":
            continue
        poses, stamps = pose_fields(fields)
        if poses is None:
            sys.exit(f"repeat_log: {src}:{number}: message type {fields[0]} not handled")
        times.append(float(fields[stamps[0]]))
        robot = poses[-1]
        odom = tuple(float(v) for v in fields[robot:robot + 3])
        first_odom = first_odom or odom
        last_odom = odom
    if not times:
        sys.exit(f"repeat_log: {src}: no ODOM, FLASER or RLASER line")
    period = max(times) - min(times) + 1.0
    if a.relations:
        write_relations(a.relations[0], n_passes, period, a.relations[1])
    start_inv = inverse(first_odom)
    with open_text(out, "w") as f:
        end = first_odom  # pass 0 starts where the log does
        for p in range(n_passes):
            base = compose(end, start_inv)  # E_{p-1} (+) O(t_0)^-1
            for line in lines:
                fields = line.split()
                if not fields or fields[0].startswith("#") or fields[0] == "PARAM":
                    if p == 0:
                        f.write(line + "\n")
                    continue
                poses, stamps = pose_fields(fields)
                for i in poses:
                    q = compose(base, tuple(float(v) for v in fields[i:i + 3]))
                    fields[i:i + 3] = [f"{q[0]:.6f}", f"{q[1]:.6f}", f"{q[2]:.6f}"]
                for i in stamps:
                    fields[i] = f"{float(fields[i]) + p * period:.6f}"
                f.write(" ".join(fields) + "\n")
            end = first_odom if a.restart_odometry else compose(base, last_odom)


if __name__ == "__main__":
    main(sys.argv)
