#include "live/LiveQueues.h"

#include <mrpt/obs/CObservation2DRangeScan.h>

namespace lrgc::apps
{
bool CLiveQueues::push(const std::string& sensor,
					   const mrpt::serialization::CSerializable::Ptr& object)
{
	TLiveItem item;
	item.sensor = sensor;
	item.object = object;
	item.isScan =
		std::dynamic_pointer_cast<mrpt::obs::CObservation2DRangeScan>(object) != nullptr;
	item.arrived = std::chrono::steady_clock::now();
	{
		std::lock_guard<std::mutex> lock(m_mutex);
		if (m_closed) return false;
		item.seq = m_pushed++;
		m_scansPushed += item.isScan;
		m_mappingScans += item.isScan;
		m_capture.push_back(item);
		m_mapping.push_back(std::move(item));
	}
	m_captureCv.notify_one();
	m_mappingCv.notify_one();
	return true;
}

void CLiveQueues::close()
{
	{
		std::lock_guard<std::mutex> lock(m_mutex);
		m_closed = true;
	}
	m_captureCv.notify_all();
	m_mappingCv.notify_all();
}

bool CLiveQueues::closed() const
{
	std::lock_guard<std::mutex> lock(m_mutex);
	return m_closed;
}

std::vector<TLiveItem> CLiveQueues::takeForCapture(std::chrono::milliseconds timeout)
{
	std::unique_lock<std::mutex> lock(m_mutex);
	m_captureCv.wait_for(lock, timeout, [&] { return !m_capture.empty() || m_closed; });
	std::vector<TLiveItem> out(std::make_move_iterator(m_capture.begin()),
							   std::make_move_iterator(m_capture.end()));
	m_capture.clear();
	return out;
}

std::optional<TLiveItem> CLiveQueues::takeForMapping(std::chrono::milliseconds timeout,
													 size_t* scansBehind)
{
	std::unique_lock<std::mutex> lock(m_mutex);
	m_mappingCv.wait_for(lock, timeout, [&] { return !m_mapping.empty() || m_closed; });
	if (m_mapping.empty()) return std::nullopt;
	TLiveItem item = std::move(m_mapping.front());
	m_mapping.pop_front();
	m_mappingScans -= item.isScan;
	if (scansBehind) *scansBehind = m_mappingScans;
	return item;
}

bool CLiveQueues::drained() const
{
	std::lock_guard<std::mutex> lock(m_mutex);
	return m_closed && m_capture.empty() && m_mapping.empty();
}

size_t CLiveQueues::mappingDepth() const
{
	std::lock_guard<std::mutex> lock(m_mutex);
	return m_mapping.size();
}

size_t CLiveQueues::mappingScansWaiting() const
{
	std::lock_guard<std::mutex> lock(m_mutex);
	return m_mappingScans;
}

uint64_t CLiveQueues::pushed() const
{
	std::lock_guard<std::mutex> lock(m_mutex);
	return m_pushed;
}

uint64_t CLiveQueues::scansPushed() const
{
	std::lock_guard<std::mutex> lock(m_mutex);
	return m_scansPushed;
}

}  // namespace lrgc::apps
