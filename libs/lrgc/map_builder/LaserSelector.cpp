#include <lrgc/map_builder/LaserSelector.h>

#include <lrgc/scan_matching/ScanGeometry.h>
#include <mrpt/core/exceptions.h>
#include <mrpt/core/format.h>

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
			m_warnings.push_back("a second laser: mapping '" + m_label +
								 "' (the first seen), ignoring the scans of '" +
								 laser->sensorLabel + "' (counted in stats.json); to map '" +
								 laser->sensorLabel + "' instead, give --laser " +
								 laser->sensorLabel +
								 " (or [MapBuilder] laser_label = " + laser->sensorLabel + ")");
		}
		return nullptr;
	}
	auto checked = checkGeometry(laser);
	if (!checked || !m_limits.active()) return checked;
	size_t marked = 0;
	auto out = applyRangeLimits(checked, m_limits, &marked);
	m_rangeLimited += marked;
	return out;
}

mrpt::obs::CObservation2DRangeScan::Ptr CLaserSelector::checkGeometry(
	const mrpt::obs::CObservation2DRangeScan::Ptr& laser)
{
	constexpr size_t kListed = 3;  // warnings of each kind; the rest are counted
	TScanGeometryCheck c = checkScanGeometry(laser);
	const double t = mrpt::Clock::toDouble(laser->timestamp);
	if (!c.scan && m_firstGeometryProblem.empty()) m_firstGeometryProblem = c.problem;
	if (!c.scan && ++m_badGeometry <= kListed)
		m_warnings.push_back(mrpt::format(
			"scan at t=%.6f of '%s' dropped: %s%s", t, laser->sensorLabel.c_str(),
			c.problem.c_str(), m_badGeometry == kListed ? " (further ones are counted)" : ""));
	if (c.clipped > 0 && ++m_clippedScans <= kListed)
		m_warnings.push_back(mrpt::format(
			"scan at t=%.6f of '%s': %zu readings beyond %g m ignored (no 2D laser reaches "
			"that "
			"far)%s",
			t, laser->sensorLabel.c_str(), c.clipped, kMaxRange,
			m_clippedScans == kListed ? " (further scans with such readings are counted)"
									  : ""));
	m_clipped += c.clipped;
	return std::move(c.scan);
}

std::optional<std::string> CLaserSelector::takeWarning()
{
	if (m_warnings.empty()) return std::nullopt;
	std::string w = std::move(m_warnings.front());
	m_warnings.pop_front();
	return w;
}

}  // namespace lrgc
