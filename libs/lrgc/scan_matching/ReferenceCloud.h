/* CReferenceCloud: the "model" side of scan matching (paper section 2.1): the points of one
 * scan or of a local patch of scans, expressed in the reference frame, prepared once and
 * matched against many times.
 *
 * Preparation (O(n log n) for n input points):
 *  1. Voxel reduction: points are averaged per square cell of side ref_resolution_m, so a patch
 *     of overlapping scans does not hold ten copies of each wall (and is denoised). The
 *     local registration's window patches widen the cell to their measured noise
 *     (cellForNoise, CLocalRegistration::patchParams).
 *  2. Local line fit (Cox's "line segments" without segmentation): for every reduced point a
 *     weighted PCA of its neighbours within normal_radius_m (widened up to 4x where the data
 *     are sparse). A thin neighbourhood (thickness < 1/4 of its length along the line) makes a
 *     LINE anchor: the point projected onto the fitted line, plus the unit normal. Otherwise
 *     (corners, clutter, isolated returns) it is a POINT anchor as in Lu & Milios'
 * point-to-point correspondences.
 *  3. Noise model: how each fitted line's error depends on the reduced points' noise, for the
 *     match covariance (ScanMatcherCovariance.cpp).
 * Queries go through a CAnchorGrid over the anchors (exact bounded nearest neighbour), and the
 * free-space check through the views of the scans that made the cloud (CFreeSpaceViews).
 *
 * Frames: everything here is in the reference frame (ref). Units: metres.
 */
#pragma once

#include <lrgc/scan_matching/FreeSpace.h>
#include <lrgc/scan_matching/AnchorGrid.h>
#include <mrpt/math/TPose2D.h>

#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <utility>
#include <vector>

namespace lrgc
{
struct TScan2D;
struct TScanMatcherParams;

/** Runs fn(i) for every i in [0, n), in any order and on any threads; returns when all are
 * done (rethrowing an error of fn). */
using TParallelFor = std::function<void(size_t n, const std::function<void(size_t)>& fn)>;

class CReferenceCloud
{
public:
	/** One reduced reference point with its local geometry. */
	struct TAnchor
	{
		Eigen::Vector2d pos;           //!< [m] in ref; on the fitted line for LINE anchors
		Eigen::Vector2d normal{0, 0};  //!< unit normal for LINE anchors, (0,0) for POINT
		bool isLine = false;
		float fitRadius = 0;  //!< [m] neighbourhood radius of the line fit (0 for POINT)
		float u = 0;  //!< [m] position along the fitted line, relative to the fit's mean
		float normalVar = 0;  //!< [rad^2] variance of the normal's direction (line fit slope)
		/** POINT anchors: extra variance per axis [m^2] for sampling, (spacing to the nearest
		 * neighbour)^2 / 12: a point-to-point pair need not be the same surface point. */
		float samplingVar = 0;
		/** False for isolated returns (fewer than 3 neighbours within 4 normal_radius_m): no
		 * line and no trustworthy point (a wall sampled at grazing incidence); never matched.
		 */
		bool usable = true;
	};

	CReferenceCloud() = default;
	/** Builds from points already in the reference frame. Non-finite points are ignored.
	 * `parallel`, if given, runs the line fits (blocks of anchors, each fit independent of
	 * the others: the same cloud on any threads). */
	CReferenceCloud(std::vector<Eigen::Vector2d> pointsInRef, const TScanMatcherParams& p,
					const TParallelFor& parallel = {});

	/** One scan as the reference (its robot frame is the reference frame). */
	static CReferenceCloud fromScan(const TScan2D& scan, const TScanMatcherParams& p);
	/** A local patch: scans[k] placed at scansInRef[k] (ref <- scan k). Sizes must match. */
	static CReferenceCloud fromScans(const std::vector<TScan2D>& scans,
									 const std::vector<mrpt::math::TPose2D>& scansInRef,
									 const TScanMatcherParams& p,
									 const TParallelFor& parallel = {});
	/** fromScans keeping only the points within about `margin` [m] of some point of
	 * `nearInRef` (cells of side margin: a kept point is within 2 sqrt(2) margin).
	 * For matching a scan known to lie at nearInRef to within a few cm: with margin >=
	 * maxCorrespondenceDist + 4 normalRadius (the widest line fit) every anchor the match can
	 * reach gets the same line fit as without the crop. The views (free-space check) are
	 * kept whole; withViews false builds none (for a matcher whose free-space check is off:
	 * max_free_space_violation 1, a scan's range image per view saved). */
	static CReferenceCloud fromScansNear(const std::vector<TScan2D>& scans,
										 const std::vector<mrpt::math::TPose2D>& scansInRef,
										 const TScanMatcherParams& p,
										 const std::vector<Eigen::Vector2d>& nearInRef,
										 double margin, const TParallelFor& parallel = {},
										 bool withViews = true);

	bool empty() const { return m_anchors.empty(); }
	size_t size() const { return m_anchors.size(); }
	const std::vector<TAnchor>& anchors() const { return m_anchors; }
	/** Number of input points before reduction. */
	size_t inputPointCount() const { return m_inputCount; }

	/** Index of the anchor nearest to q within maxDist [m] (exact), or -1. If found and d2 is
	 * given, *d2 is the squared distance [m^2]. */
	int nearest(const Eigen::Vector2d& q, double maxDist, double* d2 = nullptr) const
	{
		return m_grid.nearest(q, maxDist, d2);
	}
	/** nearest() with a lower bound [m] on the distance from q to every other anchor
	 * (CAnchorGrid::nearestWithBound; the grid holds the anchors' positions as anchors()). */
	int nearestWithBound(const Eigen::Vector2d& q, double maxDist, double* otherBound) const
	{
		return m_grid.nearestWithBound(q, maxDist, otherBound);
	}

	/** Noise model, for the covariance of a match. The error of LINE anchor j's fitted line
	 * along its normal, at line coordinate u (anchor.u + tangent offset), is
	 * delta_j(u) = sum over the fit's points k of (b0 + u b1) nu_k; a POINT anchor's error is
	 * nu_j (2D). nu_k has variance pointVariance(k) [m^2] (per axis), independent over k.
	 * Calls fn(k, b0, b1) for each point k of LINE anchor j's fit (none for a POINT anchor),
	 * with b0 [1] and b1 [1/m] as in fitLines. Computed on demand from the fit's neighbourhood
	 * (a match's covariance needs a few hundred of a patch's thousands of fits). */
	template <class F>
	void forEachFitTerm(size_t j, F&& fn) const
	{
		if (!m_anchors[j].isLine) return;
		const TLineFit f = m_lineFits[j];
		const Eigen::Vector2d t(-m_anchors[j].normal.y(), m_anchors[j].normal.x());
		// forEachPointWithin's points and order, read through pointers held by value: fn's
		// stores (the caller's sums) would otherwise make every read reload them.
		const Eigen::Vector2d* pos = m_rawGrid.cellPoints().data();
		const uint32_t* index = m_rawGrid.cellIndices().data();
		const double* count = m_count.data();
		const double r2 = f.radius * f.radius;
		m_rawGrid.forEachRun(
			f.centre, f.radius,
			[&fn, f, t, pos, index, count, r2](uint32_t b, uint32_t e)
			{
				for (uint32_t i = b; i < e; ++i)
				{
					if (!((pos[i] - f.centre).squaredNorm() <= r2)) continue;
					const uint32_t k = index[i];
					const double uk = (pos[i] - f.mean).dot(t);
					fn(k, static_cast<float>(count[k] / f.W),
					   static_cast<float>(f.suu > 0 ? count[k] * uk / f.suu : 0));
				}
			});
	}
	/** One of forEachFitTerm's calls: fn(point, b0, b1). */
	struct TFitTerm
	{
		uint32_t point;
		float b0, b1;
	};
	/** forEachFitTerm, on a cloud that records them (recordFitTerms()) with each anchor's
	 * terms recorded at its first walk and replayed from then on: the same calls in the same
	 * order, so the same sums. A match's covariance walks the fits of the anchors its pairs
	 * use, and the next matches against the same cloud mostly the same ones (a keyframe's own
	 * cloud: the pairwise links of the next keyframes; the window patch would gain too, but
	 * does not record: CLocalRegistration::patchOf); a replay reads 12 bytes a term instead
	 * of the fit's grid cells, their distance tests and two divisions. Holds the cloud's
	 * record locked while it lives (one per covariance; clouds are matched from several
	 * threads). */
	class CFitTermReader
	{
	public:
		template <class F>
		void forEach(size_t j, F&& fn)
		{
			if (!m_rec) return m_cloud->forEachFitTerm(j, std::forward<F>(fn));
			auto& rec = *m_rec;
			if (rec.first.empty())
			{
				rec.first.assign(m_cloud->size(), kNotRecorded);
				rec.end.resize(m_cloud->size());
			}
			if (rec.first[j] == kNotRecorded)
			{
				rec.first[j] = static_cast<uint32_t>(rec.terms.size());
				m_cloud->forEachFitTerm(j,
										[&](uint32_t k, float b0, float b1)
										{
											rec.terms.push_back(TFitTerm{k, b0, b1});
											fn(k, b0, b1);
										});
				rec.end[j] = static_cast<uint32_t>(rec.terms.size());
				return;
			}
			const TFitTerm* t = rec.terms.data();
			for (uint32_t i = rec.first[j], e = rec.end[j]; i < e; ++i)
				fn(t[i].point, t[i].b0, t[i].b1);
		}

	private:
		friend class CReferenceCloud;
		struct TRecord
		{
			std::mutex mutex;
			std::vector<uint32_t> first, end;  //!< per anchor: its terms' range in `terms`
			std::vector<TFitTerm> terms;
		};
		static constexpr uint32_t kNotRecorded = ~uint32_t(0);
		CFitTermReader(const CReferenceCloud& cloud, TRecord* rec) : m_cloud(&cloud), m_rec(rec)
		{
			if (rec) m_lock = std::unique_lock<std::mutex>(rec->mutex);
		}
		const CReferenceCloud* m_cloud;
		TRecord* m_rec;
		std::unique_lock<std::mutex> m_lock;
	};
	CFitTermReader fitTermReader() const { return CFitTermReader(*this, m_fitTerms.get()); }
	/** This cloud's fitTermReader() records the terms it reads: for a cloud matched many
	 * times (memory: 12 bytes a term read); a cloud matched once gains nothing from it. */
	void recordFitTerms() { m_fitTerms = std::make_shared<CFitTermReader::TRecord>(); }
	double pointVariance(size_t k) const { return m_noiseVar / m_count[k]; }
	/** Estimated range noise variance of one raw input point along the surface normal [m^2]. */
	double noiseVariance() const { return m_noiseVar; }
	/** The voxel side [m] for points of noise std sigma [m] (noiseVariance()): the widest
	 * res 2^k (k >= 0) not above sigma, nor above maxCell; res if none. A cell no wider
	 * than the noise adds a quantisation variance (side^2 / 12) of at most a twelfth of the
	 * noise's, and finer cells only split one noisy stretch of wall into more reduced points
	 * that differ by noise alone: the fits read more points for the same line, and widen. */
	static double cellForNoise(double res, double sigma, double maxCell);

	/** Free-space consistency of an alignment, in both directions, as a fraction [0..1]:
	 *  - scan -> ref: scan points (in scan order) lying, by more than margin [m], in front of
	 *    the returns of a reference scan (where its beams passed), counted only when a
	 *    neighbour in scan order within 0.3 m does too (walls, not isolated spurious returns);
	 *    over all scan points; needs a reference built from scans (else 0);
	 *  - ref -> scan: LINE anchors lying in front of the scan's own returns, over the LINE
	 *    anchors inside the scan's observed rays; an anchor that lies in the free space of one
	 *    of the reference's own views (a porous surface: glass, a railing) never counts.
	 * Returns the larger. A wrong alignment moves walls into space the other side saw empty.
	 * `parallel`, if given, runs the two directions' tests in parts on a cloud of several
	 * views (kFreeSpaceParts ranges of the scan's points, as many of the anchors; flags and
	 * integer counts, so the same value on any threads). With minRun_m > 0 the scan -> ref
	 * share counts only runs of at least that length (CScanViolation::share). */
	double freeSpaceViolation(const TScan2D& scan, const mrpt::math::TPose2D& scanInRef,
							  double margin, const TParallelFor& parallel = {},
							  double minRun_m = 0) const;

	/** Calls fn(index) for every usable anchor within radius [m] of q. */
	template <class F>
	void forEachWithin(const Eigen::Vector2d& q, double radius, F&& fn) const
	{
		m_grid.forEachWithin(q, radius, std::forward<F>(fn));
	}

private:
	/** Parts per direction of a parallel freeSpaceViolation: a window patch's check is
	 * 0.1-0.5 ms (a scan's points times 15 views, and ~5000 anchors), one job for the
	 * window's helper, which idles during the plain match. */
	static constexpr size_t kFreeSpaceParts = 2;
	/** freeSpaceViolation's ref -> scan test on anchors [begin, end): (known, violating). */
	std::pair<size_t, size_t> anchorsInFreeSpace(const CRangeImage& img,
												 const mrpt::math::TPose2D& refInScan,
												 double margin, size_t begin, size_t end) const;
	/** Indexes the usable anchors at their current positions in m_grid, cells of side `cell`
	 * [m] (radiusOnly: CAnchorGrid's). */
	void buildGrid(double cell, bool radiusOnly = false);
	/** The nearest-anchor grid's cell side over the fits' grid's (see the constructor). */
	static constexpr double kNearestCellsPerFitCell = 3;
	/** Line fits in blocks of kFitsPerBlock anchors (the unit `parallel` hands out). */
	static constexpr size_t kFitsPerBlock = 64;
	void fitLines(const TScanMatcherParams& p, const std::vector<double>& weights,
				  const TParallelFor& parallel);
	/** Sets `sigma2` to the fit's noise estimate if anchor i is a LINE (else leaves it). */
	Eigen::Vector2d fitAnchor(size_t i, const TScanMatcherParams& p,
							  const std::vector<double>& w, double& sigma2);

	std::vector<TAnchor> m_anchors;
	CAnchorGrid m_grid;
	size_t m_inputCount = 0;
	CFreeSpaceViews m_views;  // one per scan the cloud was built from
	/** fromScans keeping only the points (in ref) for which keep() is true (all if empty). */
	static CReferenceCloud fromScansWhere(
		const std::vector<TScan2D>& scans, const std::vector<mrpt::math::TPose2D>& scansInRef,
		const TScanMatcherParams& p, const std::function<bool(const Eigen::Vector2d&)>& keep,
		const TParallelFor& parallel = {}, bool withViews = true);
	std::vector<double> m_count;  // raw points per reduced point
	// What forEachFitTerm needs of each LINE anchor's fit: its neighbourhood (the reduced
	// points before they were moved onto their lines, indexed by m_rawGrid, within radius [m]
	// of centre), their weighted mean [m], total weight W and sum w u^2 [m^2] (u along the
	// tangent). Frame: ref.
	struct TLineFit
	{
		Eigen::Vector2d centre{0, 0}, mean{0, 0};
		double radius = 0, W = 0, suu = 0;
	};
	std::vector<TLineFit> m_lineFits;  // one per anchor (unused for POINT anchors)
	CAnchorGrid m_rawGrid;
	double m_noiseVar = 0;  // [m^2]
	/** fitTermReader()'s record (recordFitTerms(); else none); shared by copies of the cloud
	 * (the same fits). */
	std::shared_ptr<CFitTermReader::TRecord> m_fitTerms;
};

}  // namespace lrgc
