#include "child_process.h"

#include "lms1xx_emulator.h"  // waitUntil

#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace lrgc::test
{
CChildProcess::CChildProcess(const std::string& program, const std::vector<std::string>& args,
							 const std::string& outputFile)
	: m_outputFile(outputFile)
{
	std::vector<std::string> argvStore{program};
	argvStore.insert(argvStore.end(), args.begin(), args.end());
	std::vector<char*> argv;
	for (auto& a : argvStore) argv.push_back(a.data());
	argv.push_back(nullptr);
	m_pid = ::fork();
	if (m_pid < 0) throw std::runtime_error("fork failed for " + program);
	if (m_pid == 0)
	{
		const int in = ::open("/dev/null", O_RDONLY);
		const int out = ::open(outputFile.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
		if (in < 0 || out < 0) ::_exit(127);
		::dup2(in, 0);
		::dup2(out, 1);
		::dup2(out, 2);
		::execv(program.c_str(), argv.data());
		::_exit(127);
	}
}

CChildProcess::~CChildProcess()
{
	if (m_pid > 0 && !m_exit)
	{
		::kill(m_pid, SIGKILL);
		int status = 0;
		::waitpid(m_pid, &status, 0);
	}
}

void CChildProcess::signal(int sig) const
{
	if (m_pid > 0 && !m_exit) ::kill(m_pid, sig);
}

std::optional<int> CChildProcess::waitExit(double timeoutSeconds)
{
	if (m_exit) return m_exit;
	waitUntil(
		[&]
		{
			int status = 0;
			const pid_t r = ::waitpid(m_pid, &status, WNOHANG);
			if (r == m_pid)
				m_exit = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
			return m_exit.has_value();
		},
		timeoutSeconds);
	return m_exit;
}

std::string CChildProcess::output() const
{
	std::ifstream f(m_outputFile, std::ios::binary);
	std::ostringstream ss;
	ss << f.rdbuf();
	return ss.str();
}

bool CChildProcess::waitForOutput(const std::string& text, double timeoutSeconds, size_t from)
{
	bool found = false;
	waitUntil(
		[&]
		{
			const std::string out = output();
			found = out.size() > from && out.find(text, from) != std::string::npos;
			if (found) return true;
			int status = 0;
			if (!m_exit && ::waitpid(m_pid, &status, WNOHANG) == m_pid)
				m_exit = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
			return m_exit.has_value();
		},
		timeoutSeconds);
	return found || output().find(text, from) != std::string::npos;
}

namespace
{
// The bit of `sig` in the mask of `field` ("SigCgt", "SigBlk") of a status file.
bool maskHas(const std::string& statusFile, const std::string& field, int sig)
{
	std::ifstream status(statusFile);
	for (std::string line; std::getline(status, line);)
		if (line.rfind(field + ":", 0) == 0)
			return (std::stoull(line.substr(field.size() + 1), nullptr, 16) >> (sig - 1)) &
				   1ULL;
	return false;
}
}  // namespace

TSignalDisposition signalDisposition(pid_t pid, int sig)
{
	const std::string proc = "/proc/" + std::to_string(pid);
	TSignalDisposition d;
	d.caught = maskHas(proc + "/status", "SigCgt", sig);
	d.blockedInMain = maskHas(proc + "/status", "SigBlk", sig);
	std::error_code ec;
	for (const auto& task : std::filesystem::directory_iterator(proc + "/task", ec))
	{
		++d.threads;
		if (!maskHas(task.path().string() + "/status", "SigBlk", sig)) ++d.unblockedThreads;
	}
	return d;
}

}  // namespace lrgc::test
