/* CLocalRegistration, registering each scan (paper 2.2): the plain match against the window
 * patch, checked against the motion prior, and the scan placed by it, the prior or a second
 * try (LocalRegistration_wide.cpp). The window and its patch: LocalRegistration_patch.cpp; a
 * new keyframe's links and the window solve: LocalRegistration_links.cpp; the helper thread's
 * share: LocalRegistration_window.cpp. */
#include <lrgc/local_registration/LocalRegistration.h>

#include <lrgc/common/params_io.h>
#include <lrgc/common/se2.h>

#include <mrpt/config/CConfigFileBase.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <mrpt/math/wrap2pi.h>

namespace lrgc
{
namespace
{
/** [rad] A plain match that contradicts the odometry prior (chi2 above glitch_gate_chi2) by a
 * turn larger than this, where nothing made the odometry suspect, is checked by the wide
 * search (registerScan). Odometry that is right turns by at most a few degrees per step
 * beyond its model; on the benchmark logs 0 to 11 matches per log contradict it by more. */
const double kSecondOpinionTurn = mrpt::DEG2RAD(10.0);
/** [m] ... or shifts it by more than this (0 to 2 matches per benchmark log beyond it). */
constexpr double kSecondOpinionShift = 0.3;

/** The match turns the robot by more than kSecondOpinionTurn against `guess`, or shifts it by
 * more than kSecondOpinionShift. People or a repetitive scene (a hall's pillar rows) can pull
 * a plain match into another basin, and one such scan turns every later scan with it (a
 * 70 x 45 m hall with 25 people: 23 deg in one step, the map's tail 10 m off). */
bool farFrom(const mrpt::math::TPose2D& guess, const TScanMatch& m)
{
	return std::abs(mrpt::math::wrapToPi(m.scanInRef.phi - guess.phi)) > kSecondOpinionTurn ||
		   translationNorm(between(guess, m.scanInRef)) > kSecondOpinionShift;
}

/** [-] "Clearly" for onlyReversesTheWheels: a step longer than this many of the odometry's own
 * sigma along it; a pose behind the last scan's by more than this many of the match's. */
constexpr double kClearStep = 2.0;

/** [-] forwardWinner's onlyReversesTheWheels: a wide search's winner, to be refused, must
 * also put the scan behind the last scan (the registered step last scan <- scan, in the last
 * scan's frame) by more than this part of the wheels' step length, along the step's direction
 * u (a match a few cm behind in a turn disputes the step's offset across u, not its
 * direction). Glass atrium seed 2, scan 2331 (glass_stress): 0.848 m behind on a 0.419 m
 * straight step (2.0 of it): refused. Sparse Killian (bench/make-sparse-log, seed 1), a
 * 47.5 deg turn: the retry's winner 0.03 m behind on a 0.533 m step (0.05 of it), 0.40 m
 * across it, passed the kClearStep test only by its match sigma along u (under 1.5 cm): kept
 * (helper kink22). Only for the winner: matchOverrules (a plain match, which still places the
 * scan) asks for no part of the step (0); with 0.5 there dense Killian's trajectory changed. */
constexpr double kReversedPart = 0.5;

/** The match disagrees with the prior only by putting the robot behind its previous pose,
 * against a step the wheels clearly rolled forward: the odometry's step is longer than
 * kClearStep of its sigma along its direction u; the registered step (last scan <- scan, the
 * last scan at guess (+) motion^-1, both in the last scan's frame) has a component along u
 * below -kClearStep of the match's own sigma along u and below -reversedPart of the wheels'
 * step length (forwardWinner: kReversedPart; matchOverrules: 0); and the match slid along u
 * to the odometry's step agrees with the prior (`disagrees` false: its heading and its offset
 * across u are not in question). Wheels that slip read more than the robot travelled, a late
 * reading less, then more; neither turns forward travel into backward, an alias along a
 * corridor does.
 * On dense Killian's long corridor (scans 7924-7951, 0.086 m per scan, no turn) 8 of 27 plain
 * matches, confident (C_xx 5e-5 .. 1e-3 m^2) and 0.09-0.30 m short of the prior (repeating
 * doors), put the robot 0.003-0.21 m behind the last scan; with this rule 4 scans there keep
 * the odometry (0.07-0.16 m behind).
 * On Intel, ACES and MIT-CSAIL no match that rejects the odometry does: 3 are behind by 1-6 mm
 * on steps of 1-2 cm (under kClearStep) in turns, and dispute the heading too; ACES's late
 * readings register 2-5 times the odometry's step, forward. */
bool onlyReversesTheWheels(const mrpt::math::TPose2D& guess,
						   const TMotionPrediction& prediction, const TScanMatch& m,
						   const std::function<bool(const TScanMatch&)>& disagrees,
						   double reversedPart)
{
	if (!prediction.fromOdometry) return false;
	const Eigen::Vector2d t(prediction.motion.x, prediction.motion.y);
	const double length = t.norm();
	if (length == 0) return false;
	const Eigen::Vector2d u = t / length;
	const double sigma = std::sqrt(u.dot(prediction.cov.topLeftCorner<2, 2>() * u));
	if (length <= kClearStep * sigma) return false;
	const mrpt::math::TPose2D last = compose(guess, inverse(prediction.motion));
	const mrpt::math::TPose2D step = between(last, m.scanInRef);
	const double along = u.x() * step.x + u.y() * step.y;
	// Clearly behind: by more than kClearStep of the match's own sigma along u.
	const Eigen::Matrix2d C = m.covariance().get().topLeftCorner<2, 2>();
	if (along >= -kClearStep * std::sqrt(u.dot(C * u))) return false;
	// ... and by `reversedPart` of the wheels' step (kReversedPart for a wide winner: one a few
	// cm behind in a turn disputes the step's offset across u, not its direction).
	if (along >= -reversedPart * length) return false;
	TScanMatch slid = m;
	const double slide = length - along;
	slid.scanInRef = compose(
		last, mrpt::math::TPose2D(step.x + slide * u.x(), step.y + slide * u.y(), step.phi));
	return !disagrees(slid);
}

/** The match `m` (from the wide search: `wide`) overrules the odometry, the keyframe's odometry
 * link becoming the registered motion (CMetricMapBuilderLRGC::odometryLink): it disagrees with
 * the prior, and not only by reversing the wheels' clear forward step. Where that is all it
 * disputes, the odometry stands and the match, which still places the scan, is the suspect. */
bool matchOverrules(const TScanMatch& m, bool wide, const mrpt::math::TPose2D& guess,
					const TMotionPrediction& prediction,
					const std::function<bool(const TScanMatch&)>& disagrees)
{
	return disagrees(m) &&
		   (wide || !onlyReversesTheWheels(guess, prediction, m, disagrees, 0.0));
}
}  // namespace

/** `won` (a wide search's winner), unless it disagrees with the prior only by putting the robot
 * behind the last scan against the wheels' clear forward step (onlyReversesTheWheels). The wide
 * search looks for a heading the plain match could not reach (a glitch, a failed match's
 * odometry heading error); a winner at the prior's heading but behind the last scan is an alias
 * along the hall, and the prior stands (registerScan: the plain match where it agreed, else no
 * match). glass_stress's atrium, seed 2, scan 2331 (east hall, lap 3): the plain match failed,
 * the retry's winner (heading 1.4 deg from the prior's, inside its 1.7 deg std) put the robot
 * 0.85 m behind the last scan against the wheels' 0.42 m forward, its odometry link was
 * replaced by that and its keyframe placed 1.25 m back; the patch it blurred failed the next
 * three scans' matches, which then hung on the odometry's 2.4 deg error (the map's worst
 * pose, 1.27 m, and its three 10 s relations over 2 deg). */
std::optional<TScanMatch> forwardWinner(std::optional<TScanMatch> won,
										const mrpt::math::TPose2D& guess,
										const TMotionPrediction& prediction,
										const std::function<bool(const TScanMatch&)>& disagrees)
{
	if (won && disagrees(*won) &&
		onlyReversesTheWheels(guess, prediction, *won, disagrees, kReversedPart))
		return std::nullopt;
	return won;
}

CLocalRegistration::CLocalRegistration(const TLocalRegistrationParams& p,
									   const TScanMatcherParams& matcher,
									   const TPoseGraphOptimizerParams& optimizer,
									   bool helperThread)
	: m_params(p), m_matcherParams(matcher), m_optimizer(optimizer), m_helper(helperThread)
{
	// [LocalRegistration] max_free_space_violation (0.3) replaces [ScanMatcher]'s (0.15) for
	// every match of this stage (scan to window, pairwise): with an odometry prior a wrong
	// match is unlikely, and people and glass in the window's scans would make the strict
	// value reject good matches. Loop closing and revisits keep [ScanMatcher]'s.
	m_matcherParams.max_free_space_violation = p.max_free_space_violation;
	m_matcher = CScanMatcher(m_matcherParams);
	// The window patch's free-space test (a scan's points times 15 views, and the patch's
	// anchors: 5-15 % of the mapping thread's mapping instructions on MIT-CSAIL, range_030,
	// ACES) shared with the helper, idle during the plain match but for the deferred
	// covariances (CReferenceCloud::freeSpaceViolation: the same value on any threads).
	m_matcher.setFreeSpaceParallel([this](size_t n, const std::function<void(size_t)>& fn)
								   { parallelFor(n, fn); });
	TScanMatcherParams crowd = m_matcherParams;
	crowd.free_space_min_run_m = p.crowd_min_run_m;
	m_crowdMatcher = CScanMatcher(crowd);
	m_crowdMatcher.setFreeSpaceParallel([this](size_t n, const std::function<void(size_t)>& fn)
										{ parallelFor(n, fn); });
}

CLocalRegistration::~CLocalRegistration() = default;  // the helper's jobs end first

// A loose fit against the patch (the robot turning into ground the window has not seen) is
// refitted with the inlier gate (CScanMatcher::refitLoose): a compromise between the unseen
// part and the shared walls would be confirmed by the pairwise matches started from it (sparse
// MIT-CSAIL 334 -> 335: patch and pairwise links both 6 deg off).
// With `deferOn` (the shared `cloud`) the match's covariance is deferred (matchDeferred).
std::optional<TScanMatch> CLocalRegistration::plainMatch(const CScanMatcher& matcher,
														 const CReferenceCloud& cloud,
														 const TScan2D& scan,
														 const TPose2D& guess,
														 const TCloudPtr& deferOn)
{
	std::optional<TScanMatch> match = deferOn ? matcher.matchDeferred(deferOn, scan, guess)
											  : matcher.match(cloud, scan, guess);
	if (match) match = matcher.refitLoose(cloud, scan, *match, deferOn);
	return match;
}

// A loose prior (sparse steps): people standing where the window saw through do not refuse
// the plain match, as the prior that would stand instead is the worse guess (crowd_min_run_m).
const CScanMatcher& CLocalRegistration::plainMatcherFor(const Eigen::Matrix3d& priorCov) const
{
	return std::sqrt(priorCov(2, 2)) > m_params.crowd_min_prior_std ? m_crowdMatcher
																	: m_matcher;
}

TRegistration CLocalRegistration::registerScan(const CPoseGraph& graph,
											   const TKeyframes& keyframes, const TScan2D& scan,
											   const mrpt::math::TPose2D& priorInMap,
											   const TMotionPrediction& prediction)
{
	const Eigen::Matrix3d& priorCov = prediction.cov;
	TRegistration reg{priorInMap, priorCov, false, false};
	m_lastPatchMatch.reset();
	m_patchLinkable = prediction.fromOdometry;
	resizeWindowFor(prediction);
	if (m_window.empty()) return reg;  // no keyframe of this session yet
	if (auto still = stillRegistration(graph, scan, prediction)) return *still;
	const CReferenceCloud& cloud = windowCloud(graph, keyframes);
	const TPose2D newestInMap = graph.pose(*m_cloudNewest);
	const TPose2D guess = between(newestInMap, priorInMap);

	auto disagrees = [&](const TScanMatch& m) { return disagreesWith(guess, priorCov, m); };
	auto match = plainMatch(plainMatcherFor(priorCov), cloud, scan, guess, m_cloud);
	// A pause in the scans, a large predicted turn or an odometry jump (the prior is then the
	// constant-velocity one), and the plain match failed or contradicts the prior: the
	// odometry may lag or jump, so the wide search decides and may overrule the prior, but
	// only with evidence an aliased scene cannot fake (matchWide: a clear majority of the scan
	// matched, a clear lead over every other heading and over the prior's own optimum). A
	// doubtful case keeps the prior, not a contradicting match.
	const bool suspect = std::abs(prediction.motion.phi) > m_params.glitch_min_turn ||
						 prediction.stepSeconds > m_params.glitch_min_gap_s ||
						 prediction.odometryJump;
	// A match that could not place the scan against the prior (a suspect step or a second
	// opinion's, below): found the heading and slid into another basin? (headingFirstMatch)
	if (match && (suspect || farFrom(guess, *match)) && disagrees(*match))
		if (auto again = headingFirstMatch(cloud, scan, guess, *match, disagrees))
			match = std::move(again);
	const bool disagreed = match && disagrees(*match);
	// The prediction's match failed or contradicts it: the odometry's alternative, if any.
	if ((!match || disagreed) && prediction.alternative)
		if (auto alt = alternativeMatch(cloud, scan, newestInMap, priorInMap, prediction))
			return placedByAlternative(reg, scan, *alt, newestInMap, prediction);
	const bool standstill = isZeroStep(prediction.motion);
	// Nothing made the odometry suspect, yet the match is far from it (farFrom: another basin,
	// people or a hall's pillar rows): the wide search's second opinion, with the same
	// evidence.
	const bool implausible = disagreed && farFrom(guess, *match);
	// A wide winner, unless it only reverses the wheels' step (forwardWinner), with evidence.
	auto second = [&](std::optional<TScanMatch> won)
	{
		return withEvidence(graph, keyframes, scan,
							forwardWinner(std::move(won), guess, prediction, disagrees));
	};
	if ((implausible || (suspect && (!match || disagreed))) && m_params.wide_search_angle > 0)
	{
		match = second(wideMatch(cloud, scan, guess, m_params.wide_search_angle, 0));
		reg.wideSearch = match.has_value();
	}
	// The plain match failed on a step nothing made suspect (and the wheels moved: else the
	// prior stands, as below): retried over the heading the odometry's error may span (a
	// far-turning step's wider), with the same evidence.
	else if (!match && !standstill && m_params.wide_search_angle > 0)
	{
		match = second(retriedMatch(cloud, scan, guess, prediction));
		reg.wideSearch = match.has_value();
	}
	// Wheels that did not turn at all are the one odometry reading to trust over a match
	// that moves the robot: such a match is a wrong fit (people walking by a robot that
	// stands still, a rotationally ambiguous place); keep the prior.
	else if (disagreed && standstill)
		match.reset();
	// A suspect step whose plain match agrees with the prior: the prior itself may be what is
	// wrong (sparse scans on MIT-CSAIL: odometry that stalled reads -2.6 deg where the robot
	// turned -27), and a match started there settles in the basin nearest to it. The wide
	// search may overrule it, with the same evidence as above.
	else if (suspect && match && m_params.wide_search_angle > 0)
	{
		if (auto wide = second(overrulingWideMatch(cloud, scan, guess, *match)))
			match = std::move(wide), reg.wideSearch = true;
	}
	m_lastAccepted.reset();
	if (!match) return reg;
	reg.odometryRejected = matchOverrules(*match, reg.wideSearch, guess, prediction, disagrees);
	return placedByMatch(reg, scan, *match, newestInMap, prediction);
}

// The match disagrees with the prior: their squared Mahalanobis distance (3 dof) over the
// gate. A plain match's covariance C is deferred (the helper computes it for the links and the
// scan's record, DeferredCovariance.h), and most scans do not need it here: for C positive
// semidefinite (P + C)^-1 <= P^-1, so d^T (P + C)^-1 d <= d^T P^-1 d, and the prior's
// covariance P alone proves agreement (agreesWhateverTheOtherCovariance, se2.h; 98 % of the
// scans on ACES and simul, 92 % on MIT-CSAIL, 78 % on range_030_bearing_015); the others
// compute C at once.
bool CLocalRegistration::disagreesWith(const TPose2D& guess, const Eigen::Matrix3d& priorCov,
									   const TScanMatch& m) const
{
	if (m.deferredCov && agreesWhateverTheOtherCovariance(guess, m.scanInRef, priorCov,
														  m_params.glitch_gate_chi2))
		return false;
	return disagreementChi2(guess, m.scanInRef, priorCov + m.covariance().get()) >
		   m_params.glitch_gate_chi2;
}

TRegistration CLocalRegistration::placedByMatch(TRegistration reg, const TScan2D& scan,
												const TScanMatch& match,
												const TPose2D& newestInMap,
												const TMotionPrediction& prediction)
{
	reg.matched = true;
	// Only with an odometry prior: laser alone, the patch link let a robot standing at the
	// start of Intel slide 0.6 m per 20 scans (laser-only relation error 0.44 -> 1.48 m).
	const CLazyCovariance cov = match.covariance();
	if (prediction.fromOdometry)
		m_lastPatchMatch = TPatchMatch{*m_cloudNewest, match.scanInRef, cov, nullptr};
	// The range image only for the still robot's reuse, its one reader (rangeImageOf bins the
	// points again where the scan holds no image of its own).
	if (!reg.odometryRejected && !reg.wideSearch)
		m_lastAccepted =
			TPatchMatch{*m_cloudNewest, match.scanInRef, cov,
						m_params.reuse_match_when_still ? rangeImageOf(scan) : nullptr};
	reg.scanInMap = compose(newestInMap, match.scanInRef);
	// Newest keyframe's axes -> map's.
	reg.cov = cov.then([phi = newestInMap.phi](const Eigen::Matrix3d& c)
					   { return rotateCovariance(c, phi); });
	// Not needed yet: the helper computes it meanwhile (unless a thread has begun).
	if (cov.deferred() && !cov.deferred()->claimed())
		m_helper.post([d = cov.deferred()] { d->compute(); });
	return reg;
}

std::optional<TRegistration> CLocalRegistration::stillRegistration(
	const CPoseGraph& graph, const TScan2D& scan, const TMotionPrediction& prediction)
{
	// Only wheels that really report no motion (odometry, no jump), and only while the patch
	// the last match was made against is the one in use (m_cloudNewest is reset whenever the
	// window or its poses change).
	if (!m_params.reuse_match_when_still || !m_lastAccepted || !prediction.fromOdometry ||
		prediction.odometryJump || !isZeroStep(prediction.motion) ||
		m_cloudNewest != m_lastAccepted->node)
		return std::nullopt;
	// Odometry that lags while the robot moves reads zero too (ACES: 19 of its 2608 zero
	// steps, the median range change 2-5 cm against 0-1 cm for the others): the scan must
	// show the place as the matched scan did, bin by bin (medianChange), over most bins.
	const auto [change, shared] = m_lastAccepted->view->medianChange(*rangeImageOf(scan));
	if (change > m_params.still_max_range_change_m || shared < 0.5) return std::nullopt;
	// (node <- scan) = (node <- last scan) (+) (last scan <- scan); the covariance is the
	// last match's, rotated from the node's axes to the map's.
	m_lastAccepted->scanInNode = compose(m_lastAccepted->scanInNode, prediction.motion);
	m_lastPatchMatch = m_lastAccepted;
	const TPose2D nodeInMap = graph.pose(m_lastAccepted->node);
	TRegistration reg;
	reg.scanInMap = compose(nodeInMap, m_lastAccepted->scanInNode);
	reg.cov = m_lastAccepted->cov.then([phi = nodeInMap.phi](const Eigen::Matrix3d& c)
									   { return rotateCovariance(c, phi); });
	reg.matched = true;
	return reg;
}

// The odometry read since the last scan that followed it says otherwise than the prediction
// (an odometry glitch of one reading, a turn the jump test took for a jump: MotionPredictor.h),
// and a match from there agrees with that odometry: it places the scan, as a plain match on
// its prior would.
TRegistration CLocalRegistration::placedByAlternative(TRegistration reg, const TScan2D& scan,
													  const TScanMatch& match,
													  const TPose2D& newestInMap,
													  const TMotionPrediction& prediction)
{
	reg.alternativePrior = true;
	return placedByMatch(reg, scan, match, newestInMap, followingAlternative(prediction));
}

std::optional<TScanMatch> CLocalRegistration::alternativeMatch(
	const CReferenceCloud& cloud, const TScan2D& scan, const TPose2D& newestInMap,
	const TPose2D& priorInMap, const TMotionPrediction& prediction)
{
	// (map <- last scan) = prior (+) motion^-1; the alternative from there, in the patch's
	// frame.
	const TPose2D lastInMap = compose(priorInMap, inverse(prediction.motion));
	const TPose2D guess =
		between(newestInMap, compose(lastInMap, prediction.alternative->motion));
	// Only an alternative that turns the robot otherwise by more than glitch_min_turn, as a
	// glitch or a refused turn does, beyond what a plain match or its retry bridges: one that
	// differs by a slip along a corridor, which a match from either prior confirms, placed
	// ACES's scans by the odometry they had rejected (local registration alone 0.121 -> 0.179
	// m with every distinct alternative; with those over 10 deg the ACES pieces test's second
	// session 0.03752 m, above Cartographer's 0.0375).
	if (std::abs(mrpt::math::wrapToPi(guess.phi - between(newestInMap, priorInMap).phi)) <=
		m_params.glitch_min_turn)
		return std::nullopt;
	auto m = m_matcher.match(cloud, scan, guess);
	if (!m || disagreementChi2(guess, m->scanInRef, prediction.alternative->cov + m->cov) >
				  m_params.glitch_gate_chi2)
		return std::nullopt;
	return m;
}

}  // namespace lrgc
