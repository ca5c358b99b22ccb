/* Continuing a saved map and localising on it (issue 14), in synthetic worlds with ground
 * truth: the whole graph comes back exactly; a plain CSimpleMap keeps its loops; a log that
 * starts at an unknown place in the old map is located by global correlation and continues
 * the map; a log mapped as a piece of its own from its first scan is joined to the map where
 * correlation finds it, the map held as it was; a localisation-only run tracks the robot and
 * relocalises after a kidnap. */
#include <gtest/gtest.h>
#include <lrgc/common/se2.h>
#include <lrgc/localization/Localizer.h>
#include <lrgc/localization/PieceJoiner.h>
#include <lrgc/localization/StartFinder.h>
#include <lrgc_apps/io/PoseGraphText.h>
#include <mrpt/maps/CSimpleMap.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/poses/CPose2D.h>

#include <algorithm>
#include <sstream>

#include "synthetic_run.h"

using namespace lrgc::test;
using lrgc::CMetricMapBuilderLRGC;
using lrgc::LinkType;
using lrgc::TLRGCParams;
using mrpt::math::TPose2D;

namespace
{
/** The observations of a synthetic run, step by step (as feedBuilder makes them). */
std::vector<std::pair<mrpt::obs::CObservation::Ptr, mrpt::obs::CObservation::Ptr>> steps(
	const CSyntheticWorld& world, const TTrajectory& tr, double t0, uint32_t seed)
{
	std::mt19937 rng(seed);
	TLaserSimParams laser;
	std::vector<std::pair<mrpt::obs::CObservation::Ptr, mrpt::obs::CObservation::Ptr>> out;
	for (size_t k = 0; k < tr.truePoses.size(); ++k)
	{
		const auto t = mrpt::Clock::fromDouble(t0 + 0.2 * double(k));
		auto odo = mrpt::obs::CObservationOdometry::Create();
		odo->timestamp = t;
		odo->odometry = mrpt::poses::CPose2D(tr.odometryPoses[k]);
		out.emplace_back(odo, laserObservationFromScan(
								  simulateScan(world, tr.truePoses[k], laser, rng), laser, t));
	}
	return out;
}

template <class Consumer>
void feed(Consumer& c,
		  const std::pair<mrpt::obs::CObservation::Ptr, mrpt::obs::CObservation::Ptr>& s)
{
	c.processObservation(s.first);
	c.processObservation(s.second);
}

/** RMS and max position error [m] of estimates (map = frame of `mapOrigin`) against truth. */
std::pair<double, double> errorInMap(const lrgc::TTrajectory& est,
									 const std::vector<TPose2D>& truth,
									 const TPose2D& mapOrigin, size_t from = 0)
{
	double s2 = 0, mx = 0;
	size_t n = 0;
	for (size_t k = from; k < est.size(); ++k)
	{
		const double d = lrgc::translationNorm(
			lrgc::between(truth[k], lrgc::compose(mapOrigin, est[k].robotInMap)));
		s2 += d * d, mx = std::max(mx, d), ++n;
	}
	return {std::sqrt(s2 / double(std::max<size_t>(n, 1))), mx};
}

/** Map A: the room, driven round twice (loops). */
struct TMapA
{
	CSyntheticWorld world = makeRoomWorld(42);
	TTrajectory tr = makeTrajectory(
		{{1.5, 1.2}, {8.5, 1.2}, {8.5, 5.8}, {1.5, 5.8}, {1.5, 1.2}, {8.5, 1.2}, {8.5, 5.8}},
		0.1, TOdometryNoise{}, 5);
	CMetricMapBuilderLRGC builder;
	/** reuse = false: the second round adds its keyframes too (as icp-slam's maps do). */
	explicit TMapA(bool reuse = true)
	{
		lrgc::TLRGCParams p;
		p.reuse.enabled = reuse;
		builder.setParams(p);
		TSyntheticRunOptions opt;
		feedBuilder(builder, world, tr, opt);
	}
};

size_t countLinks(const lrgc::CPoseGraph& g, LinkType type)
{
	size_t n = 0;
	for (size_t id = 0; id < g.numLinks(); ++id)
		n += g.isLinkEnabled(id) && g.link(id).type == type;
	return n;
}
}  // namespace

TEST(SavedMap, theWholeGraphComesBackExactly)
{
	const TMapA a;
	ASSERT_GT(countLinks(a.builder.graph(), LinkType::LoopClosure), 0U);
	std::istringstream text(lrgc::poseGraphToText(a.builder.graph(), a.builder.laserLabel()));
	const auto saved = lrgc::poseGraphFromText(text, "graph.lrgc");
	mrpt::maps::CSimpleMap keyframes;
	a.builder.getCurrentlyBuiltMap(keyframes);
	CMetricMapBuilderLRGC b;
	b.initialize(keyframes, saved.graph, saved.laserLabel);
	const auto &ga = a.builder.graph(), &gb = b.graph();
	ASSERT_EQ(gb.numNodes(), ga.numNodes());
	ASSERT_EQ(gb.numLinks(), ga.numLinks());
	for (size_t i = 0; i < ga.numNodes(); ++i)
	{
		EXPECT_EQ(gb.pose(i).x, ga.pose(i).x);
		EXPECT_EQ(gb.pose(i).y, ga.pose(i).y);
		EXPECT_EQ(gb.pose(i).phi, ga.pose(i).phi);
	}
	for (size_t id = 0; id < ga.numLinks(); ++id)
	{
		const auto &la = ga.link(id), &lb = gb.link(id);
		EXPECT_EQ(lb.from, la.from);
		EXPECT_EQ(lb.to, la.to);
		EXPECT_EQ(lb.type, la.type);
		EXPECT_EQ(gb.isLinkEnabled(id), ga.isLinkEnabled(id));
		EXPECT_EQ(lb.toInFrom.x, la.toInFrom.x);
		EXPECT_EQ(lb.toInFrom.phi, la.toInFrom.phi);
		EXPECT_EQ(lb.information, la.information);
	}
	EXPECT_EQ(b.keyframes().size(), ga.numNodes());
	EXPECT_TRUE(b.trajectory().empty());  // the old keyframes are not scans of this run
}

TEST(SavedMap, aPlainSimplemapKeepsItsPosesAndItsLoops)
{
	const TMapA a(false);  // a map whose keyframes revisit its places
	mrpt::maps::CSimpleMap keyframes;
	a.builder.getCurrentlyBuiltMap(keyframes);
	CMetricMapBuilderLRGC b;
	b.initialize(keyframes);
	const auto& g = b.graph();
	ASSERT_EQ(g.numNodes(), keyframes.size());
	for (size_t i = 0; i < g.numNodes(); ++i)
		EXPECT_NEAR(lrgc::translationNorm(lrgc::between(g.pose(i), a.builder.graph().pose(i))),
					0, 1e-9);
	// A chain of scan matches, and loop links where the map revisits its places (the room
	// is driven round twice): before the fix only the chain was there.
	EXPECT_EQ(countLinks(g, LinkType::ScanMatch) + countLinks(g, LinkType::Odometry),
			  g.numNodes() - 1);
	EXPECT_GT(countLinks(g, LinkType::ScanMatch), (g.numNodes() - 1) * 9 / 10);
	EXPECT_GE(countLinks(g, LinkType::LoopClosure), 5U);
}

TEST(SavedMap, aLogStartingAnywhereInTheMapIsLocatedAndContinuesIt)
{
	const TMapA a;
	mrpt::maps::CSimpleMap keyframes;
	a.builder.getCurrentlyBuiltMap(keyframes);
	std::istringstream text(lrgc::poseGraphToText(a.builder.graph(), a.builder.laserLabel()));
	const auto saved = lrgc::poseGraphFromText(text, "graph.lrgc");
	// Log B starts in the room's far corner facing back, and crosses the room.
	const TTrajectory trB = makeTrajectory({{8.0, 5.2}, {2.0, 5.2}, {2.0, 2.0}, {8.0, 2.0}},
										   0.1, TOdometryNoise{}, 9);
	const auto obsB = steps(a.world, trB, 2e9, 3);

	CMetricMapBuilderLRGC b;
	b.initialize(keyframes, saved.graph, saved.laserLabel);
	const size_t oldLoopLinks = countLinks(b.graph(), LinkType::LoopClosure);
	const lrgc::CGlobalLocalizer global(b.graph(), b.keyframes(), b.params().correlator);
	lrgc::CStartFinder finder(global, b.params(), {});
	std::optional<lrgc::TStartFound> found;
	size_t read = 0;
	while (!found && read < obsB.size())
		feed(finder.probe(), obsB[read++]), found = finder.tryLocate();
	ASSERT_TRUE(found) << "last rejection: " << finder.lastRejection();
	EXPECT_LT(read, 60U);
	const TPose2D start =
		lrgc::compose(found->probeInMap, finder.probe().trajectory().front().robotInMap);
	const TPose2D trueStart = lrgc::between(a.tr.truePoses.front(), trB.truePoses.front());
	EXPECT_LT(lrgc::translationNorm(lrgc::between(trueStart, start)), 0.1);
	b.startSessionAt(start, found->cov);
	for (const auto& s : obsB) feed(b, s);
	b.finish();

	ASSERT_EQ(b.trajectory().size(), trB.truePoses.size());
	const auto [rms, mx] = errorInMap(b.trajectory(), trB.truePoses, a.tr.truePoses.front());
	RecordProperty("rms_m", std::to_string(rms));
	// As good as mapping log B on its own (which has its own few-scan slip of 0.3 m near
	// its start in this world, at scans 10-12), now in the old map's frame.
	CMetricMapBuilderLRGC alone;
	for (const auto& s : obsB) feed(alone, s);
	alone.finish();
	const auto [rmsAlone, mxAlone] =
		errorInMap(alone.trajectory(), trB.truePoses, trB.truePoses.front());
	RecordProperty("rms_alone_m", std::to_string(rmsAlone));
	EXPECT_LT(rms, rmsAlone + 0.01);
	EXPECT_LT(mx, mxAlone + 0.05);
	std::vector<double> errors;
	for (size_t k = 0; k < trB.truePoses.size(); ++k)
		errors.push_back(lrgc::translationNorm(lrgc::between(
			trB.truePoses[k],
			lrgc::compose(a.tr.truePoses.front(), b.trajectory()[k].robotInMap))));
	std::nth_element(errors.begin(), errors.begin() + long(errors.size() / 2), errors.end());
	EXPECT_LT(errors[errors.size() / 2], 0.02);
	// B's loops to the old map closed: new loop links beyond the old map's own.
	EXPECT_GT(countLinks(b.graph(), LinkType::LoopClosure), oldLoopLinks + 5);
}

TEST(SavedMap, aLogMappedAsAPieceIsJoinedWhereCorrelationFindsIt)
{
	const TMapA a;
	mrpt::maps::CSimpleMap keyframes;
	a.builder.getCurrentlyBuiltMap(keyframes);
	std::istringstream text(lrgc::poseGraphToText(a.builder.graph(), a.builder.laserLabel()));
	const auto saved = lrgc::poseGraphFromText(text, "graph.lrgc");
	const TTrajectory trB = makeTrajectory({{8.0, 5.2}, {2.0, 5.2}, {2.0, 2.0}, {8.0, 2.0}},
										   0.1, TOdometryNoise{}, 9);
	const auto obsB = steps(a.world, trB, 2e9, 3);

	CMetricMapBuilderLRGC b;
	b.initialize(keyframes, saved.graph, saved.laserLabel);
	b.freezeMap();
	const size_t oldNodes = b.graph().numNodes();
	lrgc::CPieceJoiner joiner(b.graph(), b.keyframes(), b.params().correlator, {}, false);
	b.startPiece();
	std::optional<size_t> joinedAt;
	for (size_t k = 0; k < obsB.size(); ++k)
	{
		feed(b, obsB[k]);
		if (k == 0)  // the piece's frame: its first scan at its odometry pose
		{
			EXPECT_NEAR(lrgc::translationNorm(
							lrgc::between(trB.odometryPoses[0], b.trajectory()[0].robotInMap)),
						0, 1e-9);
		}
		if (!b.pieceFirstNode()) continue;
		if (const auto j = joiner.service(b, mrpt::Clock::toDouble(b.lastScanTimestamp())))
			b.joinPiece(j->node, j->nodeInMap, j->cov), joinedAt = k;
	}
	b.finish();
	ASSERT_TRUE(joinedAt) << "last rejection: " << joiner.lastRejection();
	EXPECT_LT(*joinedAt, 60U);
	EXPECT_FALSE(b.pieceFirstNode());
	for (size_t i = 0; i < oldNodes; ++i)  // frozen: the saved map as it was
		EXPECT_EQ(b.graph().pose(i).x, saved.graph.pose(i).x);
	// Every scan, those mapped before the join too, in the map's frame, as good as log B
	// mapped on its own (see the test above).
	ASSERT_EQ(b.trajectory().size(), trB.truePoses.size());
	const auto [rms, mx] = errorInMap(b.trajectory(), trB.truePoses, a.tr.truePoses.front());
	CMetricMapBuilderLRGC alone;
	for (const auto& s : obsB) feed(alone, s);
	alone.finish();
	const auto [rmsAlone, mxAlone] =
		errorInMap(alone.trajectory(), trB.truePoses, trB.truePoses.front());
	RecordProperty("rms_m", std::to_string(rms));
	RecordProperty("rms_alone_m", std::to_string(rmsAlone));
	EXPECT_LT(rms, rmsAlone + 0.01);
	EXPECT_LT(mx, mxAlone + 0.05);
}

TEST(SavedMap, localisationTracksTheRobotAndRelocalisesAfterAKidnap)
{
	const TMapA a;
	// Log B drives along the south wall, is carried (kidnapped) to the north-west corner
	// without its wheels knowing, and drives on east.
	const TTrajectory b1 = makeTrajectory({{2.0, 2.0}, {8.0, 2.0}}, 0.1, TOdometryNoise{}, 21);
	const TTrajectory b2 =
		makeTrajectory({{2.0, 5.3}, {8.0, 5.3}, {8.0, 3.0}}, 0.1, TOdometryNoise{}, 22);
	TTrajectory tr = b1;
	const TPose2D jumpOdo = tr.odometryPoses.back();
	for (size_t k = 0; k < b2.truePoses.size(); ++k)
	{
		tr.truePoses.push_back(b2.truePoses[k]);
		// The odometry goes on from where it was, with b2's own increments.
		tr.odometryPoses.push_back(lrgc::compose(
			jumpOdo, lrgc::between(b2.odometryPoses.front(), b2.odometryPoses[k])));
	}
	const auto obs = steps(a.world, tr, 3e9, 4);
	lrgc::CLocalizer loc(a.builder.graph(), a.builder.keyframes(), a.builder.params(), {});
	for (const auto& s : obs) feed(loc, s);

	const auto& st = loc.stats();
	EXPECT_TRUE(st.started);
	EXPECT_GE(st.lostEvents + st.kidnapEvents, 1U);
	EXPECT_GE(st.relocalizations, 1U);
	// Every scan has a pose: those read before the start was found get theirs from it.
	ASSERT_EQ(loc.trajectory().size(), tr.truePoses.size());
	EXPECT_GT(st.scansBeforeStart, 0U);
	const size_t offset = 0;
	const std::vector<TPose2D>& truth = tr.truePoses;
	// Before the kidnap, and over the second half of b2 (relocalised by then).
	lrgc::TTrajectory before(loc.trajectory().begin(),
							 loc.trajectory().begin() + long(b1.truePoses.size() - offset));
	const auto [rms1, max1] = errorInMap(before, truth, a.tr.truePoses.front());
	const size_t late = b1.truePoses.size() - offset + b2.truePoses.size() / 2;
	const auto [rms2, max2] = errorInMap(loc.trajectory(), truth, a.tr.truePoses.front(), late);
	RecordProperty("rms_before_m", std::to_string(rms1));
	RecordProperty("rms_after_m", std::to_string(rms2));
	EXPECT_LT(rms1, 0.03);
	EXPECT_LT(max1, 0.10);
	EXPECT_LT(rms2, 0.03);
	EXPECT_LT(max2, 0.10);
}
