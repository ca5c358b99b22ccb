/* CStopSignalWatcher: Ctrl-C (SIGINT), SIGTERM, SIGHUP (the terminal closed) and SIGPIPE (the
 * reader of our output went away: `lrgc-slam ... 2>&1 | head`) for lrgc-slam, offline and
 * live: each asks the run to stop and save what it mapped.
 *
 * A signal handler is not enough: METIS (CHOLMOD's ordering, used by the pose-graph
 * optimiser) traps SIGTERM around every ordering with System V signal() and re-installs the
 * previous handler as a one-shot one (measured with strace -k on MRPT 2.5.8 / Debian 12: after
 * the first optimisation a second SIGTERM killed the process with the default action, status
 * 143, and a SIGTERM arriving during an ordering is taken by METIS). So the watcher blocks both
 * signals in the calling thread, and thereby in every thread created afterwards, and takes
 * them in its own thread with sigtimedwait(): handlers, whoever installs them, never run. The
 * first signal asks the run to stop; the second (0.25 s or more after the first: `timeout`
 * delivers its one signal twice, to the child and to its group) calls _exit(130) at once
 * (everything on disk is whole by then: see CCaptureWriter and writeFileAtomically; a temporary
 * file being written may stay behind). Create it before any other thread of the run. A signal
 * that comes after the watcher's last look, before its destructor unblocks the signals again,
 * is taken (and counted) by the destructor, not left pending to kill the process once
 * unblocked. The first signal also stops token(): the map builder, the localiser and global
 * localisation end the computation in hand early (a loop search, an optimisation, a
 * correlation), so that what was mapped is saved promptly however large the map.
 *
 * SIGHUP is taken as SIGINT and SIGTERM are. SIGPIPE cannot be: the kernel sends it to the
 * thread whose write failed, where a blocked one would stay pending, unseen by the watcher.
 * It gets a handler instead (METIS leaves SIGPIPE alone) that counts it; it asks for a stop
 * but never for the immediate exit, since every later write to the closed pipe raises it
 * again (those writes fail with EPIPE, and the run goes on to save). The count is the one
 * global of the class: a signal handler has nowhere else to put it.
 */
#pragma once

#include <lrgc/common/StopToken.h>
#include <signal.h>

#include <atomic>
#include <thread>

namespace lrgc::apps
{
class CStopSignalWatcher
{
public:
	CStopSignalWatcher();
	/** Ends the watcher and restores the caller's signal mask. */
	~CStopSignalWatcher();
	CStopSignalWatcher(const CStopSignalWatcher&) = delete;
	CStopSignalWatcher& operator=(const CStopSignalWatcher&) = delete;

	bool stopRequested() const;
	/** Stopped by the first signal (a broken pipe: within the watcher's 0.2 s poll), for the
	 * library's long computations (CMetricMapBuilderLRGC::setStopToken, ...). */
	CStopToken token() const { return m_source.token(); }

private:
	sigset_t m_set{}, m_oldMask{};
	struct sigaction m_oldPipeAction
	{
	};
	std::atomic<int> m_signals{0};
	std::atomic<bool> m_quit{false};
	CStopSource m_source;
	std::thread m_thread;
};

}  // namespace lrgc::apps
