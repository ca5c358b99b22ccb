/* lrgc-eval: command line, evaluation, and the text and JSON reports. */
#include <algorithm>
#include "eval/CEvalApp.h"

#include "OutputsVsInputs.h"
#include "atomic_file.h"
#include <mrpt/core/exceptions.h>
#include <mrpt/core/format.h>

#include <cmath>
#include <ostream>
#include <sstream>
#include <stdexcept>

namespace lrgc::apps::eval
{
namespace
{
double parseDouble(const std::string& opt, const std::string& value)
{
	std::size_t used = 0;
	double v = 0;
	try
	{
		v = std::stod(value, &used);
	}
	catch (const std::exception&)
	{
		used = 0;
	}
	if (used != value.size() || !std::isfinite(v))
		throw std::invalid_argument(opt + ": '" + value + "' is not a number");
	return v;
}

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
		m_s << quote(v);
		return *this;
	}

private:
	std::ostringstream m_s;
	int m_depth = 0;
	bool m_first = true;
	std::string indent() const { return std::string(2 * m_depth, ' '); }
	static std::string quote(const std::string& v)
	{
		std::string q = "\"";
		for (const char c : v)
		{
			if (c == '"' || c == '\\')
				q += std::string("\\") + c;
			else if (static_cast<unsigned char>(c) < 0x20)
				q += mrpt::format("\\u%04x", c);
			else
				q += c;
		}
		return q + "\"";
	}
	void item(const char* key)
	{
		if (m_depth > 0) m_s << (m_first ? "\n" : ",\n") << indent();
		if (key) m_s << quote(key) << ": ";
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

void jsonLoops(JsonOut& j, const TEvalOptions& o, const TLoopRecall& r)
{
	j.beginObject("loops")
		.text("output", o.loopsDir)
		.text("reference", o.reference)
		.integer("places", r.places.size())
		.integer("closed", r.closed)
		.num("recall", r.recall(), "%.4f")
		.integer("loop_links", r.loopLinks.size())
		.integer("false_closures", r.falseClosures)
		.integer("judged_by_relations", r.byRelation)
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
		if (!l.agrees)
			j.beginObject()
				.integer("from", l.from)
				.integer("to", l.to)
				.num("off_m", l.offXY_m)
				.num("off_deg", l.offPhi_rad * 180 / M_PI)
				.num("chi2", l.chi2)
				.text("judged_by", l.byRelation ? "relations" : "reference")
				.end('}');
	j.end(']').end('}');
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

TRelationReport relationReport(const CTrajectory2D& trajectory,
							   std::vector<TRelation> relations, double tol)
{
	TRelationReport r;
	r.total = relations.size();
	r.evaluation = evaluateRelations(trajectory, relations, tol);
	r.relations = std::move(relations);
	return r;
}
}  // namespace

std::string CEvalApp::usage()
{
	return "Usage: lrgc-eval --trajectory T.tum [--relations R.relations] "
		   "[--ground-truth GT.txt]\n"
		   "                 [--json OUT.json] [--time-tolerance S] [--rpe-distance M]\n"
		   "  --trajectory     estimate, TUM `t x y z qx qy qz qw` or `t x y phi`\n"
		   "  --relations      relations file `t1 t2 x y z roll pitch yaw` (Kuemmerle et al. "
		   "2009)\n"
		   "  --ground-truth   ground truth `t x y phi` (or TUM): ATE after SE(2) alignment, "
		   "RPE\n"
		   "  --json           also write the figures as JSON\n"
		   "  --time-tolerance timestamps this close [s] are equal (default 1e-5)\n"
		   "  --rpe-distance   path length of the fixed-distance RPE [m] (default 1)\n"
		   "  --loops DIR      loop recall of an lrgc-slam output folder (graph.lrgc, "
		   "map.simplemap.gz)\n"
		   "  --reference      with --loops: trajectory standing in for the truth (e.g. the\n"
		   "                   dense run's trajectory.tum); places revisited after 60 s within "
		   "2 m,\n"
		   "                   10 m each; loop links off by > 0.3 m / 5 deg and chi2 > 16.27 "
		   "are false\n"
		   "                   (by --relations where one joins both ends within 20 s)\n"
		   "  --help, --version\n";
}

TEvalOptions CEvalApp::parseArguments(const std::vector<std::string>& args)
{
	TEvalOptions o;
	for (std::size_t i = 0; i < args.size(); ++i)
	{
		const std::string& a = args[i];
		const auto value = [&]() -> const std::string&
		{
			if (i + 1 >= args.size()) throw std::invalid_argument(a + ": missing value");
			return args[++i];
		};
		if (a == "--trajectory")
			o.trajectory = value();
		else if (a == "--relations")
			o.relations = value();
		else if (a == "--ground-truth")
			o.groundTruth = value();
		else if (a == "--json")
			o.jsonOut = value();
		else if (a == "--time-tolerance")
			o.timeTolerance_s = parseDouble(a, value());
		else if (a == "--rpe-distance")
			o.rpeDistance_m = parseDouble(a, value());
		else if (a == "--loops")
			o.loopsDir = value();
		else if (a == "--reference")
			o.reference = value();
		else
			throw std::invalid_argument("unknown argument '" + a + "'");
	}
	if (o.loopsDir.empty() != o.reference.empty())
		throw std::invalid_argument("--loops and --reference go together");
	if (o.trajectory.empty() && o.loopsDir.empty())
		throw std::invalid_argument("--trajectory is required");
	if (!o.trajectory.empty() && o.relations.empty() && o.groundTruth.empty())
		throw std::invalid_argument("give --relations and/or --ground-truth");
	if (o.timeTolerance_s < 0) throw std::invalid_argument("--time-tolerance must be >= 0");
	if (!(o.rpeDistance_m > 0)) throw std::invalid_argument("--rpe-distance must be > 0");
	return o;
}

TEvalResult CEvalApp::evaluate(const TEvalOptions& o)
{
	TEvalResult r;
	if (!o.loopsDir.empty())
	{
		TRecallInputs in = loadRecallInputs(o.loopsDir, o.reference, o.timeTolerance_s);
		const TLoopRecallParams params;
		const TTruthBetween truth =
			o.relations.empty()
				? TTruthBetween()
				: truthFromRelations(loadRelations(o.relations), std::move(in.reference),
									 params.relationReach_s, o.timeTolerance_s);
		r.loops = evaluateLoopRecall(in.graph, in.keyframes, params, truth);
	}
	if (o.trajectory.empty()) return r;
	const CTrajectory2D trajectory = CTrajectory2D::loadFromFile(o.trajectory);
	r.trajectoryPoses = trajectory.size();
	r.backwardTimeJumps = trajectory.backwardTimeJumps();
	r.earliest_s = trajectory.earliestTime();
	r.latest_s = trajectory.latestTime();
	if (!o.relations.empty())
		r.relations = relationReport(trajectory, loadRelations(o.relations), o.timeTolerance_s);
	if (!o.groundTruth.empty())
	{
		const CTrajectory2D gt = CTrajectory2D::loadFromFile(o.groundTruth);
		r.groundTruthPoses = gt.size();
		r.ate = evaluateAte(trajectory, gt, o.timeTolerance_s);
		r.rpeStep = relationReport(trajectory, relationsOverSteps(gt, 1), o.timeTolerance_s);
		r.rpeDistance = relationReport(trajectory, relationsOverDistance(gt, o.rpeDistance_m),
									   o.timeTolerance_s);
	}
	return r;
}

void CEvalApp::printReport(const TEvalResult& r, const TEvalOptions& o, std::ostream& out)
{
	if (r.loops)
		out << "loops of " << o.loopsDir << " against " << o.reference << "\n"
			<< recallReport(*r.loops);
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

int CEvalApp::run(const std::vector<std::string>& args, std::ostream& out, std::ostream& err)
{
	if (std::find(args.begin(), args.end(), "--help") != args.end() ||
		std::find(args.begin(), args.end(), "-h") != args.end())
	{
		out << usage();
		return 0;
	}
	if (std::find(args.begin(), args.end(), "--version") != args.end())
	{
		out << "lrgc-eval " << LRGC_VERSION << "\n";
		return 0;
	}
	TEvalOptions o;
	try
	{
		o = parseArguments(args);
	}
	catch (const std::invalid_argument& e)
	{
		err << "lrgc-eval: " << e.what() << "; lrgc-eval --help lists the options\n";
		return 2;
	}
	if (const std::string clash =
			outputOverInput({{"--json", o.jsonOut}}, {{"--trajectory", o.trajectory},
													  {"--relations", o.relations},
													  {"--ground-truth", o.groundTruth},
													  {"--reference", o.reference}});
		!clash.empty())
	{
		err << "lrgc-eval: " << clash << "\n";
		return 2;
	}
	try
	{
		const TEvalResult r = evaluate(o);
		printReport(r, o, out);
		if (!o.jsonOut.empty()) writeTextFileAtomically(o.jsonOut, toJson(r, o));
		if (r.relations && r.relations->evaluation.errors.empty())
		{
			err << "lrgc-eval: no relation could be matched to the trajectory\n";
			return 1;
		}
		return 0;
	}
	catch (const std::exception& e)
	{
		err << "lrgc-eval: " << userMessage(e) << "\n";
		return 1;
	}
}

}  // namespace lrgc::apps::eval
