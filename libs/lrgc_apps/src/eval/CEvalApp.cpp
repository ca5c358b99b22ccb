/* lrgc-eval: command line and evaluation; the text and JSON reports are in
 * CEvalApp_report.cpp. */
#include <algorithm>
#include "eval/CEvalApp.h"

#include "OutputsVsInputs.h"
#include "atomic_file.h"
#include <mrpt/core/exceptions.h>

#include <cmath>
#include <ostream>
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
		   "map.simplemap.gz);\n"
		   "                   with --relations alone: judged by chains of relations (no\n"
		   "                   reference), places where they join keyframes 60 s apart "
		   "within 2 m\n"
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
	if (!o.reference.empty() && o.loopsDir.empty())
		throw std::invalid_argument("--reference goes with --loops");
	if (!o.loopsDir.empty() && o.reference.empty() && o.relations.empty())
		throw std::invalid_argument("--loops needs --reference and/or --relations");
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
		if (o.reference.empty())  // the relations alone (relation_truth.h)
		{
			TRelationTruthParams tp;
			tp.tolerance_s = o.timeTolerance_s;
			const CRelationTruth truth(loadRelations(o.relations), in.keyframes, tp);
			r.loops = evaluateLoopRecall(in.graph, in.keyframes, truth, params);
		}
		else
		{
			const TTruthBetween truth =
				o.relations.empty()
					? TTruthBetween()
					: truthFromRelations(loadRelations(o.relations), std::move(in.reference),
										 params.relationReach_s, o.timeTolerance_s);
			r.loops = evaluateLoopRecall(in.graph, in.keyframes, params, truth);
		}
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
