/* CLaserSelector: which of a log's 2D lasers the map is built from, and that laser's range
 * limits ([MapBuilder] laser_label, min_range_m, max_range_m; lrgc-slam --laser).
 *
 * A robot may carry several lasers (a CARMEN log's FLASER and RLASER lines become the labels
 * "LASER" and "REAR_LASER"); the map is built from one. With no label given, the first label
 * seen is mapped and, when a second one appears, a warning names both and the option that
 * picks the other: mapping one rear-laser scan and dropping every front one in silence is the
 * failure this class exists for. Scans of the other lasers are counted per label. The mapped
 * laser's readings outside [min_range_m, max_range_m] are marked invalid (applyRangeLimits), so
 * that matching, the occupancy grid and the saved keyframes all go without them.
 * Before any of that, each of the mapped laser's scans goes through checkScanGeometry()
 * (ScanGeometry.h): a scan whose geometry cannot place its rays is dropped, a reading beyond
 * kMaxRange clipped, each counted and the first few of each kind warned about.
 */
#pragma once

#include <lrgc/map_builder/MapBuilderParams.h>
#include <lrgc/scan_matching/Scan.h>
#include <mrpt/obs/CObservation2DRangeScan.h>

#include <deque>
#include <map>
#include <optional>
#include <string>

namespace lrgc
{
class CLaserSelector
{
public:
	explicit CLaserSelector(const TMapBuilderParams& params = {});

	/** The scan to map (range limits applied; `laser` itself when none changes it), or
	 * nullptr when `laser` is another laser's (counted in ignoredScans()) or its geometry is
	 * unusable (counted in badGeometryScans()). */
	mrpt::obs::CObservation2DRangeScan::Ptr select(
		const mrpt::obs::CObservation2DRangeScan::Ptr& laser);
	/** Makes `label` the mapped laser if none is chosen yet (scans entering through
	 * initialize(initialMap)). */
	void adopt(const std::string& label);

	/** The mapped laser's label: the one asked for, else the first seen (empty before). */
	const std::string& label() const { return m_label; }
	/** Whether the label was asked for ([MapBuilder] laser_label) rather than first seen. */
	bool chosen() const { return m_chosen; }
	/** Scans of the other lasers, ignored, per sensor label. */
	const std::map<std::string, size_t>& ignoredScans() const { return m_ignored; }
	/** Readings of the mapped laser dropped by min_range_m / max_range_m. */
	size_t rangeLimitedReadings() const { return m_rangeLimited; }
	/** Scans of the mapped laser dropped by checkScanGeometry(). */
	size_t badGeometryScans() const { return m_badGeometry; }
	/** Why the first of those was dropped ("maxRange = 0 m (...)"), or empty. */
	const std::string& firstGeometryProblem() const { return m_firstGeometryProblem; }
	/** Readings of the mapped laser beyond kMaxRange, clipped by checkScanGeometry(). */
	size_t clippedReadings() const { return m_clipped; }
	/** The next warning not yet taken (a second laser, once per run; the first scans dropped
	 * or clipped by checkScanGeometry()), or nullopt. */
	std::optional<std::string> takeWarning();

private:
	std::string m_label;
	bool m_chosen = false;
	TRangeLimits m_limits;
	std::map<std::string, size_t> m_ignored;
	size_t m_rangeLimited = 0;
	size_t m_badGeometry = 0, m_clipped = 0, m_clippedScans = 0;
	std::string m_firstGeometryProblem;
	bool m_warned = false;
	std::deque<std::string> m_warnings;

	/** `laser` through checkScanGeometry(), counted and warned about. */
	mrpt::obs::CObservation2DRangeScan::Ptr checkGeometry(
		const mrpt::obs::CObservation2DRangeScan::Ptr& laser);
};

}  // namespace lrgc
