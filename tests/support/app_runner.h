/* Runs the real lrgc-slam (or any program) as a child process for end-to-end tests. */
#pragma once

#include <string>
#include <vector>

namespace lrgc::test
{
struct TProcessResult
{
	int exitCode = -1;
	std::string output;  //!< stdout and stderr together
};

/** Runs `program args...` with stdin from /dev/null, capturing output; `cwd` if not empty. */
TProcessResult runProcess(const std::string& program, const std::vector<std::string>& args,
						  const std::string& cwd = {});

/** build/bin/<name> */
std::string binaryPath(const std::string& name);

std::string readTextFile(const std::string& path);
void writeTextFile(const std::string& path, const std::string& text);

}  // namespace lrgc::test
