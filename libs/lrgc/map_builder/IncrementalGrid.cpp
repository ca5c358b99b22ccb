/* CIncrementalGrid: see IncrementalGrid.h. Costs, per update(): the comparison of every
 * keyframe with what was inserted (O(n) pose comparisons), then Appended: the new scans, into
 * the result and, once settled, into the base (each scan twice in all); TailReinserted: a copy
 * of the base grid (one copy of its cells) and settleKeyframes scans; Rebuilt: every scan, as
 * a fresh build, plus that copy. The first call (every keyframe new) builds the base, copies it
 * and inserts the tail, not every scan twice. With several sessions: every scan, and one pass
 * over each newer session's cells (overlay). */
#include <lrgc/map_builder/IncrementalGrid.h>

#include <mrpt/poses/CPose3D.h>

#include <algorithm>

namespace lrgc
{
namespace
{
bool sameKeyframe(const TGridKeyframe& a, const TGridKeyframe& b)
{
	// Exact: a pose that moved by any amount is re-inserted (see the header).
	return a.laser == b.laser && a.session == b.session && a.robotInMap.x == b.robotInMap.x &&
		   a.robotInMap.y == b.robotInMap.y && a.robotInMap.phi == b.robotInMap.phi;
}

/** The distinct sessions of the keyframes, oldest first. */
std::vector<size_t> sessionsOf(const TGridKeyframes& keyframes)
{
	std::vector<size_t> s;
	for (const auto& k : keyframes) s.push_back(k.session);
	std::sort(s.begin(), s.end());
	s.erase(std::unique(s.begin(), s.end()), s.end());
	return s;
}
}  // namespace

CIncrementalGrid::CIncrementalGrid(const TGridSettings& settings)
	: m_settings(settings),
	  m_base(mrpt::maps::COccupancyGridMap2D::Create()),
	  m_result(mrpt::maps::COccupancyGridMap2D::Create())
{
	ASSERT_GT_(settings.resolution, 0);
	reset(*m_base, m_settings);
	reset(*m_result, m_settings);
}

void CIncrementalGrid::reset(mrpt::maps::COccupancyGridMap2D& grid,
							 const TGridSettings& settings)
{
	// The extent grows with the scans inserted (MRPT resizes on insertion).
	grid.setSize(-10, 10, -10, 10, settings.resolution);
	grid.insertionOptions.maxDistanceInsertion = static_cast<float>(settings.maxRayLength);
}

void CIncrementalGrid::insert(mrpt::maps::COccupancyGridMap2D& grid, const TGridKeyframe& k)
{
	ASSERT_(k.laser);
	const mrpt::poses::CPose3D robotInMap(k.robotInMap.x, k.robotInMap.y, 0, k.robotInMap.phi,
										  0, 0);
	grid.insertObservation(*k.laser, robotInMap);
}

void CIncrementalGrid::insertSession(mrpt::maps::COccupancyGridMap2D& grid,
									 const TGridKeyframes& keyframes, size_t session)
{
	for (const auto& k : keyframes)
		if (k.session == session) insert(grid, k);
}

void CIncrementalGrid::overlay(mrpt::maps::COccupancyGridMap2D& older,
							   const mrpt::maps::COccupancyGridMap2D& newer)
{
	// Both grids share the cell lattice (same resolution, grown from the same setSize), so a
	// cell centre of `newer` falls in the centre of a cell of `older`.
	older.resizeGrid(std::min(older.getXMin(), newer.getXMin()),
					 std::max(older.getXMax(), newer.getXMax()),
					 std::min(older.getYMin(), newer.getYMin()),
					 std::max(older.getYMax(), newer.getYMax()), 0.5f, false);
	const auto& cells = newer.getRawMap();
	const unsigned nx = newer.getSizeX();
	for (unsigned cy = 0; cy < newer.getSizeY(); ++cy)
		for (unsigned cx = 0; cx < nx; ++cx)
		{
			const auto l = cells[cx + cy * nx];
			if (l == 0) continue;  // unknown to the newer session: the older value stays
			const int ox = older.x2idx(newer.idx2x(cx)), oy = older.y2idx(newer.idx2y(cy));
			auto* row = older.getRow(oy);
			ASSERT_(row != nullptr && ox >= 0 && ox < static_cast<int>(older.getSizeX()));
			row[ox] = l;
		}
}

mrpt::maps::COccupancyGridMap2D::Ptr CIncrementalGrid::buildFromScratch(
	const TGridKeyframes& keyframes, const TGridSettings& settings)
{
	auto grid = mrpt::maps::COccupancyGridMap2D::Create();
	reset(*grid, settings);
	const std::vector<size_t> sessions = sessionsOf(keyframes);
	if (sessions.size() <= 1)
	{
		for (const auto& k : keyframes) insert(*grid, k);
		return grid;
	}
	insertSession(*grid, keyframes, sessions.front());
	for (size_t i = 1; i < sessions.size(); ++i)
	{
		mrpt::maps::COccupancyGridMap2D newer;
		reset(newer, settings);
		insertSession(newer, keyframes, sessions[i]);
		overlay(*grid, newer);
	}
	return grid;
}

void CIncrementalGrid::advanceBase(const TGridKeyframes& keyframes, size_t end)
{
	for (; m_baseCount < end; ++m_baseCount) insert(*m_base, keyframes[m_baseCount]);
}

CIncrementalGrid::Update CIncrementalGrid::update(const TGridKeyframes& keyframes)
{
	const size_t n = keyframes.size();
	// Keyframes 0..same-1 are in the result as they are now.
	size_t same = 0;
	const size_t common = std::min(n, m_inserted.size());
	while (same < common && sameKeyframe(keyframes[same], m_inserted[same])) ++same;
	const bool layered = sessionsOf(keyframes).size() > 1;
	if (m_layered && !layered) same = 0;  // the result held several sessions: built again
	const size_t baseEnd = n > m_settings.settleKeyframes ? n - m_settings.settleKeyframes : 0;

	Update kind;
	const bool nothingMoved = same == m_inserted.size();
	if (nothingMoved && same == n)
		kind = Update::Unchanged;
	else if (layered)
	{
		// Several sessions: no base; the result is built again (see the header).
		kind = Update::Rebuilt;
		reset(*m_base, m_settings);
		m_baseCount = 0;
		*m_result = *buildFromScratch(keyframes, m_settings);
	}
	else if (nothingMoved && n - same <= m_settings.settleKeyframes)
	{
		// A few new keyframes: into the result, and the base catches up.
		kind = Update::Appended;
		for (size_t i = same; i < n; ++i) insert(*m_result, keyframes[i]);
		advanceBase(keyframes, baseEnd);
	}
	else
	{
		// Keyframe `same` moved, changed or is gone (fewer keyframes than inserted); or many
		// new keyframes (the first call): the base first, then a copy of it, then the tail,
		// rather than inserting the new keyframes twice.
		kind = nothingMoved ? Update::Appended : Update::TailReinserted;
		if (same < m_baseCount)
		{
			kind = Update::Rebuilt;
			reset(*m_base, m_settings);
			m_baseCount = 0;
		}
		// The base may take keyframes up to baseEnd at their current poses: it then holds the
		// first keyframes of a fresh build whatever they were before.
		advanceBase(keyframes, baseEnd);
		*m_result = *m_base;
		for (size_t i = m_baseCount; i < n; ++i) insert(*m_result, keyframes[i]);
	}
	if (kind != Update::Unchanged) m_inserted = keyframes;
	m_layered = layered;
	++m_counts[static_cast<size_t>(kind)];
	return kind;
}

}  // namespace lrgc
