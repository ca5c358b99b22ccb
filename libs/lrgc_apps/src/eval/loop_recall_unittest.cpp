/* Loop recall (loop_recall.h) on a hand-made run: 30 m out along x at 1 m/s, a pause, 30 m
 * back 100 s after the start, so that every keyframe of the way back is a revisit. */
#include <gtest/gtest.h>
#include <lrgc/common/se2.h>
#include <lrgc_apps/eval/loop_recall.h>

#include <cmath>
#include <tuple>

using namespace lrgc::apps::eval;
using mrpt::math::TPose2D;

namespace
{
struct TOutAndBack
{
	std::vector<TRecallKeyframe> kfs;
	lrgc::CPoseGraph graph;

	TOutAndBack()
	{
		for (int i = 0; i <= 30; ++i) kfs.push_back({double(i), TPose2D(i, 0, 0)});
		for (int i = 0; i <= 30; ++i)  // keyframes 31..61, x = 30..0, heading back
			kfs.push_back({100.0 + i, TPose2D(30 - i, 0.5, M_PI)});
		for (const auto& k : kfs) graph.addNode(k.reference);
	}
	/** A loop link from -> to measuring the reference's relative pose (+) `error`. */
	size_t link(size_t from, size_t to, const TPose2D& error, double information = 1e4)
	{
		lrgc::TLink l;
		l.from = from, l.to = to, l.type = lrgc::LinkType::LoopClosure;
		l.toInFrom =
			lrgc::compose(lrgc::between(kfs[from].reference, kfs[to].reference), error);
		l.information = information * Eigen::Matrix3d::Identity();
		return graph.addLink(l);
	}
};
}  // namespace

TEST(LoopRecall, placesOfTenMetresAndTheLinksThatCloseThem)
{
	TOutAndBack run;
	run.link(5, 35, {0, 0, 0});          // closes place 0 (keyframes 31-40)
	run.link(45, 15, {0.2, 0.1, 0.07});  // newer end 45, 0.22 m and 4 deg off: closes place 1
	run.link(20, 52, {0.31, 0, 0});      // 0.31 m off, chi2 961: a false closure
	run.link(54, 55, {0, 0, 0});         // agrees, but 1 s apart: closes no revisit
	run.graph.setLinkEnabled(run.link(2, 58, {0, 0, 0}), false);  // not kept: place 2 open
	run.link(0, 61, {0.5, 0, 0}, 10);  // 0.5 m off, but chi2 2.5 by its information: agrees

	const TLoopRecall r = evaluateLoopRecall(run.graph, run.kfs);
	// The way back starts 30.5 m along the path; a place every 10 m from there on.
	ASSERT_EQ(r.places.size(), 4U);
	EXPECT_EQ(r.places[0].firstKeyframe, 31U);
	EXPECT_EQ(r.places[0].lastKeyframe, 40U);
	EXPECT_EQ(r.places[1].firstKeyframe, 41U);
	EXPECT_EQ(r.places[3].firstKeyframe, 61U);
	EXPECT_DOUBLE_EQ(r.places[3].firstTime_s, 130.0);
	EXPECT_TRUE(r.places[0].closed);
	EXPECT_TRUE(r.places[1].closed);
	EXPECT_FALSE(r.places[2].closed);
	EXPECT_TRUE(r.places[3].closed);
	EXPECT_EQ(r.closed, 3U);
	EXPECT_DOUBLE_EQ(r.recall(), 0.75);
	EXPECT_EQ(r.loopLinks.size(), 5U);
	EXPECT_EQ(r.falseClosures, 1U);
	EXPECT_NEAR(r.loopLinks[2].offXY_m, 0.31, 1e-9);
	EXPECT_NEAR(r.loopLinks[2].chi2, 961, 1e-6);
	EXPECT_NE(recallReport(r).find("false closure: keyframe 20 -> 52, 0.31 m"),
			  std::string::npos)
		<< recallReport(r);
	EXPECT_NE(recallReport(r).find("not closed: keyframes 51-60"), std::string::npos);
}

// A link's information is over (x, y, phi) of `to` in the axes of `from`: a link turned by
// 90 deg whose match knows only y (a corridor along from's x) and lies 0.31 m off along x
// agrees (chi2 0.1). Judged in the truth's axes, as before stop 43, it read the information
// with x and y swapped: chi2 961, a false closure.
TEST(LoopRecall, aLinksInformationIsReadInTheAxesOfItsFromKeyframe)
{
	std::vector<TRecallKeyframe> kfs{{0.0, TPose2D(0, 0, 0)},
									 {100.0, TPose2D(0, 0.5, M_PI / 2)}};
	lrgc::CPoseGraph graph;
	for (const auto& k : kfs) graph.addNode(k.reference);
	lrgc::TLink l;
	l.from = 0, l.to = 1, l.type = lrgc::LinkType::LoopClosure;
	l.toInFrom = TPose2D(0.31, 0.5, M_PI / 2);  // the truth (0, 0.5, 90 deg), 0.31 m along x
	l.information = Eigen::Vector3d(1, 1e4, 1e4).asDiagonal();
	graph.addLink(l);
	const TLoopRecall r = evaluateLoopRecall(graph, kfs);
	ASSERT_EQ(r.loopLinks.size(), 1U);
	EXPECT_NEAR(r.loopLinks[0].offXY_m, 0.31, 1e-9);
	EXPECT_NEAR(r.loopLinks[0].chi2, 0.0961, 1e-9);
	EXPECT_EQ(r.falseClosures, 0U);
}

TEST(LoopRecall, noRevisitWithinTheGapOrBeyondTheDistance)
{
	// Straight back without the pause: keyframe i at i s. Keyframe 60 (x = 1) lies 1.12 m
	// from keyframe 0, 60 s older: a revisit; keyframe 59 (x = 2) is 2.06 m from keyframe 0
	// and 58 s after keyframe 1: none.
	TOutAndBack run;
	for (size_t i = 31; i < run.kfs.size(); ++i) run.kfs[i].t = double(i);
	const auto r = evaluateLoopRecall(run.graph, run.kfs);
	ASSERT_EQ(r.places.size(), 1U);
	EXPECT_EQ(r.places[0].firstKeyframe, 60U);
	EXPECT_EQ(r.places[0].lastKeyframe, 61U);
	TOutAndBack far;
	for (size_t i = 31; i < far.kfs.size(); ++i) far.kfs[i].reference.y = 2.0;
	EXPECT_TRUE(evaluateLoopRecall(far.graph, far.kfs).places.empty());
	EXPECT_EQ(evaluateLoopRecall(far.graph, far.kfs).recall(), 0.0);
}

TEST(LoopRecall, aGraphWithMoreNodesThanKeyframesThrows)
{
	TOutAndBack run;
	run.kfs.pop_back();
	EXPECT_THROW(evaluateLoopRecall(run.graph, run.kfs), std::invalid_argument);
}

// The reference is 0.5 m off at the way back (its own join wrong); a ground-truth relation
// from 1 s after keyframe 5 to 2 s before keyframe 35 decides instead: the link measuring the
// truth agrees, judged by the relation; one 0.4 m off it is false.
TEST(LoopRecall, aRelationNearBothEndsJudgesTheLinkInsteadOfTheReference)
{
	TOutAndBack run;  // run.kfs: the truth
	std::vector<TTimedPose2D> ref;
	for (const auto& k : run.kfs)
		ref.push_back({k.t, lrgc::compose(k.reference, TPose2D(0, k.t > 50 ? 0.5 : 0, 0)), 0});
	TRelation r;  // keyframe 6 (6 s) to keyframe 33 (102 s)
	r.t1 = run.kfs[6].t, r.t2 = run.kfs[33].t;
	r.motion = lrgc::between(run.kfs[6].reference, run.kfs[33].reference);
	auto kfs = run.kfs;
	for (auto& k : kfs)
		if (k.t > 50) k.reference = lrgc::compose(k.reference, TPose2D(0, 0.5, 0));
	run.link(5, 35, {0, 0, 0});    // the truth
	run.link(4, 36, {0.4, 0, 0});  // 0.4 m off the truth
	const auto judge = truthFromRelations({r}, CTrajectory2D(ref), 20);
	const TLoopRecall byRef = evaluateLoopRecall(run.graph, kfs);
	EXPECT_EQ(byRef.falseClosures, 2U);  // the reference's 0.5 m error
	const TLoopRecall byRel = evaluateLoopRecall(run.graph, kfs, {}, judge);
	EXPECT_EQ(byRel.byRelation, 2U);
	EXPECT_TRUE(byRel.loopLinks[0].agrees);
	EXPECT_NEAR(byRel.loopLinks[0].offXY_m, 0, 1e-9);
	EXPECT_FALSE(byRel.loopLinks[1].agrees);
	EXPECT_NEAR(byRel.loopLinks[1].offXY_m, 0.4, 1e-9);
	// Beyond the reach no relation decides.
	const TLoopRecall far = evaluateLoopRecall(
		run.graph, kfs, {}, truthFromRelations({r}, CTrajectory2D(ref), 0.5));
	EXPECT_EQ(far.byRelation, 0U);
}

// linkCalibration: per-axis normalised errors in the link's own axes. Two links claim 1 m along
// from's x (a corridor) and 1 cm across it and 0.01 rad in heading; one is 0.5 m off along the
// corridor (honest: 0.25 along the weak axis), the other 0.05 m across it (25 along the strong
// axis: over-confident there).
TEST(LoopRecall, calibrationReadsEachAxisUnderItsOwnClaimedStd)
{
	TOutAndBack run;
	for (const auto& [from, to, error] :
		 {std::tuple(5, 35, TPose2D(0.5, 0, 0)), std::tuple(6, 34, TPose2D(0, 0.05, 0))})
	{
		lrgc::TLink l;
		l.from = from, l.to = to, l.type = lrgc::LinkType::LoopClosure;
		l.toInFrom =
			lrgc::compose(lrgc::between(run.kfs[from].reference, run.kfs[to].reference), error);
		l.information = Eigen::Vector3d(1, 1e4, 1e4).asDiagonal();
		run.graph.addLink(l);
	}
	const TLoopRecall r = evaluateLoopRecall(run.graph, run.kfs);
	ASSERT_EQ(r.loopLinks.size(), 2U);
	const TLinkCalibration c = linkCalibration(r.loopLinks);
	EXPECT_EQ(c.links, 2U);
	// The errors are in from's axes, whose x the weak axis is.
	EXPECT_NEAR(c.weak.mean, (0.25 + 0.0) / 2, 1e-6);
	EXPECT_NEAR(c.strong.mean, (0.0 + 25.0) / 2, 1e-6);
	EXPECT_NEAR(c.heading.mean, 0.0, 1e-9);
	EXPECT_DOUBLE_EQ(c.strong.over99, 0.5);
	EXPECT_DOUBLE_EQ(c.weak.over99, 0.0);
	EXPECT_NEAR(c.weakStdMedian_m, 1.0, 1e-9);
	EXPECT_NEAR(c.strongStdMedian_m, 0.01, 1e-9);
	EXPECT_NE(calibrationReport(r).find("over 2 judged links"), std::string::npos)
		<< calibrationReport(r);
}
