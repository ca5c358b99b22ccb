/* Loop recall judged by relations alone (relation_truth.h) on a hand-made run: 30 m out along
 * x at 1 m/s (keyframes 0-30), 30 m back 0.5 m aside from 100 s on (keyframes 31-61, x =
 * 61 - i), relations between consecutive keyframes and one revisit relation, keyframe 6 (x = 6)
 * to keyframe 55 (x = 6 on the way back). */
#include <gtest/gtest.h>
#include <lrgc/common/se2.h>
#include <lrgc_apps/eval/relation_truth.h>

#include <cmath>

using namespace lrgc::apps::eval;
using mrpt::math::TPose2D;

namespace
{
struct TRelationRun
{
	std::vector<TRecallKeyframe> kfs;  //!< .reference: the truth, which the map equals here
	std::vector<TRelation> relations;
	lrgc::CPoseGraph graph;

	TRelationRun()
	{
		for (int i = 0; i <= 30; ++i) kfs.push_back({double(i), TPose2D(i, 0, 0)});
		for (int i = 0; i <= 30; ++i) kfs.push_back({100.0 + i, TPose2D(30 - i, 0.5, M_PI)});
		for (const auto& k : kfs) graph.addNode(k.reference);
		// Consecutive relations, except that keyframe 56's scan is named by none (55 -> 57).
		for (std::size_t i = 0; i + 1 < kfs.size(); ++i)
			if (i != 30 && i != 55 && i != 56) relate(i, i + 1);
		relate(55, 57);
		relate(6, 55);  // the revisit
	}
	void relate(std::size_t a, std::size_t b)
	{
		TRelation r;
		r.t1 = kfs[a].t, r.t2 = kfs[b].t;
		r.motion = lrgc::between(kfs[a].reference, kfs[b].reference);
		relations.push_back(r);
	}
	/** A loop link from -> to measuring the truth (+) `error`. */
	void link(std::size_t from, std::size_t to, const TPose2D& error)
	{
		lrgc::TLink l;
		l.from = from, l.to = to, l.type = lrgc::LinkType::LoopClosure;
		l.toInFrom =
			lrgc::compose(lrgc::between(kfs[from].reference, kfs[to].reference), error);
		l.information = 1e4 * Eigen::Matrix3d::Identity();
		graph.addLink(l);
	}
};
}  // namespace

TEST(RelationTruth, chainsOfRelationsJudgeTheLinksAndFindTheRevisits)
{
	TRelationRun run;
	TRelationTruthParams tp;
	tp.maxHops = 4;
	const CRelationTruth truth(run.relations, run.kfs, tp);
	EXPECT_EQ(truth.ownAnchors(), 61U);
	EXPECT_EQ(truth.bridgedAnchors(), 1U);
	// 5 -> 54: 5 -> 6 -> 55 -> 54, three relations composed.
	const auto d = truth.between(5, 54);
	ASSERT_TRUE(d.has_value());
	const auto expected = lrgc::between(run.kfs[5].reference, run.kfs[54].reference);
	EXPECT_NEAR(d->x, expected.x, 1e-9);
	EXPECT_NEAR(d->y, expected.y, 1e-9);
	EXPECT_NEAR(d->phi, expected.phi, 1e-9);
	EXPECT_FALSE(truth.between(0, 30).has_value()) << "30 relations apart, over maxHops";
	EXPECT_EQ(truth.relationsBetween(5, 54), 3U);
	EXPECT_EQ(truth.relationsBetween(6, 55), 1U);
	EXPECT_EQ(truth.relationsBetween(0, 30), 0U) << "no path";

	run.link(6, 55, {0, 0, 0});       // the truth: closes the place
	run.link(5, 54, {0.4, 0, 0});     // 0.4 m off: false, by the relations
	run.link(7, 56, {0.1, 0, 0.01});  // 56 bridged by the map (to 55): agrees, not byRelation
	run.link(20, 40, {0, 0, 0});      // no path: not judged
	const TLoopRecall r = evaluateLoopRecall(run.graph, run.kfs, truth);
	ASSERT_EQ(r.loopLinks.size(), 4U);
	EXPECT_TRUE(r.loopLinks[0].agrees && r.loopLinks[0].byRelation);
	EXPECT_FALSE(r.loopLinks[1].agrees);
	EXPECT_TRUE(r.loopLinks[1].judged && r.loopLinks[1].byRelation);
	EXPECT_NEAR(r.loopLinks[1].offXY_m, 0.4, 1e-9);
	EXPECT_EQ(r.loopLinks[1].relations, 3U);
	EXPECT_NE(recallReport(r).find("(by the relations: 3 on the path)"), std::string::npos);
	EXPECT_TRUE(r.loopLinks[2].agrees && r.loopLinks[2].bridged);
	EXPECT_FALSE(r.loopLinks[2].byRelation);
	EXPECT_FALSE(r.loopLinks[3].judged);
	EXPECT_EQ(r.falseClosures, 1U);
	EXPECT_EQ(r.notJudged, 1U);
	EXPECT_EQ(r.byRelation, 2U);
	// Revisits only where the relations reach within 4: x = 4..8 on the way back (keyframes
	// 53-57), within 2 m of an outbound keyframe; one place, closed. By a reference every
	// keyframe of the way back would be one (4 places, loop_recall_unittest.cpp).
	ASSERT_EQ(r.places.size(), 1U);
	EXPECT_EQ(r.places[0].firstKeyframe, 53U);
	EXPECT_EQ(r.places[0].lastKeyframe, 57U);
	EXPECT_TRUE(r.places[0].closed);
	EXPECT_EQ(r.closed, 1U);
}

// Without the revisit relation nothing joins the two legs: no revisit, no judged loop link.
TEST(RelationTruth, withoutARevisitRelationThereIsNoRevisit)
{
	TRelationRun run;
	run.relations.pop_back();
	run.link(6, 55, {0, 0, 0});
	const CRelationTruth truth(run.relations, run.kfs);
	const TLoopRecall r = evaluateLoopRecall(run.graph, run.kfs, truth);
	EXPECT_TRUE(r.places.empty());
	EXPECT_EQ(r.notJudged, 1U);
	EXPECT_EQ(r.falseClosures, 0U);
}

// The judge's own error grows with its path (TLoopRecallParams::maxXYPerRelation_m): 0.4 m off
// is false over 3 relations (above) but within what 13 relations may drift themselves
// (sqrt(0.3^2 + (13 x 0.03)^2) = 0.49 m); 0.6 m off is false over 13 as well.
TEST(RelationTruth, theToleranceGrowsWithTheRelationsOnThePath)
{
	TRelationRun run;
	run.link(12, 49, {0.4, 0, 0});  // x = 12 out and back: 12 -> 6 -> 55 -> 49
	run.link(13, 48, {0.6, 0, 0});  // x = 13: 13 -> 6 -> 55 -> 48
	const CRelationTruth truth(run.relations, run.kfs);
	ASSERT_EQ(truth.relationsBetween(12, 49), 13U);
	ASSERT_EQ(truth.relationsBetween(13, 48), 15U);
	const TLoopRecall r = evaluateLoopRecall(run.graph, run.kfs, truth);
	ASSERT_EQ(r.loopLinks.size(), 2U);
	EXPECT_TRUE(r.loopLinks[0].judged && r.loopLinks[0].agrees);
	EXPECT_TRUE(r.loopLinks[1].judged);
	EXPECT_FALSE(r.loopLinks[1].agrees);  // sqrt(0.3^2 + 0.45^2) = 0.54 m
	TLoopRecallParams fixed;
	fixed.maxXYPerRelation_m = 0;  // the fixed 0.3 m of before: both false
	EXPECT_EQ(evaluateLoopRecall(run.graph, run.kfs, truth, fixed).falseClosures, 2U);
}
