/* Fuzz target: the scan door (checkScanGeometry) and what follows it: scanFromObservation and
 * the CAnchorGrid searches of scan matching, on scans whose every field comes from the input
 * (aperture, sensor pose, maxRange, ranges and validity: NaN, infinities, 1e300 included).
 *
 * Invariants: a scan the door passes converts to finite points only; the grid built on them
 * answers nearest() and forEachWithin() (libFuzzer's -timeout catches a search that does not
 * end) with indices of its own points within the distance asked. */
#include <lrgc/scan_matching/AnchorGrid.h>
#include <lrgc/scan_matching/Scan.h>
#include <lrgc/scan_matching/ScanGeometry.h>

#include <cmath>
#include <cstring>

#include "fuzz_common.h"

namespace
{
// Reads the next double of the input (zero once it is used up).
class CBytes
{
public:
	CBytes(const uint8_t* d, size_t n) : m_d(d), m_n(n) {}
	double next()
	{
		double v = 0;
		if (m_at + sizeof v <= m_n) std::memcpy(&v, m_d + m_at, sizeof v);
		m_at += sizeof v;
		return v;
	}
	bool more() const { return m_at + sizeof(double) <= m_n; }

private:
	const uint8_t* m_d;
	size_t m_n, m_at = 0;
};
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
	CBytes in(data, size);
	auto scan = mrpt::obs::CObservation2DRangeScan::Create();
	scan->aperture = static_cast<float>(in.next());
	scan->maxRange = static_cast<float>(in.next());
	const double x = in.next(), y = in.next(), yaw = in.next();
	scan->sensorPose = mrpt::poses::CPose3D(x, y, 0, yaw, 0, 0);
	const double cell = std::abs(in.next());
	const mrpt::math::TPose2D sweep(in.next(), in.next(), in.next());
	std::vector<float> ranges;
	while (in.more() && ranges.size() < 2000) ranges.push_back(static_cast<float>(in.next()));
	scan->resizeScan(ranges.size());
	for (size_t i = 0; i < ranges.size(); ++i)
		scan->setScanRange(i, ranges[i]), scan->setScanRangeValidity(i, i % 7 != 3);

	const lrgc::TScanGeometryCheck checked = lrgc::checkScanGeometry(scan);
	LRGC_FUZZ_CHECK(bool(checked.scan) == checked.problem.empty(),
					"dropped exactly with a reason");
	if (!checked.scan) return 0;
	// The de-skewing motion is the builder's estimate, finite and small: bound it likewise.
	const auto bounded = [](double v) { return std::isfinite(v) ? std::fmod(v, 10.0) : 0.0; };
	const lrgc::TScan2D s = lrgc::scanFromObservation(
		*checked.scan, nullptr, {bounded(sweep.x), bounded(sweep.y), bounded(sweep.phi)});
	for (const auto& p : s.points)
		LRGC_FUZZ_CHECK(p.allFinite() && p.norm() < 2e3, "points finite and within reach");
	if (s.points.empty() || !(cell >= 0.01 && cell <= 10)) return 0;
	const lrgc::CAnchorGrid grid(s.points, std::vector<bool>(s.points.size(), true), cell);
	for (const auto& p : s.points)
	{
		const Eigen::Vector2d q = p + Eigen::Vector2d(0.3, -0.2);
		double d2 = 0;
		const int k = grid.nearest(q, 1.0, &d2);
		LRGC_FUZZ_CHECK(k < 0 || (size_t(k) < s.points.size() && d2 < 1.0),
						"nearest within the gate");
		grid.forEachWithin(
			q, 0.5,
			[&](uint32_t i)
			{
				LRGC_FUZZ_CHECK(i < s.points.size() && (s.points[i] - q).norm() <= 0.5 + 1e-9,
								"radius query within the radius");
			});
	}
	return 0;
}
