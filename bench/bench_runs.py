"""Running the systems under test for bench/run, and reading back what they measured.

Each run happens in its own directory under /usr/bin/time -v (wall, CPU, peak RSS of the
whole process, measured the same way for every system), with standard input closed (MRPT
programs poll it) and a time limit.

Python standard library only.
"""

import json
import math
import os
import re
import subprocess
import time

ICP_SLAM_INI = os.path.join(os.path.dirname(os.path.abspath(__file__)), "icp-slam_headless.ini")


class RunResult:
    """What one system run produced: process figures, outputs, and an error if it failed."""

    def __init__(self, system):
        self.system = system
        self.ok = False
        self.error = None  # short text when not ok
        self.wall_s = None
        self.cpu_s = None
        self.peak_rss_mb = None
        self.scans = None
        self.data_duration_s = None
        self.latencies_ms = []
        self.loop_closures = None
        self.stages = None  # lrgc-slam's stats.json "stages" (dict), None for other systems
        self.trajectory = None  # TUM path
        self.eval = None  # lrgc-eval JSON (dict)
        self.plot = None  # PNG path

    def latency(self):
        """(median, p99, max) [ms] by nearest rank, or None."""
        return latency_summary(self.latencies_ms)

    def real_time_factor(self):
        if self.data_duration_s and self.wall_s:
            return self.data_duration_s / self.wall_s
        return None


def latency_summary(values):
    if not values:
        return None
    v = sorted(values)

    def rank(p):  # nearest-rank percentile
        k = max(1, min(len(v), int(math.ceil(p * len(v)))))
        return v[k - 1]

    return rank(0.5), rank(0.99), v[-1]


def parse_gnu_time(path):
    """Wall [s], CPU (user + system) [s], peak RSS [MiB], exit status from `time -v -o`."""
    text = open(path, encoding="utf-8", errors="replace").read()

    def field(name):
        m = re.search(r"^\s*" + re.escape(name) + r":\s*(.+)$", text, re.M)
        return m.group(1).strip() if m else None

    wall = field("Elapsed (wall clock) time (h:mm:ss or m:ss)")
    secs = None
    if wall:
        parts = [float(p) for p in wall.split(":")]
        secs = 0.0
        for p in parts:
            secs = secs * 60 + p
    user, system = field("User time (seconds)"), field("System time (seconds)")
    rss = field("Maximum resident set size (kbytes)")
    status = field("Exit status")
    return {
        "wall_s": secs,
        "cpu_s": float(user) + float(system) if user and system else None,
        "peak_rss_mb": int(rss) / 1024.0 if rss else None,
        "exit_status": int(status) if status else None,
        "signalled": "Command terminated by signal" in text,
    }


def run_timed(cmd, workdir, name, timeout_s):
    """Runs cmd under /usr/bin/time -v in workdir; stdout+stderr to NAME.log.
    Returns (gnu_time dict or None, error text or None)."""
    os.makedirs(workdir, exist_ok=True)
    time_file = os.path.join(workdir, name + ".time")
    log_file = os.path.join(workdir, name + ".log")
    full = ["/usr/bin/time", "-v", "-o", time_file] + cmd
    t0 = time.monotonic()
    with open(log_file, "w") as log:
        try:
            proc = subprocess.run(full, cwd=workdir, stdin=subprocess.DEVNULL, stdout=log,
                                  stderr=subprocess.STDOUT, timeout=timeout_s)
        except subprocess.TimeoutExpired:
            return None, "timed out after %d s (log: %s)" % (timeout_s, log_file)
    if not os.path.exists(time_file):
        return None, "no /usr/bin/time output (log: %s)" % log_file
    t = parse_gnu_time(time_file)
    if proc.returncode != 0:
        with open(log_file, errors="replace") as f:
            lines = [l.strip() for l in f if l.strip() and not l.startswith("\t")]
        return t, "exit code %d after %.1f s: %s (log: %s)" % (
            proc.returncode, time.monotonic() - t0, lines[-1][:200] if lines else "", log_file)
    return t, None


def read_tum(path):
    """[(t, x, y, yaw)] of a TUM file (comments skipped)."""
    out = []
    with open(path) as f:
        for line in f:
            s = line.split()
            if not s or s[0].startswith("#"):
                continue
            t, x, y, qx, qy, qz, qw = (float(s[i]) for i in (0, 1, 2, 4, 5, 6, 7))
            yaw = math.atan2(2 * (qw * qz + qx * qy), 1 - 2 * (qy * qy + qz * qz))
            out.append((t, x, y, yaw))
    return out


def write_tum(path, poses):
    with open(path, "w") as f:
        f.write("# t x y z qx qy qz qw\n")
        for t, x, y, yaw in poses:
            f.write("%.6f %.6f %.6f 0 0 0 %.9f %.9f\n"
                    % (t, x, y, math.sin(yaw / 2), math.cos(yaw / 2)))


def run_eval(tools, result, workdir, relations=None, ground_truth=None):
    """lrgc-eval on result.trajectory; stores the JSON in result.eval."""
    if not result.trajectory or not (relations or ground_truth):
        return
    out = os.path.join(workdir, "eval.json")
    cmd = [tools["lrgc-eval"], "--trajectory", result.trajectory, "--json", out]
    if relations:
        cmd += ["--relations", relations]
    if ground_truth:
        cmd += ["--ground-truth", ground_truth]
    with open(os.path.join(workdir, "eval.txt"), "w") as log:
        proc = subprocess.run(cmd, stdin=subprocess.DEVNULL, stdout=log, stderr=subprocess.STDOUT)
    if os.path.exists(out):
        with open(out) as f:
            result.eval = json.load(f)
    if proc.returncode != 0 and result.error is None:
        lines = [l.strip() for l in open(os.path.join(workdir, "eval.txt")) if l.strip()]
        result.error = "lrgc-eval: %s" % (lines[-1] if lines else "failed")


def convert_to_rawlog(tools, log_path, out_rawlog, timeout_s):
    """Our converter: `lrgc-slam --input LOG --save-rawlog OUT`. Returns an error or None."""
    workdir = os.path.dirname(out_rawlog)
    _, err = run_timed([tools["lrgc-slam"], "--input", log_path, "--save-rawlog", out_rawlog],
                       workdir, "convert", timeout_s)
    if err is None and not os.path.exists(out_rawlog):
        err = "converter wrote no %s" % out_rawlog
    return err


def run_lrgc_slam(tools, log_path, workdir, timeout_s, config=None):
    r = RunResult("lrgc-slam")
    outdir = os.path.join(workdir, "out")
    cmd = [tools["lrgc-slam"], "--input", log_path, "--out", outdir, "--quiet"]
    if config:
        cmd += ["--config", config]
    t, err = run_timed(cmd, workdir, "lrgc-slam", timeout_s)
    if t:
        r.wall_s, r.cpu_s, r.peak_rss_mb = t["wall_s"], t["cpu_s"], t["peak_rss_mb"]
    if err:
        r.error = err
        return r
    stats_path = os.path.join(outdir, "stats.json")
    try:
        with open(stats_path) as f:
            stats = json.load(f)
    except (OSError, ValueError) as e:
        r.error = "cannot read %s: %s" % (stats_path, e)
        return r
    r.scans = stats.get("scans")
    r.data_duration_s = stats.get("data_duration_s")
    r.loop_closures = stats.get("loop_closures")
    r.stages = stats.get("stages")
    timing = os.path.join(outdir, "timing.csv")
    if os.path.exists(timing):
        with open(timing) as f:
            next(f, None)  # header: scan_index,timestamp,latency_ms
            r.latencies_ms = [float(line.split(",")[2]) for line in f if line.strip()]
    r.trajectory = os.path.join(outdir, "trajectory.tum")
    if not os.path.exists(r.trajectory):
        r.error, r.trajectory = "no trajectory.tum written", None
        return r
    r.ok = True
    return r


def rawlog_entries(rawlog, workdir):
    """[(timestamp, class name)] of every observation in a rawlog, in file order, from
    `rawlog-edit --list-timestamps` (one line per rawlog step for icp-slam)."""
    listing = os.path.join(workdir, "timestamps.txt")
    subprocess.run(["rawlog-edit", "-q", "-i", rawlog, "--list-timestamps",
                    "--text-file-output", listing], cwd=workdir, stdin=subprocess.DEVNULL,
                   stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, check=True)
    out = []
    with open(listing) as f:
        for line in f:
            s = line.split()
            if len(s) >= 2 and not s[0].startswith("#"):
                out.append((float(s[0]), s[-1]))
    return out


def run_icp_slam(rawlog, workdir, timeout_s):
    """MRPT's icp-slam with the headless demo config. Its log_estimated_path.txt (`step x y
    phi`, one line per rawlog step) and log_times.txt (milliseconds of map building per step)
    are mapped to scan timestamps through the rawlog's own entry list."""
    r = RunResult("icp-slam")
    os.makedirs(workdir, exist_ok=True)
    logdir = os.path.join(workdir, "out")
    ini = os.path.join(workdir, "icp-slam.ini")
    with open(ICP_SLAM_INI) as src, open(ini, "w") as dst:
        for line in src:
            if line.startswith("logOutput_dir"):
                line = "logOutput_dir=%s\n" % logdir
            dst.write(line)
    t, err = run_timed(["icp-slam", ini, rawlog], workdir, "icp-slam", timeout_s)
    if t:
        r.wall_s, r.cpu_s, r.peak_rss_mb = t["wall_s"], t["cpu_s"], t["peak_rss_mb"]
    if err:
        r.error = err
        return r
    try:
        entries = rawlog_entries(rawlog, workdir)
    except (subprocess.CalledProcessError, OSError) as e:
        r.error = "rawlog-edit --list-timestamps failed: %s" % e
        return r
    path = [line.split() for line in open(os.path.join(logdir, "log_estimated_path.txt"))
            if line.strip()]
    times = [line.split() for line in open(os.path.join(logdir, "log_times.txt"))
             if line.strip()]
    if len(path) != len(entries):
        r.error = ("icp-slam logged %d steps but the rawlog lists %d observations: cannot "
                   "map steps to timestamps" % (len(path), len(entries)))
        return r
    poses, stamps = [], []
    for k, (step, cls) in enumerate(zip(path, entries)):
        if "2DRangeScan" not in cls[1]:
            continue
        poses.append((cls[0], float(step[1]), float(step[2]), float(step[3])))
        stamps.append(cls[0])
        if k < len(times):
            r.latencies_ms.append(float(times[k][0]))  # already in ms
    r.scans = len(poses)
    r.data_duration_s = max(stamps) - min(stamps) if stamps else None
    r.trajectory = os.path.join(workdir, "trajectory.tum")
    write_tum(r.trajectory, poses)
    r.ok = True
    return r
