/* CStopSource and CStopToken: asking long computations to end early, from any thread. The
 * roles of C++20's std::stop_source and std::stop_token (lrgc is C++17).
 *
 * Some of lrgc's computations can take seconds to minutes on a large map: the whole-graph
 * optimisation at the end of a run and after a loop closure, the end-of-run revisit linking,
 * a loop search's branch and bound correlation, global localisation on a saved map, the scan
 * matcher's wide search. A program that must stop promptly (Ctrl-C, a GUI's Stop button, a
 * service shutting down) keeps a CStopSource, hands its token() to the map builder
 * (CMetricMapBuilderLRGC::setStopToken) or the localiser (CLocalizer::setStopToken), and calls
 * requestStop() from any thread, a signal-watching thread included (one store to a lock-free
 * atomic: no lock, no allocation). Each computation reads the flag at its own steps (an
 * iteration of Levenberg-Marquardt, 4096 bound evaluations of the branch and bound, a start
 * heading, a keyframe of a sweep), one relaxed load each, and ends with a consistent state:
 * each class says which (an optimisation keeps its last accepted iterate, a search finds
 * nothing, a loop search adds nothing). A stop is final: it cannot be withdrawn.
 * A default-constructed token has no source and is never stopped.
 */
#pragma once

#include <atomic>
#include <memory>

namespace lrgc
{
class CStopToken
{
public:
	CStopToken() = default;  //!< never stopped
	bool stopRequested() const { return m_flag && m_flag->load(std::memory_order_relaxed); }

private:
	friend class CStopSource;
	explicit CStopToken(std::shared_ptr<const std::atomic<bool>> flag) : m_flag(std::move(flag))
	{
	}
	std::shared_ptr<const std::atomic<bool>> m_flag;
};

class CStopSource
{
public:
	CStopSource() : m_flag(std::make_shared<std::atomic<bool>>(false)) {}
	/** Every token of this source reports the stop from now on. */
	void requestStop() const { m_flag->store(true, std::memory_order_relaxed); }
	bool stopRequested() const { return m_flag->load(std::memory_order_relaxed); }
	CStopToken token() const { return CStopToken(m_flag); }

private:
	std::shared_ptr<std::atomic<bool>> m_flag;
};

}  // namespace lrgc
