/* CDelayedStop: a stop token that follows another one after a grace period, for a live run.
 *
 * In an offline run the first signal stops the computation in hand at once (StopToken.h). In
 * a live run the first signal is also the normal way to end: the queued scans are mapped and
 * the map saved as a replay of the capture would give it. So the live run's computations get
 * this token instead: it is stopped `grace` seconds after the trigger (the signal watcher's
 * token), by a thread of its own that looks every 50 ms. An ordinary stop is over by then
 * and cuts nothing; a computation that would hold the stop up (a global search of a minute, a
 * scan match that does not converge, an optimisation of a huge graph) is cut `grace` s after
 * the signal, as offline. A default trigger never fires.
 */
#pragma once

#include <lrgc/common/StopToken.h>

#include <atomic>
#include <thread>

namespace lrgc::apps
{
class CDelayedStop
{
public:
	CDelayedStop(CStopToken trigger, double graceSeconds);
	~CDelayedStop();  //!< ends the thread (never fires afterwards)
	CDelayedStop(const CDelayedStop&) = delete;
	CDelayedStop& operator=(const CDelayedStop&) = delete;

	CStopToken token() const { return m_source.token(); }

private:
	CStopSource m_source;
	std::atomic<bool> m_quit{false};
	std::thread m_thread;  //!< last: started once the rest exists
};

}  // namespace lrgc::apps
