/* lrgc-eval as a library class: evaluates a trajectory against the relations of the SLAM
 * benchmark of Kuemmerle et al. 2009 (relation_metric.h) and/or against a ground-truth
 * trajectory (ATE and RPE, trajectory_error.h). Prints a human-readable report and optionally
 * writes the same figures as JSON.
 *
 *   lrgc-eval --trajectory T.tum --relations R.relations [--json out.json]
 *   lrgc-eval --trajectory T.tum --ground-truth GT.txt [--rpe-distance 1.0] [--json out.json]
 *   lrgc-eval --loops OUT_DIR --reference REF.tum [--json out.json]   (loop_recall.h)
 */
#pragma once

#include <lrgc_apps/eval/loop_recall.h>
#include <lrgc_apps/eval/relation_truth.h>
#include <lrgc_apps/eval/relation_metric.h>
#include <lrgc_apps/eval/trajectory_error.h>

#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

namespace lrgc::apps::eval
{
struct TEvalOptions
{
	std::string trajectory;          //!< TUM (or `t x y phi`) file of the estimate
	std::string relations;           //!< relations file, optional
	std::string groundTruth;         //!< ground-truth trajectory, optional
	std::string jsonOut;             //!< JSON report path, optional
	std::string loopsDir;            //!< lrgc-slam output folder whose loops are scored
	std::string reference;           //!< trajectory standing in for the truth (--loops)
	double timeTolerance_s = 1e-5;   //!< equal timestamps within this [s] use the pose as is
	double rpeDistance_m = 1.0;      //!< path length of the fixed-distance RPE [m]
	std::size_t listUnmatched = 20;  //!< unmatched relations listed in the text report
};

struct TRelationReport
{
	std::size_t total = 0;
	TRelationEvaluation evaluation;
	std::vector<TRelation> relations;  //!< kept to name lines and times of unmatched ones
};

struct TEvalResult
{
	std::size_t trajectoryPoses = 0;
	std::size_t backwardTimeJumps = 0;
	double earliest_s = 0, latest_s = 0;
	std::optional<TRelationReport> relations;
	std::optional<TAbsoluteTrajectoryError> ate;
	std::optional<TRelationReport> rpeStep;      //!< ground-truth relations, 1 step
	std::optional<TRelationReport> rpeDistance;  //!< ground-truth relations, fixed distance
	std::size_t groundTruthPoses = 0;
	std::optional<TLoopRecall> loops;  //!< --loops
};

class CEvalApp
{
public:
	/** Parses the arguments after the program name. Throws std::invalid_argument with a
	 * message for an unknown option, a missing value, or a missing --trajectory. */
	static TEvalOptions parseArguments(const std::vector<std::string>& args);
	static std::string usage();

	/** Loads the inputs and computes every metric requested. Throws (MRPT exceptions,
	 * naming file and line) on unreadable or malformed inputs. */
	static TEvalResult evaluate(const TEvalOptions& options);

	static void printReport(const TEvalResult& result, const TEvalOptions& options,
							std::ostream& out);
	static std::string toJson(const TEvalResult& result, const TEvalOptions& options);

	/** The whole CLI: parse, evaluate, print to `out`, write JSON. Returns 0 on success, 1 on
	 * input errors or when no relation/ground-truth pose could be matched, 2 on usage errors;
	 * messages go to `err`. */
	static int run(const std::vector<std::string>& args, std::ostream& out, std::ostream& err);
};

}  // namespace lrgc::apps::eval
