/* CStartFinder: finds where a new log starts in a saved map, with no prior.
 *
 * The new log's first scans are mapped on their own by a probe map builder (local
 * registration only, in the frame of its first scan). Global localisation (CGlobalLocalizer)
 * is tried with a patch of the probe's keyframes (in its newest keyframe's frame, points
 * within patch_max_range_m) when the probe holds 1, 2, 4, ... keyframes, up to
 * patch_keyframes, then every quarter of patch_keyframes with the newest patch_keyframes:
 * one scan is enough in a distinctive place, a corridor needs the robot to drive on until its
 * patch is unambiguous. With `backoff` the attempts with the full patch are spaced by
 * patch_keyframes new keyframes, then twice, four times as many ... (a search that keeps
 * failing costs less and less per metre driven). The first patch passing the filters gives (map
 * <- probe frame), and so the map pose of every scan the probe saw. */
#pragma once

#include <lrgc/localization/LocalizationParams.h>
#include <lrgc/localization/GlobalLocalizer.h>
#include <lrgc/map_builder/CMetricMapBuilderLRGC.h>

#include <memory>
#include <optional>
#include <string>

namespace lrgc
{
struct TStartFound
{
	mrpt::math::TPose2D probeInMap;  //!< (map <- probe frame)
	/** Covariance of the located patch pose [m^2, rad^2], map axes. */
	Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
	double score = 0, ambiguity = 0;  //!< of the accepted correlation
	size_t patchKeyframes = 0;        //!< keyframes in the accepted patch
};

/** The patch of one attempt: the newest probe keyframes' points in the newest one's frame. */
struct TPatchRequest
{
	std::vector<Eigen::Vector2d> points;         //!< [m], (probe keyframe `newest`) frame
	mrpt::math::TPose2D newestInProbe{0, 0, 0};  //!< (probe frame <- newest keyframe)
	size_t keyframes = 0;                        //!< in the patch
};

/** The patch of keyframes first..newest of `graph` (`keyframes[i]`: node i's scan): their
 * points within maxRange [m] of keyframe `newest`, in its frame. */
TPatchRequest patchOfKeyframes(const CPoseGraph& graph, const TKeyframes& keyframes,
							   size_t first, size_t newest, double maxRange);

/** When an attempt is due as a new log's keyframes come (see the file comment): at 1, 2, 4,
 * ... keyframes up to patch_keyframes P, then every `spacing` new keyframes (P / 4; with
 * `backoff`, P, then twice, four times as many ...). */
class CPatchSchedule
{
public:
	CPatchSchedule(size_t patchKeyframes, bool backoff);
	/** An attempt is due with `n` keyframes (the schedule then moves on). */
	bool due(size_t n);

private:
	size_t m_patch;
	size_t m_nextAttemptAt = 1;  //!< keyframes at the next attempt
	bool m_backoff = false;
	size_t m_spacing = 1;  //!< [keyframes] between attempts with the full patch
};

class CStartFinder
{
public:
	/** `params`: the pipeline's parameters (the probe uses them with loop closing off). */
	CStartFinder(const CGlobalLocalizer& localizer, const TLRGCParams& params,
				 const TLocalizationParams& localization, bool backoff = false);

	/** The probe: feed it the new log's entries (processObservation or
	 * processActionObservation), then call tryLocate(). */
	CMetricMapBuilderLRGC& probe() { return *m_probe; }
	const CMetricMapBuilderLRGC& probe() const { return *m_probe; }

	/** The probe's wide search honours `stop` (the localiser's correlation has its own:
	 * CGlobalLocalizer::setStopToken). */
	void setStopToken(const CStopToken& stop) { m_probe->setStopToken(stop); }

	/** Tries global localisation on the whole map if an attempt is due (see the file
	 * comment): nextPatch() and conclude() in one, waiting for the correlation. */
	std::optional<TStartFound> tryLocate();
	/** The patch of the attempt due now, or nullopt if none is (the schedule moves on). */
	std::optional<TPatchRequest> nextPatch();
	/** The outcome of the attempt on `request` (counted): the start if it passed. */
	std::optional<TStartFound> conclude(const TPatchRequest& request,
										const TGlobalLocation& location);

	size_t attempts() const { return m_attempts; }
	double secondsSpent() const { return m_seconds; }  //!< in correlation [s]
	/** Why the last attempt failed ("score 0.41 < min_score 0.60"), empty before one. */
	const std::string& lastRejection() const { return m_lastRejection; }

private:
	const CGlobalLocalizer& m_localizer;
	TLocalizationParams m_params;
	std::unique_ptr<CMetricMapBuilderLRGC> m_probe;
	CPatchSchedule m_schedule;
	size_t m_attempts = 0;
	double m_seconds = 0;
	std::string m_lastRejection;
};

}  // namespace lrgc
