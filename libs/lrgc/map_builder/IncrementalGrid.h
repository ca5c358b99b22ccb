/* CIncrementalGrid: the occupancy grid of the keyframes (MRPT's COccupancyGridMap2D, each
 * keyframe's laser inserted at its pose in keyframe order), kept up to date without building
 * it from scratch after every scan.
 *
 * The grid is a fold: a log-odds cell is updated by each ray through it, clamped to MRPT's
 * cell range, in insertion order. Clamping makes a scan's contribution impossible to remove
 * exactly, so nothing is ever removed; instead the grid keeps two states:
 *  - the *base*: keyframes 0..b-1 inserted, b = n - settleKeyframes (the keyframes the local
 *    window no longer moves: only a loop closure moves them);
 *  - the *result*: the base plus keyframes b..n-1, what grid() returns.
 * update() compares each keyframe with the pose (exactly, bit for bit) and laser it was
 * inserted with, and takes the cheapest exact way:
 *  - none moved: only the new keyframes are inserted into the result (Appended; when more
 *    than settleKeyframes are new, as on the first call, the base is built first and copied);
 *  - only keyframes of the tail (b..n-1) moved, as the local window does at each keyframe:
 *    the result is the base copied plus the tail inserted (TailReinserted);
 *  - an older keyframe moved (a loop closure): everything is inserted again (Rebuilt).
 * So the result is always, cell for cell, the grid built from scratch from the current poses
 * (tested against it). Exact comparison rather than a tolerance: a tolerance would keep scans
 * at poses that are no longer the estimate, and the grid would then differ from a fresh build.
 *
 * A map continued over several sessions (TKeyframe::session) shows each cell as the newest
 * session that saw it: the keyframes of each session are folded into a grid of their own (as
 * above), and a cell known to a newer session's grid (log-odds not 0: a ray ended in it or
 * crossed it) takes that grid's value, whatever older sessions said:
 *     l(cell) = l_s(cell),  s = the newest session with l_s(cell) != 0  (else unknown).
 * So furniture moved or a door closed since an older session shows where it now stands, as
 * in a fresh map of the newer session, and cells the newer session did not see keep the older
 * map. With more than one session, every update() that changes something builds all the
 * sessions' grids again (Rebuilt); a plain run is one session, and its grid the fold above.
 *
 * A keyframe's laser must not change once given: a keyframe that shows a newer scan gets a
 * new laser object (CMetricMapBuilderLRGC::showNewerScan). A laser is recognised by its
 * address. Not thread-safe: one owner (the builder under its map lock, or
 * the live saver thread with its own instance).
 */
#pragma once

#include <lrgc/map_builder/GridKeyframes.h>
#include <mrpt/maps/COccupancyGridMap2D.h>

#include <vector>

namespace lrgc
{
class CIncrementalGrid
{
public:
	enum class Update
	{
		Unchanged,       //!< same keyframes at the same poses
		Appended,        //!< new keyframes inserted into the result
		TailReinserted,  //!< base copied, newest keyframes inserted again
		Rebuilt          //!< an old keyframe moved: everything inserted again
	};

	explicit CIncrementalGrid(const TGridSettings& settings);

	/** Brings grid() to `keyframes` (entry i = keyframe i, current poses); says how. */
	Update update(const TGridKeyframes& keyframes);
	/** The grid of the keyframes of the last update(). The object stays the same across
	 * updates (its contents change), so a CMultiMetricMap may hold it. */
	const mrpt::maps::COccupancyGridMap2D::Ptr& grid() const { return m_result; }
	const TGridSettings& settings() const { return m_settings; }

	/** Counts of each kind of update() since construction. */
	size_t count(Update kind) const { return m_counts[static_cast<size_t>(kind)]; }

	/** The grid built from scratch, every keyframe in order (each session's keyframes in a
	 * grid of their own, newer sessions over older ones): what update() must equal. */
	static mrpt::maps::COccupancyGridMap2D::Ptr buildFromScratch(
		const TGridKeyframes& keyframes, const TGridSettings& settings);

private:
	static void reset(mrpt::maps::COccupancyGridMap2D& grid, const TGridSettings& settings);
	static void insert(mrpt::maps::COccupancyGridMap2D& grid, const TGridKeyframe& k);
	/** The fold of the keyframes of one session, in keyframe order. */
	static void insertSession(mrpt::maps::COccupancyGridMap2D& grid,
							  const TGridKeyframes& keyframes, size_t session);
	/** Every cell that `newer` knows takes its value in `older` (grown to cover it). */
	static void overlay(mrpt::maps::COccupancyGridMap2D& older,
						const mrpt::maps::COccupancyGridMap2D& newer);
	/** Inserts keyframes [m_baseCount, end) into the base. */
	void advanceBase(const TGridKeyframes& keyframes, size_t end);

	TGridSettings m_settings;
	mrpt::maps::COccupancyGridMap2D::Ptr m_base, m_result;
	size_t m_baseCount = 0;     //!< keyframes in the base: 0..m_baseCount-1
	TGridKeyframes m_inserted;  //!< what the result holds, as inserted
	bool m_layered = false;     //!< the result holds several sessions (no base)
	size_t m_counts[4] = {0, 0, 0, 0};
};

}  // namespace lrgc
