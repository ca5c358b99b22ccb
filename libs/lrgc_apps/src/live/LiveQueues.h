/* CLiveQueues: where the sensor threads hand over what they receive, in one order for all.
 *
 * push() appends each object to two FIFO queues under one lock, so the capture writer and the
 * mapper see the same objects in the same order: the capture (DIR/capture.rawlog) holds the
 * observations in exactly the order they were mapped, which is what makes an offline replay of
 * the capture give the same map. The queues are unbounded on purpose: acquisition never waits
 * for the writer or the mapper, and nothing is dropped here (the mapper's keep-up policy
 * decides what it skips; the capture keeps everything). close() ends the intake: later pushes
 * are refused, and the consumers drain what is queued.
 */
#pragma once

#include <mrpt/serialization/CSerializable.h>

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

namespace lrgc::apps
{
struct TLiveItem
{
	uint64_t seq = 0;    //!< arrival order, from 0
	std::string sensor;  //!< .ini section of the sensor it came from
	mrpt::serialization::CSerializable::Ptr object;
	bool isScan = false;  //!< a 2D laser scan (the keep-up policy counts these)
	std::chrono::steady_clock::time_point arrived;  //!< when push() took it
};

class CLiveQueues
{
public:
	/** From any sensor thread. False (and nothing queued) once closed. */
	bool push(const std::string& sensor, const mrpt::serialization::CSerializable::Ptr& object);
	/** Refuses further pushes and wakes the consumers. */
	void close();
	bool closed() const;

	/** Capture side: everything queued, waiting up to `timeout` for something; empty if
	 * nothing came (or closed and drained). */
	std::vector<TLiveItem> takeForCapture(std::chrono::milliseconds timeout);
	/** Mapping side: the oldest item, waiting up to `timeout`; `scansBehind` receives the
	 * number of laser scans still queued after it. */
	std::optional<TLiveItem> takeForMapping(std::chrono::milliseconds timeout,
											size_t* scansBehind);

	/** True once closed and both queues are empty. */
	bool drained() const;
	size_t mappingDepth() const;         //!< items waiting for the mapper
	size_t mappingScansWaiting() const;  //!< laser scans waiting for the mapper
	uint64_t pushed() const;             //!< objects accepted so far
	uint64_t scansPushed() const;        //!< laser scans accepted so far

private:
	mutable std::mutex m_mutex;
	std::condition_variable m_captureCv, m_mappingCv;
	std::deque<TLiveItem> m_capture, m_mapping;
	size_t m_mappingScans = 0;
	uint64_t m_pushed = 0, m_scansPushed = 0;
	bool m_closed = false;
};

}  // namespace lrgc::apps
