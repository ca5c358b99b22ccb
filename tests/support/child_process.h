/* A program run in the background for end-to-end tests that must act while it runs (send it
 * a signal, watch its output): stdin from /dev/null, stdout and stderr to a file. The
 * destructor kills (SIGKILL) and reaps a child that is still running, so a failing test never
 * leaves one behind. */
#pragma once

#include <sys/types.h>

#include <optional>
#include <string>
#include <vector>

namespace lrgc::test
{
class CChildProcess
{
public:
	/** Starts `program args...`; its output goes to `outputFile`. Throws if fork fails. */
	CChildProcess(const std::string& program, const std::vector<std::string>& args,
				  const std::string& outputFile);
	~CChildProcess();
	CChildProcess(const CChildProcess&) = delete;
	CChildProcess& operator=(const CChildProcess&) = delete;

	pid_t pid() const { return m_pid; }
	void signal(int sig) const;
	/** Exit status (128 + signal if killed), or nullopt if still running after the timeout. */
	std::optional<int> waitExit(double timeoutSeconds);
	/** Everything the child has written so far. */
	std::string output() const;
	/** Waits until the output contains `text` (after byte `from`); false on time-out or if the
	 * child exits without writing it. */
	bool waitForOutput(const std::string& text, double timeoutSeconds, size_t from = 0);

private:
	pid_t m_pid = -1;
	std::string m_outputFile;
	std::optional<int> m_exit;
};

/** Signal masks of a process, from /proc/PID/status (main thread) and /proc/PID/task/TID/status
 * (each thread). */
struct TSignalDisposition
{
	bool caught = false;         //!< a handler is installed (SigCgt)
	bool blockedInMain = false;  //!< the main thread blocks it (SigBlk)
	size_t threads = 0;          //!< threads seen
	/** Threads that do not block it. A thread waiting for it in sigtimedwait() counts here
	 * (the kernel unblocks the awaited signals while it waits): a signal-watcher thread. */
	size_t unblockedThreads = 0;
};
TSignalDisposition signalDisposition(pid_t pid, int sig);

}  // namespace lrgc::test
