#include "live/KeepUpPolicy.h"

namespace lrgc::apps
{
bool CKeepUpPolicy::shouldMap(size_t waiting)
{
	if (m_max == 0 || waiting <= m_max)
	{
		m_behind = false;
		m_skippedRun = 0;
		return true;
	}
	if (!m_behind) m_skippedEpisode = 0;
	m_behind = true;
	const size_t allowed = waiting / m_max;  // >= 1 here
	if (m_skippedRun < allowed)
	{
		++m_skippedRun;
		++m_skippedTotal;
		++m_skippedEpisode;
		return false;
	}
	m_skippedRun = 0;
	return true;
}

}  // namespace lrgc::apps
