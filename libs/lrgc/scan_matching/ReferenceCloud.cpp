/* CReferenceCloud: voxel reduction, local line fits (PCA) and their noise model. See the
 * header for the method; the formulas are below. */
#include <lrgc/scan_matching/ReferenceCloud.h>

#include <lrgc/scan_matching/ScanMatcher.h>
#include <lrgc/common/OrderStatistic.h>
#include <lrgc/common/se2.h>
#include <mrpt/core/exceptions.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <functional>
#include <limits>
#include <numeric>
#include <optional>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace lrgc
{
namespace
{
int64_t cellIndex(double v, double cell)
{
	return CAnchorGrid::cellIndex(v, cell);
}

/** Points averaged per square cell of side `res`: returns means and counts (as weights). */
void voxelReduce(const std::vector<Eigen::Vector2d>& pts, double res,
				 std::vector<Eigen::Vector2d>& out, std::vector<double>& weights)
{
	std::vector<std::pair<std::pair<int64_t, int64_t>, uint32_t>> keyed;
	keyed.reserve(pts.size());
	for (uint32_t i = 0; i < pts.size(); ++i)
		if (pts[i].allFinite())
			keyed.push_back({{cellIndex(pts[i].x(), res), cellIndex(pts[i].y(), res)}, i});
	std::sort(keyed.begin(), keyed.end());
	out.clear();
	weights.clear();
	for (size_t k = 0; k < keyed.size();)
	{
		Eigen::Vector2d sum(0, 0);
		size_t m = k;
		for (; m < keyed.size() && keyed[m].first == keyed[k].first; ++m)
			sum += pts[keyed[m].second];
		out.push_back(sum / double(m - k));
		weights.push_back(double(m - k));
		k = m;
	}
}
}  // namespace

CReferenceCloud::CReferenceCloud(std::vector<Eigen::Vector2d> pointsInRef,
								 const TScanMatcherParams& p, const TParallelFor& parallel)
{
	p.validate();
	m_inputCount = pointsInRef.size();
	std::vector<Eigen::Vector2d> reduced;
	std::vector<double> weights;
	voxelReduce(pointsInRef, p.ref_resolution_m, reduced, weights);
	m_anchors.resize(reduced.size());
	for (size_t i = 0; i < reduced.size(); ++i) m_anchors[i].pos = reduced[i];
	// Cell side of the fits' grid: a few reduced points per cell along a wall.
	const double fitCell = std::max(0.1, 3 * p.ref_resolution_m);
	buildGrid(fitCell, true);  // for the fits' radius queries only
	fitLines(p, weights, parallel);
	m_rawGrid = std::move(m_grid);  // the fits' neighbourhoods, for forEachFitTerm
	// The nearest-anchor grid (line anchors moved, by about the noise, onto their lines), on
	// cells kNearestCellsPerFitCell times wider: a correspondence search walks rings of cells
	// until its best distance is below the unvisited cells' (2.4-3 rings of 0.1 m cells on
	// average, 4 table runs a ring, on ACES and range_030_bearing_015), and wider cells need
	// fewer rings for a few more points each. The answers are the same (exact search).
	buildGrid(kNearestCellsPerFitCell * fitCell);
}

double CReferenceCloud::cellForNoise(double res, double sigma, double maxCell)
{
	double cell = res;
	while (2 * cell <= sigma && 2 * cell <= maxCell) cell *= 2;
	return cell;
}

CReferenceCloud CReferenceCloud::fromScan(const TScan2D& scan, const TScanMatcherParams& p)
{
	CReferenceCloud c(scan.points, p);
	c.m_views.add(scan, mrpt::math::TPose2D(0, 0, 0));
	return c;
}

double CReferenceCloud::freeSpaceViolation(const TScan2D& scan,
										   const mrpt::math::TPose2D& scanInRef, double margin,
										   const TParallelFor& parallel, double minRun_m) const
{
	if (scan.points.empty()) return 0;
	CScanViolation scanToRef(m_views, scan, scanInRef, margin);
	// ref -> scan: LINE anchors in front of the scan's own returns, but for those the
	// reference's own views saw through too: a pane that returns some beams and passes the
	// others, a railing's posts, a mixed pixel are porous, and the scan seeing past them is
	// no sign of a wrong alignment (a glass-and-railings building: 30-60 % of the anchors of
	// right matches, which were refused). The test is run only on violating anchors.
	const auto img = rangeImageOf(scan);
	const auto refInScan = inverse(scanInRef);
	// Parts 0..kFreeSpaceParts-1: ranges of the scan's points; the next ones: of the anchors.
	constexpr size_t kParts = kFreeSpaceParts;
	std::pair<size_t, size_t> counts[kParts];
	const size_t nPts = scanToRef.size(), nAnchors = m_anchors.size();
	auto part = [&](size_t i)
	{
		if (i < kParts)
			scanToRef.flag(i * nPts / kParts, (i + 1) * nPts / kParts);
		else
			counts[i - kParts] =
				anchorsInFreeSpace(*img, refInScan, margin, (i - kParts) * nAnchors / kParts,
								   (i - kParts + 1) * nAnchors / kParts);
	};
	// In parts only for a cloud of several views (a window patch): one scan's cloud (a
	// pairwise link's) is tested in a few microseconds, less than a job for another thread.
	if (parallel && m_views.size() > 1)
		parallel(2 * kParts, part);
	else
		for (size_t i = 0; i < 2 * kParts; ++i) part(i);
	size_t known = 0, viol = 0;
	for (const auto& [k, v] : counts) known += k, viol += v;
	const double refToScan = known >= 20 ? static_cast<double>(viol) / known : 0.0;
	return std::max(scanToRef.share(minRun_m), refToScan);
}

std::pair<size_t, size_t> CReferenceCloud::anchorsInFreeSpace(
	const CRangeImage& img, const mrpt::math::TPose2D& refInScan, double margin, size_t begin,
	size_t end) const
{
	const double c1 = std::cos(refInScan.phi), s1 = std::sin(refInScan.phi);
	size_t known = 0, viol = 0;
	for (size_t i = begin; i < end; ++i)
	{
		const TAnchor& a = m_anchors[i];
		if (!a.isLine) continue;
		bool k = false;
		const Eigen::Vector2d d(refInScan.x + c1 * a.pos.x() - s1 * a.pos.y(),
								refInScan.y + s1 * a.pos.x() + c1 * a.pos.y());
		const bool v = img.inFreeSpace(d, margin, &k);
		known += k, viol += v && k && !m_views.seenThrough(a.pos, margin);
	}
	return {known, viol};
}

CReferenceCloud CReferenceCloud::fromScansWhere(
	const std::vector<TScan2D>& scans, const std::vector<mrpt::math::TPose2D>& scansInRef,
	const TScanMatcherParams& p, const std::function<bool(const Eigen::Vector2d&)>& keep,
	const TParallelFor& parallel, bool withViews)
{
	if (scans.size() != scansInRef.size())
		THROW_EXCEPTION_FMT("CReferenceCloud::fromScans: %zu scans but %zu poses", scans.size(),
							scansInRef.size());
	std::vector<Eigen::Vector2d> pts;
	size_t n = 0;
	for (const auto& s : scans) n += s.points.size();
	pts.reserve(n);
	for (size_t k = 0; k < scans.size(); ++k)
	{
		const CPointTransform toRef(scansInRef[k]);
		for (const auto& q : scans[k].points)
			if (const Eigen::Vector2d r = toRef(q); !keep || keep(r)) pts.push_back(r);
	}
	CReferenceCloud c(std::move(pts), p, parallel);
	if (withViews)
		for (size_t k = 0; k < scans.size(); ++k) c.m_views.add(scans[k], scansInRef[k]);
	return c;
}

CReferenceCloud CReferenceCloud::fromScans(const std::vector<TScan2D>& scans,
										   const std::vector<mrpt::math::TPose2D>& scansInRef,
										   const TScanMatcherParams& p,
										   const TParallelFor& parallel)
{
	return fromScansWhere(scans, scansInRef, p, {}, parallel);
}

CReferenceCloud CReferenceCloud::fromScansNear(
	const std::vector<TScan2D>& scans, const std::vector<mrpt::math::TPose2D>& scansInRef,
	const TScanMatcherParams& p, const std::vector<Eigen::Vector2d>& nearInRef, double margin,
	const TParallelFor& parallel, bool withViews)
{
	if (!(margin > 0))
		THROW_EXCEPTION_FMT("CReferenceCloud::fromScansNear: margin %g m must be > 0", margin);
	// Cells of side `margin` holding a query point, dilated by one cell: every point within
	// `margin` of a query point lies in a marked cell, and a point in a marked cell is within
	// 2 sqrt(2) margin of one.
	std::vector<std::pair<int64_t, int64_t>> marked;
	marked.reserve(9 * nearInRef.size());
	for (const auto& q : nearInRef)
	{
		if (!q.allFinite()) continue;
		const int64_t ix = cellIndex(q.x(), margin), iy = cellIndex(q.y(), margin);
		for (int64_t dx = -1; dx <= 1; ++dx)
			for (int64_t dy = -1; dy <= 1; ++dy) marked.emplace_back(ix + dx, iy + dy);
	}
	std::sort(marked.begin(), marked.end());
	marked.erase(std::unique(marked.begin(), marked.end()), marked.end());
	return fromScansWhere(
		scans, scansInRef, p,
		[&](const Eigen::Vector2d& r)
		{
			return std::binary_search(
				marked.begin(), marked.end(),
				std::pair{cellIndex(r.x(), margin), cellIndex(r.y(), margin)});
		},
		parallel, withViews);
}

void CReferenceCloud::buildGrid(double cell, bool radiusOnly)
{
	std::vector<Eigen::Vector2d> pos(m_anchors.size());
	std::vector<bool> usable(m_anchors.size());
	for (size_t i = 0; i < m_anchors.size(); ++i)
		pos[i] = m_anchors[i].pos, usable[i] = m_anchors[i].usable;
	m_grid = CAnchorGrid(pos, usable, cell, radiusOnly);
}

namespace
{
/** Weighted moments of the reduced points within r of x, relative to x (for numerical range):
 * W = sum w, s = sum w dx, S = sum w dx dx^T; count of points; with kNearest, the squared
 * distance [m^2] from x to the nearest other point (else left infinite). */
struct TMoments
{
	double W = 0, sx = 0, sy = 0, sxx = 0, sxy = 0, syy = 0;
	size_t count = 0;
	double nearest2 = std::numeric_limits<double>::infinity();
};

template <bool kNearest>
TMoments momentsWithin(const CAnchorGrid& grid, const std::vector<double>& w, size_t self,
					   const Eigen::Vector2d& x, double r)
{
	// Local scalar sums over the query's runs stay in registers (summed into a TMoments
	// through forEachPointWithin they lived on the stack: a store and a load on each sum's
	// dependency chain per point). Same points, same order, same operations as
	// forEachPointWithin: the same sums, bit for bit.
	const Eigen::Vector2d* pos = grid.cellPoints().data();
	const uint32_t* index = grid.cellIndices().data();
	const double* wp = w.data();
	const double r2 = r * r;
	double W = 0, sx = 0, sy = 0, sxx = 0, sxy = 0, syy = 0;
	double nearest2 = std::numeric_limits<double>::infinity();
	size_t count = 0;
#if defined(__SSE2__)
	// The same sums with (sx, sy) and (sxx, syy) as lanes of one register each: every lane
	// computes what its scalar does, (wk dx) dx and (wk dy) dy as wk * dx * dx and wk * dy *
	// dy, so the sums are bit for bit the scalar loop's below.
	const __m128d xv = _mm_loadu_pd(x.data());
	__m128d s1 = _mm_setzero_pd(), s2 = _mm_setzero_pd();
	grid.forEachRun(x, r,
					[&](uint32_t b, uint32_t e)
					{
						for (uint32_t k = b; k < e; ++k)
						{
							const __m128d d = _mm_sub_pd(_mm_loadu_pd(pos[k].data()), xv);
							const __m128d d2v = _mm_mul_pd(d, d);
							const double d2 = _mm_cvtsd_f64(
								_mm_add_sd(d2v, _mm_unpackhi_pd(d2v, d2v)));  // dx dx + dy dy
							if (!(d2 <= r2)) continue;
							const double wk = wp[index[k]];
							const __m128d wd = _mm_mul_pd(_mm_set1_pd(wk), d);  // wk dx, wk dy
							W += wk;
							s1 = _mm_add_pd(s1, wd);
							s2 = _mm_add_pd(s2, _mm_mul_pd(wd, d));
							sxy += _mm_cvtsd_f64(wd) * _mm_cvtsd_f64(_mm_unpackhi_pd(d, d));
							++count;
							if (kNearest && index[k] != self) nearest2 = std::min(nearest2, d2);
						}
					});
	double lanes[4];
	_mm_storeu_pd(lanes, s1);
	_mm_storeu_pd(lanes + 2, s2);
	sx = lanes[0], sy = lanes[1], sxx = lanes[2], syy = lanes[3];
#else
	grid.forEachRun(x, r,
					[&](uint32_t b, uint32_t e)
					{
						for (uint32_t k = b; k < e; ++k)
						{
							if (!((pos[k] - x).squaredNorm() <= r2)) continue;
							const double wk = wp[index[k]], dx = pos[k].x() - x.x(),
										 dy = pos[k].y() - x.y();
							W += wk, sx += wk * dx, sy += wk * dy;
							sxx += wk * dx * dx, sxy += wk * dx * dy, syy += wk * dy * dy;
							++count;
							if (kNearest && index[k] != self)
								nearest2 = std::min(nearest2, dx * dx + dy * dy);
						}
					});
#endif
	return TMoments{W, sx, sy, sxx, sxy, syy, count, nearest2};
}

/** The weighted PCA of the moments: mean m [map frame], tangent t and normal n, eigenvalues
 * l1 >= l2 of C in closed form. */
struct TLineFromMoments
{
	Eigen::Vector2d m, t, n;
	double l1 = 0, l2 = 0;
};

/** A line if at least 4 points and thickness sqrt(l2) < 0.25 sqrt(l1); else none. */
std::optional<TLineFromMoments> lineOf(const TMoments& mo, const Eigen::Vector2d& x)
{
	if (mo.count < 4) return std::nullopt;
	const double W = mo.W;
	const double mx = mo.sx / W, my = mo.sy / W;
	const double cxx = mo.sxx / W - mx * mx, cxy = mo.sxy / W - mx * my,
				 cyy = mo.syy / W - my * my;
	TLineFromMoments f;
	f.m = x + Eigen::Vector2d(mx, my);
	const double tr = cxx + cyy,
				 disc = std::sqrt(std::max(0.0, 0.25 * (cxx - cyy) * (cxx - cyy) + cxy * cxy));
	f.l1 = 0.5 * tr + disc, f.l2 = std::max(0.0, 0.5 * tr - disc);
	if (!(f.l1 > 0) || f.l2 > 0.0625 * f.l1) return std::nullopt;
	// Tangent: eigenvector of l1, (l1 - cyy, cxy) or (cxy, l1 - cxx), whichever is longer (both
	// are, unless one vanishes); the normal is its perpendicular.
	const Eigen::Vector2d v1(f.l1 - cyy, cxy), v2(cxy, f.l1 - cxx);
	const Eigen::Vector2d tdir = (v1.squaredNorm() >= v2.squaredNorm() ? v1 : v2).normalized();
	f.n = Eigen::Vector2d(-tdir.y(), tdir.x());
	f.t = Eigen::Vector2d(-f.n.y(), f.n.x());
	return f;
}
}  // namespace

void CReferenceCloud::fitLines(const TScanMatcherParams& p, const std::vector<double>& w,
							   const TParallelFor& parallel)
{
	// Weighted PCA of the neighbourhood N (weights = raw points per voxel):
	//   mean m = sum w_k x_k / W,  C = sum w_k (x_k - m)(x_k - m)^T / W,
	// eigenvalues l1 >= l2 with eigenvectors t (tangent), n (normal). A LINE if at least 4
	// reduced points and thickness sqrt(l2) < 0.25 * sqrt(l1) (spread along the line); then the
	// anchor is the point projected onto the line: a = m + ((x - m) . t) t.
	// Noise model of the anchors (used by the covariance): the line's offset at the anchor,
	// delta_j = sum_k beta_jk nu_k, with nu_k the normal-direction noise of reduced point k
	// (variance sigma^2 / w_k) and, from the weighted least-squares line,
	//   beta_jk = w_k / W + u_j w_k u_k / sum_l w_l u_l^2,   u = (x - m) . t.
	// sigma^2 per raw point is estimated from each fit, l2 W / (n - 2), and its median kept.
	// The beta_jk are not stored: forEachFitTerm recomputes them from the fit (m, W, sum w
	// u^2). Each fit reads the grid (the positions before any moved) and writes its own
	// anchor only: blocks of them may run on any threads, and the noise estimates are
	// collected in anchor order afterwards, so the cloud is the same bit for bit.
	const size_t n = m_anchors.size();
	std::vector<Eigen::Vector2d> newPos(n);
	std::vector<double> fitSigma2(n);
	m_count = w;
	m_lineFits.assign(n, TLineFit{});
	auto fitBlock = [&](size_t block)
	{
		const size_t end = std::min(n, (block + 1) * kFitsPerBlock);
		for (size_t i = block * kFitsPerBlock; i < end; ++i)
			newPos[i] = fitAnchor(i, p, w, fitSigma2[i]);
	};
	const size_t blocks = (n + kFitsPerBlock - 1) / kFitsPerBlock;
	if (parallel && blocks > 1)
		parallel(blocks, fitBlock);
	else
		for (size_t block = 0; block < blocks; ++block) fitBlock(block);
	std::vector<double> sigma2;
	for (size_t i = 0; i < n; ++i)
	{
		m_anchors[i].pos = newPos[i];
		if (m_anchors[i].isLine) sigma2.push_back(fitSigma2[i]);
	}
	m_noiseVar = p.min_residual_std_m * p.min_residual_std_m;
	if (!sigma2.empty()) m_noiseVar = std::max(m_noiseVar, upperMedian(sigma2));
	for (auto& a : m_anchors) a.normalVar = static_cast<float>(a.normalVar * m_noiseVar);
}

// Anchor i's line fit (fitLines): the neighbourhood is widened (radius r0, 2 r0, 4 r0) while it
// has too few points or is too thick: range noise thickens a small neighbourhood, a corner
// stays thick at every size. Then, where the far fit is on, once more within R = range x
// far_fit_angle (capped), if that is wider: a wall at range r is sampled every r x (beam
// spacing) by one scan, R = 3 deg x r holds three such returns of a 1-degree laser either
// side. Returns the anchor's position (projected onto its line); sets `sigma2` to the fit's
// noise estimate l2 W / (n - 2).
Eigen::Vector2d CReferenceCloud::fitAnchor(size_t i, const TScanMatcherParams& p,
										   const std::vector<double>& w, double& sigma2)
{
	const Eigen::Vector2d x = m_anchors[i].pos;
	const double r0 = p.normal_radius_m;
	double r = r0;
	TMoments mo;
	// Anchor i made a LINE by the fit f of the moments m within radius [m].
	const auto toLine = [&](const TMoments& m, const TLineFromMoments& f, double radius)
	{
		TAnchor& a = m_anchors[i];
		a.normal = f.n;
		a.isLine = true;
		a.fitRadius = static_cast<float>(radius);
		// sum w u^2 = W t^T C t = W l1 (t is C's eigenvector of l1).
		const double suu = m.W * f.l1;
		m_lineFits[i] = TLineFit{x, f.m, radius, m.W, suu};
		a.u = static_cast<float>((x - f.m).dot(f.t));
		// slope variance sigma^2 / sum w u^2, sigma^2 filled in by fitLines
		a.normalVar = static_cast<float>(suu > 0 ? 1 / suu : 0);
		sigma2 = f.l2 * m.W / static_cast<double>(m.count - 2);
		return Eigen::Vector2d(f.m + (x - f.m).dot(f.t) * f.t);
	};
	for (int widen = 0; widen < 3; ++widen, r *= 2)
	{
		// Only the widest neighbourhood's nearest neighbour is used (below the loop).
		mo = widen < 2 ? momentsWithin<false>(m_grid, w, i, x, r)
					   : momentsWithin<true>(m_grid, w, i, x, r);
		if (const auto f = lineOf(mo, x)) return toLine(mo, *f, r);
	}
	const double far = std::min(p.far_fit_max_radius_m, x.norm() * p.far_fit_angle);
	if (far > 4 * r0)
	{
		const TMoments farMo = momentsWithin<false>(m_grid, w, i, x, far);
		if (const auto f = lineOf(farMo, x)) return toLine(farMo, *f, far);
	}
	// count and nearest2 are of the 4 r0 neighbourhood here (r is twice its radius now, as
	// the cap of the spacing).
	m_anchors[i].usable = mo.count >= 3;
	m_anchors[i].samplingVar = static_cast<float>(std::min(r * r, mo.nearest2) / 12);
	return x;
}

}  // namespace lrgc
