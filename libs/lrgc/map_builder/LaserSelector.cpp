#include <lrgc/map_builder/LaserSelector.h>

#include <mrpt/core/exceptions.h>

namespace lrgc
{
CLaserSelector::CLaserSelector(const TMapBuilderParams& params)
	: m_label(params.laser_label),
	  m_chosen(!params.laser_label.empty()),
	  m_limits{params.min_range_m, params.max_range_m}
{
}

void CLaserSelector::adopt(const std::string& label)
{
	if (m_label.empty()) m_label = label;
}

mrpt::obs::CObservation2DRangeScan::Ptr CLaserSelector::select(
	const mrpt::obs::CObservation2DRangeScan::Ptr& laser)
{
	ASSERT_(laser);
	adopt(laser->sensorLabel);
	if (laser->sensorLabel != m_label)
	{
		++m_ignored[laser->sensorLabel];
		if (!m_chosen && !m_warned)
		{
			m_warned = true;
			m_warning =
				"a second laser: mapping '" + m_label + "' (the first seen), ignoring the scans of '" +
				laser->sensorLabel + "' (counted in stats.json); to map '" + laser->sensorLabel +
				"' instead, give --laser " + laser->sensorLabel + " (or [MapBuilder] laser_label = " +
				laser->sensorLabel + ")";
		}
		return nullptr;
	}
	if (!m_limits.active()) return laser;
	size_t marked = 0;
	auto out = applyRangeLimits(laser, m_limits, &marked);
	m_rangeLimited += marked;
	return out;
}

}  // namespace lrgc
