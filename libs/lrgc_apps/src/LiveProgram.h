/* lrgc-slam --live runs in a program of its own, lrgc-slam-live, which lrgc-slam execs.
 *
 * Why. mrpt::hwdrivers (the live sensors) drags 37 shared libraries more into a process than
 * the rest of MRPT that lrgc-slam needs (GTK 3, wxWidgets, OpenNI2, libftdi, ...): every
 * offline run paid for loading them, about 0.1 s of wall time and 16 MB of resident memory a
 * run (an empty program linked like lrgc-slam: 0.38 s against 0.26 s wall, 114 against 98 MB;
 * doc/architecture.md, "Where the time goes"). So lrgc-slam links no hwdrivers; given --live,
 * after checking its command line as for any run, it replaces itself (execv: same process,
 * same arguments, signals and standard streams) with lrgc-slam-live, the same application
 * linked with lrgc_live. */
#pragma once

#include <cstdio>
#include <string>
#include <vector>

namespace lrgc::apps
{
/** Where lrgc-slam-live is looked for, in this order: beside the running program (a build
 * tree's bin/), then in `installedDir` relative to it (an install: ../libexec/lrgc). */
std::vector<std::string> liveProgramCandidates(const std::string& programDir,
											   const std::string& installedDir);

/** Execs lrgc-slam-live with `argv` (argv[0] replaced by its path). Returns only on failure:
 * throws CSetupError naming where it looked, or why the exec failed. */
[[noreturn]] void execLiveProgram(char* const* argv);

}  // namespace lrgc::apps
