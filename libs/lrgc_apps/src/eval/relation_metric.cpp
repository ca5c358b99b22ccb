/* The relation metric of Kuemmerle et al. 2009: relation files, per-relation error
 * transforms and their statistics. Formulas in relation_metric.h. */
#include "lrgc_apps/eval/relation_metric.h"

#include <lrgc/common/se2.h>
#include <mrpt/core/exceptions.h>
#include <mrpt/core/format.h>
#include <mrpt/math/wrap2pi.h>

#include <cmath>

namespace lrgc::apps::eval
{
std::vector<TRelation> loadRelations(const std::string& path)
{
	return parseRelations(readTextFile(path), path);
}

std::vector<TRelation> parseRelations(const std::string& text, const std::string& sourceName)
{
	std::vector<TRelation> out;
	forEachDataLine(
		text,
		[&](const std::string& line, std::size_t lineNo)
		{
			const auto v = parseNumberLine(line, sourceName, lineNo);
			if (v.size() != 8)
				THROW_EXCEPTION_FMT(
					"%s:%zu: expected 8 numbers (t1 t2 x y z roll pitch yaw), got %zu",
					sourceName.c_str(), lineNo, v.size());
			TRelation r;
			r.t1 = v[0];
			r.t2 = v[1];
			r.motion = {v[2], v[3], mrpt::math::wrapToPi(v[7])};
			r.line = lineNo;
			out.push_back(r);
		});
	if (out.empty())
		THROW_EXCEPTION_FMT("%s: no relation line in the file", sourceName.c_str());
	return out;
}

double TErrorStats::rms() const
{
	return std::sqrt(meanSq);
}

TErrorStats TErrorStats::fromSamples(const std::vector<double>& x)
{
	TErrorStats s;
	s.count = x.size();
	if (x.empty()) return s;
	const double n = static_cast<double>(x.size());
	for (const double v : x)
	{
		s.mean += v;
		s.meanSq += v * v;
		s.max = std::max(s.max, v);
	}
	s.mean /= n;
	s.meanSq /= n;
	// Two-pass population variances, sum (v - mean)^2 / n, for numerical robustness.
	double var = 0, varSq = 0;
	for (const double v : x)
	{
		var += (v - s.mean) * (v - s.mean);
		varSq += (v * v - s.meanSq) * (v * v - s.meanSq);
	}
	s.stddev = std::sqrt(var / n);
	s.stddevSq = std::sqrt(varSq / n);
	return s;
}

mrpt::math::TPose2D relationErrorTransform(const mrpt::math::TPose2D& a,
										   const mrpt::math::TPose2D& b,
										   const mrpt::math::TPose2D& relation)
{
	return lrgc::compose(lrgc::between(a, b), lrgc::inverse(relation));
}

TRelationEvaluation evaluateRelations(const CTrajectory2D& trajectory,
									  const std::vector<TRelation>& relations,
									  double exactTolerance_s)
{
	TRelationEvaluation ev;
	std::vector<double> trans, rot;
	const auto span = [&]
	{
		return trajectory.empty() ? std::string("(empty trajectory)")
								  : mrpt::format("[%.6f, %.6f]", trajectory.earliestTime(),
												 trajectory.latestTime());
	};
	for (std::size_t i = 0; i < relations.size(); ++i)
	{
		const TRelation& r = relations[i];
		const auto a = trajectory.poseAt(r.t1, exactTolerance_s);
		const auto b = trajectory.poseAt(r.t2, exactTolerance_s);
		if (!a || !b)
		{
			std::string why;
			if (!a) why += mrpt::format("t1 = %.6f", r.t1);
			if (!b) why += mrpt::format("%st2 = %.6f", a ? "" : " and ", r.t2);
			why += " outside the trajectory time span " + span();
			ev.unmatched.push_back({i, why});
			continue;
		}
		const auto e = relationErrorTransform(a->pose, b->pose, r.motion);
		TRelationError err;
		err.relationIndex = i;
		err.trans_m = std::hypot(e.x, e.y);
		err.rot_deg = std::abs(mrpt::math::wrapToPi(e.phi)) * 180.0 / M_PI;
		err.interpolated =
			a->how == TPoseLookup::Interpolated || b->how == TPoseLookup::Interpolated;
		if (err.interpolated) ++ev.interpolatedCount;
		trans.push_back(err.trans_m);
		rot.push_back(err.rot_deg);
		if (std::abs(r.t2 - r.t1) < kShortRelation_s)
		{
			++ev.shortCount;
			ev.shortOver2deg += err.rot_deg > 2.0;
			ev.shortOver5deg += err.rot_deg > 5.0;
		}
		ev.errors.push_back(err);
	}
	ev.trans_m = TErrorStats::fromSamples(trans);
	ev.rot_deg = TErrorStats::fromSamples(rot);
	return ev;
}

}  // namespace lrgc::apps::eval
