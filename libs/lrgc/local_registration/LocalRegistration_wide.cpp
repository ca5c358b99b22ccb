/* CLocalRegistration, a plain match's second tries (registerScan): from the prior's position at
 * the match's heading (headingFirstMatch), the wide search's second opinion on a suspect step
 * (overrulingWideMatch), the retries over the odometry's heading error (retriedMatch) and the
 * wide search itself (wideMatch). Registering each scan: LocalRegistration.cpp. */
#include <lrgc/local_registration/LocalRegistration.h>

#include <lrgc/common/se2.h>

#include <Eigen/Dense>
#include <cmath>
#include <mrpt/math/wrap2pi.h>

#include <limits>

namespace lrgc
{
namespace
{
/** [rad] A plain match that fails is retried from headings guess.phi + k kRetryStep over
 * +- kRetryAngle (matchWide, its standard of evidence): beyond ~1.5 deg of heading error at a
 * lever arm of 20 m (a long laser's far returns) the far points lie outside the match's gate,
 * so the match settles in a wrong basin and fails, the odometry is kept and the keyframe
 * enters the window misplaced, blurring the patch for the next scans (GlassBuilding, twice
 * the default odometry noise: straight steps 3 deg off, corner steps 5-9 deg off). */
const double kRetryAngle = mrpt::DEG2RAD(7.5);
/** [rad] ... over +- kRetryTurnAngle where the step turns by more than kRetryTurn, the
 * odometry's heading error growing with the turn (3.4 deg std for 34 deg there). */
const double kRetryTurnAngle = mrpt::DEG2RAD(15.0);
const double kRetryTurn = mrpt::DEG2RAD(10.0);
/** [rad] Step between the retry's starts: within the basin of a start (matchWide explores
 * with twice the gate, 1 m: 2.9 deg at 20 m). */
const double kRetryStep = mrpt::DEG2RAD(2.5);

/** [rad] The wide search's second opinion on a suspect step's plain match that agrees with the
 * prior (overrulingWideMatch) explores the heading within +- kOverruleAngle of the prior only:
 * half a right angle. The odometry errs by a share of the turn, or stalls in it (sparse
 * MIT-CSAIL: -2.6 deg read where the robot turned -27; the right overrules on the sparse
 * variants moved the match by 5-24 deg), while a building's aliases of a matched pose lie a
 * right angle or two away: after 80-105 deg turns at corridor junctions the plain match agreed
 * with the prior and the search's winner turned it 80-91 deg further, laying the scan onto the
 * corridor the window had seen rather than the one it looks into (sparse variants of Intel and
 * Killian with 1.5 m or 80 deg between scans: five such overrules; Killian's map turned round,
 * 72 m mean; doc/generalisation.md). A prior farther off than this is not agreed with by a
 * plain match; the full search (wide_search_angle) stays for a step whose plain match fails or
 * disagrees. */
const double kOverruleAngle = mrpt::DEG2RAD(45.0);
}  // namespace

// A plain match that disagrees with the prior may have found the heading and slid along a
// weakly held direction: started a few degrees off (the odometry's turn error: 3-4 deg std for
// a 34 deg turn in place at twice the default noise), the far returns and a railing's posts
// pull the translation while the heading converges, and the match settles 0.8-2.2 m along the
// hall at the right heading (glass_stress's atrium: the turns in place at its corners). The
// prior then stood, 3-7 deg off, and the next scans' patch held that error (keyframes
// 1277-1279 of seed 2; up to 7.5 deg a step, 1.1 % of the 10 s relations over 2 deg).
// Started again at the prior's position with the match's heading, the match lands in the
// prior's basin. It places the scan where it agrees with the prior and the disagreeing match
// does not explain clearly more of the scan (wide_ambiguity_margin: matchWide's standard for
// a hypothesis to beat the prior's own optimum). Only where the plain match could not place
// the scan anyway (a suspect step, or one far enough off for the second opinion): a small
// disagreement lets the scan win over the odometry as before (retried on every disagreement,
// ACES's local registration alone went from 0.120 to 0.171 m: 7 of 146 retries agreed, one
// where the plain match explained 0.94 of the scan and the retry 0.85).
std::optional<TScanMatch> CLocalRegistration::headingFirstMatch(
	const CReferenceCloud& cloud, const TScan2D& scan, const TPose2D& guess,
	const TScanMatch& plain, const std::function<bool(const TScanMatch&)>& disagrees)
{
	const TPose2D start(guess.x, guess.y, plain.scanInRef.phi);
	auto again = plainMatch(cloud, scan, start, m_cloud);
	if (!again || disagrees(*again) ||
		m_matcher.explainedFraction(cloud, scan, plain.scanInRef) -
				m_matcher.explainedFraction(cloud, scan, again->scanInRef) >=
			m_matcherParams.wide_ambiguity_margin)
		return std::nullopt;
	return again;
}

std::optional<TScanMatch> CLocalRegistration::overrulingWideMatch(const CReferenceCloud& cloud,
																  const TScan2D& scan,
																  const TPose2D& guess,
																  const TScanMatch& plain)
{
	// matchWide's winner must explain wide_ambiguity_margin more of the scan than the local
	// optimum from the guess, which is this plain match: a match that leaves less than that
	// unexplained cannot be overruled, and the search is skipped (the common case).
	if (m_matcher.explainedFraction(cloud, scan, plain.scanInRef) >
		1 - m_matcherParams.wide_ambiguity_margin)
		return std::nullopt;
	auto wide =
		wideMatch(cloud, scan, guess, std::min(kOverruleAngle, m_params.wide_search_angle), 0);
	if (!wide) return std::nullopt;
	// The plain match's own basin: nothing to overrule.
	if (!CScanMatcher::distinctHypotheses(plain.scanInRef, wide->scanInRef))
		return std::nullopt;
	return wide;
}

std::optional<TScanMatch> CLocalRegistration::retriedMatch(const CReferenceCloud& cloud,
														   const TScan2D& scan,
														   const TPose2D& guess,
														   const TMotionPrediction& prediction)
{
	const double angle =
		std::abs(prediction.motion.phi) > kRetryTurn ? kRetryTurnAngle : kRetryAngle;
	double heading = std::numeric_limits<double>::quiet_NaN();
	auto won = wideMatch(cloud, scan, guess, std::min(angle, m_params.wide_search_angle),
						 kRetryStep, &heading);
	// Rivals that share the winner's heading (a niche further along, people): the heading is
	// clear, the position is not. Matched again from the prior's position at that heading,
	// kept if it passes the plain match's checks and stays at that heading.
	if (!won && std::isfinite(heading))
		if (auto again = plainMatch(cloud, scan, TPose2D(guess.x, guess.y, heading), m_cloud);
			again &&
			std::abs(mrpt::math::wrapToPi(again->scanInRef.phi - heading)) <= kRetryStep / 2)
			won = std::move(again);
	// A winner within half a step of the guess's heading is the guess's own start, the basin
	// the plain match had already reached and failed its checks in (people, clutter): the
	// prior stands. The retry is for a heading the plain match could not reach.
	if (won && std::abs(mrpt::math::wrapToPi(won->scanInRef.phi - guess.phi)) <= kRetryStep / 2)
		return std::nullopt;
	return won;
}

std::optional<TScanMatch> CLocalRegistration::wideMatch(const CReferenceCloud& cloud,
														const TScan2D& scan,
														const TPose2D& guess, double angle,
														double step, double* sharedHeading)
{
	return m_matcher.matchWide(
		cloud, scan, guess, angle,
		[this](size_t n, const std::function<void(size_t)>& fn) { parallelFor(n, fn); }, step,
		sharedHeading);
}

}  // namespace lrgc
