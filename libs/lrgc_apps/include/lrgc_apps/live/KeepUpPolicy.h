/* CKeepUpPolicy: how a live mapper that falls behind its lasers keeps up, without ever
 * touching the capture (every scan is already on disk when the mapper sees it).
 *
 * Policy: while more than M laser scans wait behind the one at the head of the queue (M =
 * [LiveMapping] max_backlog_scans), the mapper maps one scan, then skips the next
 * k = floor(waiting / M) scans. If mapping a scan takes s scan periods, the backlog B settles
 * where k + 1 = s, i.e. B ~ M (s - 1): bounded for any s, and the latency too. Skipping is
 * safe for the map: keyframes are chosen by distance travelled, so the next mapped scan becomes
 * the keyframe a skipped one would have been; the local registration sees a larger step, which
 * the odometry (or the constant-velocity prior) covers. Odometry is never skipped: the caller
 * only asks about laser scans. M = 0 disables skipping (every scan is mapped, however late).
 */
#pragma once

#include <cstddef>

namespace lrgc::apps
{
class CKeepUpPolicy
{
public:
	explicit CKeepUpPolicy(size_t max_backlog_scans) : m_max(max_backlog_scans) {}

	/** For the laser scan at the head of the queue, with `waiting` laser scans queued behind
	 * it: true to map it, false to skip it. */
	bool shouldMap(size_t waiting);

	/** Skipping since the backlog last exceeded the limit (and not yet back under it). */
	bool behind() const { return m_behind; }
	size_t skippedTotal() const { return m_skippedTotal; }
	/** Scans skipped since the mapper last fell behind. */
	size_t skippedThisEpisode() const { return m_skippedEpisode; }

private:
	size_t m_max;
	size_t m_skippedRun = 0;  //!< skipped since the last mapped scan
	size_t m_skippedTotal = 0, m_skippedEpisode = 0;
	bool m_behind = false;
};

}  // namespace lrgc::apps
