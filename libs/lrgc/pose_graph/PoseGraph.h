/* The LRGC map as a graph (paper section 2.4): nodes are robot poses (each with its scan,
 * held by the map builder under the same index), links are relative pose measurements from
 * dead reckoning, scan matching, or map correlation (loop closure).
 *
 * Frames: node i stores X_i = (map <- robot_i). A link i -> j stores Z_ij = (robot_i <-
 * robot_j), the measured pose of node j in the frame of node i, with its 3x3 information
 * matrix Omega_ij (inverse covariance) over (x [m], y [m], phi [rad]) in the frame of node i.
 *
 * Links are never erased, only disabled, so link ids handed out to other stages stay valid.
 * Each node keeps its incident link ids (adjacency), so a stage working on a few nodes (the
 * local registration window) never scans the whole graph.
 */
#pragma once

#include <mrpt/math/TPose2D.h>

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace lrgc
{
/** Where a link comes from. Only LoopClosure links are robustified by the optimizer. */
enum class LinkType : uint8_t
{
	Odometry,    //!< dead reckoning between consecutive poses
	ScanMatch,   //!< scan matching within the local registration window
	LoopClosure  //!< map correlation against the old map (may be wrong)
};
const char* toString(LinkType t);

/** A relative measurement between two nodes: Z = (from <- to). */
struct TLink
{
	size_t from = 0, to = 0;
	mrpt::math::TPose2D toInFrom;  //!< Z_ij: pose of `to` in the frame of `from` [m, rad]
	Eigen::Matrix3d information = Eigen::Matrix3d::Identity();  //!< over (x, y, phi)
	LinkType type = LinkType::Odometry;
};

class CPoseGraph
{
public:
	/** Appends a node with pose (map <- robot); returns its index (0, 1, 2, ...). */
	size_t addNode(const mrpt::math::TPose2D& nodeInMap);

	/** Appends an enabled link; returns its id. Throws if an index is out of range, from ==
	 * to, a value is not finite, or the information is not symmetric positive definite. */
	size_t addLink(const TLink& link);

	/** Disables (or re-enables) a link: a disabled link is kept (its id stays valid) but
	 * every optimisation, propagation and export ignores it. */
	void setLinkEnabled(size_t linkId, bool enabled);
	bool isLinkEnabled(size_t linkId) const;

	size_t numNodes() const { return m_poses.size(); }
	size_t numLinks() const { return m_links.size(); }
	const mrpt::math::TPose2D& pose(size_t node) const;
	void setPose(size_t node, const mrpt::math::TPose2D& nodeInMap);
	const std::vector<mrpt::math::TPose2D>& poses() const { return m_poses; }
	/** Lowest node index moved by setPose() since the last call (numNodes() if none), and
	 * restarts the count: what a copy of the graph kept elsewhere (the loop-closing worker's)
	 * must update, without comparing every pose. */
	size_t takeLowestMovedNode();
	const TLink& link(size_t linkId) const;
	/** All links ever added, enabled or not (check isLinkEnabled). */
	const std::vector<TLink>& links() const { return m_links; }
	/** Ids of the links (enabled or not) with `node` as one end, in insertion order. */
	const std::vector<size_t>& linksOf(size_t node) const;
	/** The lowest node index joined to `node` through enabled links (breadth-first, ended as
	 * soon as node 0 is reached): 0 in a graph of one piece; the first node of a piece not yet
	 * joined to the map (a session mapped in its own frame) otherwise. O(n + m) at most. */
	size_t lowestJoinedNode(size_t node) const;

private:
	void checkNode(size_t node, const char* where) const;

	std::vector<mrpt::math::TPose2D> m_poses;
	std::vector<TLink> m_links;
	std::vector<uint8_t> m_enabled;                // per link
	std::vector<std::vector<size_t>> m_adjacency;  // per node: incident link ids
	size_t m_lowestMoved = SIZE_MAX;               // see takeLowestMovedNode()
};

/** Node ids (keyframes, any order) cut into the robot's passes through a place: sorted, runs
 * whose consecutive ids differ by at most `maxGap` (a pass's keyframes are consecutive, a few
 * turned away leave small gaps; a larger gap is the robot leaving and coming back). */
std::vector<std::vector<size_t>> visitsOf(std::vector<size_t> nodes, size_t maxGap);

}  // namespace lrgc
