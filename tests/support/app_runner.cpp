#include "app_runner.h"

#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace lrgc::test
{
namespace
{
std::string shellQuote(const std::string& s)
{
	std::string q = "'";
	for (const char c : s) q += (c == '\'') ? std::string("'\\''") : std::string(1, c);
	return q + "'";
}
}  // namespace

TProcessResult runProcess(const std::string& program, const std::vector<std::string>& args,
						  const std::string& cwd)
{
	std::string cmd;
	if (!cwd.empty()) cmd += "cd " + shellQuote(cwd) + " && ";
	cmd += shellQuote(program);
	for (const auto& a : args) cmd += " " + shellQuote(a);
	cmd += " </dev/null 2>&1";
	TProcessResult r;
	FILE* pipe = ::popen(cmd.c_str(), "r");
	if (!pipe) throw std::runtime_error("popen failed for: " + cmd);
	std::array<char, 4096> buf{};
	size_t n;
	while ((n = std::fread(buf.data(), 1, buf.size(), pipe)) > 0)
		r.output.append(buf.data(), n);
	const int status = ::pclose(pipe);
	r.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
	return r;
}

std::string binaryPath(const std::string& name)
{
	return std::string(LRGC_BINARY_DIR) + "/bin/" + name;
}

std::string readTextFile(const std::string& path)
{
	std::ifstream f(path, std::ios::binary);
	if (!f) throw std::runtime_error("cannot read " + path);
	std::ostringstream ss;
	ss << f.rdbuf();
	return ss.str();
}

void writeTextFile(const std::string& path, const std::string& text)
{
	std::ofstream f(path, std::ios::binary);
	f << text;
	if (!f) throw std::runtime_error("cannot write " + path);
}

}  // namespace lrgc::test
