/* A synthetic run judged as lrgc-eval judges a real log, the truth exact: relations between
 * scans (lrgc_apps/eval/relation_metric.h) and loop recall (lrgc_apps/eval/loop_recall.h).
 * Header-only: its users (the e2e tests, bench/glass_stress) link lrgc_apps themselves, the
 * support library does not.
 *
 * Step k of a synthetic run is stamped syntheticStepTime(k, period) (synthetic_run.h).
 */
#pragma once

#include <lrgc/common/se2.h>
#include <lrgc/map_builder/CMetricMapBuilderLRGC.h>
#include <lrgc_apps/eval/loop_recall.h>
#include <lrgc_apps/eval/relation_metric.h>

#include <algorithm>
#include <vector>

#include "synthetic_run.h"

namespace lrgc::test
{
/** Relations from the exact truth: short ones from every fifth scan to the scans about 1, 5
 * and 9.8 s later (at least the next), or long ones from every tenth scan to every tenth scan
 * at least 60 s later. */
inline std::vector<lrgc::apps::eval::TRelation> truthRelations(
	const std::vector<mrpt::math::TPose2D>& truth, double period, bool longOnes)
{
	std::vector<lrgc::apps::eval::TRelation> rel;
	auto add = [&](size_t a, size_t b)
	{
		rel.push_back({mrpt::Clock::toDouble(syntheticStepTime(a, period)),
					   mrpt::Clock::toDouble(syntheticStepTime(b, period)),
					   lrgc::between(truth[a], truth[b])});
	};
	if (!longOnes)
	{
		for (size_t k = 0; k < truth.size(); k += 5)
			for (const double dt : {1.0, 5.0, 9.8})
				if (const size_t j = std::max<size_t>(1, size_t(dt / period));
					k + j < truth.size())
					add(k, k + j);
		return rel;
	}
	const size_t gap = size_t(60 / period);
	for (size_t a = 0; a < truth.size(); a += 10)
		for (size_t b = a + gap; b < truth.size(); b += 10) add(a, b);
	return rel;
}

/** lrgc-eval's relation metric of the estimated trajectory over `relations`. */
inline lrgc::apps::eval::TRelationEvaluation evaluateOnTruth(
	const lrgc::TTrajectory& est, const std::vector<lrgc::apps::eval::TRelation>& relations)
{
	std::vector<lrgc::apps::eval::TTimedPose2D> poses;
	for (const auto& s : est)
		poses.push_back({mrpt::Clock::toDouble(s.timestamp), s.robotInMap});
	return lrgc::apps::eval::evaluateRelations(lrgc::apps::eval::CTrajectory2D(poses),
											   relations);
}

/** Loop recall of the builder's final graph over the revisited places (10 m places of
 * keyframes within 2 m of one at least 60 s older; a place is closed by a true loop link kept
 * in the final graph), by the definition lrgc-eval --loops applies to real logs. */
inline lrgc::apps::eval::TLoopRecall truthLoopRecall(
	const lrgc::CMetricMapBuilderLRGC& builder, const std::vector<mrpt::math::TPose2D>& truth,
	double period)
{
	std::vector<lrgc::apps::eval::TRecallKeyframe> kfs;
	for (const auto& kf : builder.keyframes())
		kfs.push_back({period * double(kf.scanIndex), truth.at(kf.scanIndex)});
	return lrgc::apps::eval::evaluateLoopRecall(builder.graph(), kfs);
}
}  // namespace lrgc::test
