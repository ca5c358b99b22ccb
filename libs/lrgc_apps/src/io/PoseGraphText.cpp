/* Text form of the whole pose graph (see io/PoseGraphText.h). */
#include <lrgc_apps/io/PoseGraphText.h>

#include <mrpt/core/exceptions.h>
#include <mrpt/core/format.h>

#include <cmath>
#include <sstream>

namespace lrgc
{
namespace
{
constexpr const char* kMagic = "LRGC_POSE_GRAPH";
// 3: each node's session; 2: the END line; 1 (without it). All are read.
constexpr int kVersion = 3;

LinkType linkTypeFromName(const std::string& name, const std::string& where)
{
	for (const LinkType t : {LinkType::Odometry, LinkType::ScanMatch, LinkType::LoopClosure})
		if (name == toString(t)) return t;
	THROW_EXCEPTION_FMT("%s: unknown link type '%s' (Odometry, ScanMatch or LoopClosure)",
						where.c_str(), name.c_str());
}
// "END <nodes> <links>": the counts the writer wrote, checked against those read.
void checkEnd(std::istringstream& s, const CPoseGraph& graph, const std::string& at)
{
	size_t nodes = 0, links = 0;
	if (!(s >> nodes >> links) || !(s >> std::ws).eof())
		THROW_EXCEPTION_FMT("%s: bad END line (END nodes links)", at.c_str());
	if (nodes != graph.numNodes() || links != graph.numLinks())
		THROW_EXCEPTION_FMT("%s: END says %zu nodes and %zu links, the file has %zu and %zu",
							at.c_str(), nodes, links, graph.numNodes(), graph.numLinks());
}
}  // namespace

std::string poseGraphToText(const CPoseGraph& graph, const std::string& laserLabel,
							const std::vector<size_t>& sessions)
{
	if (!sessions.empty() && sessions.size() != graph.numNodes())
		THROW_EXCEPTION_FMT("poseGraphToText: %zu sessions for %zu nodes", sessions.size(),
							graph.numNodes());
	std::string out = mrpt::format(
		"# lrgc pose graph: node i is entry i of map.simplemap.gz; m, rad; "
		"NODE i x y phi session; LINK from to x y phi I00 I01 I02 I11 I12 I22 type enabled\n"
		"%s %d\n",
		kMagic, kVersion);
	if (!laserLabel.empty()) out += "LASER " + laserLabel + "\n";
	for (size_t i = 0; i < graph.numNodes(); ++i)
	{
		const auto& p = graph.pose(i);
		out += mrpt::format("NODE %zu %.17g %.17g %.17g %zu\n", i, p.x, p.y, p.phi,
							sessions.empty() ? size_t(0) : sessions[i]);
	}
	for (size_t id = 0; id < graph.numLinks(); ++id)
	{
		const TLink& l = graph.link(id);
		const Eigen::Matrix3d& I = l.information;
		out += mrpt::format(
			"LINK %zu %zu %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g %s %d\n",
			l.from, l.to, l.toInFrom.x, l.toInFrom.y, l.toInFrom.phi, I(0, 0), I(0, 1), I(0, 2),
			I(1, 1), I(1, 2), I(2, 2), toString(l.type), graph.isLinkEnabled(id) ? 1 : 0);
	}
	return out + mrpt::format("END %zu %zu\n", graph.numNodes(), graph.numLinks());
}

namespace
{
// NODE i x y phi session: node i (in order) at (x [m], y [m], phi [rad]) in the map frame,
// of mapping session `session` (version 3; before it, no session: 0).
void readNode(std::istringstream& s, TSavedPoseGraph& saved, int version, const std::string& at)
{
	CPoseGraph& graph = saved.graph;
	size_t i = 0;
	long long session = 0;  // signed: ">>" into an unsigned would take "-1" as 2^64 - 1
	mrpt::math::TPose2D p;
	if (!(s >> i >> p.x >> p.y >> p.phi) || (version >= 3 && !(s >> session)) ||
		!(s >> std::ws).eof())
		THROW_EXCEPTION_FMT("%s: bad NODE line (NODE i x y phi%s)", at.c_str(),
							version >= 3 ? " session" : "");
	if (i != graph.numNodes())
		THROW_EXCEPTION_FMT("%s: NODE %zu out of order (expected %zu)", at.c_str(), i,
							graph.numNodes());
	// A map spans metres to kilometres; beyond this [m] the number is corrupt, not a place
	// (and the grids built from the map could not index it).
	constexpr double kFarthest = 1e7;
	if (!(std::abs(p.x) <= kFarthest && std::abs(p.y) <= kFarthest && std::isfinite(p.phi)))
		THROW_EXCEPTION_FMT(
			"%s: NODE %zu at (%g, %g, %g): not finite or farther than %g m "
			"from the map's origin",
			at.c_str(), i, p.x, p.y, p.phi, kFarthest);
	// Sessions count the times a map was continued: beyond this the number is corrupt (and
	// the grid keeps a layer per session).
	constexpr long long kMostSessions = 100000;
	if (session < 0 || session > kMostSessions)
		THROW_EXCEPTION_FMT("%s: NODE %zu of session %lld: not in [0, %lld]", at.c_str(), i,
							session, kMostSessions);
	graph.addNode(p);
	saved.sessions.push_back(static_cast<size_t>(session));
}

// LINK from to x y phi I00 I01 I02 I11 I12 I22 type enabled: Z = (from <- to), the upper
// triangle of its information, its LinkType name, and whether the back-end kept it.
void readLink(std::istringstream& s, CPoseGraph& graph, const std::string& at)
{
	TLink l;
	double I[6];
	std::string type;
	int enabled = -1;
	if (!(s >> l.from >> l.to >> l.toInFrom.x >> l.toInFrom.y >> l.toInFrom.phi >> I[0] >>
		  I[1] >> I[2] >> I[3] >> I[4] >> I[5] >> type >> enabled) ||
		!(enabled == 0 || enabled == 1) || !(s >> std::ws).eof())
		THROW_EXCEPTION_FMT(
			"%s: bad LINK line (LINK from to x y phi I00 I01 I02 I11 I12 I22 type enabled)",
			at.c_str());
	l.information << I[0], I[1], I[2], I[1], I[3], I[4], I[2], I[4], I[5];
	l.type = linkTypeFromName(type, at);
	try
	{
		const size_t id = graph.addLink(l);
		if (!enabled) graph.setLinkEnabled(id, false);
	}
	catch (const std::exception& e)
	{
		THROW_EXCEPTION_FMT("%s: %s", at.c_str(), e.what());
	}
}
}  // namespace

TSavedPoseGraph poseGraphFromText(std::istream& in, const std::string& where)
{
	TSavedPoseGraph saved;
	std::string line;
	size_t lineNo = 0;
	int version = 0;
	bool ended = false;
	while (std::getline(in, line))
	{
		++lineNo;
		const std::string at = where + ":" + std::to_string(lineNo);
		// The writer ends every line: a last line without its newline was cut, perhaps in a
		// number ("NODE 7 1.25" of "NODE 7 1.2503"), which would still parse.
		if (in.eof())
			THROW_EXCEPTION_FMT("%s: cut short in this line (no end of line)", at.c_str());
		if (line.empty() || line[0] == '#') continue;
		std::istringstream s(line);
		s.imbue(std::locale::classic());
		std::string record;
		s >> record;
		if (version == 0)
		{
			if (record != kMagic || !(s >> version) || version < 1 || version > kVersion)
				THROW_EXCEPTION_FMT("%s: not an lrgc pose graph (expected '%s %d' first)",
									at.c_str(), kMagic, kVersion);
			continue;
		}
		if (ended)
			THROW_EXCEPTION_FMT("%s: '%s' after the END line", at.c_str(), record.c_str());
		if (record == "END" && version >= 2)
		{
			checkEnd(s, saved.graph, at);
			ended = true;
			continue;
		}
		if (record == "LASER")
		{
			std::getline(s >> std::ws, saved.laserLabel);
			continue;
		}
		if (record == "NODE")
		{
			readNode(s, saved, version, at);
			continue;
		}
		if (record == "LINK")
		{
			readLink(s, saved.graph, at);
			continue;
		}
		THROW_EXCEPTION_FMT("%s: unknown record '%s'", at.c_str(), record.c_str());
	}
	if (version == 0)
		THROW_EXCEPTION_FMT("%s: empty file, not an lrgc pose graph", where.c_str());
	// Without the END line a file cut at a line boundary would load as a smaller graph.
	if (version >= 2 && !ended)
		THROW_EXCEPTION_FMT(
			"%s: cut short after line %zu (%zu nodes, %zu links read; no END line)",
			where.c_str(), lineNo, saved.graph.numNodes(), saved.graph.numLinks());
	// Version 1 has no END line to tell: loaded, with a warning that says so.
	if (version == 1)
		saved.warning = mrpt::format(
			"%s:%zu: a version 1 graph (no END line): whether it was cut after this line (%zu "
			"nodes, %zu links read) cannot be checked; a map saved by this lrgc-slam can",
			where.c_str(), lineNo, saved.graph.numNodes(), saved.graph.numLinks());
	return saved;
}

}  // namespace lrgc
