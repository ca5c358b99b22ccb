"""Tables of bench/run: per log and per system, printed and written to doc/benchmarks.md with
the machine and the commit they were measured on. Python standard library only."""

import os
import platform
import re
import subprocess
import time


def published_figures(readme_path):
    """Cartographer's published figures from the datasets README, keyed by a normalised
    dataset name ("intel", "aces", "mitcsail"): {"error": "m +/- s / deg +/- s",
    "data_s": .., "wall_s": ..}. Empty if the README is absent."""
    out = {}
    if not readme_path or not os.path.exists(readme_path):
        return out
    text = open(readme_path, encoding="utf-8").read()
    for m in re.finditer(r"^\|\s*([A-Za-z][A-Za-z ]*?)\s*\|\s*([0-9.]+ \+/- [0-9.]+ / "
                         r"[0-9.]+ \+/- [0-9.]+)\s*\|(.*)$", text, re.M):
        entry = out.setdefault(normalise(m.group(1)), {})
        entry["error"] = m.group(2)
        # The table's last column: "scan matching only" (translational mean +/- std, m).
        cols = [c.strip() for c in m.group(3).split("|") if c.strip()]
        if cols and re.fullmatch(r"[0-9.]+ \+/- [0-9.]+", cols[-1]):
            entry["scan_matching"] = cols[-1]
    wall = re.search(r"Cartographer's published wall-clock[^:]*:(.*?)\.\s*$", text, re.M | re.S)
    if wall:
        for m in re.finditer(r"([A-Za-z][A-Za-z ]*?)\s+(\d+)/(\d+)", wall.group(1)):
            entry = out.setdefault(normalise(m.group(1)), {})
            entry["data_s"], entry["wall_s"] = float(m.group(2)), float(m.group(3))
    return out


def normalise(name):
    return re.sub(r"[^a-z0-9]", "", name.lower())


def machine_description():
    cpu = "unknown CPU"
    try:
        for line in open("/proc/cpuinfo"):
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    mem = ""
    try:
        for line in open("/proc/meminfo"):
            if line.startswith("MemTotal"):
                mem = ", %.0f GiB RAM" % (int(line.split()[1]) / 1024.0 / 1024.0)
    except OSError:
        pass
    debian = ""
    if os.path.exists("/etc/debian_version"):
        debian = ", Debian " + open("/etc/debian_version").read().strip()
    mrpt = subprocess.run(["dpkg-query", "-W", "-f=${Version}", "libmrpt-dev"],
                          capture_output=True, text=True).stdout.strip()
    return "%s, %d cores%s, %s %s%s, MRPT %s" % (
        cpu, os.cpu_count() or 0, mem, platform.system(), platform.release(), debian,
        mrpt or "?")


def commit_description(repo):
    def git(*args):
        return subprocess.run(["git", "-C", repo] + list(args), capture_output=True,
                              text=True).stdout.strip()
    head = git("rev-parse", "--short=12", "HEAD") or "unknown"
    dirty = git("status", "--porcelain", "--untracked-files=no")
    subject = git("log", "-1", "--format=%s")
    if len(subject) > 72:
        subject = subject[:69] + "..."
    return "%s%s (%s)" % (head, " + uncommitted changes" if dirty else "", subject)


def fmt(v, spec="%.2f", none="–"):
    return none if v is None else spec % v


def pm(stats, spec="%.3f"):
    """"mean +/- std" of an lrgc-eval stats object."""
    if not stats or not stats.get("count"):
        return "–"
    return (spec + " ± " + spec) % (stats["mean"], stats["std"])


def ratio(a, b, spec="%.2f"):
    if a is None or b is None or b == 0:
        return "–"
    return spec % (a / b)


def latency_ratio(ours_ms, icp_ms):
    """Latency ratio, but not against a near-zero icp-slam figure: icp-slam skips the scan
    match for most scans (it matches only after 0.2 m or 5 deg of odometry), so its median
    is often about 0 ms and a ratio to it means nothing."""
    return ratio(ours_ms, icp_ms) if icp_ms >= 0.1 else "–"


def relation_cells(run):
    rel = (run.eval or {}).get("relations")
    if not rel:
        return ["–", "–", "–", "–"]
    used = "%d/%d" % (rel["used"], rel["total"])
    return [pm(rel["translational_m"], "%.3f"), pm(rel["rotational_deg"], "%.2f"), used,
            short_relation_cell(run)]


def short_relation_cell(run):
    """Relations under 10 s apart off by more than 2 deg (issue 28: the heading's tail)."""
    short = ((run.eval or {}).get("relations") or {}).get("short_relations")
    if not short or not short.get("count"):
        return "–"
    return "%d/%d (%.1f %%)" % (short["rotational_over_2_deg"], short["count"],
                                100.0 * short["rotational_over_2_deg"] / short["count"])


def ate_cells(run):
    ev = run.eval or {}
    ate, step = ev.get("ate"), ev.get("rpe_step")
    if not ate:
        return ["–", "–", "–"]
    return ["%.3f" % ate["translational_m"]["rms"], pm(ate["translational_m"], "%.3f"),
            pm(step["translational_m"], "%.4f") if step else "–"]


# The stages of lrgc-slam's stats.json "stages" in the "CPU by stage" column, in order;
# start-up, input and the mapping thread's bookkeeping ("other") share the last figure.
STAGE_GROUPS = (("local_registration",), ("keyframe_patch",), ("loop_closing_worker",),
                ("final_optimization",), ("outputs",), ("start_up", "input", "other"))


def stage_cells(run):
    """[CPU per scan [ms], CPU by stage [%]] from lrgc-slam's stats.json "stages"."""
    st = run.stages if run.ok else None
    if not st or "cpu_share" not in st:
        return ["–", "–"]
    share = st["cpu_share"]
    parts = ["%.0f" % (100.0 * sum(share.get(k, 0.0) for k in group)) for group in STAGE_GROUPS]
    return [fmt(st.get("mapping_cpu_ms_per_scan"), "%.2f"), " / ".join(parts)]


def system_cells(run):
    if not run.ok:
        return ["–"] * 10
    lat = run.latency()
    return [fmt(run.scans, "%d"), fmt(run.data_duration_s, "%.0f"), fmt(run.wall_s, "%.1f"),
            fmt(run.cpu_s, "%.1f"), fmt(run.real_time_factor(), "%.1f"),
            fmt(run.peak_rss_mb, "%.0f"),
            "%.2f / %.1f / %.1f" % lat if lat else "–", fmt(run.loop_closures, "%d")] + \
        stage_cells(run)


REAL_HEADER = ["log", "system", "scans", "data [s]", "wall [s]", "CPU [s]", "real-time ×",
               "peak RSS [MB]", "latency med / p99 / max [ms]", "loops", "CPU / scan [ms]",
               "CPU by stage LR / KF / LC / opt / out / start [%]",
               "rel. error [m]", "rel. error [deg]", "relations used",
               "10 s relations off > 2°"]
SYN_HEADER = REAL_HEADER[:12] + ["ATE rmse [m]", "ATE [m]", "RPE 1 step [m]"]


def real_rows(log_name, runs, published):
    """Rows for one real log: each system, Cartographer's published figures, ratios."""
    rows = []
    for run in runs:
        cells = [log_name, run.system] + system_cells(run) + relation_cells(run)
        if not run.ok and run.error:
            cells[1] += " (failed, see notes)"
        rows.append(cells)
    pub = published.get(normalise(log_name))
    if pub:
        err = pub.get("error", "– / –").split(" / ")
        rows.append([log_name, "Cartographer (published)", "–", fmt(pub.get("data_s"), "%.0f"),
                     fmt(pub.get("wall_s"), "%.0f"), "–",
                     ratio(pub.get("data_s"), pub.get("wall_s"), "%.1f"), "–", "–", "–", "–",
                     "–", err[0], err[1] if len(err) > 1 else "–", "–", "–"])
    if pub and pub.get("scan_matching"):
        rows.append([log_name, "scan matching only (published)", "–", "–", "–", "–", "–", "–",
                     "–", "–", "–", "–", pub["scan_matching"], "–", "–", "–"])
    by = {r.system: r for r in runs}
    ours, icp = by.get("lrgc-slam"), by.get("icp-slam")
    if ours and icp and ours.ok and icp.ok:
        def mean_of(run, key):
            rel = (run.eval or {}).get("relations") or {}
            return (rel.get(key) or {}).get("mean")
        lo, li = ours.latency(), icp.latency()
        rows.append([log_name, "ratio lrgc-slam / icp-slam", "", "", ratio(ours.wall_s, icp.wall_s),
                     ratio(ours.cpu_s, icp.cpu_s), "", ratio(ours.peak_rss_mb, icp.peak_rss_mb),
                     " / ".join(latency_ratio(a, b) for a, b in zip(lo, li)) if lo and li else "–",
                     "", "", "",
                     ratio(mean_of(ours, "translational_m"), mean_of(icp, "translational_m")),
                     ratio(mean_of(ours, "rotational_deg"), mean_of(icp, "rotational_deg")), "", ""])
    return rows


GEN_HEADER = ["log", "lrgc-slam [m]", "Cartographer (published) [m]", "below",
              "local registration only [m]", "scan matching only (published) [m]", "below"]


def generalisation_row(log_name, runs, published):
    """One row of the generalisation check: lrgc-slam's mean translational relation error
    against Cartographer's published one, and local registration alone against published scan
    matching (issue 11's bars). None without a published figure for this log."""
    pub = published.get(normalise(log_name))
    if not pub:
        return None

    def ours(system):
        run = {r.system: r for r in runs}.get(system)
        rel = ((run.eval or {}).get("relations") or {}) if run and run.ok else {}
        return (rel.get("translational_m") or {}).get("mean")

    def bar(text):
        m = re.match(r"\s*([0-9.]+)", text or "")
        return float(m.group(1)) if m else None

    def below(v, b):
        return "–" if v is None or b is None else ("yes" if v < b else "**no**")
    full, local = ours("lrgc-slam"), ours("lrgc-slam, local registration only")
    carto, scan = bar(pub.get("error")), bar(pub.get("scan_matching"))
    return [log_name, fmt(full, "%.4f"), fmt(carto, "%.4f"), below(full, carto),
            fmt(local, "%.3f"), fmt(scan, "%.3f"), below(local, scan)]


def synthetic_rows(log_name, runs):
    rows = []
    for run in runs:
        cells = [log_name, run.system] + system_cells(run) + ate_cells(run)
        if not run.ok and run.error:
            cells[1] += " (failed, see notes)"
        rows.append(cells)
    return rows


def markdown_table(header, rows):
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    for r in rows:
        lines.append("| " + " | ".join(str(c) for c in r) + " |")
    return "\n".join(lines)


def document(real, synthetic, plots, machine, commit, total_s, data_dir, notes, repeat=None,
             generalisation=None, config=None):
    """The whole doc/benchmarks.md. `repeat`: (title, what the run is, header, rows, summary
    line) of each run of Intel driven several times over (bench_repeat.py), or None.
    `generalisation`: generalisation_row()s; `config`: the .ini every lrgc-slam run used (None: the built-in defaults)."""
    out = ["# Benchmarks", "",
           "Written by `bench/run` (do not edit by hand): every system on every log, in one run, "
           "one process after the other.", "",
           "- Measured on: " + machine,
           "- Commit: " + commit,
           "- Date: " + time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime()),
           "- Data: %s; whole run %.0f s" % (data_dir or "(none)", total_s), ""]
    out += ["Wall, CPU and peak RSS are of the whole process (`/usr/bin/time -v`), including start-up "
            "and writing outputs. Real-time × = data duration / wall time. CPU / scan and CPU by "
            "stage are lrgc-slam's own timers (stats.json `stages`, CPU time of the threads, so "
            "they hold on a loaded machine): CPU / scan is the mapping stage's CPU (all threads, "
            "reading the input included) per scan; CPU by stage is each stage's share of the "
            "process's CPU time: LR local registration of each scan (mapping thread), KF "
            "keyframes and the window patch (the mapping thread placing scans, loop results "
            "applied there included, and the window's helper thread), LC the loop-closing "
            "worker thread, opt the end of the run (loop results still due, revisit sweep, final "
            "optimisation), out writing the outputs, start the process start-up (library "
            "loading, MRPT's class registration, configuration, opening the input) with reading "
            "the input and the mapping thread's bookkeeping. Latency is per scan: "
            "lrgc-slam's `timing.csv`, icp-slam's `log_times.txt` (icp-slam matches a scan only "
            "after 0.2 m or 5° of odometry, so most of its scans cost about 0 ms). The relation error is the metric "
            "of Kuemmerle et al., \"On measuring the accuracy of SLAM algorithms\", Autonomous "
            "Robots 27(4), 2009 (mean ± std of the translational and rotational error over all "
            "relations, computed by `lrgc-eval`); icp-slam runs MRPT's demo configuration "
            "(`bench/icp-slam_headless.ini`) on the same log converted by `lrgc-slam "
            "--save-rawlog`. Cartographer's figures are the published ones (Hess et al. 2016, on "
            "a desktop Xeon), not measured here. \"lrgc-slam, local registration only\" is the "
            "same run with `[MapBuilder] loop_closing = false` (no global correlation, no loop "
            "closing), to compare with the published \"scan matching only\" baseline of "
            "Kuemmerle et al. (2009). Logs: Intel Research Lab (D. Haehnel), ACES "
            "(P. Beeson), MIT CSAIL (C. Stachniss), MIT Killian Court (mit-killian: M. Bosse and "
            "J. Leonard).", ""]
    if real:
        out += ["## Real logs: relation error", "", markdown_table(REAL_HEADER, real), ""]
    if generalisation:
        out += ["## Generalisation", "",
                "Every lrgc-slam run in this document uses one configuration: %s. Below, each "
                "log's error against the published bars: Cartographer for full SLAM, scan "
                "matching only (Kuemmerle et al. 2009) for local registration alone. The "
                "defaults are judged on all these logs together, real and synthetic; how each "
                "was chosen, with a leave-one-out check (chosen on three benchmark logs, the "
                "fourth reported), is in doc/generalisation.md."
                % ("`--config %s`" % os.path.basename(config) if config
                   else "lrgc-slam's built-in defaults"),
                "", markdown_table(GEN_HEADER, generalisation), ""]
    if synthetic:
        out += ["## MRPT synthetic logs: exact ground truth", "",
                "ATE: absolute trajectory error after the best-fit SE(2) alignment (rmse, and "
                "mean ± std); RPE: relative pose error between consecutive ground-truth poses.",
                "", markdown_table(SYN_HEADER, synthetic), ""]
    for title, what, header, rows, summary in repeat or []:
        out += ["## " + title, "",
                "`bench/repeat_log.py` makes Intel four times over (" + what + "); lrgc-slam "
                "maps it in one run with the defaults. Per pass: mapping time = sum of the "
                "per-scan latencies of timing.csv (loop-closing waits included), the keyframes "
                "the pass added (graph.lrgc), and the relation error of its scans (the log's "
                "relations shifted to the pass, scored on the whole run's final trajectory). "
                + summary, "", markdown_table(header, rows), ""]
    if notes:
        out += ["## Notes", ""] + ["- " + n for n in notes] + [""]
    if plots:
        out += ["## Plots", "",
                "Map (lrgc-slam's `map.pgm`) with its trajectory (blue) and the loop links of "
                "its pose graph (red: graph.lrgc's links of type LoopClosure, stats.json's "
                "`links.loop`), and the per-scan latency against scan index.", ""]
        for name, png in plots:
            out += ["### " + name, "", "![%s](%s)" % (name, png), ""]
    return "\n".join(out)


def print_table(header, rows):
    """Plain-text table for the terminal, columns padded."""
    widths = [len(h) for h in header]
    for r in rows:
        for i, c in enumerate(r):
            widths[i] = max(widths[i], len(str(c)))
    line = lambda cells: "  ".join(str(c).ljust(widths[i]) for i, c in enumerate(cells))
    print(line(header))
    print("  ".join("-" * w for w in widths))
    for r in rows:
        print(line(r))
