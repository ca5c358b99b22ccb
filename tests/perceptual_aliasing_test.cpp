/* Perceptual aliasing: a 3 x 2 grid of identical, identically furnished 6 m rooms joined by
 * doorways, a loop through all six rooms and back through the first two, drifting odometry,
 * a 10 m laser (it sees through the doorways). Every place has a twin one room away. The
 * final map must hold no false loop closure: every enabled LoopClosure link of builder.graph()
 * agrees with the true relative pose of its two keyframes within 0.3 m / 5 deg (or within its
 * own stated covariance, see auditLoopLinks), and the
 * trajectory stays on the truth. Run twice: with the default loop closer, and with search
 * windows forced to span a whole room period (window_sigmas 20, max_window_xy_m 7 m) and a
 * looser local registration, so that every correlation sees an aliased twin inside its window
 * and aliased links reach the robust back-end. */
#include <gtest/gtest.h>
#include <lrgc/common/se2.h>

#include "synthetic_run.h"

using namespace lrgc::test;
using lrgc::CMetricMapBuilderLRGC;
using lrgc::TLRGCParams;

namespace
{
constexpr double kLinkTolXY = 0.3;                // [m]
constexpr double kLinkTolPhi = 5.0 * M_PI / 180;  // [rad]
constexpr double kRoom = 6.0;                     // [m] the aliasing period

struct TAliasingRun
{
	TTrajectory tr;
	TTrajectoryError error;
	TLoopLinkAudit links;
	lrgc::TLoopCloserStats loop;
	size_t loopClosures = 0;
};

TAliasingRun runRooms(const TLRGCParams& params)
{
	const auto world = makeRepeatedRoomsWorld(3, 2, kRoom, 1.0);
	TAliasingRun r;
	// Through the doorways: east along y = 3 through rooms (0,0), (1,0), (2,0), north into
	// (2,1), west through (1,1), (0,1), south back into (0,0) and east again into (1,0).
	r.tr = makeTrajectory({{1.5, 3}, {15, 3}, {15, 9}, {3, 9}, {3, 3}, {10, 3}}, 0.2,
						  TOdometryNoise{}, 13);
	EXPECT_GT(minClearance(world, r.tr.truePoses), 0.4);
	TSyntheticRunOptions opt;
	opt.laser.maxRange = 10;
	CMetricMapBuilderLRGC builder(params);
	feedBuilder(builder, world, r.tr, opt);
	EXPECT_EQ(builder.stats().scans, r.tr.truePoses.size());
	r.error = trajectoryError(builder.trajectory(), r.tr.truePoses);
	r.links = auditLoopLinks(builder, r.tr.truePoses, kLinkTolXY, kLinkTolPhi);
	r.loop = builder.loopCloserStats();
	r.loopClosures = builder.stats().loopClosures;
	return r;
}

void expectNoFalseLoopInTheMap(const TAliasingRun& r)
{
	EXPECT_EQ(r.links.enabledFalse, 0U)
		<< "false loop closure in the final map: " << r.links.firstEnabledFalse;
	::testing::Test::RecordProperty("worst_enabled_link_error_m",
									std::to_string(r.links.worstEnabledXY));
	// The loop through the rooms is closed with true links ...
	EXPECT_GT(r.loopClosures, 0U);
	EXPECT_GT(r.links.enabledTrue, 0U);
	// ... and the trajectory stays on the truth (odometry alone drifts metres).
	EXPECT_LT(r.error.maxXY, 0.10) << "worst scan " << r.error.worstIndex;
	EXPECT_LT(r.error.maxPhi, 2.0 * M_PI / 180);
	EXPECT_GT(trajectoryError(r.tr.odometryPoses, r.tr.truePoses).maxXY, 2.0);
}
}  // namespace

TEST(PerceptualAliasing, identicalRoomsDefaultLoopCloserKeepsNoFalseLoop)
{
	const TAliasingRun r = runRooms(TLRGCParams{});
	expectNoFalseLoopInTheMap(r);
	RecordProperty("false_links_rejected", std::to_string(r.links.disabledFalse));
}

TEST(PerceptualAliasing, identicalRoomsSearchWindowsSpanningARoomKeepNoFalseLoop)
{
	TLRGCParams p;
	p.loop.window_sigmas = 20;
	p.loop.max_window_xy_m = kRoom + 1;
	// With the default local registration (tight patch links) the drift stays so small that
	// the filters alone keep every aliased candidate out and the back-end is not exercised:
	// the window's links at the looser floor of earlier versions (1 cm / 0.25 deg) leave the
	// drift that lets aliased links through to the back-end.
	p.local.patch_link_noise = p.local.link_noise;
	const TAliasingRun r = runRooms(p);
	expectNoFalseLoopInTheMap(r);
	RecordProperty("false_links_rejected", std::to_string(r.links.disabledFalse));
	RecordProperty("correlations", std::to_string(r.loop.attempts));
	RecordProperty("true_links_rejected", std::to_string(r.links.disabledTrue));
	// The scenario does produce aliased candidates here (seen: links one room period off
	// that passed the correlation filters and the scan match): they must all have ended
	// disabled by the robust back-end, none in the map. If this count drops to zero the
	// scenario no longer exercises the back-end and should be made harder.
	EXPECT_GE(r.links.disabledFalse, 1U);
}
