#include "StopSignalWatcher.h"

#include "SlamApp.h"  // kExitInterrupted

#include <pthread.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <ctime>

namespace lrgc::apps
{
namespace
{
std::atomic<int> g_brokenPipes{0};  // SIGPIPEs taken since the watcher was made

/** [s] A signal this soon after the first is the same request delivered twice, not a second
 * Ctrl-C: coreutils' `timeout -s INT` sends its signal to the child and then to the child's
 * process group, so lrgc-slam took two SIGINTs microseconds apart and exited at once with
 * nothing written (when the two did not merge while pending). A person's second Ctrl-C comes
 * hundreds of milliseconds after the first. */
constexpr double kSameRequestSeconds = 0.25;

extern "C" void countBrokenPipe(int)
{
	g_brokenPipes.fetch_add(1);
}
}  // namespace

CStopSignalWatcher::CStopSignalWatcher()
{
	sigemptyset(&m_set);
	sigaddset(&m_set, SIGINT);
	sigaddset(&m_set, SIGTERM);
	sigaddset(&m_set, SIGHUP);
	pthread_sigmask(SIG_BLOCK, &m_set, &m_oldMask);
	g_brokenPipes = 0;
	struct sigaction pipe
	{
	};
	pipe.sa_handler = countBrokenPipe;
	pipe.sa_flags = SA_RESTART;
	sigemptyset(&pipe.sa_mask);
	sigaction(SIGPIPE, &pipe, &m_oldPipeAction);
	m_thread = std::thread(
		[this]
		{
			const timespec poll = {0, 200 * 1000 * 1000};  // to notice a broken pipe
			std::chrono::steady_clock::time_point first;
			while (!m_quit)
			{
				if (sigtimedwait(&m_set, nullptr, &poll) < 0)
				{  // time-out or EINTR; a broken pipe is seen here
					if (g_brokenPipes.load() > 0) m_source.requestStop();
					continue;
				}
				// The destructor's wake-up, or a signal while the run ends: not a request.
				// (Its si_code cannot tell it from a user's: this machine's kernel reports
				// pthread_kill's tgkill as SI_USER, so a live run stopped by SIGTERM counted
				// the wake-up as the second signal and left by _exit(130).)
				if (m_quit) continue;
				const auto now = std::chrono::steady_clock::now();
				m_source.requestStop();
				if (m_signals.fetch_add(1) == 0)
					first = now;
				else if (std::chrono::duration<double>(now - first).count() >=
						 kSameRequestSeconds)
					::_exit(kExitInterrupted);
			}
		});
}

CStopSignalWatcher::~CStopSignalWatcher()
{
	m_quit = true;
	// Woken at once: waiting out its poll kept every run up to 0.2 s longer (the process's
	// wall came in steps of 0.2 s after the watcher's start).
	if (m_thread.joinable())
	{
		pthread_kill(m_thread.native_handle(), SIGHUP);
		m_thread.join();
	}
	const timespec now = {0, 0};
	while (sigtimedwait(&m_set, nullptr, &now) > 0) ++m_signals;  // taken, not left pending
	pthread_sigmask(SIG_SETMASK, &m_oldMask, nullptr);
	sigaction(SIGPIPE, &m_oldPipeAction, nullptr);
}

bool CStopSignalWatcher::stopRequested() const
{
	return m_signals.load() > 0 || g_brokenPipes.load() > 0;
}

}  // namespace lrgc::apps
