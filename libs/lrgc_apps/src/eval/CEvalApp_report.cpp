/* lrgc-eval's reports of an evaluation (CEvalApp::printReport, CEvalApp::toJson): the text
 * a reader sees and the same figures as JSON, by a minimal emitter of our own (JsonOut). */
#include "eval/CEvalApp.h"
#include "lrgc_apps/JsonString.h"

#include <Eigen/LU>

#include <mrpt/core/format.h>

#include <cmath>
#include <ostream>
#include <sstream>
#include <string>

namespace lrgc::apps::eval
{
namespace
{
/** Minimal JSON emitter: nested objects and arrays, numbers (non-finite as null), strings. */
class JsonOut
{
public:
	std::string str() const { return m_s.str() + "\n"; }
	JsonOut& beginObject(const char* key = nullptr) { return open(key, '{'); }
	JsonOut& beginArray(const char* key = nullptr) { return open(key, '['); }
	JsonOut& end(char c)
	{
		m_first = false;
		--m_depth;
		m_s << "\n" << indent() << c;
		return *this;
	}
	/** `fmt` "%.10g" by default; timestamps [s] need "%.6f" to keep their microseconds. */
	JsonOut& num(const char* key, double v, const char* fmt = "%.10g")
	{
		item(key);
		if (std::isfinite(v))
			m_s << mrpt::format(fmt, v);
		else
			m_s << "null";
		return *this;
	}
	JsonOut& integer(const char* key, std::size_t v)
	{
		item(key);
		m_s << v;
		return *this;
	}
	JsonOut& text(const char* key, const std::string& v)
	{
		item(key);
		m_s << jsonString(v);
		return *this;
	}

private:
	std::ostringstream m_s;
	int m_depth = 0;
	bool m_first = true;
	std::string indent() const { return std::string(2 * m_depth, ' '); }
	void item(const char* key)
	{
		if (m_depth > 0) m_s << (m_first ? "\n" : ",\n") << indent();
		if (key) m_s << jsonString(key) << ": ";
		m_first = false;
	}
	JsonOut& open(const char* key, char c)
	{
		item(key);
		m_s << c;
		++m_depth;
		m_first = true;
		return *this;
	}
};

void jsonStats(JsonOut& j, const char* key, const TErrorStats& s)
{
	j.beginObject(key)
		.integer("count", s.count)
		.num("mean", s.mean)
		.num("std", s.stddev)
		.num("mean_sq", s.meanSq)
		.num("std_sq", s.stddevSq)
		.num("rms", s.rms())
		.num("max", s.max)
		.end('}');
}

void jsonRelations(JsonOut& j, const char* key, const TRelationReport& r)
{
	const auto& ev = r.evaluation;
	j.beginObject(key)
		.integer("total", r.total)
		.integer("used", ev.errors.size())
		.integer("unmatched", ev.unmatched.size())
		.integer("interpolated", ev.interpolatedCount);
	jsonStats(j, "translational_m", ev.trans_m);
	jsonStats(j, "rotational_deg", ev.rot_deg);
	// The heading's tail over relations under 10 s apart (issue 28).
	j.beginObject("short_relations")
		.num("max_dt_s", kShortRelation_s, "%g")
		.integer("count", ev.shortCount)
		.integer("rotational_over_2_deg", ev.shortOver2deg)
		.integer("rotational_over_5_deg", ev.shortOver5deg)
		.num("share_over_2_deg", ev.shortOver2degShare(), "%.6f")
		.end('}');
	j.beginArray("unmatched_relations");
	for (const auto& u : ev.unmatched)
	{
		const TRelation& rel = r.relations[u.relationIndex];
		j.beginObject()
			.integer("line", rel.line)
			.num("t1", rel.t1, "%.6f")
			.num("t2", rel.t2, "%.6f")
			.text("reason", u.reason)
			.end('}');
	}
	j.end(']').end('}');
}

/** linkCalibration and every judged loop link's error and claimed covariance (from's axes). */
void jsonCalibration(JsonOut& j, const TLoopRecall& r)
{
	const TLinkCalibration c = linkCalibration(r.loopLinks);
	const auto axis = [&j](const char* name, const TLinkCalibration::TAxis& a)
	{
		j.beginObject(name)
			.num("median", a.median)
			.num("mean", a.mean)
			.num("over_6_63", a.over99)
			.end('}');
	};
	j.beginObject("calibration").integer("links", c.links);
	j.num("chi2_median", c.chi2Median).num("chi2_over_7_81", c.chi2Over95);
	axis("weak", c.weak), axis("strong", c.strong), axis("heading", c.heading);
	j.num("weak_std_median_m", c.weakStdMedian_m)
		.num("strong_std_median_m", c.strongStdMedian_m)
		.num("weak_error_median_m", c.weakErrMedian_m)
		.end('}')
		.beginArray("judged_links");
	for (const auto& l : r.loopLinks)
	{
		if (!l.judged) continue;
		const Eigen::Matrix3d C = l.information.inverse();
		j.beginObject()
			.integer("from", l.from)
			.integer("to", l.to)
			.num("ex_m", l.error.x(), "%.5f")
			.num("ey_m", l.error.y(), "%.5f")
			.num("ephi_rad", l.error.z(), "%.6f")
			.num("cxx", C(0, 0), "%.4g")
			.num("cxy", C(0, 1), "%.4g")
			.num("cyy", C(1, 1), "%.4g")
			.num("cxphi", C(0, 2), "%.4g")
			.num("cyphi", C(1, 2), "%.4g")
			.num("cphiphi", C(2, 2), "%.4g")
			.num("chi2", l.chi2)
			.end('}');
	}
	j.end(']');
}

void jsonLoops(JsonOut& j, const TEvalOptions& o, const TLoopRecall& r)
{
	j.beginObject("loops")
		.text("output", o.loopsDir)
		.text("reference", o.reference)
		.text("judge", o.reference.empty() ? "relations" : "reference")
		.integer("places", r.places.size())
		.integer("closed", r.closed)
		.num("recall", r.recall(), "%.4f")
		.integer("loop_links", r.loopLinks.size())
		.integer("false_closures", r.falseClosures)
		.integer("judged_by_relations", r.byRelation)
		.integer("not_judged", r.notJudged)
		.beginArray("places_not_closed");
	for (const auto& p : r.places)
		if (!p.closed)
			j.beginObject()
				.integer("first_keyframe", p.firstKeyframe)
				.integer("last_keyframe", p.lastKeyframe)
				.num("first_time_s", p.firstTime_s, "%.6f")
				.num("last_time_s", p.lastTime_s, "%.6f")
				.end('}');
	j.end(']').beginArray("false_closures_list");
	for (const auto& l : r.loopLinks)
		if (l.judged && !l.agrees)
			j.beginObject()
				.integer("from", l.from)
				.integer("to", l.to)
				.num("off_m", l.offXY_m)
				.num("off_deg", l.offPhi_rad * 180 / M_PI)
				.num("chi2", l.chi2)
				.integer("relations", l.relations)
				.text("judged_by", l.byRelation ? "relations"
								   : l.bridged  ? "relations and a map bridge"
												: "reference")
				.end('}');
	j.end(']');
	jsonCalibration(j, r);
	j.end('}');
}

std::string statsLine(const char* what, const TErrorStats& s, const char* unit)
{
	return mrpt::format(
		"  %-15s mean %.4f +/- %.4f %s   squared %.6f +/- %.6f %s^2   rms %.4f   max %.4f\n",
		what, s.mean, s.stddev, unit, s.meanSq, s.stddevSq, unit, s.rms(), s.max);
}

void printRelations(std::ostream& out, const char* title, const TRelationReport& r,
					std::size_t listMax)
{
	const auto& ev = r.evaluation;
	out << mrpt::format(
		"%s: %zu relations, %zu used (%zu with an interpolated pose), %zu unmatched\n", title,
		r.total, ev.errors.size(), ev.interpolatedCount, ev.unmatched.size());
	if (!ev.errors.empty())
	{
		out << statsLine("translational", ev.trans_m, "m");
		out << statsLine("rotational", ev.rot_deg, "deg");
		out << mrpt::format(
			"  under %g s apart: %zu relations, %zu (%.2f %%) off by > 2 deg, %zu by > 5 deg\n",
			kShortRelation_s, ev.shortCount, ev.shortOver2deg, 100 * ev.shortOver2degShare(),
			ev.shortOver5deg);
	}
	for (std::size_t k = 0; k < ev.unmatched.size() && k < listMax; ++k)
		out << "  unmatched, line " << r.relations[ev.unmatched[k].relationIndex].line << ": "
			<< ev.unmatched[k].reason << "\n";
	if (ev.unmatched.size() > listMax)
		out << "  ... and " << ev.unmatched.size() - listMax << " more unmatched (see JSON)\n";
}
}  // namespace

void CEvalApp::printReport(const TEvalResult& r, const TEvalOptions& o, std::ostream& out)
{
	if (r.loops)
		out << "loops of " << o.loopsDir << " against "
			<< (o.reference.empty() ? o.relations + " alone" : o.reference) << "\n"
			<< recallReport(*r.loops) << calibrationReport(*r.loops);
	if (o.trajectory.empty()) return;
	out << mrpt::format(
		"trajectory %s: %zu poses over [%.6f, %.6f] s (%.1f s), %zu backward time jumps\n",
		o.trajectory.c_str(), r.trajectoryPoses, r.earliest_s, r.latest_s,
		r.latest_s - r.earliest_s, r.backwardTimeJumps);
	if (r.relations)
		printRelations(out, ("relations " + o.relations).c_str(), *r.relations,
					   o.listUnmatched);
	if (r.ate)
	{
		const auto& a = *r.ate;
		out << mrpt::format(
			"ground truth %s: %zu poses, %zu paired, %zu outside the trajectory's time span\n",
			o.groundTruth.c_str(), r.groundTruthPoses, a.matched,
			a.unmatchedGroundTruth.size());
		out << mrpt::format("ATE after SE(2) alignment (x %.3f m, y %.3f m, phi %.2f deg):\n",
							a.alignment.x, a.alignment.y, a.alignment.phi * 180.0 / M_PI);
		out << statsLine("translational", a.trans_m, "m");
		out << statsLine("rotational", a.rot_deg, "deg");
	}
	if (r.rpeStep) printRelations(out, "RPE over 1 step", *r.rpeStep, o.listUnmatched);
	if (r.rpeDistance)
		printRelations(out, mrpt::format("RPE over %.3g m", o.rpeDistance_m).c_str(),
					   *r.rpeDistance, o.listUnmatched);
}

std::string CEvalApp::toJson(const TEvalResult& r, const TEvalOptions& o)
{
	JsonOut j;
	j.beginObject();
	if (r.loops) jsonLoops(j, o, *r.loops);
	if (o.trajectory.empty()) return j.end('}').str();
	j.beginObject("trajectory")
		.text("path", o.trajectory)
		.integer("poses", r.trajectoryPoses)
		.integer("backward_time_jumps", r.backwardTimeJumps)
		.num("earliest_s", r.earliest_s, "%.6f")
		.num("latest_s", r.latest_s, "%.6f")
		.end('}')
		.num("time_tolerance_s", o.timeTolerance_s);
	if (r.relations)
	{
		j.text("relations_path", o.relations);
		jsonRelations(j, "relations", *r.relations);
	}
	if (r.ate)
	{
		const auto& a = *r.ate;
		j.text("ground_truth_path", o.groundTruth)
			.integer("ground_truth_poses", r.groundTruthPoses);
		j.beginObject("ate")
			.integer("matched", a.matched)
			.integer("unmatched", a.unmatchedGroundTruth.size())
			.beginObject("alignment")
			.num("x", a.alignment.x)
			.num("y", a.alignment.y)
			.num("phi_deg", a.alignment.phi * 180.0 / M_PI)
			.end('}');
		jsonStats(j, "translational_m", a.trans_m);
		jsonStats(j, "rotational_deg", a.rot_deg);
		j.end('}');
	}
	if (r.rpeStep) jsonRelations(j, "rpe_step", *r.rpeStep);
	if (r.rpeDistance)
	{
		j.num("rpe_distance_m", o.rpeDistance_m);
		jsonRelations(j, "rpe_distance", *r.rpeDistance);
	}
	j.end('}');
	return j.str();
}

}  // namespace lrgc::apps::eval
