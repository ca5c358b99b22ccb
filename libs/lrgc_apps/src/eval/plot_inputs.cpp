/* Readers of map.yaml, graph.graph and timing.csv for lrgc-plot. */
#include "eval/plot_inputs.h"

#include <lrgc_apps/eval/trajectory.h>
#include <lrgc_apps/io/PoseGraphText.h>
#include <mrpt/core/exceptions.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <optional>
#include <sstream>

namespace lrgc::apps::eval
{
namespace
{
std::string trim(const std::string& s)
{
	const auto b = s.find_first_not_of(" \t\r\n");
	if (b == std::string::npos) return "";
	const auto e = s.find_last_not_of(" \t\r\n");
	return s.substr(b, e - b + 1);
}

std::string unquote(const std::string& s)
{
	if (s.size() >= 2 && (s.front() == '"' || s.front() == '\'') && s.back() == s.front())
		return s.substr(1, s.size() - 2);
	return s;
}
}  // namespace

TRosMapInfo loadRosMapYaml(const std::string& path)
{
	const std::string text = readTextFile(path);
	TRosMapInfo info;
	std::optional<std::string> image;
	bool haveResolution = false, haveOrigin = false;
	forEachDataLine(
		text,
		[&](const std::string& line, std::size_t lineNo)
		{
			const auto colon = line.find(':');
			if (colon == std::string::npos) return;
			const std::string key = trim(line.substr(0, colon));
			std::string value = trim(line.substr(colon + 1));
			if (const auto hash = value.find(" #"); hash != std::string::npos)
				value = trim(value.substr(0, hash));
			if (key == "image")
				image = unquote(value);
			else if (key == "resolution")
			{
				const auto v = parseNumberLine(value, path, lineNo);
				if (v.size() != 1 || !(v[0] > 0))
					THROW_EXCEPTION_FMT("%s:%zu: resolution must be one positive number",
										path.c_str(), lineNo);
				info.resolution = v[0];
				haveResolution = true;
			}
			else if (key == "origin")
			{
				if (value.size() < 2 || value.front() != '[' || value.back() != ']')
					THROW_EXCEPTION_FMT("%s:%zu: origin must be [x, y, yaw]", path.c_str(),
										lineNo);
				std::string inner = value.substr(1, value.size() - 2);
				std::replace(inner.begin(), inner.end(), ',', ' ');
				const auto v = parseNumberLine(inner, path, lineNo);
				if (v.size() != 3)
					THROW_EXCEPTION_FMT("%s:%zu: origin must be [x, y, yaw], got %zu numbers",
										path.c_str(), lineNo, v.size());
				info.origin = {v[0], v[1], v[2]};
				haveOrigin = true;
			}
			else if (key == "negate")
				info.negate = (value == "1" || value == "true");
		});
	if (!image || image->empty()) THROW_EXCEPTION_FMT("%s: no 'image:' key", path.c_str());
	if (!haveResolution) THROW_EXCEPTION_FMT("%s: no 'resolution:' key", path.c_str());
	if (!haveOrigin) THROW_EXCEPTION_FMT("%s: no 'origin:' key", path.c_str());
	namespace fs = std::filesystem;
	const fs::path img(*image);
	info.imagePath =
		img.is_absolute() ? img.string() : (fs::path(path).parent_path() / img).string();
	return info;
}

namespace
{
// graph.lrgc (PoseGraphText.h): every node, the enabled links, LoopClosure ones apart.
TGraphFile typedGraph(const std::string& text, const std::string& path)
{
	std::istringstream in(text);
	const TSavedPoseGraph saved = poseGraphFromText(in, path);
	const CPoseGraph& pg = saved.graph;
	TGraphFile g;
	g.warning = saved.warning;
	g.loopLinks.emplace();
	for (std::size_t i = 0; i < pg.numNodes(); ++i) g.vertices[i] = pg.pose(i);
	for (std::size_t id = 0; id < pg.numLinks(); ++id)
	{
		if (!pg.isLinkEnabled(id)) continue;
		const TLink& l = pg.link(id);
		g.edges.emplace_back(l.from, l.to);
		if (l.type == LinkType::LoopClosure) g.loopLinks->emplace_back(l.from, l.to);
	}
	return g;
}
}  // namespace

TGraphFile loadGraphFile(const std::string& path)
{
	const std::string text = readTextFile(path);
	if (text.find("LRGC_POSE_GRAPH") != std::string::npos) return typedGraph(text, path);
	TGraphFile g;
	forEachDataLine(
		text,
		[&](const std::string& line, std::size_t lineNo)
		{
			std::istringstream ss(line);
			std::string keyword;
			ss >> keyword;
			if (keyword != "VERTEX_SE2" && keyword != "EDGE_SE2") return;
			std::string rest;
			std::getline(ss, rest);
			const auto v = parseNumberLine(rest, path, lineNo);
			const auto id = [&](double x)
			{
				if (x < 0 || x != static_cast<double>(static_cast<std::size_t>(x)))
					THROW_EXCEPTION_FMT(
						"%s:%zu: %s: vertex id %g is not a non-negative integer", path.c_str(),
						lineNo, keyword.c_str(), x);
				return static_cast<std::size_t>(x);
			};
			if (keyword == "VERTEX_SE2")
			{
				if (v.size() != 4)
					THROW_EXCEPTION_FMT("%s:%zu: VERTEX_SE2 needs id x y phi, got %zu numbers",
										path.c_str(), lineNo, v.size());
				g.vertices[id(v[0])] = {v[1], v[2], v[3]};
			}
			else
			{
				if (v.size() < 5)
					THROW_EXCEPTION_FMT(
						"%s:%zu: EDGE_SE2 needs from to x y phi [information], got %zu numbers",
						path.c_str(), lineNo, v.size());
				g.edges.emplace_back(id(v[0]), id(v[1]));
			}
		});
	return g;
}

std::vector<std::pair<std::size_t, std::size_t>> loopClosureEdges(const TGraphFile& graph,
																  std::size_t minIdGap)
{
	if (graph.loopLinks) return *graph.loopLinks;
	std::vector<std::pair<std::size_t, std::size_t>> out;
	for (const auto& [a, b] : graph.edges)
		if ((a > b ? a - b : b - a) > minIdGap) out.emplace_back(a, b);
	return out;
}

std::vector<TScanTiming> loadTimingCsv(const std::string& path)
{
	std::vector<TScanTiming> out;
	bool header = true;
	forEachDataLine(readTextFile(path),
					[&](const std::string& line, std::size_t lineNo)
					{
						if (header)
						{
							header = false;
							if (line.find("scan_index") != std::string::npos) return;
						}
						std::string fields = line;
						std::replace(fields.begin(), fields.end(), ',', ' ');
						const auto v = parseNumberLine(fields, path, lineNo);
						// --localize's timing.csv has more columns after these three.
						if (v.size() < 3 || v[0] < 0)
							THROW_EXCEPTION_FMT(
								"%s:%zu: expected scan_index,timestamp,latency_ms",
								path.c_str(), lineNo);
						out.push_back({static_cast<std::size_t>(v[0]), v[1], v[2]});
					});
	return out;
}

}  // namespace lrgc::apps::eval
