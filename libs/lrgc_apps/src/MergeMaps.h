/* lrgc-slam --merge MAP_A MAP_B (issue 29): two saved maps made one, in MAP_A's frame.
 *
 * The method is the one a second session continuing a map goes through (--initial-map,
 * CMetricMapBuilderLRGC::startPiece and CPieceJoiner): MAP_A is restored (its keyframes held
 * fixed), and MAP_B's keyframes are replayed in their saved order as a log (CKeyframeReplay):
 * each its odometry pose (B <- keyframe), then its sensory frame. The builder maps them as a
 * piece in B's frame (its first keyframe at its odometry pose, so the piece's frame is B's),
 * global correlation tries the piece's recent patch against the whole of A, and the first
 * result through the three [PatchCorrelator] filters joins the piece: B moves into A's frame
 * by (A <- B), a loop link ties them, and the keyframes after the join are mapped in A's frame
 * (keyframe reuse, loop closing against A). Replaying rather than pasting B's graph in keeps
 * one code path for pieces, and lets loop closing and keyframe reuse adjust B to A where they
 * meet (ACES, doc/localization.md: 0.0795 m over the relations across the two maps, B pasted
 * rigidly by the same join 0.509 m; SENA merged with itself grows by 2 keyframes, the others
 * reused); B's saved poses as odometry make the replay's local registration start from B's
 * optimised map, not from raw odometry.
 *
 * B's non-keyframe scans (its trajectory.tum, when MAP_B is an lrgc output folder) follow the
 * keyframe nearest in time: scan' = (K'_j (+) K_j^-1) (+) scan, K_j its keyframe in B, K'_j
 * where the merged map put it (rehangTrajectory). */
#pragma once

#include "lrgc_apps/SavedMap.h"
#include "lrgc_apps/io/LogReader.h"

#include <lrgc/map_builder/Trajectory.h>

#include <string>
#include <vector>

namespace lrgc::apps
{
/** The keyframes of a saved map as a log: for keyframe i, a CObservationOdometry with its
 * saved pose (map <- keyframe) at its scan's timestamp, then its sensory frame. */
class CKeyframeReplay final : public CLogReader
{
public:
	/** `map` is shared, not copied: it must outlive the replay. */
	explicit CKeyframeReplay(const TSavedMap& map);

	std::optional<TLogEntry> next() override;
	double fractionRead() const override;
	/** The keyframes are MRPT objects; there is no file format to report beyond that. */
	LogFormat format() const override { return LogFormat::MrptRawlog; }

	/** The saved keyframes replayed so far: (map <- keyframe) at their scans' stamps. */
	const TTrajectory& keyframePoses() const { return m_poses; }

private:
	const mrpt::maps::CSimpleMap& m_map;
	size_t m_next = 0;        //!< the keyframe whose entries come next
	bool m_frameDue = false;  //!< its odometry was given: its sensory frame comes next
	TTrajectory m_poses;
};

/** `dense` ((B <- robot) per scan of B, any stamps) moved as the keyframes of B moved:
 * `before` (B <- keyframe) and `after` (A <- keyframe) are matched by stamp, and each pose of
 * `dense` takes the move of the keyframe nearest in time. Keyframes of `before` missing from
 * `after` (not mapped in the replay) are skipped. Empty `dense`: `after` itself. */
TTrajectory rehangTrajectory(const TTrajectory& dense, const TTrajectory& before,
							 const TTrajectory& after);

/** MAP_B's trajectory.tum (B <- robot per scan) if MAP_B is a folder holding one; else
 * empty. Throws std::runtime_error naming the file if it is there but unreadable. */
TTrajectory savedMapTrajectory(const TSavedMap& map);

}  // namespace lrgc::apps
