#!/usr/bin/env python3
"""The benchmark behind bench/run: lrgc-slam and MRPT's icp-slam on every log found, one
after the other, then the relation error (real logs) or the ATE/RPE (MRPT's synthetic logs
with exact ground truth), a table on stdout and in doc/benchmarks.md, and a plot per log.

Logs found: DATA_DIR/*/*.clf.gz, *.clf, *.log, *.rawlog, each with the `*.relations` file
beside it (same stem) when there is one; and MRPT's synthetic rawlogs with `*.GT.txt` in
/usr/share/mrpt/datasets/graphslam-engine-demos/action_observations_map/.
lrgc-slam reads each log as it is; icp-slam reads it converted to a rawlog by our converter
(`lrgc-slam --input LOG --save-rawlog OUT`), rawlogs included: icp-slam cannot read CARMEN
logs, and asserts on the synthetic rawlogs, whose odometry actions carry no timestamp.

Python standard library only.
"""

import argparse
import glob
import os
import shutil
import subprocess
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import bench_repeat  # noqa: E402
import bench_report  # noqa: E402
import bench_runs  # noqa: E402

SYNTHETIC_DIR = "/usr/share/mrpt/datasets/graphslam-engine-demos/action_observations_map"
LOG_PATTERNS = ("*.clf.gz", "*.clf", "*.log.gz", "*.log", "*.rawlog")


def strip_log_suffix(path):
    name = os.path.basename(path)
    for suffix in (".clf.gz", ".clf", ".log.gz", ".log", ".rawlog"):
        if name.endswith(suffix):
            return name[: -len(suffix)]
    return name


def find_real_logs(data_dir):
    """[(name, log path, relations path or None)], sorted by name."""
    logs = []
    if not data_dir or not os.path.isdir(data_dir):
        return logs
    seen = set()
    for pattern in LOG_PATTERNS:
        for path in sorted(glob.glob(os.path.join(data_dir, "*", pattern))):
            stem = strip_log_suffix(path)
            key = (os.path.dirname(path), stem)
            if key in seen:
                continue
            seen.add(key)
            rel = os.path.join(os.path.dirname(path), stem + ".relations")
            logs.append((stem, path, rel if os.path.exists(rel) else None))
    return sorted(logs)


def find_synthetic_logs(synthetic_dir):
    out = []
    for path in sorted(glob.glob(os.path.join(synthetic_dir, "*.rawlog"))):
        gt = path + ".GT.txt"
        if os.path.exists(gt):
            out.append((strip_log_suffix(path), path, gt))
    return out


def plot(tools, name, run, png, notes):
    """lrgc-plot of lrgc-slam's outputs; returns the PNG path or None."""
    if "lrgc-plot" not in tools or not run.ok:
        return None
    outdir = os.path.dirname(run.trajectory)
    cmd = [tools["lrgc-plot"], "--map", os.path.join(outdir, "map.yaml"),
           "--trajectory", run.trajectory, "--graph", os.path.join(outdir, "graph.lrgc"),
           "--timing", os.path.join(outdir, "timing.csv"), "--title", name + " (lrgc-slam)",
           "--out", png]
    proc = subprocess.run(cmd, stdin=subprocess.DEVNULL, capture_output=True, text=True)
    if proc.returncode != 0:
        notes.append("%s: lrgc-plot failed: %s" % (name, (proc.stderr or "").strip()[-300:]))
        return None
    return png


def run_log(tools, name, log_path, workdir, args, relations=None, ground_truth=None):
    """Both systems on one log; returns their RunResults and notes."""
    notes = []
    print("== %s: %s" % (name, log_path), flush=True)
    shutil.rmtree(workdir, ignore_errors=True)  # no stale outputs of an earlier run
    ours = bench_runs.run_lrgc_slam(tools, log_path, os.path.join(workdir, "lrgc-slam"),
                                    args.timeout, args.config)
    bench_runs.run_eval(tools, ours, os.path.join(workdir, "lrgc-slam"), relations, ground_truth)
    runs = [ours]
    if relations:
        # Local registration alone (issue #3): the same run with loop closing switched off.
        local_ini = os.path.join(workdir, "local-only.ini")
        os.makedirs(workdir, exist_ok=True)
        with open(local_ini, "w") as f:
            if args.config:
                with open(args.config) as base:
                    f.write(base.read() + "\n")
            f.write("[MapBuilder]\nloop_closing = false\n")
        local = bench_runs.run_lrgc_slam(tools, log_path, os.path.join(workdir, "local-only"),
                                         args.timeout, local_ini)
        local.system = "lrgc-slam, local registration only"
        bench_runs.run_eval(tools, local, os.path.join(workdir, "local-only"), relations)
        runs.append(local)
        sweep = args.sweep_times.get(name)
        if sweep is not None:
            # The same with this log's laser sweep time, as scripts/calibrate-sweep-time finds
            # it from the log itself (no ground truth).
            sweep_ini = os.path.join(workdir, "local-only-sweep.ini")
            with open(local_ini) as base, open(sweep_ini, "w") as f:
                f.write(base.read() + "scan_sweep_time_s = %g\n" % sweep)
            cal = bench_runs.run_lrgc_slam(tools, log_path, os.path.join(workdir, "local-sweep"),
                                           args.timeout, sweep_ini)
            cal.system = "lrgc-slam, local registration only, sweep %g s" % sweep
            notes.append("%s, local registration only, sweep %g s: [MapBuilder] scan_sweep_time_s = "
                         "%g, the laser sweep time scripts/calibrate-sweep-time finds from this "
                         "log without ground truth (bench/run --sweep-times)" % (name, sweep, sweep))
            bench_runs.run_eval(tools, cal, os.path.join(workdir, "local-sweep"), relations)
            runs.append(cal)
    icp = bench_runs.RunResult("icp-slam")
    rawlog = os.path.join(workdir, "converted", name + ".rawlog")
    os.makedirs(os.path.dirname(rawlog), exist_ok=True)
    err = bench_runs.convert_to_rawlog(tools, log_path, rawlog, args.timeout)
    if err:
        icp.error = "conversion to rawlog failed: " + err
    else:
        icp = bench_runs.run_icp_slam(rawlog, os.path.join(workdir, "icp-slam"), args.timeout)
        bench_runs.run_eval(tools, icp, os.path.join(workdir, "icp-slam"), relations,
                            ground_truth)
    runs.append(icp)
    for r in runs:
        if r.error:
            notes.append("%s, %s: %s" % (name, r.system, r.error))
        print("   %-9s %s" % (r.system, "ok, wall %.1f s" % r.wall_s if r.ok and r.wall_s
                                else "FAILED: %s" % r.error), flush=True)
    return runs, notes


def tool_paths(build_dir):
    tools = {}
    for name in ("lrgc-slam", "lrgc-eval", "lrgc-plot"):
        path = os.path.abspath(os.path.join(build_dir, "bin", name))
        if os.path.exists(path):
            tools[name] = path
    missing = [n for n in ("lrgc-slam", "lrgc-eval") if n not in tools]
    for n in ("icp-slam", "rawlog-edit"):
        if not shutil.which(n):
            missing.append(n + " (Debian mrpt-apps)")
    if not os.path.exists("/usr/bin/time"):
        missing.append("/usr/bin/time (Debian time)")
    return tools, missing


def run_repeats(tools, intel, args, doc_dir, notes, plots):
    """Intel driven four times over, the odometry continued and then restarting at each pass
    (bench_repeat.py): a list of (title, what the run is, header, rows, summary line)."""
    out = []
    log, relations = intel
    for restart, tag, title, what in (
            (False, "intel-x4", "Intel driven four times over",
             "timestamps shifted, odometry continued: a robot that keeps driving the same "
             "building"),
            (True, "intel-x4-restart", "Intel driven four times over, the odometry restarting",
             "timestamps shifted, each pass's odometry starting again at the log's first pose: "
             "a robot whose base is rebooted before each pass (`--restart-odometry`)")):
        print("== " + tag, flush=True)
        rows, r, n = bench_repeat.run(tools, log, os.path.join(args.work_dir, tag),
                                      4 * args.timeout, 4, args.config, relations=relations,
                                      restart_odometry=restart)
        notes += n
        if rows:
            out.append((title, what, bench_repeat.HEADER, rows,
                        "Whole run: wall %.1f s, peak RSS %.0f MB." % (r.wall_s, r.peak_rss_mb)))
        # Per-scan latency against scan index over the four passes: flat if the cost grows
        # with the area mapped, not with the time driven (issue 12).
        png = plot(tools, tag, r, os.path.join(doc_dir, "bench_%s.png" % tag), notes)
        if png:
            plots.append((tag, os.path.relpath(png, doc_dir)))
    return out


def main():
    repo = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("data_dir", nargs="?", help="folder with <name>/<log> and .relations")
    ap.add_argument("--build-dir", default=os.path.join(repo, "build"))
    ap.add_argument("--work-dir", default=os.path.join(repo, "out", "bench"),
                    help="per-run outputs (default out/bench)")
    ap.add_argument("--doc", default=os.path.join(repo, "doc", "benchmarks.md"))
    ap.add_argument("--config", help="lrgc-slam .ini for every run (default: built-in)")
    ap.add_argument("--timeout", type=int, default=600, help="per process [s]")
    ap.add_argument("--only", help="run only logs whose name contains this")
    ap.add_argument("--no-synthetic", action="store_true")
    ap.add_argument("--no-repeat", action="store_true",
                    help="skip Intel driven four times over (bench_repeat.py)")
    ap.add_argument("--sweep-times", default="",
                    help="NAME=SECONDS,...: also run local registration alone on log NAME with "
                         "[MapBuilder] scan_sweep_time_s SECONDS (scripts/calibrate-sweep-time)")
    args = ap.parse_args()
    try:
        args.sweep_times = {k: float(v) for k, v in
                            (item.split("=") for item in args.sweep_times.split(",") if item)}
    except ValueError:
        sys.exit("bench: --sweep-times wants NAME=SECONDS,... (got %r)" % args.sweep_times)
    if args.config:
        # lrgc-slam runs in other folders: a relative path must name the file from here.
        if not os.path.isfile(args.config):
            sys.exit("bench: --config %r: no such file" % args.config)
        args.config = os.path.abspath(args.config)

    t0 = time.monotonic()
    tools, missing = tool_paths(args.build_dir)
    if missing:
        sys.exit("bench: missing " + ", ".join(missing))
    real = find_real_logs(args.data_dir)
    synthetic = [] if args.no_synthetic else find_synthetic_logs(SYNTHETIC_DIR)
    if args.only:
        real = [l for l in real if args.only in l[0]]
        synthetic = [l for l in synthetic if args.only in l[0]]
    if not real and not synthetic:
        sys.exit("bench: no log found (data dir: %s)" % args.data_dir)
    readme = os.path.join(args.data_dir, "README.md") if args.data_dir else None
    published = bench_report.published_figures(readme)

    doc_dir = os.path.dirname(os.path.abspath(args.doc))
    os.makedirs(doc_dir, exist_ok=True)
    real_rows, syn_rows, gen_rows, plots, notes = [], [], [], [], []
    commit = bench_report.commit_description(repo)  # before anything is written
    for name, log, rel in real:
        runs, n = run_log(tools, name, log, os.path.join(args.work_dir, name), args,
                          relations=rel)
        notes += n
        if rel is None:
            notes.append("%s: no relations file beside the log: no relation error" % name)
        real_rows += bench_report.real_rows(name, runs, published)
        gen = bench_report.generalisation_row(name, runs, published)
        if gen:
            gen_rows.append(gen)
        png = plot(tools, name, runs[0], os.path.join(doc_dir, "bench_%s.png" % name), notes)
        if png:
            plots.append((name, os.path.relpath(png, doc_dir)))
    intel = [(log, rel) for name, log, rel in real if name == "intel"]
    repeat = run_repeats(tools, intel[0], args, doc_dir, notes, plots) \
        if intel and not args.no_repeat else []
    for name, log, gt in synthetic:
        runs, n = run_log(tools, name, log, os.path.join(args.work_dir, name), args,
                          ground_truth=gt)
        notes += n
        syn_rows += bench_report.synthetic_rows(name, runs)
        png = plot(tools, name, runs[0], os.path.join(doc_dir, "bench_%s.png" % name), notes)
        if png:
            plots.append((name, os.path.relpath(png, doc_dir)))

    total = time.monotonic() - t0
    machine = bench_report.machine_description()
    print()
    print("Measured on: " + machine)
    print("Commit: " + commit)
    if real_rows:
        print("\nReal logs (relation error, Kuemmerle et al. 2009):")
        bench_report.print_table(bench_report.REAL_HEADER, real_rows)
    for title, _, header, rows, summary in repeat:
        print("\n%s: %s" % (title, summary))
        bench_report.print_table(header, rows)
    if syn_rows:
        print("\nMRPT synthetic logs (exact ground truth):")
        bench_report.print_table(bench_report.SYN_HEADER, syn_rows)
    for n in notes:
        print("note: " + n)
    with open(args.doc, "w") as f:
        f.write(bench_report.document(real_rows, syn_rows, plots, machine, commit, total,
                                      args.data_dir, notes, repeat, gen_rows, args.config))
    print("\nwrote %s and %d plot(s); whole run %.0f s" % (args.doc, len(plots), total))
    return 0


if __name__ == "__main__":
    sys.exit(main())
