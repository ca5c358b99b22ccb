/* CGlobalLocalizer: where in a saved map is a patch of new scans, with no prior at all?
 * The paper's global correlation (Gutmann & Konolige, section 2.3) over the whole map: the
 * old map is every keyframe's scan placed at its pose, blurred into one CCorrelationGrid; the
 * patch is correlated by exact branch and bound (CPatchCorrelator) over every heading and
 * every position within the keyframe poses' bounding box grown by kWindowMargin. The three
 * filters of [PatchCorrelator] (score, ambiguity, variance) decide: in a map with look-alike
 * places a small patch is ambiguous and rejected, and a larger one (CStartFinder) is tried.
 *
 * Cost: the pose grid has (2W+1)^2 translations times 2 pi r / resolution headings for a
 * patch of radius r; branch and bound bounds blocks of up to 128 x 128 translations and
 * several headings at once, so a whole building (Intel, 40 x 40 m, r = 10 m) takes one to a
 * few seconds per attempt (doc/localization.md).
 */
#pragma once

#include <lrgc/loop_closing/PatchCorrelator.h>
#include <lrgc/loop_closing/CorrelationGrid.h>
#include <lrgc/scan_matching/Keyframe.h>
#include <lrgc/pose_graph/PoseGraph.h>

#include <cmath>
#include <functional>
#include <optional>
#include <vector>

namespace lrgc
{
/** Outcome of one global localisation attempt. */
struct TGlobalLocation
{
	/** The best pose (map <- patch) and its figures; nullopt if no pose reaches min_score. */
	std::optional<TCorrelationResult> correlation;
	TCorrelationVerdict verdict;  //!< of the three filters
	double seconds = 0;           //!< time of the attempt [s]
	/** Its modelled time on the reference machine [ms] (TLoopWork's correlation model: a
	 * count of headings x patch cells and poses scored x patch cells, not a clock). */
	double modelledMs = 0;
	bool stopped = false;  //!< ended early by a stop request (setStopToken): nothing found
	bool accepted() const { return correlation && verdict.accepted(); }
};

/** Where to look: headings within +-halfTheta of centre.phi, positions within +-halfXY. */
struct TSearchArea
{
	mrpt::math::TPose2D centre{0, 0, 0};  //!< (map <- patch) at the window's centre
	double halfXY = 0;                    //!< [m]
	double halfTheta = M_PI;              //!< [rad]; pi: every heading
};

class CGlobalLocalizer
{
public:
	/** [m] The search window reaches this far beyond the keyframe poses' bounding box: a
	 * new robot may stand where the old one only looked. */
	static constexpr double kWindowMargin = 3.0;

	/** The map: node i of `map` at its pose with keyframes[i]'s scan. Throws if empty. */
	CGlobalLocalizer(const CPoseGraph& map, const TKeyframes& keyframes,
					 const TPatchCorrelatorParams& p);

	/** Called as a search goes on with its modelled work so far [ms] (a lower bound of the
	 * final TGlobalLocation::modelledMs). */
	using TWorkProgress = std::function<void(double modelledMs)>;

	/** The whole map: the keyframe poses' bounding box + kWindowMargin, every heading. */
	const TSearchArea& wholeMap() const { return m_whole; }
	/** `area` reduced to the whole map's (a window reaching past it searches nothing more). */
	TSearchArea clipped(const TSearchArea& area) const;
	/** locate() ends early, finding nothing, once `stop` is stopped. */
	void setStopToken(const CStopToken& stop) { m_correlator.setStopToken(stop); }

	/** Correlates `patchPoints` (patch frame [m]) against the whole map. */
	TGlobalLocation locate(const std::vector<Eigen::Vector2d>& patchPoints) const
	{
		return locate(patchPoints, m_whole);
	}
	/** ... against the map within `area`. */
	TGlobalLocation locate(const std::vector<Eigen::Vector2d>& patchPoints,
						   const TSearchArea& area, const TWorkProgress& progress = {}) const;

	const CPatchCorrelator& correlator() const { return m_correlator; }

private:
	CPatchCorrelator m_correlator;
	CCorrelationGrid m_grid;
	TSearchArea m_whole;  //!< the whole map's window (centre heading 0)
};

}  // namespace lrgc
