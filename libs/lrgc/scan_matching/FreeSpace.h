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

	/** Share [0..1] of `scan`'s points (placed at scanInRef) lying in the free space of some
	 * view, counted only when a neighbour in scan order within kWallGap_m does too (walls, not
	 * isolated spurious returns). 0 without views. */
	double scanViolation(const TScan2D& scan, const mrpt::math::TPose2D& scanInRef,
						 double margin) const;

	/** True if p (reference frame [m]) lies more than margin [m] in the free space of some
	 * view: a surface the reference's own beams passed through (glass, a railing, a mixed
	 * pixel, someone who walked on). */
	bool seenThrough(const Eigen::Vector2d& p, double margin) const;

private:
	struct TView
	{
		mrpt::math::TPose2D scanInRef;
		std::shared_ptr<const CRangeImage> image;
	};
	std::vector<TView> m_views;
};

}  // namespace lrgc
