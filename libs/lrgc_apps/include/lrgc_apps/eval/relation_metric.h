/* The relation metric of Kuemmerle et al., "On measuring the accuracy of SLAM algorithms",
 * Autonomous Robots 27(4), 2009.
 *
 * A relation is the true motion delta* from the robot pose at laser timestamp t1 to the one at
 * t2, in the frame of the first. With the estimated poses x(t1), x(t2) of a trajectory:
 *
 *   delta = x(t1)^-1 (+) x(t2)           estimated motion (t1 -> t2), frame of x(t1)
 *   e     = delta (+) (delta*)^-1        the error transform
 *   translational error  |trans(e)|      [m]
 *   rotational error     |wrap(rot(e))|  [deg], wrap to (-180, 180]
 *
 * Reported over all matched relations: mean and (population) standard deviation of the
 * absolute errors and of their squares. A relation whose t1 or t2 lies outside the trajectory
 * time span cannot be evaluated; it is counted and listed, never silently dropped.
 *
 * Relations files: one per line, `t1 t2 x y z roll pitch yaw` (metres, radians); z, roll and
 * pitch are ignored for 2D.
 */
#pragma once

#include <lrgc_apps/eval/trajectory.h>
#include <mrpt/math/TPose2D.h>

#include <cstddef>
#include <string>
#include <vector>

namespace lrgc::apps::eval
{
struct TRelation
{
	double t1 = 0, t2 = 0;       //!< [s]
	mrpt::math::TPose2D motion;  //!< true pose at t2 in the frame of the pose at t1
	std::size_t line = 0;        //!< 1-based line in the relations file, 0 if not from a file
};

/** Reads a relations file. Throws "file:line: ..." on a line without exactly 8 numbers or
 * with a non-finite number, and if the file has no relation. */
std::vector<TRelation> loadRelations(const std::string& path);
/** Parses text as if it were a relations file named `sourceName`. */
std::vector<TRelation> parseRelations(const std::string& text, const std::string& sourceName);

/** Mean and population standard deviation of samples x_i and of their squares x_i^2. */
struct TErrorStats
{
	std::size_t count = 0;
	double mean = 0, stddev = 0;      //!< of x_i
	double meanSq = 0, stddevSq = 0;  //!< of x_i^2
	double max = 0;
	double rms() const;  //!< sqrt(meanSq)
	static TErrorStats fromSamples(const std::vector<double>& x);
};

/** Error of one matched relation. */
struct TRelationError
{
	std::size_t relationIndex = 0;  //!< into the relations vector
	double trans_m = 0;             //!< |trans(e)| [m]
	double rot_deg = 0;             //!< |rot(e)| [deg], in [0, 180]
	bool interpolated = false;      //!< at least one endpoint pose was interpolated
};

/** A relation that could not be evaluated, and why. */
struct TUnmatchedRelation
{
	std::size_t relationIndex = 0;
	std::string reason;  //!< e.g. "t1 = 12.5 outside the trajectory time span [13, 99]"
};

struct TRelationEvaluation
{
	std::vector<TRelationError> errors;         //!< matched relations, in input order
	std::vector<TUnmatchedRelation> unmatched;  //!< in input order
	TErrorStats trans_m;                        //!< of |trans(e)| [m]
	TErrorStats rot_deg;                        //!< of |rot(e)| [deg]
	std::size_t interpolatedCount = 0;  //!< matched relations with an interpolated endpoint
	/** The heading's tail over short relations (issue 28): of the matched relations less than
	 * kShortRelation_s apart, how many, and how many are off by more than 2 and 5 deg. */
	std::size_t shortCount = 0, shortOver2deg = 0, shortOver5deg = 0;
	double shortOver2degShare() const
	{
		return shortCount ? double(shortOver2deg) / double(shortCount) : 0.0;
	}
};

/** [s] a relation this short measures local registration (the heading's tail). */
constexpr double kShortRelation_s = 10.0;

/** e = (a^-1 (+) b) (+) relation^-1: the error transform of one relation, given the
 * estimated poses a = x(t1) and b = x(t2). */
mrpt::math::TPose2D relationErrorTransform(const mrpt::math::TPose2D& a,
										   const mrpt::math::TPose2D& b,
										   const mrpt::math::TPose2D& relation);

/** Evaluates every relation against `trajectory`, looking poses up with
 * CTrajectory2D::poseAt(t, exactTolerance_s). */
TRelationEvaluation evaluateRelations(const CTrajectory2D& trajectory,
									  const std::vector<TRelation>& relations,
									  double exactTolerance_s = 1e-5);

}  // namespace lrgc::apps::eval
