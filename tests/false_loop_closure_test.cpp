/* A false loop closure injected into a real map: the graph that CMetricMapBuilderLRGC built
 * from a synthetic run (a grid of identical rooms, drifting odometry, loops closed) receives
 * one confident but wrong LoopClosure link (sigma 2 cm / 0.5 deg), and CPoseGraphOptimizer
 * optimises the whole graph. The robust back-end must report exactly that link in
 * downweightedLinks (none of the builder's own, true, loop links) and the poses must barely
 * move; with plain least squares the same link bends the map, so the check can fail. */
#include <gtest/gtest.h>
#include <lrgc/pose_graph/PoseGraphOptimizer.h>
#include <lrgc/common/se2.h>

#include <algorithm>
#include <functional>
#include <ostream>

#include "synthetic_run.h"

using namespace lrgc::test;
using lrgc::CPoseGraph;
using lrgc::CPoseGraphOptimizer;
using lrgc::TLink;
using mrpt::math::TPose2D;

namespace
{
struct TBuiltMap
{
	CPoseGraph graph;
	std::vector<TPose2D> truth;  //!< true keyframe poses in the map frame
	size_t loopLinks = 0;        //!< enabled LoopClosure links the builder added
};

const TBuiltMap& builtMap()
{
	static const TBuiltMap m = []
	{
		const auto world = makeRepeatedRoomsWorld(3, 2, 6.0, 1.0);
		const auto tr = makeTrajectory({{1.5, 3}, {15, 3}, {15, 9}, {3, 9}, {3, 3}, {10, 3}},
									   0.2, TOdometryNoise{}, 13);
		TSyntheticRunOptions opt;
		opt.laser.maxRange = 10;
		// Keyframes on the revisited leg too (without keyframe reuse): the injected links
		// pair keyframes of the two passes.
		lrgc::TLRGCParams p;
		p.reuse.enabled = false;
		lrgc::CMetricMapBuilderLRGC builder(p);
		feedBuilder(builder, world, tr, opt);
		TBuiltMap b{builder.graph(), trueKeyframePoses(builder, tr.truePoses), 0};
		for (size_t id = 0; id < b.graph.numLinks(); ++id)
			b.loopLinks += b.graph.link(id).type == lrgc::LinkType::LoopClosure &&
						   b.graph.isLinkEnabled(id);
		return b;
	}();
	return m;
}

struct TFalseLink
{
	const char* name;
	/** Picks (from, to) and the false measurement from the true keyframe poses. */
	std::function<TLink(const std::vector<TPose2D>&)> make;
	double minBendWithoutDcs;  //!< [m] least squares must move some pose at least this much
};
void PrintTo(const TFalseLink& f, std::ostream* os)
{
	*os << f.name;
}

TLink confident(size_t from, size_t to, const TPose2D& z)
{
	const Eigen::Vector3d sigma(0.02, 0.02, 0.5 * M_PI / 180);
	return {from, to, z, sigma.cwiseProduct(sigma).cwiseInverse().asDiagonal(),
			lrgc::LinkType::LoopClosure};
}

/** The first pair (a, b) whose true relation is close to `offset` in the map frame, with
 * headings differing by less than maxTurn [rad]. */
std::pair<size_t, size_t> pairAt(const std::vector<TPose2D>& t, const Eigen::Vector2d& offset,
								 double tol, double maxTurn = 0.1)
{
	for (size_t a = 0; a < t.size(); ++a)
		for (size_t b = a + 1; b < t.size(); ++b)
			if ((Eigen::Vector2d(t[b].x - t[a].x, t[b].y - t[a].y) - offset).norm() < tol &&
				std::abs(lrgc::between(t[a], t[b]).phi) < maxTurn)
				return {a, b};
	throw std::runtime_error("no keyframe pair at the requested offset");
}

double maxPositionChange(const CPoseGraph& a, const CPoseGraph& b)
{
	double m = 0;
	for (size_t i = 0; i < a.numNodes(); ++i)
		m = std::max(m, lrgc::translationNorm(lrgc::between(a.pose(i), b.pose(i))));
	return m;
}
double maxHeadingChange(const CPoseGraph& a, const CPoseGraph& b)
{
	double m = 0;
	for (size_t i = 0; i < a.numNodes(); ++i)
		m = std::max(m, std::abs(lrgc::between(a.pose(i), b.pose(i)).phi));
	return m;
}

class FalseLoopClosure : public ::testing::TestWithParam<TFalseLink>
{
};
}  // namespace

TEST_P(FalseLoopClosure, isDownweightedAndThePosesBarelyMove)
{
	const TBuiltMap& m = builtMap();
	ASSERT_GT(m.loopLinks, 0U) << "the run should have closed its loop";
	// The builder's final map is the reference (finish() optimised it); optimise it once more
	// without the false link so that "before" is the optimiser's own fixed point.
	CPoseGraph before = m.graph;
	CPoseGraphOptimizer().optimize(before, 0);

	const TLink bad = GetParam().make(m.truth);
	const TPose2D truthRel = lrgc::between(m.truth[bad.from], m.truth[bad.to]);
	ASSERT_GT(lrgc::translationNorm(lrgc::between(truthRel, bad.toInFrom)), 0.4)
		<< "the link must be false";

	CPoseGraph g = before;
	const size_t id = g.addLink(bad);
	const auto report = CPoseGraphOptimizer().optimize(g, 0);
	EXPECT_EQ(report.downweightedLinks, std::vector<size_t>{id})
		<< "exactly the injected link must be reported (no true loop link of the builder)";
	EXPECT_LT(maxPositionChange(before, g), 0.02);
	EXPECT_LT(maxHeadingChange(before, g), 0.2 * M_PI / 180);
	RecordProperty("max_position_change_m", std::to_string(maxPositionChange(before, g)));

	// Plain least squares on the same graph: the link bends the map.
	lrgc::TPoseGraphOptimizerParams plain;
	plain.robust_loop_closures = false;
	CPoseGraph bent = before;
	bent.addLink(bad);
	CPoseGraphOptimizer(plain).optimize(bent, 0);
	EXPECT_GT(maxPositionChange(before, bent), GetParam().minBendWithoutDcs);
}

INSTANTIATE_TEST_SUITE_P(
	BuilderGraph, FalseLoopClosure,
	::testing::Values(
		// Perceptual aliasing: a keyframe claimed to be at its twin's place one room west.
		TFalseLink{"AliasedTwinOneRoomAway",
				   [](const std::vector<TPose2D>& kf)
				   {
					   const auto [a, b] = pairAt(kf, {6.0, 0.0}, 0.3);
					   const TPose2D twin(kf[b].x - 6.0, kf[b].y, kf[b].phi);
					   return confident(a, b, lrgc::between(kf[a], twin));
				   },
				   0.3},
		// Two keyframes far apart claimed to be at the same pose.
		TFalseLink{"SamePlaceAcrossTheMap",
				   [](const std::vector<TPose2D>& kf)
				   {
					   const auto [a, b] = pairAt(kf, {12.0, 6.0}, 1.5, M_PI);
					   return confident(a, b, TPose2D(0, 0, 0));
				   },
				   0.3},
		// A subtle one: neighbours 1 m apart, the link off by 0.5 m and 6 deg.
		TFalseLink{"HalfAMetreOffNearby",
				   [](const std::vector<TPose2D>& kf)
				   {
					   const auto [a, b] = pairAt(kf, {1.0, 0.0}, 0.15);
					   return confident(
						   a, b,
						   lrgc::compose(lrgc::between(kf[a], kf[b]), TPose2D(0.3, 0.4, 0.1)));
				   },
				   0.05}),
	[](const ::testing::TestParamInfo<TFalseLink>& p) { return std::string(p.param.name); });
