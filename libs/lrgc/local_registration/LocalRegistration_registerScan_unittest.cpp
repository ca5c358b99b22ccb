/* CLocalRegistration::registerScan: a scan's pose from a rough prior, an odometry glitch (a
 * prior turned 70 deg wrongly) found only by the wide rotational search, a suspect step's
 * plain match in the wrong basin overruled by it (sparse scans), and a failed plain match
 * retried over the odometry's heading error (a long laser); a turn in place whose plain
 * match slides along a hall matched again at its heading (the glass atrium); a confident match
 * that only reverses the wheels' forward step along a corridor, which leaves the odometry
 * standing (a wide winner that only reverses it: LocalRegistration_forwardWinner_unittest.cpp).
 */
#include <gtest/gtest.h>
#include <lrgc/local_registration/LocalRegistration.h>
#include <lrgc/local_registration/MotionPredictor.h>
#include <lrgc/common/se2.h>

#include <cmath>
#include <random>

#include "LocalRegistration_unittest.h"

using namespace lrgc;
using namespace lrgc::test;
using mrpt::math::TPose2D;

TEST(LocalRegistration, registerScanFromARoughPriorAndAGlitchOnlyByTheWideSearch)
{
	const TKnownRun run;
	const auto& truth = run.tr.truePoses;
	TStageParams p;
	// A window of the first 6 keyframes at their true poses.
	CPoseGraph graph;
	TKeyframes keyframes;
	for (size_t i = 0; i < 6; ++i)
		graph.addNode(truth[i]), keyframes.push_back(run.keyframes[i]);
	const auto enterWindow = [&graph](CLocalRegistration& local)
	{
		for (size_t i = 0; i < 6; ++i) local.enterKeyframe(i, false, graph);
	};
	// The scan 15 cm past the newest keyframe.
	const TPose2D scanTruth = compose(truth[5], TPose2D(0.15, 0, 0));
	std::mt19937 rng(5);
	const TScan2D scan = lrgc::test::simulateScan(run.world, scanTruth, {}, rng);
	const Eigen::Matrix3d priorCov =
		Eigen::Vector3d(0.1 * 0.1, 0.1 * 0.1, std::pow(5 * M_PI / 180, 2)).asDiagonal();
	// The odometry prediction of one 0.2 s step that turns `turn` [rad].
	const auto step = [&](double turn)
	{
		lrgc::TMotionPrediction m;
		m.motion = TPose2D(0.15, 0, turn);
		m.cov = priorCov;
		m.fromOdometry = true;
		m.stepSeconds = 0.2;
		return m;
	};

	{  // A prior 12 cm / 4 deg off, consistent with its covariance.
		CLocalRegistration local(p.local, p.matcher, p.optimizer);
		enterWindow(local);
		const TPose2D prior = compose(scanTruth, TPose2D(0.08, -0.09, 0.07));
		const TRegistration reg = local.registerScan(graph, keyframes, scan, prior, step(0.0));
		ASSERT_TRUE(reg.matched);
		EXPECT_FALSE(reg.odometryRejected);
		EXPECT_FALSE(reg.wideSearch);
		EXPECT_LT(positionError(scanTruth, reg.scanInMap), 0.02);
		EXPECT_LT(headingError(scanTruth, reg.scanInMap), 0.3 * M_PI / 180);
	}
	// An odometry glitch: the step claims a 70 deg turn that did not happen.
	const TPose2D glitchPrior = compose(scanTruth, TPose2D(0, 0, 70 * M_PI / 180));
	{  // The prior is suspect (its step turns more than glitch_min_turn): wide search.
		CLocalRegistration local(p.local, p.matcher, p.optimizer);
		enterWindow(local);
		const TRegistration reg =
			local.registerScan(graph, keyframes, scan, glitchPrior, step(70 * M_PI / 180));
		ASSERT_TRUE(reg.matched);
		EXPECT_TRUE(reg.wideSearch);
		EXPECT_TRUE(reg.odometryRejected);
		EXPECT_LT(positionError(scanTruth, reg.scanInMap), 0.02);
		EXPECT_LT(headingError(scanTruth, reg.scanInMap), 0.3 * M_PI / 180);
	}
	{  // The same prior, but its step looks harmless: the first failure keeps the prior.
		CLocalRegistration local(p.local, p.matcher, p.optimizer);
		enterWindow(local);
		const TRegistration reg =
			local.registerScan(graph, keyframes, scan, glitchPrior, step(0.0));
		EXPECT_FALSE(reg.matched);
		EXPECT_FALSE(reg.wideSearch);
		EXPECT_EQ(reg.scanInMap, glitchPrior);
	}
	{  // Without a wide search the glitch cannot be recovered at all.
		TStageParams narrow = p;
		narrow.local.wide_search_angle = 0;
		CLocalRegistration local(narrow.local, narrow.matcher, narrow.optimizer);
		enterWindow(local);
		const TRegistration reg =
			local.registerScan(graph, keyframes, scan, glitchPrior, step(70 * M_PI / 180));
		EXPECT_FALSE(reg.matched);
	}
}

TEST(LocalRegistration, suspectStepsPlainMatchInTheWrongBasinIsOverruledByTheWideSearch)
{
	// Sparse scans (issue 28): keyframes 1 m apart along an open hall's pillar rows, a scan
	// 1 m past the newest after a 1.5 s pause (a suspect step), its prior 20 deg off with a
	// loose covariance (odometry that stalled). From there the plain match settles 1.3 m off
	// along the pillar rows, agreeing with that prior; it leaves half the scan unexplained.
	const CSyntheticWorld world = lrgc::test::makeOpenHallWorld(3);
	const auto tr = lrgc::test::makeTrajectory({{5, 5}, {40, 5}}, 1.0, {}, 21);
	TStageParams p;
	std::mt19937 rng(4);
	CPoseGraph graph;
	TKeyframes keyframes;
	std::vector<TScan2D> scans;
	for (size_t k = 0; k < 6; ++k)
	{
		TKeyframe kf;
		kf.scan = lrgc::test::simulateScan(world, tr.truePoses[k], {}, rng);
		kf.scanIndex = k;
		scans.push_back(kf.scan);
		keyframes.push_back(std::move(kf));
		graph.addNode(tr.truePoses[k]);
	}
	const TPose2D scanTruth = tr.truePoses[6];
	const TScan2D scan = lrgc::test::simulateScan(world, scanTruth, {}, rng);
	const TPose2D prior = compose(scanTruth, TPose2D(0.1, 0.05, -20 * M_PI / 180));
	lrgc::TMotionPrediction step;
	step.motion = TPose2D(1.0, 0, 0.1);
	step.cov = Eigen::Vector3d(2.0 * 2.0, 2.0 * 2.0, std::pow(25 * M_PI / 180, 2)).asDiagonal();
	step.fromOdometry = true;

	// The plain match alone, against the window's patch (newest keyframe's frame).
	std::vector<TPose2D> inNewest;
	for (size_t k = 0; k < 6; ++k) inNewest.push_back(between(graph.pose(5), graph.pose(k)));
	const CReferenceCloud patch = CReferenceCloud::fromScans(scans, inNewest, p.matcher);
	TScanMatcherParams local = p.matcher;
	local.max_free_space_violation = p.local.max_free_space_violation;
	const CScanMatcher matcher(local);
	const auto plain = matcher.match(patch, scan, between(graph.pose(5), prior));
	ASSERT_TRUE(plain);
	EXPECT_GT(positionError(scanTruth, compose(graph.pose(5), plain->scanInRef)), 0.9);
	EXPECT_LT(matcher.explainedFraction(patch, scan, plain->scanInRef),
			  1 - p.matcher.wide_ambiguity_margin);

	for (const double seconds : {1.5, 0.2})
	{
		CLocalRegistration reg(p.local, p.matcher, p.optimizer);
		for (size_t i = 0; i < 6; ++i) reg.enterKeyframe(i, false, graph);
		step.stepSeconds = seconds;
		const TRegistration r = reg.registerScan(graph, keyframes, scan, prior, step);
		ASSERT_TRUE(r.matched);
		if (seconds > p.local.glitch_min_gap_s)
		{  // suspect: the wide search's second opinion overrules the plain match
			EXPECT_TRUE(r.wideSearch);
			EXPECT_LT(positionError(scanTruth, r.scanInMap), kTolXY);
			EXPECT_LT(headingError(scanTruth, r.scanInMap), kTolPhi);
		}
		else
		{  // nothing suspect: the plain match stands (no wide search on every step)
			EXPECT_FALSE(r.wideSearch);
			EXPECT_GT(positionError(scanTruth, r.scanInMap), 0.9);
		}
	}
}

TEST(LocalRegistration, aFailedPlainMatchIsRetriedOverTheOdometrysHeadingError)
{
	// A long laser (80 m, 181 beams) in the glass-and-railings building's south hall
	// (issue 28): keyframes 0.4 m apart heading east, the scan 0.4 m past the newest, its
	// prior some degrees off on a step that is not suspect. Beyond a few degrees the far
	// walls lie outside the plain match's gate and it fails; the retry over the heading the
	// odometry's error may span (+-7.5 deg, +-15 deg where the step turns more than 10)
	// finds the pose. A prior farther off than that keeps the prior.
	const CSyntheticWorld world = lrgc::test::makeGlassBuildingWorld(5, 0.2);
	lrgc::test::TLaserSimParams laser;
	laser.beams = 181, laser.maxRange = 80, laser.dropRate = 0.02, laser.mixedPixelRate = 1;
	TStageParams p;
	std::mt19937 rng(7);
	CPoseGraph graph;
	TKeyframes keyframes;
	std::vector<TScan2D> scans;
	for (size_t k = 0; k < 8; ++k)
	{
		TKeyframe kf;
		kf.scan = lrgc::test::simulateScan(world, TPose2D(24 + 0.4 * k, 12, 0), laser, rng);
		kf.scanIndex = k;
		scans.push_back(kf.scan);
		keyframes.push_back(std::move(kf));
		graph.addNode(TPose2D(24 + 0.4 * k, 12, 0));
	}
	const TPose2D scanTruth(24 + 0.4 * 8, 12, 0);
	const TScan2D scan = lrgc::test::simulateScan(world, scanTruth, laser, rng);
	std::vector<TPose2D> inNewest;
	for (size_t k = 0; k < 8; ++k) inNewest.push_back(between(graph.pose(7), graph.pose(k)));
	const CReferenceCloud patch = CReferenceCloud::fromScans(scans, inNewest, p.matcher);
	TScanMatcherParams localMatcher = p.matcher;
	localMatcher.max_free_space_violation = p.local.max_free_space_violation;
	const CScanMatcher matcher(localMatcher);

	struct TCase
	{
		double offDeg, turnDeg;  // prior's heading error; the step's odometry turn
		bool recovered;
	};
	for (const TCase c : {TCase{-4, 0, true}, TCase{4, 0, true}, TCase{-6, 0, true},
						  TCase{12, 20, true}, TCase{25, 0, false}})
	{
		SCOPED_TRACE(c.offDeg);
		const TPose2D prior = compose(scanTruth, TPose2D(0.05, -0.03, c.offDeg * M_PI / 180));
		ASSERT_FALSE(matcher.match(patch, scan, between(graph.pose(7), prior)))
			<< "the plain match must fail from this prior";
		lrgc::TMotionPrediction step;
		step.motion = TPose2D(0.4, 0, c.turnDeg * M_PI / 180);
		step.cov = Eigen::Vector3d(0.05 * 0.05, 0.05 * 0.05, std::pow(0.05, 2)).asDiagonal();
		step.fromOdometry = true;
		step.stepSeconds = 0.7;
		CLocalRegistration reg(p.local, p.matcher, p.optimizer);
		for (size_t i = 0; i < 8; ++i) reg.enterKeyframe(i, false, graph);
		const TRegistration r = reg.registerScan(graph, keyframes, scan, prior, step);
		ASSERT_EQ(r.matched, c.recovered);
		EXPECT_EQ(r.wideSearch, c.recovered);
		if (!c.recovered)
		{
			EXPECT_EQ(r.scanInMap, prior);
			continue;
		}
		EXPECT_LT(positionError(scanTruth, r.scanInMap), kTolXY);
		EXPECT_LT(headingError(scanTruth, r.scanInMap), kTolPhi);
	}
}

// reuse_match_when_still: a robot whose wheels report no motion keeps the last match's pose
// relative to the unchanged window; a re-match of another scan from there would move it by
// the scans' noise. Moving the window (invalidate), a real step, or ranges that show the robot
// moved on while its wheels read zero (lagging odometry: still_max_range_change_m) make the
// scan match again.
TEST(LocalRegistration, aScanThatStandsStillReusesTheLastMatchWhileTheWindowIsUnchanged)
{
	const TKnownRun run;
	const auto& truth = run.tr.truePoses;
	CPoseGraph graph;
	TKeyframes keyframes;
	for (size_t i = 0; i < 6; ++i)
		graph.addNode(truth[i]), keyframes.push_back(run.keyframes[i]);
	const TPose2D scanTruth = compose(truth[5], TPose2D(0.15, 0, 0));
	std::mt19937 rng(5);
	const TScan2D first = lrgc::test::simulateScan(run.world, scanTruth, {}, rng);
	const TScan2D second = lrgc::test::simulateScan(run.world, scanTruth, {}, rng);
	const TPose2D movedOn = compose(scanTruth, TPose2D(0.06, 0, 0));
	const TScan2D ahead = lrgc::test::simulateScan(run.world, movedOn, {}, rng);
	const auto odometryStep = [](const TPose2D& motion, double var)
	{
		lrgc::TMotionPrediction m;
		m.motion = motion;
		m.cov = Eigen::Vector3d(var, var, var).asDiagonal();
		m.fromOdometry = true;
		m.stepSeconds = 0.2;
		return m;
	};
	const TPose2D still(0, 0, 0), creep(0.002, 0, 0);
	const auto runNext = [&](bool reuse, bool moveWindow, const TPose2D& step,
							 const TScan2D& next, const TPose2D& nextTruth, double var)
	{
		TStageParams p;
		p.local.reuse_match_when_still = reuse;
		CLocalRegistration local(p.local, p.matcher, p.optimizer);
		for (size_t i = 0; i < 6; ++i) local.enterKeyframe(i, false, graph);
		const TPose2D prior = compose(scanTruth, TPose2D(0.03, -0.02, 0.01));
		const TRegistration a = local.registerScan(graph, keyframes, first, prior,
												   odometryStep(TPose2D(0.15, 0, 0), 1e-4));
		if (moveWindow) local.invalidate();
		const TRegistration b = local.registerScan(
			graph, keyframes, next, compose(a.scanInMap, step), odometryStep(step, var));
		EXPECT_TRUE(a.matched && b.matched);
		EXPECT_LT(positionError(nextTruth, b.scanInMap), 0.02);
		return std::make_pair(a, b);
	};
	const auto run2 = [&](bool reuse, bool moveWindow, const TPose2D& step)
	{ return runNext(reuse, moveWindow, step, second, scanTruth, 1e-4); };
	const auto [a, b] = run2(true, false, still);
	EXPECT_EQ(b.scanInMap, a.scanInMap);
	EXPECT_TRUE(b.cov.get().isApprox(a.cov.get()));
	// Matched again: the second scan's own noise moves the pose (by micrometres at least).
	const auto differs = [](const TRegistration& x, const TRegistration& y)
	{ return !(x.scanInMap == y.scanInMap); };
	EXPECT_TRUE(std::apply(differs, run2(false, false, still)));
	EXPECT_TRUE(std::apply(differs, run2(true, true, still)));
	const auto [c, d] = run2(true, false, creep);
	EXPECT_FALSE(d.scanInMap == compose(c.scanInMap, creep));
	// Wheels that read zero while the robot rolled 6 cm on (within the odometry's 6.3 cm std,
	// so that a match may move it): matched again, where it is.
	const auto [e, f] = runNext(true, false, still, ahead, movedOn, 4e-3);
	EXPECT_GT(positionError(e.scanInMap, f.scanInMap), 0.04);
}

TEST(LocalRegistration, aTurnInPlaceWhosePlainMatchSlidesAlongTheHallIsMatchedAgainAtItsHeading)
{
	// The glass atrium's south-east corner (glass_stress, issue 28 item 2): a long laser (80 m,
	// 181 beams, mixed pixels, max-range dropouts), keyframes 0.4 m apart heading east along
	// the south hall's centre line to the corner (144, 16), the newest turned 34.4 deg there,
	// and the scan turned as much again in place, its prior 4-6 deg off (the odometry's turn
	// error). From there the plain match finds the heading but slides 0.7-1.4 m along a hall,
	// disagreeing with the prior, and the wide search finds no clear winner: main kept the
	// prior, its heading error and all. Matched again from the prior's position at the plain
	// match's heading (CLocalRegistration::headingFirstMatch) it lands on the truth.
	const CSyntheticWorld world = lrgc::test::makeGlassAtriumWorld(2);
	lrgc::test::TLaserSimParams laser;
	laser.beams = 181, laser.maxRange = 80, laser.dropRate = 0.02, laser.outlierRate = 0.005;
	laser.maxRangeDropRate = 0.3, laser.mixedPixelRate = 1;
	TStageParams p;
	std::mt19937 rng(5);
	CPoseGraph graph;
	TKeyframes keyframes;
	std::vector<TScan2D> scans;
	const double turn = 34.4 * M_PI / 180;
	for (size_t k = 0; k < 15; ++k)
	{
		const TPose2D pose = k < 14 ? TPose2D(138.8 + 0.4 * k, 16, 0) : TPose2D(144, 16, turn);
		TKeyframe kf;
		kf.scan = lrgc::test::simulateScan(world, pose, laser, rng);
		kf.scanIndex = k;
		scans.push_back(kf.scan);
		keyframes.push_back(std::move(kf));
		graph.addNode(pose);
	}
	const TPose2D scanTruth(144, 16, 2 * turn);
	const TScan2D scan = lrgc::test::simulateScan(world, scanTruth, laser, rng);
	std::vector<TPose2D> inNewest;
	for (size_t k = 0; k < 15; ++k) inNewest.push_back(between(graph.pose(14), graph.pose(k)));
	const CReferenceCloud patch = CReferenceCloud::fromScans(scans, inNewest, p.matcher);
	const CScanMatcher matcher(p.matcher);
	for (const double offDeg : {-6.0, -4.0, 4.0, 6.0})
	{
		SCOPED_TRACE(offDeg);
		const TPose2D prior = compose(scanTruth, TPose2D(0, 0, offDeg * M_PI / 180));
		const auto plain = matcher.match(patch, scan, between(graph.pose(14), prior));
		ASSERT_TRUE(plain);
		const TPose2D plainInMap = compose(graph.pose(14), plain->scanInRef);
		EXPECT_GT(positionError(scanTruth, plainInMap), 0.5) << "the plain match must slide";
		EXPECT_LT(headingError(scanTruth, plainInMap), kTolPhi);
		lrgc::TMotionPrediction step;  // a turn in place, 2 cm and 3.5 deg std
		step.motion = TPose2D(0, 0, turn + offDeg * M_PI / 180);
		step.cov = Eigen::Vector3d(0.02 * 0.02, 0.02 * 0.02, std::pow(3.5 * M_PI / 180, 2))
					   .asDiagonal();
		step.fromOdometry = true;
		step.stepSeconds = 0.7;
		CLocalRegistration reg(p.local, p.matcher, p.optimizer);
		for (size_t i = 0; i < 15; ++i) reg.enterKeyframe(i, false, graph);
		const TRegistration r = reg.registerScan(graph, keyframes, scan, prior, step);
		ASSERT_TRUE(r.matched);
		EXPECT_FALSE(r.wideSearch);
		EXPECT_FALSE(r.odometryRejected);
		EXPECT_LT(positionError(scanTruth, r.scanInMap), kTolXY);
		EXPECT_LT(headingError(scanTruth, r.scanInMap), kTolPhi);
	}
}

TEST(LocalRegistration, aMatchThatOnlyReversesTheWheelsForwardStepLeavesTheOdometryStanding)
{
	// A corridor 2 m wide along x whose walls have a 1 m wide, 0.8 m deep door recess every
	// 3 m (dense Killian's long corridor, issue 28), its end 3.4 m ahead of the scan: a match
	// there is confident along the corridor (the doors alone leave x to the prior). Six
	// keyframes 0.3 m apart at their true poses; the scan 0.1 m past the newest.
	CSyntheticWorld world;
	world.addSegment({0, 0}, {30, 0});
	world.addSegment({0, 2}, {30, 2});
	world.addSegment({15, 0}, {15, 2});
	for (double x = 1.0; x < 30; x += 3.0)
		for (const double y : {0.0, 2.0})
		{
			const double back = y == 0 ? -0.8 : 2.8;
			world.addSegment({x, back}, {x + 1, back});
			world.addSegment({x, y}, {x, back});
			world.addSegment({x + 1, y}, {x + 1, back});
		}
	TStageParams p;
	std::mt19937 rng(7);
	CPoseGraph graph;
	TKeyframes keyframes;
	for (size_t k = 0; k < 6; ++k)
	{
		const TPose2D pose(10.0 + 0.3 * k, 1.0, 0);
		TKeyframe kf;
		kf.scan = lrgc::test::simulateScan(world, pose, {}, rng);
		kf.scanIndex = k;
		keyframes.push_back(std::move(kf));
		graph.addNode(pose);
	}
	const TPose2D scanTruth(11.6, 1.0, 0);
	const TScan2D scan = lrgc::test::simulateScan(world, scanTruth, {}, rng);
	// The wheels rolled 0.09 m straight on, 2 cm and 0.5 deg std.
	lrgc::TMotionPrediction step;
	step.motion = TPose2D(0.09, 0, 0);
	step.cov =
		Eigen::Vector3d(0.02 * 0.02, 0.02 * 0.02, std::pow(0.5 * M_PI / 180, 2)).asDiagonal();
	step.fromOdometry = true;
	step.stepSeconds = 0.2;
	// The scan registered with the last scan at `lastInMap` (its prior: that (+) the step).
	const auto registered = [&](const TPose2D& lastInMap)
	{
		CLocalRegistration local(p.local, p.matcher, p.optimizer);
		for (size_t i = 0; i < 6; ++i) local.enterKeyframe(i, false, graph);
		return local.registerScan(graph, keyframes, scan, compose(lastInMap, step.motion),
								  step);
	};
	{  // The last scan 0.05 m ahead of this one: the match, 0.14 m short of its prior
		// (chi2 ~ 49), puts the robot 5 cm behind it against a 9 cm forward step. Wheels do not
		// do that, an alias does (on Killian the doors): the odometry stands (and its
		// keyframe's odometry link with it); the match still places the scan.
		const TRegistration r = registered(compose(scanTruth, TPose2D(0.05, 0, 0)));
		ASSERT_TRUE(r.matched);
		EXPECT_FALSE(r.wideSearch);
		EXPECT_FALSE(r.odometryRejected) << "a short match replaced the odometry's slide";
		EXPECT_LT(positionError(scanTruth, r.scanInMap), kTolXY);
	}
	{  // The last scan 0.23 m behind: the match registers 0.23 m forward against 0.09 m (a
		// late odometry reading): that the wheels can do; the odometry is rejected.
		const TRegistration r = registered(compose(scanTruth, TPose2D(-0.23, 0, 0)));
		ASSERT_TRUE(r.matched);
		EXPECT_TRUE(r.odometryRejected);
		EXPECT_LT(positionError(scanTruth, r.scanInMap), kTolXY);
	}
	{  // Behind as in the first case, but the prior also turned 3 deg off the match: more than
		// the direction of the step is disputed, and the odometry is rejected.
		const TRegistration r =
			registered(compose(scanTruth, TPose2D(0.05, 0, 3 * M_PI / 180)));
		ASSERT_TRUE(r.matched);
		EXPECT_TRUE(r.odometryRejected);
		EXPECT_LT(headingError(scanTruth, r.scanInMap), kTolPhi);
	}
}
