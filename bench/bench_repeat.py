"""Intel driven four times over, for bench/run (issue 12): does each pass cost as much as the
first, and does memory grow with the area mapped or with the time driven?

The log is made by bench/repeat_log.py (timestamps shifted, odometry continued; or, with
restart_odometry, restarting at the log's first pose on every pass, as after a reboot of the
base: issue 29). lrgc-slam maps it once, with the defaults; per pass, from timing.csv: the mapping time (sum of the per-scan
latencies, loop-closing waits included, [s]), the p99 and max latency [ms]; and the
keyframes each pass added (graph.lrgc's NODE lines, found in trajectory.tum by their poses).
Peak RSS is of the whole run.

Python standard library only.
"""

import math
import os
import subprocess
import sys
import types

import bench_runs

HERE = os.path.dirname(os.path.abspath(__file__))
HEADER = ["pass", "scans", "mapping time [s]", "× pass 1", "p99 / max latency [ms]",
          "keyframes added", "relation error [m]"]


def relations_prefix(out_path):
    """repeat_log.py writes pass p's relations to <prefix>.pass<p>.relations."""
    return os.path.splitext(out_path)[0]


def make_log(log_path, passes, out_path, relations=None, restart_odometry=False):
    cmd = [sys.executable, os.path.join(HERE, "repeat_log.py"), log_path, str(passes), out_path]
    if restart_odometry:
        cmd.append("--restart-odometry")
    if relations:
        cmd += ["--relations", relations, relations_prefix(out_path)]
    subprocess.run(cmd, check=True)


def pass_error(tools, trajectory, relations, workdir, p):
    """bench_runs.run_eval of the whole run's trajectory against pass p's relations:
    "mean ± std" [m], or "?"."""
    run = types.SimpleNamespace(trajectory=trajectory, eval=None, error=None)
    passdir = os.path.join(workdir, "pass%d" % p)
    os.makedirs(passdir, exist_ok=True)
    bench_runs.run_eval(tools, run, passdir, relations=relations)
    t = ((run.eval or {}).get("relations") or {}).get("translational_m")
    return "%.4f ± %.4f" % (t["mean"], t["std"]) if t and run.error is None else "?"


def keyframe_rows(graph_lrgc, trajectory_tum):
    """Row index in trajectory.tum (one row per scan) of every keyframe, or None.

    graph.lrgc lists the keyframes (NODE i x y phi) in the order they were made, and a
    keyframe's row in trajectory.tum holds its pose (6 decimals), so one forward pass over the
    rows finds them all."""
    try:
        with open(graph_lrgc) as f:
            nodes = [l.split()[2:4] for l in f if l.startswith("NODE ")]
        with open(trajectory_tum) as f:
            rows = [l.split()[1:3] for l in f if l.strip() and not l.startswith("#")]
    except OSError:
        return None
    out, k = [], 0
    for x, y in nodes:
        key = ["%.6f" % float(x), "%.6f" % float(y)]
        j = k
        while j < len(rows) and rows[j] != key:
            j += 1
        if j == len(rows):
            # A keyframe whose scan the end of the run settled onto its neighbours' odometry
            # chain (stats.json scans_settled) is no longer exactly at its node's pose (a few
            # cm off): the first of the next rows within 0.1 m. Not a fixed number of rows:
            # where keyframes are reused (a second pass), thousands of scans pass between two
            # new keyframes.
            j = next((i for i in range(k, len(rows))
                      if math.hypot(float(rows[i][0]) - float(x),
                                    float(rows[i][1]) - float(y)) <= 0.1), None)
            if j is None:
                return None
        out.append(j)
        k = j + 1
    return out


def run(tools, log_path, workdir, timeout_s, passes=4, config=None, relations=None,
        restart_odometry=False):
    """Returns (rows, run result, notes). relations: the log's, for each pass's error;
    restart_odometry: each pass's odometry starts again at the log's first pose."""
    os.makedirs(workdir, exist_ok=True)
    repeated = os.path.join(workdir, "intel-x%d.clf.gz" % passes)
    make_log(log_path, passes, repeated, relations, restart_odometry)
    r = bench_runs.run_lrgc_slam(tools, repeated, os.path.join(workdir, "lrgc-slam"), timeout_s,
                                 config)
    if not r.ok:
        return [], r, ["intel x%d: %s" % (passes, r.error)]
    n = len(r.latencies_ms) // passes
    out = os.path.join(workdir, "lrgc-slam", "out")
    keyframes = keyframe_rows(os.path.join(out, "graph.lrgc"), r.trajectory)
    notes = [] if keyframes else ["intel x%d: keyframes per pass not found in graph.lrgc" % passes]
    rows, first = [], None
    for p in range(passes):
        end = (p + 1) * n if p + 1 < passes else len(r.latencies_ms)
        lat = r.latencies_ms[p * n:end]
        total_s = sum(lat) / 1000.0
        first = first or total_s
        _, p99, mx = bench_runs.latency_summary(lat)
        added = sum(1 for k in keyframes if p * n <= k < end) if keyframes else None
        err = pass_error(tools, r.trajectory, "%s.pass%d.relations" % (
            relations_prefix(repeated), p + 1), workdir, p + 1) if relations else "–"
        rows.append([str(p + 1), str(len(lat)), "%.1f" % total_s, "%.2f" % (total_s / first),
                     "%.1f / %.0f" % (p99, mx), "?" if added is None else str(added), err])
    return rows, r, notes
