/* CLocalRegistration: LRGC's local registration (Gutmann & Konolige, section 2.2, use 1).
 *
 * Each new scan is matched against a local patch made of the last K keyframes' scans (in the
 * frame of the newest keyframe), which gives its pose. The window is the last K distinct
 * keyframes the robot was at (enterKeyframe): the newest ones, or on ground the map already
 * has, existing keyframes it came back to (CKeyframeReuse); those are held fixed. When the scan
 * becomes a keyframe it is linked to the previous keyframe by odometry and by that patch match
 * (the "patch link", scan to map; with an odometry prior only), and to window keyframes it
 * overlaps by pairwise scan matches (down-weighted when the patch link is there), and
 * consistent pose estimation (Lu & Milios 1997) over the window only adjusts the last K poses,
 * all older poses held fixed: constant cost per scan.
 *
 * Odometry glitches (the benchmark logs have single steps turning 60-85 deg wrongly, after
 * pauses of seconds in the scans): a step is suspect when its predicted turn exceeds
 * glitch_min_turn or the scans paused for more than glitch_min_gap_s. If then the plain match
 * fails or contradicts the prior beyond the chi-square gate, a wide rotational search around
 * the prior (CScanMatcher::matchWide: tens of ms, so only then) decides and may overrule the
 * odometry, but only with evidence a symmetric or repetitive scene cannot fake (a clear
 * majority of the scan matched, a clear lead over every other heading and over the prior's
 * own optimum); a doubtful case keeps the prior rather than risk a wrong pose (issue 11: a
 * true 31-deg turn in an alcoved hall overruled, a 29 %-inlier 108-deg "recovery" on Intel).
 * After an override the keyframe's odometry link is down-weighted to the constant-velocity
 * noise so it cannot pull the map. Otherwise the scans win over the odometry, except when the
 * wheels did not move at all: a match moving a robot that stands still is a wrong fit (people
 * walking by, a rotationally ambiguous place), and the prior is kept. A plain match that fails
 * on a step nothing made suspect (the wheels moved) is retried by the same search over the
 * heading the odometry's error may span (retriedMatch), with the same evidence and a winner
 * that turns more than half a start step from the prior; else the prior stands. A plain
 * match that contradicts the prior where it could not place the scan on its own (a suspect
 * step, or one the second opinion is asked on) is first matched again from the prior's
 * position at its own heading (headingFirstMatch): started a few degrees off, a match among
 * railings and far returns finds the heading but slides along the hall (the glass atrium's
 * turns in place). A plain match that is a loose fit (its residual scale kept the gate wide:
 * the robot turning into ground the window has not seen) is refitted with the inlier gate
 * first (CScanMatcher::refitLoose).
 * A keyframe whose patch match failed from its (odometry) prior, where a strict majority of
 * its pairwise matches agree on its pose, is matched against the patch again from there; if
 * that passes every check it is placed there with its patch link (linkAndOptimize;
 * LocalRegistration_links.cpp).
 * An unmatched scan never bends the map (issue 28 item 3): a keyframe no scan match placed
 * (its prior kept) is no evidence. The wide search's winner, where such a keyframe is in the
 * window, must hold against the patch of the others too (a plain match from it there lands in
 * its basin): in the room world a glitched scan kept its prior 80 deg off, became a keyframe,
 * and the next scan's wide search won on that keyframe's own points, taking every later scan
 * 75 deg off with it. And two such keyframes' pairwise match may not overrule the odometry
 * between them; the older leaves the window (a one-reading glitch puts it off, and left in the
 * patch its scan refuses every later match). Where a scan was placed off its odometry, the
 * next scans may follow the odometry since the last that was not (MotionPredictor.h).
 *
 * Cost per keyframe: one patch build, at most `max_pairwise_links` pairwise matches against
 * reference clouds cached per window keyframe, and a window solve; none depends on the map
 * size. A helper thread (CHelperThread) keeps two of them off a keyframe's latency: once the
 * window is solved it builds the patch the next scan will be matched against (then the new
 * keyframe's own cloud, for the next keyframe's pairwise links), while the mapping thread
 * returns the scan's pose, and the next scan, waiting for the patch, runs blocks of its line
 * fits meanwhile; and it shares the pairwise matches with the mapping thread. The next scan
 * takes that patch only if the window still has the nodes and poses it was built from (else
 * it is built again, as without the helper), and pairwise links are added in their fixed
 * order: the map does not depend on the helper's timing.
 */
#pragma once

#include <lrgc/pose_graph/PoseGraphOptimizer.h>
#include <lrgc/common/HelperThread.h>
#include <lrgc/common/SharedLoop.h>
#include <lrgc/local_registration/LocalRegistrationParams.h>
#include <lrgc/scan_matching/Keyframe.h>
#include <lrgc/scan_matching/RangeDenoiser.h>
#include <lrgc/pose_graph/LinkNoise.h>
#include <lrgc/local_registration/MotionPredictor.h>
#include <lrgc/pose_graph/PoseGraph.h>
#include <lrgc/scan_matching/ReferenceCloud.h>
#include <lrgc/scan_matching/ScanMatcher.h>
#include <mrpt/config/CLoadableOptions.h>

#include <atomic>
#include <condition_variable>
#include <deque>
#include <exception>
#include <functional>
#include <mutex>
#include <memory>
#include <optional>
#include <utility>
#include <vector>

namespace lrgc
{
/** Pose of one scan from the local registration. */
struct TRegistration
{
	mrpt::math::TPose2D scanInMap;  //!< (map <- robot at the scan)
	/** Of the scan pose relative to the newest keyframe, map axes. A plain match's is
	 * deferred (CScanMatcher::matchDeferred): the window's helper thread computes it while the
	 * mapping thread goes on, and get() waits for it (or computes it) where it is read. */
	CLazyCovariance cov;
	bool matched = false;  //!< false: no acceptable match, the prior was kept
	/** The match disagrees with the prior beyond the gate and overrules it: not where it only
	 * puts the robot behind a clear forward step of the wheels (matchOverrules,
	 * LocalRegistration.cpp: aliased corridor doors), unless a wide search won. */
	bool odometryRejected = false;
	bool wideSearch = false;  //!< the match came from the wide rotational search
	/** Matched from the prediction's alternative (TMotionPrediction::alternative), within its
	 * gate: the scan followed that odometry (followingAlternative) rather than the prediction.
	 */
	bool alternativePrior = false;
};

/** A keyframe's patch link that no pairwise match confirmed, where the scan's returns are
 * sparse, gets its position covariance widened by (d / r)^2 where d > r (x and y scaled by
 * d / r: their correlation kept, the heading's variance as it was), d [m] the median distance
 * between consecutive points of the scan, r [m] the line fits' radius (normal_radius_m).
 * Where the returns are that sparse (a hall's far walls, one degree between beams: 0.4-1.3 m
 * at 25-75 m) the scan shares no wall stretch with any single window scan; its patch match
 * rests on the window's scans as placed and lands among optima about one beam apart, so its
 * covariance (exact for the patch as built) is over-confident: CrowdedHall's links after the
 * corner at (64, 39) err 2-10 cm sideways, same side, claiming 1-2 cm. The heading is kept:
 * that link is what holds a hall's heading against biased odometry (OpenHall, heading
 * widened too: mean drift 0.66 -> 0.85 deg / 100 m and a wrong wide-search override). The
 * shared logs' unconfirmed links have d 0.05-0.15 m: none widened (their sparse variants:
 * 0-2 per log).
 * A scan that does not become a keyframe is registered by the patch match alone: the same
 * widening gives its covariance for the end of the run (ScanSmoothing.h), where it weighs
 * the registered position against the odometry (CrowdedHall, trajectory seed 44: after the
 * corner at (64, 38) the keyframes' matches fail and the odometry places them, while the
 * scans between them match 5-10 cm sideways, all to one side, claiming 1.5-2.5 cm; scan
 * 1137 stayed 0.070 m off, 0.038 m above its neighbours). */
Eigen::Matrix3d lonePatchLinkCov(const Eigen::Matrix3d& cov, const TScan2D& scan, double r);
/** lonePatchLinkCov in two steps, for a covariance known later: d / r of `scan` (1 where it
 * does not widen), then `cov` widened by it; lonePatchLinkCov(cov, scan, r) is
 * widenedPosition(cov, sparseReturnsRatio(scan, r)), bit for bit. */
double sparseReturnsRatio(const TScan2D& scan, double r);
Eigen::Matrix3d widenedPosition(const Eigen::Matrix3d& cov, double ratio);

/** A wide search's winner `won` (wideMatch, retriedMatch, overrulingWideMatch), unless it
 * disagrees with the prior (`guess`, the scan's prior in the newest keyframe's frame) only by
 * putting the robot behind the last scan against the wheels' clear forward step (more than
 * 2 sigma of the odometry along it; behind by more than 2 of the match's sigma and by more
 * than half the wheels' step length; the match slid to the odometry's step agreeing with the
 * prior by `disagrees`): then none, and the prior stands. The wide search is for a heading the
 * plain match could not reach; a winner that disputes only the direction of travel is an alias
 * along a hall (glass_stress's atrium, seed 2, scan 2331: the retry's winner 0.85 m behind the
 * last scan against the wheels' 0.42 m forward, LocalRegistration.cpp). */
std::optional<TScanMatch> forwardWinner(
	std::optional<TScanMatch> won, const mrpt::math::TPose2D& guess,
	const TMotionPrediction& prediction,
	const std::function<bool(const TScanMatch&)>& disagrees);

class CLocalRegistration
{
public:
	/** `helperThread` false: the helper's work runs on the caller's thread (same results). */
	CLocalRegistration(const TLocalRegistrationParams& p, const TScanMatcherParams& matcher,
					   const TPoseGraphOptimizerParams& optimizer, bool helperThread = true);
	~CLocalRegistration();

	/** Matches `scan` against the window of the newest keyframes of `graph`.
	 * priorInMap: `prediction` composed onto the previous scan's pose. */
	TRegistration registerScan(const CPoseGraph& graph, const TKeyframes& keyframes,
							   const TScan2D& scan, const mrpt::math::TPose2D& priorInMap,
							   const TMotionPrediction& prediction);

	/** The robot is now at keyframe `node`: the window's newest entry, the frame of its patch.
	 * A new keyframe (just added to the graph), or with `reused` an existing one it came back
	 * to: the window solve then holds every node older than the graph's newest fixed (they
	 * belong to the map, and the grid's settled part stays settled). */
	void enterKeyframe(size_t node, bool reused, const CPoseGraph& graph,
					   bool placedByMatch = true);

	/** The keyframe the window is anchored at (its newest entry); none before the first. */
	std::optional<size_t> anchor() const
	{
		return m_window.empty() ? std::nullopt : std::optional<size_t>(m_window.back());
	}

	/** Links the newest node (just added to `graph` at its registered pose and entered) to
	 * the window: `odometryLink` (from the previous anchor) plus the patch link and pairwise
	 * scan matches, then optimises the window. Returns the number of scan-match links added. */
	size_t linkAndOptimize(CPoseGraph& graph, const TKeyframes& keyframes,
						   const TLink& odometryLink);

	/** Every match of this stage, the wide rotational search (CScanMatcher::matchWide) among
	 * them, honours `stop`. */
	void setStopToken(const CStopToken& stop)
	{
		m_matcher.setStopToken(stop);
		m_crowdMatcher.setStopToken(stop);
	}

	/** Poses changed outside the window (loop closure): rebuild the patch on next use. */
	void invalidate() { m_cloudNewest.reset(); }

	/** A new session (a log continuing a saved map elsewhere in it) starts at node `first`:
	 * the window holds only nodes >= first, so the session's scans are registered against
	 * its own keyframes, not against the old map's last ones. With `holdFirst` node `first`
	 * is held fixed as node 0 is (the first of a piece mapped in its own frame). */
	void setWindowStart(size_t first, bool holdFirst = false)
	{
		m_window.clear();
		m_unplaced.clear();
		m_firstFree = holdFirst ? first + 1 : first;
		m_cloudNewest.reset();
		m_keyframeClouds.clear();
		m_preparedNewest.reset();
	}

	/** The window's keyframes, oldest first. */
	const std::deque<size_t>& window() const { return m_window; }

	/** Patch links widened so far: no pairwise match confirmed them and the scan's returns
	 * were sparser than the line fits' radius (linkAndOptimize, lonePatchLinkScale). */
	size_t patchLinksWidened() const { return m_patchLinksWidened; }

	/** Keyframes whose patch match failed and was found again from their pairwise matches'
	 * basin (linkAndOptimize, reseedPatchMatch). */
	size_t keyframesReseeded() const { return m_keyframesReseeded; }

private:
	/** K: window_size after a scan with an odometry prior, laser_only_window_size after one
	 * with the constant-velocity prior (the last registerScan's). */
	size_t windowSize() const
	{
		return m_withOdometry ? m_params.window_size : m_params.laser_only_window_size;
	}
	/** K for this scan's prior; the window shrinks to it if needed. */
	void resizeWindowFor(const TMotionPrediction& prediction);
	bool m_withOdometry = true;  //!< the last registered scan's prior came from odometry
	using TCloudPtr = std::shared_ptr<const CReferenceCloud>;
	/** One piece of a prepared window, built once by whichever thread claims it first. */
	template <class T>
	struct TPreparedPart
	{
		std::atomic<bool> claimed{false};  //!< a thread builds `value`
		T value;
		std::exception_ptr error;
		bool built = false;  //!< guarded by the window's mutex
	};
	/** The patch for the next scans, built from the window as it was after a keyframe's
	 * solve (nodes, scans and poses copied), and that keyframe's own cloud; each by the
	 * helper thread or, if it has not started on it when needed, by the mapping thread. The
	 * next scan waits for the patch only, taking part in its line fits while they run
	 * (waitForPatch); the own cloud waits for the next keyframe's pairwise links
	 * (takeNewestCloud). */
	struct TPreparedWindow
	{
		std::vector<size_t> nodes;
		std::vector<TScan2D> scans;
		std::vector<mrpt::math::TPose2D> posesInMap;  //!< of `nodes`, (map <- node)
		TScanMatcherParams patchParams;               //!< patchParams() when prepared
		TPreparedPart<CReferenceCloud> patch;
		TPreparedPart<TCloudPtr> newestCloud;
		std::mutex mutex;  //!< guards the parts' `built` and `fits`
		std::condition_variable cv;
		/** The patch's line fits while the helper runs them, for a waiting thread to join. */
		std::shared_ptr<CSharedLoop> fits;
	};

	/** The window's keyframes, oldest first (a copy). */
	std::vector<size_t> windowNodes() const { return {m_window.begin(), m_window.end()}; }
	const CReferenceCloud& windowCloud(const CPoseGraph& graph, const TKeyframes& keyframes);
	/** The patch of `scans` placed at `posesInMap`, in the frame of the last one (line
	 * fits run by `parallel`, if given). */
	static CReferenceCloud patchOf(const std::vector<TScan2D>& scans,
								   const std::vector<mrpt::math::TPose2D>& posesInMap,
								   const TScanMatcherParams& p,
								   const TParallelFor& parallel = {});
	void prepareNextWindow(const CPoseGraph& graph, const TKeyframes& keyframes);
	/** Builds the part (part.value = make()) unless another thread claimed it. */
	template <class T, class Fn>
	static void buildUnlessClaimed(TPreparedWindow& job, TPreparedPart<T>& part, Fn&& make);
	/** Waits until the part is built; rethrows what its build threw. */
	template <class T>
	static void waitFor(TPreparedWindow& job, TPreparedPart<T>& part);
	/** The patch, unless claimed; its line fits shared through job.fits (the helper's
	 * build) or by parallel (the mapping thread's). */
	static void buildPatch(TPreparedWindow& job, const TScanMatcherParams& p,
						   const TParallelFor& parallel);
	/** Waits for the patch, running iterations of its line fits meanwhile. */
	static void waitForPatch(TPreparedWindow& job);
	static TParallelFor sharedFits(TPreparedWindow& job);
	static void buildNewestCloud(TPreparedWindow& job, const TScanMatcherParams& p);
	/** Waits for the prepared patch; true (and m_cloud set) if the window is unchanged. */
	bool takePreparedWindow(const CPoseGraph& graph);
	/** The prepared window's own keyframe cloud (built or waited for) into the cache. */
	void takeNewestCloud();
	/** The matches of keyframes[newNode].scan against refs[l] from guesses[l], computed by
	 * this thread and the helper together; nullopt where a match failed. */
	std::vector<std::optional<TScanMatch>> matchAll(
		const std::vector<TCloudPtr>& refs, const TScan2D& scan,
		const std::vector<mrpt::math::TPose2D>& guesses);
	/** fn(i) for every i in [0, n), by this thread and the helper together (TParallelFor). */
	void parallelFor(size_t n, const std::function<void(size_t)>& fn);
	/** The plain match from the prediction's alternative (priorInMap: the prediction's), if
	 * that turns the robot otherwise than the prediction by more than glitch_min_turn and the
	 * match agrees with it within glitch_gate_chi2. */
	std::optional<TScanMatch> alternativeMatch(const CReferenceCloud& cloud,
											   const TScan2D& scan,
											   const mrpt::math::TPose2D& newestInMap,
											   const mrpt::math::TPose2D& priorInMap,
											   const TMotionPrediction& prediction);
	/** placedByMatch from the alternative's match, the scan following it (reg.alternativePrior,
	 * followingAlternative). */
	TRegistration placedByAlternative(TRegistration reg, const TScan2D& scan,
									  const TScanMatch& match,
									  const mrpt::math::TPose2D& newestInMap,
									  const TMotionPrediction& prediction);
	/** The wide search's second opinion on a suspect step's plain match that agrees with the
	 * prior: its winner if it overrules the match (a distinct pose), else nullopt. It searches
	 * within half a right angle of the prior only (kOverruleAngle, LocalRegistration_wide.cpp):
	 * a building's aliases of the match lie a right angle away. */
	std::optional<TScanMatch> overrulingWideMatch(const CReferenceCloud& cloud,
												  const TScan2D& scan,
												  const mrpt::math::TPose2D& guess,
												  const TScanMatch& plain);
	/** A plain match that disagrees with the prior (`disagrees`), matched again from the
	 * prior's position (`guess`) at the match's heading; that match if it agrees with the
	 * prior and `plain` explains less than wide_ambiguity_margin more of the scan, else
	 * nullopt (LocalRegistration_wide.cpp). */
	std::optional<TScanMatch> headingFirstMatch(
		const CReferenceCloud& cloud, const TScan2D& scan, const mrpt::math::TPose2D& guess,
		const TScanMatch& plain, const std::function<bool(const TScanMatch&)>& disagrees);
	/** The scan matched from `guess` (newest keyframe <- scan), a loose fit refitted
	 * (CScanMatcher::refitLoose); nullopt if the match fails. */
	std::optional<TScanMatch> plainMatch(const CReferenceCloud& cloud, const TScan2D& scan,
										 const mrpt::math::TPose2D& guess,
										 const TCloudPtr& deferOn = {})
	{
		return plainMatch(m_matcher, cloud, scan, guess, deferOn);
	}
	/** The plain match's matcher for a prior of covariance priorCov (x, y, phi): m_crowdMatcher
	 * where its heading std exceeds crowd_min_prior_std, else m_matcher. */
	const CScanMatcher& plainMatcherFor(const Eigen::Matrix3d& priorCov) const;
	/** plainMatch() by `matcher` (m_matcher, or plainMatcherFor's: registerScan). */
	std::optional<TScanMatch> plainMatch(const CScanMatcher& matcher,
										 const CReferenceCloud& cloud, const TScan2D& scan,
										 const mrpt::math::TPose2D& guess,
										 const TCloudPtr& deferOn);
	/** A failed plain match retried (registerScan): matchWide over the heading the
	 * odometry's error may span, kRetryAngle, or kRetryTurnAngle for a step turning more than
	 * kRetryTurn, with starts kRetryStep apart (LocalRegistration_wide.cpp); where the only
	 * rivals share the winner's heading (matchWide's sharedHeading), the scan matched again
	 * from the guess's position at that heading. nullopt unless the winner turns more than
	 * kRetryStep / 2 from the guess. */
	std::optional<TScanMatch> retriedMatch(const CReferenceCloud& cloud, const TScan2D& scan,
										   const mrpt::math::TPose2D& guess,
										   const TMotionPrediction& prediction);
	/** CScanMatcher::matchWide over guess.phi +- angle [rad] with starts `step` [rad] apart
	 * (0: wide_search_step), run by this thread and the helper. */
	std::optional<TScanMatch> wideMatch(const CReferenceCloud& cloud, const TScan2D& scan,
										const mrpt::math::TPose2D& guess, double angle,
										double step, double* sharedHeading = nullptr);

	TLocalRegistrationParams m_params;
	TScanMatcherParams m_matcherParams;
	CScanMatcher m_matcher;
	/** m_matcher but for free_space_min_run_m = crowd_min_run_m: the plain match where the
	 * prior is loose (registerScan). */
	CScanMatcher m_crowdMatcher;
	CPoseGraphOptimizer m_optimizer;
	TCloudPtr keyframeCloud(size_t node, const TKeyframes& keyframes);
	void cacheKeyframeCloud(size_t node, TCloudPtr cloud);

	/** The last registration against the patch: (node <- scan) and its covariance in the
	 * node's frame, for the patch link of the keyframe it may become. */
	struct TPatchMatch
	{
		size_t node;
		mrpt::math::TPose2D scanInNode;
		CLazyCovariance cov;
		/** The matched scan's range image, what a still scan must agree with: read from
		 * m_lastAccepted only, and set only while reuse_match_when_still is on. */
		std::shared_ptr<const CRangeImage> view;
	};
	std::optional<TPatchMatch> m_lastPatchMatch;
	/** The last scan's registration if it was an accepted plain match (not refused by the
	 * gate, not from the wide search): what a scan that stands still reuses. */
	std::optional<TPatchMatch> m_lastAccepted;
	size_t m_patchLinksWidened = 0;
	/** A scan whose wheels did not turn and whose ranges agree with the last accepted
	 * match's scan, against the patch that scan was matched to: that match moved by the
	 * odometry step (reuse_match_when_still); else nullopt. */
	std::optional<TRegistration> stillRegistration(const CPoseGraph& graph, const TScan2D& scan,
												   const TMotionPrediction& prediction);
	/** `m` (newest keyframe <- scan) disagrees with the prior `guess` of covariance
	 * `priorCov` beyond glitch_gate_chi2 (the match's deferred covariance read only where the
	 * prior's alone cannot prove agreement). */
	bool disagreesWith(const mrpt::math::TPose2D& guess, const Eigen::Matrix3d& priorCov,
					   const TScanMatch& m) const;
	/** `reg` (its odometryRejected and wideSearch set) placed by `match` against the patch of
	 * the newest keyframe at newestInMap; remembers the match for the patch link and, with
	 * `scan`'s range image, for a scan that stands still. */
	TRegistration placedByMatch(TRegistration reg, const TScan2D& scan, const TScanMatch& match,
								const mrpt::math::TPose2D& newestInMap,
								const TMotionPrediction& prediction);

	/** The window patch in the frame of node *m_cloudNewest; shared, for a deferred match
	 * covariance reads it after the patch is replaced. */
	TCloudPtr m_cloud;
	/** The window patches' noise (CReferenceCloud::noiseVariance, as a std [m]): the median
	 * of the last patches' (a running median: CRangeNoiseEstimate), and the patches' voxel
	 * side follows it (patchParams). One patch's is not the laser's: a cluttered or blurred
	 * window measures up to twice the log's median (ACES: two patches of 7374 scans above
	 * 0.04 m, against a median of 0.022 m). */
	CRangeNoiseEstimate m_patchNoise;
	double m_patchNoiseStd = 0;  //!< [m] m_patchNoise's median, 0 before the first patch
	/** [ScanMatcher] as the window patch is built with: ref_resolution_m widened to the
	 * patches' noise (CReferenceCloud::cellForNoise, at most normal_radius_m / 2). The
	 * synthetic logs' patches measure 0.038-0.054 m on 2 cm cells (range_030_bearing_015's
	 * denoised scans disagree by that; simul.rawlog's walls are ray-cast on a 5 cm grid),
	 * 96 % and 52 % of their fits widening to 4 normal_radius_m there; the shared real
	 * logs' 0.004-0.029 m. */
	TScanMatcherParams patchParams() const;
	/** The window's keyframes no scan match placed (enterKeyframe). */
	std::vector<size_t> m_unplaced;
	/** `wide` (a wide search's winner against the window's patch) if every window keyframe
	 * was placed by a scan match, or if the patch of those that were holds it too (a plain
	 * match from it there lands in its basin); else nullopt. */
	std::optional<TScanMatch> withEvidence(const CPoseGraph& graph, const TKeyframes& keyframes,
										   const TScan2D& scan, std::optional<TScanMatch> wide);
	/** The pairwise match of keyframe newNode against window keyframe `node` from `guess`
	 * contradicts the odometry (odometryLink's covariance) where neither was placed by a scan
	 * match: not linked, and `node` leaves the window (leaveWindow). */
	bool overrulesOdometry(size_t newNode, size_t node, const mrpt::math::TPose2D& guess,
						   const TScanMatch& match, const TLink& odometryLink) const;
	void leaveWindow(size_t node);
	/** The new keyframe's pose in the map each pairwise match (against window keyframe
	 * nodes[l]) implies; nullopt where it failed or matched under min_link_inlier_fraction. */
	std::vector<std::optional<mrpt::math::TPose2D>> impliedPoses(
		const CPoseGraph& graph, const std::vector<size_t>& nodes,
		const std::vector<std::optional<TScanMatch>>& matches) const;
	/** The basin (one of the poses) a strict majority of `implied` agrees on, if any. */
	static std::optional<mrpt::math::TPose2D> majorityBasin(
		const std::vector<std::optional<mrpt::math::TPose2D>>& implied);
	/** The patch match of keyframe newNode, whose own failed, started in `basin` (in the map)
	 * against the window's patch without it in the frame of `from`: if it passes and stays
	 * in that basin, the keyframe is placed where it puts it, with it as its patch link. */
	bool reseedPatchMatch(CPoseGraph& graph, const TKeyframes& keyframes, size_t from,
						  size_t newNode, const mrpt::math::TPose2D& basin);
	/** The last registered scan's prior came from odometry (a failed patch match may be run
	 * again from the pairwise matches' basin). */
	bool m_patchLinkable = false;
	size_t m_keyframesReseeded = 0;
	bool isUnplaced(size_t node) const
	{
		return std::find(m_unplaced.begin(), m_unplaced.end(), node) != m_unplaced.end();
	}
	bool inWindow(size_t node) const
	{
		return std::find(m_window.begin(), m_window.end(), node) != m_window.end();
	}
	std::optional<size_t> m_cloudNewest;  //!< reset whenever the window or its poses change
	std::deque<size_t> m_window;  //!< the last K distinct keyframes entered, oldest first
	size_t m_firstFree = 0;  //!< the window solve moves only nodes >= this (and never node 0)
	/** Reference cloud of each window keyframe's own scan, for pairwise links. */
	std::deque<std::pair<size_t, TCloudPtr>> m_keyframeClouds;
	std::shared_ptr<TPreparedWindow> m_prepared;
	/** The last prepared window whose own keyframe cloud is not in the cache yet. */
	std::shared_ptr<TPreparedWindow> m_preparedNewest;
	CHelperThread m_helper;  //!< last: destroyed (its jobs run to their end) first
};

}  // namespace lrgc
