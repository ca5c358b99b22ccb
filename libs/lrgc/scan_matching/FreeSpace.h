/* Free-space consistency of an alignment (a check beyond the paper: a wrong match moves walls
 * into space the other scan saw empty).
 *
 * A scan's beams pass through free space up to their returns. CRangeImage keeps, per 1-degree
 * bearing bin of a scan (sensor frame), the nearest return [m]; a point lies in free space when
 * it is nearer than the returns around its bearing by more than a margin. CFreeSpaceViews keeps
 * the range images of the scans that made a reference, with their poses in the reference frame.
 */
#pragma once

#include <Eigen/Core>
#include <mrpt/math/TPose2D.h>

#include <memory>
#include <utility>
#include <vector>

namespace lrgc
{
struct TScan2D;

/** Bearing bin of the direction (x, y) [m], (atan2(y, x) + pi) / (1 deg) truncated (0..360),
 * computed without atan2 unless (x, y) lies within 1e-9 rad of a bin border: always the same
 * bin as that formula. */
long bearingBin(double x, double y);

class CRangeImage
{
public:
	/** Bins the points (sensor frame, [m]) by bearing: nearest return per bin, 0 where none;
	 * a single empty bin between two returns takes the nearer (beam spacing vs bin phase). */
	explicit CRangeImage(const std::vector<Eigen::Vector2d>& pointsInSensor);

	/** True if d (sensor frame) lies more than margin [m] in front of the returns of the bins
	 * around its bearing; *known (if given): all those bins hold a return. */
	bool inFreeSpace(const Eigen::Vector2d& d, double margin, bool* known = nullptr) const;

	/** [m] The median over the bearing bins known in both images of the change in their
	 * nearest return, |other - this|, and [0..1] those bins' share of the bins known in
	 * either: how far a scan taken from what may be the same pose differs from this one's
	 * (CLocalRegistration's still robot). {inf, 0} where no bin is known in both. */
	std::pair<double, double> medianChange(const CRangeImage& other) const;

	/** Number of points binned: rangeImageOf's check against a scan changed since. */
	size_t numPoints() const { return m_numPoints; }

private:
	/** [m] per bearing bin b, the nearest return of bins b - 1, b, b + 1 (the bins around
	 * a bearing); 0: one of them holds no return (unknown). */
	std::vector<float> m_nearest3;
	size_t m_numPoints = 0;
};

/** The range image of scan.points: the scan's own (TScan2D::rangeImage) where it has one of
 * as many points, else built now. */
std::shared_ptr<const CRangeImage> rangeImageOf(const TScan2D& scan);

class CFreeSpaceViews
{
public:
	/** Adds the view of `scan`, taken at scanInRef (ref <- scan). */
	void add(const TScan2D& scan, const mrpt::math::TPose2D& scanInRef);
	bool empty() const { return m_views.empty(); }
	size_t size() const { return m_views.size(); }

	/** Share [0..1] of `scan`'s points (placed at scanInRef) lying in the free space of some
	 * view, counted only when a neighbour in scan order within kWallGap_m does too (walls, not
	 * isolated spurious returns). 0 without views. (CScanViolation, all points at once.) */
	double scanViolation(const TScan2D& scan, const mrpt::math::TPose2D& scanInRef,
						 double margin) const;

	/** True if p (reference frame [m]) lies more than margin [m] in the free space of some
	 * view: a surface the reference's own beams passed through (glass, a railing, a mixed
	 * pixel, someone who walked on). */
	bool seenThrough(const Eigen::Vector2d& p, double margin) const;

private:
	friend class CScanViolation;
	struct TView
	{
		mrpt::math::TPose2D scanInRef;
		std::shared_ptr<const CRangeImage> image;
	};
	std::vector<TView> m_views;
};

/** CFreeSpaceViews::scanViolation in parts, so that the points' tests (a scan's points times
 * the views: a window patch has 15) can run on several threads: flag() ranges of the points,
 * each point in one range, in any order and on any threads, then share(). Each point's flag
 * is the same test whichever range and thread computes it, so share() is scanViolation's
 * value bit for bit. The object must outlive the flag() calls; views and scan are read, not
 * copied. */
class CScanViolation
{
public:
	CScanViolation(const CFreeSpaceViews& views, const TScan2D& scan,
				   const mrpt::math::TPose2D& scanInRef, double margin);
	/** Number of the scan's points (flag()'s index range). */
	size_t size() const { return m_viol.size(); }
	/** Tests points [begin, end) against the views. */
	void flag(size_t begin, size_t end);
	/** The share of flagged points with a flagged neighbour within kWallGap_m (all flagged).
	 * With minRun_m > 0, only runs of such points (consecutive in scan order, each within
	 * kWallGap_m of the last) that span at least minRun_m [m] count: a person standing where
	 * the views saw through is a run of about 0.3-0.5 m, a misplaced wall a longer one. */
	double share(double minRun_m = 0) const;

private:
	double longRunsShare(double minRun_m) const;  //!< share() with minRun_m > 0

	const CFreeSpaceViews& m_views;
	const std::vector<Eigen::Vector2d>& m_pts;
	double m_margin, m_c0, m_s0;
	mrpt::math::TPose2D m_scanInRef;
	/** (view <- ref) as rotation and translation, per view. */
	std::vector<std::pair<Eigen::Matrix2d, Eigen::Vector2d>> m_toView;
	std::vector<char> m_viol;
	std::vector<Eigen::Vector2d> m_inRef;  //!< the points in ref
};

}  // namespace lrgc
