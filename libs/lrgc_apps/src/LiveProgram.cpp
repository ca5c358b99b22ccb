#include "LiveProgram.h"

#include "CommandLine.h"

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <unistd.h>

#ifndef LRGC_LIVE_PROGRAM_DIR
#define LRGC_LIVE_PROGRAM_DIR "../libexec/lrgc"
#endif

namespace lrgc::apps
{
namespace
{
const char* const kLiveProgram = "lrgc-slam-live";

/** The folder of the running program (/proc/self/exe, links resolved). */
std::string runningProgramDir()
{
	std::error_code ec;
	const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
	if (ec) throw CSetupError("--live: cannot find the running program: " + ec.message());
	return exe.parent_path().string();
}
}  // namespace

std::vector<std::string> liveProgramCandidates(const std::string& programDir,
											   const std::string& installedDir)
{
	const std::filesystem::path dir(programDir);
	return {(dir / kLiveProgram).string(),
			(dir / installedDir / kLiveProgram).lexically_normal().string()};
}

void execLiveProgram(char* const* argv)
{
	const auto candidates = liveProgramCandidates(runningProgramDir(), LRGC_LIVE_PROGRAM_DIR);
	for (const std::string& path : candidates)
	{
		if (::access(path.c_str(), X_OK) != 0) continue;
		std::vector<char*> args{const_cast<char*>(path.c_str())};
		for (char* const* a = argv + 1; *a; ++a) args.push_back(*a);
		args.push_back(nullptr);
		::execv(path.c_str(), args.data());
		throw CSetupError("--live: cannot start " + path + ": " + std::strerror(errno));
	}
	throw CSetupError(std::string("--live: ") + kLiveProgram +
					  " (live sensor support) is not " + "installed: looked for " +
					  candidates[0] + " and " + candidates[1]);
}

}  // namespace lrgc::apps
