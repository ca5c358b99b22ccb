/* lrgc-plot: map with trajectory and loop-closure links, and per-scan latency, drawn with
 * OpenCV into one PNG. */
#include "eval/CPlotApp.h"

#include "OutputsVsInputs.h"
#include "atomic_file.h"
#include "eval/plot_inputs.h"
#include <lrgc_apps/eval/trajectory.h>
#include <mrpt/core/exceptions.h>
#include <mrpt/core/format.h>

#include <algorithm>
#include <cmath>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <ostream>
#include <stdexcept>

namespace lrgc::apps::eval
{
namespace
{
const cv::Scalar kBlue(200, 60, 0), kRed(30, 30, 220), kGreen(40, 160, 40), kBlack(0, 0, 0),
	kGrey(120, 120, 120), kOrange(0, 140, 255), kWhite(255, 255, 255);
constexpr int kFont = cv::FONT_HERSHEY_SIMPLEX;

void label(cv::Mat& img, const std::string& text, cv::Point at, double scale = 0.5,
		   const cv::Scalar& color = kBlack)
{
	cv::putText(img, text, at, kFont, scale, color, 1, cv::LINE_AA);
}

/** Largest of 1, 2, 5 x 10^k not above x. */
double niceStep(double x)
{
	const double p = std::pow(10.0, std::floor(std::log10(x)));
	for (const double m : {5.0, 2.0, 1.0})
		if (m * p <= x) return m * p;
	return p;
}

/** A scale bar of a round length, about a sixth of the panel width, at its bottom left. */
void drawScaleBar(cv::Mat& panel, int left, int width, double pxPerM)
{
	const double barM = niceStep(width / 6.0 / pxPerM);
	const cv::Point b0(left + 15, panel.rows - 15);
	const cv::Point b1(b0.x + static_cast<int>(std::lround(barM * pxPerM)), b0.y);
	cv::line(panel, b0, b1, kBlack, 3);
	label(panel, mrpt::format("%g m", barM), cv::Point(b0.x, b0.y - 8));
}

/** Map panel: the grid cropped to known cells and trajectory, scaled to fit. */
cv::Mat drawMapPanel(const TPlotOptions& o, const TRosMapInfo& info,
					 const std::vector<TTimedPose2D>& traj, const TGraphFile& graph,
					 const std::vector<std::pair<std::size_t, std::size_t>>& loops,
					 TPlotSummary& sum)
{
	cv::Mat grid = cv::imread(info.imagePath, cv::IMREAD_GRAYSCALE);
	if (grid.empty())
		THROW_EXCEPTION_FMT("%s: cannot read the map image", info.imagePath.c_str());
	if (info.negate) grid = 255 - grid;
	// (map image pixel <- world): col = R(-yaw)(p - o).x / res, row = H - R(-yaw)(p - o).y /
	// res
	const double c = std::cos(info.origin.phi), s = std::sin(info.origin.phi);
	const auto toGrid = [&](double x, double y)
	{
		const double dx = x - info.origin.x, dy = y - info.origin.y;
		return cv::Point2d((c * dx + s * dy) / info.resolution,
						   grid.rows - (-s * dx + c * dy) / info.resolution);
	};
	// Crop: known cells (not ROS "unknown" grey 205) and the trajectory, plus a margin.
	cv::Mat known = (grid < 200) | (grid > 210);
	cv::Rect box = cv::boundingRect(known);
	for (const auto& p : traj)
	{
		const cv::Point2d g = toGrid(p.pose.x, p.pose.y);
		box |= cv::Rect(static_cast<int>(std::floor(g.x)), static_cast<int>(std::floor(g.y)), 1,
						1);
	}
	const int margin = 10;
	box = cv::Rect(box.x - margin, box.y - margin, box.width + 2 * margin,
				   box.height + 2 * margin);
	cv::Mat crop(box.size(), CV_8UC1, cv::Scalar(205));
	const cv::Rect inside = box & cv::Rect(0, 0, grid.cols, grid.rows);
	if (inside.area() > 0) grid(inside).copyTo(crop(inside - box.tl()));

	const double scale = std::min(static_cast<double>(o.width) / box.width,
								  static_cast<double>(o.maxMapHeight) / box.height);
	cv::Mat gray;
	cv::resize(crop, gray, cv::Size(), scale, scale,
			   scale < 1 ? cv::INTER_AREA : cv::INTER_NEAREST);
	cv::Mat panel(gray.rows, o.width, CV_8UC3, kWhite);
	const int left = (o.width - gray.cols) / 2;
	cv::cvtColor(gray, panel(cv::Rect(left, 0, gray.cols, gray.rows)), cv::COLOR_GRAY2BGR);
	const auto toPanel = [&](double x, double y)
	{
		const cv::Point2d g = toGrid(x, y);
		return cv::Point2d(left + (g.x - box.x) * scale, (g.y - box.y) * scale);
	};
	const auto pt = [](const cv::Point2d& p) {
		return cv::Point(static_cast<int>(std::lround(p.x)),
						 static_cast<int>(std::lround(p.y)));
	};
	std::vector<cv::Point> line;
	for (const auto& p : traj) line.push_back(pt(toPanel(p.pose.x, p.pose.y)));
	cv::polylines(panel, line, false, kBlue, 2, cv::LINE_AA);
	for (const auto& [a, b] : loops)
	{
		const auto ia = graph.vertices.find(a), ib = graph.vertices.find(b);
		if (ia == graph.vertices.end() || ib == graph.vertices.end())
			THROW_EXCEPTION_FMT(
				"%s: edge %zu -> %zu refers to a vertex that is not in the file",
				o.graph.c_str(), a, b);
		cv::line(panel, pt(toPanel(ia->second.x, ia->second.y)),
				 pt(toPanel(ib->second.x, ib->second.y)), kRed, 2, cv::LINE_AA);
	}
	cv::circle(panel, line.front(), 6, kGreen, cv::FILLED, cv::LINE_AA);
	cv::circle(panel, line.back(), 5, kBlack, cv::FILLED, cv::LINE_AA);

	const double pxPerM = scale / info.resolution;
	drawScaleBar(panel, left, o.width, pxPerM);

	sum.pixelsPerMetre = pxPerM;
	const cv::Point2d o0 = toPanel(0, 0);
	sum.mapOriginCol = o0.x;
	sum.mapOriginRow = o0.y;
	return panel;
}

/** Latency panel: one dot per scan, log10 y axis. */
cv::Mat drawLatencyPanel(const TPlotOptions& o, const std::vector<TScanTiming>& timing)
{
	const int h = 320, left = 70, right = 20, top = 30, bottom = 40;
	cv::Mat panel(h, o.width, CV_8UC3, kWhite);
	std::vector<double> lat;
	for (const auto& t : timing) lat.push_back(std::max(t.latency_ms, 1e-3));
	std::vector<double> sorted = lat;
	std::sort(sorted.begin(), sorted.end());
	const auto rank = [&](double p) {  // nearest rank
		const std::size_t k = static_cast<std::size_t>(std::ceil(p * sorted.size()));
		return sorted[std::clamp<std::size_t>(k, 1, sorted.size()) - 1];
	};
	const double median = rank(0.5), p99 = rank(0.99), maxv = sorted.back();
	const double lo = std::floor(std::log10(sorted.front())),
				 hi = std::ceil(std::log10(maxv) + 1e-9);
	const double n = static_cast<double>(std::max<std::size_t>(timing.back().scanIndex, 1));
	const int plotW = o.width - left - right, plotH = h - top - bottom;
	const auto X = [&](double i)
	{ return left + static_cast<int>(std::lround(i / n * plotW)); };
	const auto Y = [&](double ms)
	{ return top + static_cast<int>(std::lround((hi - std::log10(ms)) / (hi - lo) * plotH)); };
	cv::rectangle(panel, cv::Point(left, top), cv::Point(left + plotW, top + plotH), kGrey);
	for (double e = lo; e <= hi; e += 1)
	{
		const int y = Y(std::pow(10.0, e));
		cv::line(panel, cv::Point(left, y), cv::Point(left + plotW, y),
				 cv::Scalar(225, 225, 225));
		label(panel, mrpt::format("%g", std::pow(10.0, e)), cv::Point(5, y + 5), 0.45);
	}
	const double xStep = niceStep(n / 6.0);
	for (double i = 0; i <= n; i += xStep)
		label(panel, mrpt::format("%.0f", i), cv::Point(X(i) - 10, top + plotH + 18), 0.45);
	for (std::size_t k = 0; k < timing.size(); ++k)
		cv::circle(panel, cv::Point(X(static_cast<double>(timing[k].scanIndex)), Y(lat[k])), 1,
				   kBlue, cv::FILLED);
	cv::line(panel, cv::Point(left, Y(median)), cv::Point(left + plotW, Y(median)), kGreen, 1);
	cv::line(panel, cv::Point(left, Y(p99)), cv::Point(left + plotW, Y(p99)), kOrange, 1);
	label(panel,
		  mrpt::format(
			  "per-scan latency [ms, log scale]: median %.2f (green), p99 %.2f (orange), "
			  "max %.1f",
			  median, p99, maxv),
		  cv::Point(left, 20));
	label(panel, "scan index", cv::Point(left + plotW / 2 - 40, h - 6), 0.45);
	return panel;
}
}  // namespace

std::string CPlotApp::usage()
{
	return "Usage: lrgc-plot --map map.yaml --trajectory trajectory.tum [--graph graph.lrgc]\n"
		   "                 [--timing timing.csv] [--title TEXT] [--loop-min-gap N] --out "
		   "plot.png\n"
		   "       lrgc-plot --help | --version\n"
		   "--graph graph.lrgc draws its loop links (type LoopClosure: stats.json's "
		   "links.loop);\n"
		   "--graph graph.graph has no link types: edges spanning more than --loop-min-gap\n"
		   "(15) keyframes are drawn as loop links.\n";
}

TPlotOptions CPlotApp::parseArguments(const std::vector<std::string>& args)
{
	TPlotOptions o;
	for (std::size_t i = 0; i < args.size(); ++i)
	{
		const std::string& a = args[i];
		const auto value = [&]() -> const std::string&
		{
			if (i + 1 >= args.size()) throw std::invalid_argument(a + ": missing value");
			return args[++i];
		};
		if (a == "--map")
			o.mapYaml = value();
		else if (a == "--trajectory")
			o.trajectory = value();
		else if (a == "--graph")
			o.graph = value();
		else if (a == "--timing")
			o.timing = value();
		else if (a == "--title")
			o.title = value();
		else if (a == "--out")
			o.out = value();
		else if (a == "--loop-min-gap")
		{
			const std::string& v = value();
			if (v.empty() || v.find_first_not_of("0123456789") != std::string::npos)
				throw std::invalid_argument("--loop-min-gap: '" + v + "' is not a count");
			o.loopMinGap = std::stoul(v);
		}
		else
			throw std::invalid_argument("unknown argument '" + a + "'");
	}
	if (o.mapYaml.empty() || o.trajectory.empty() || o.out.empty())
		throw std::invalid_argument("--map, --trajectory and --out are required");
	return o;
}

TPlotSummary CPlotApp::render(const TPlotOptions& o)
{
	TPlotSummary sum;
	const TRosMapInfo info = loadRosMapYaml(o.mapYaml);
	if (const std::string clash =
			outputOverInput({{"--out", o.out}}, {{"--map", o.mapYaml},
												 {"--map's image", info.imagePath},
												 {"--trajectory", o.trajectory},
												 {"--graph", o.graph},
												 {"--timing", o.timing}});
		!clash.empty())
		throw std::invalid_argument(clash);
	const CTrajectory2D traj = CTrajectory2D::loadFromFile(o.trajectory);
	const TGraphFile graph = o.graph.empty() ? TGraphFile{} : loadGraphFile(o.graph);
	const auto loops = loopClosureEdges(graph, o.loopMinGap);
	const auto timing = o.timing.empty() ? std::vector<TScanTiming>{} : loadTimingCsv(o.timing);

	const int headerH = 50;
	cv::Mat map = drawMapPanel(o, info, traj.poses(), graph, loops, sum);
	cv::Mat header(headerH, o.width, CV_8UC3, kWhite);
	label(header, o.title.empty() ? o.trajectory : o.title, cv::Point(10, 22), 0.7);
	label(header,
		  mrpt::format("trajectory (blue, %zu poses; start green, end black), loop links "
					   "(red, %zu)",
					   traj.size(), loops.size()),
		  cv::Point(10, 42), 0.5);
	std::vector<cv::Mat> parts = {header, map};
	if (!timing.empty()) parts.push_back(drawLatencyPanel(o, timing));
	cv::Mat img;
	cv::vconcat(parts, img);

	std::vector<uchar> png;
	if (!cv::imencode(".png", img, png, {cv::IMWRITE_PNG_COMPRESSION, 9}))
		THROW_EXCEPTION_FMT("%s: PNG encoding failed", o.out.c_str());
	writeTextFileAtomically(o.out, std::string(png.begin(), png.end()));

	sum.width = img.cols;
	sum.height = img.rows;
	sum.trajectoryPoses = traj.size();
	sum.loopLinks = loops.size();
	sum.timedScans = timing.size();
	sum.warning = graph.warning;
	sum.mapPanelTop = headerH;
	sum.mapPanelHeight = map.rows;
	sum.mapOriginRow += headerH;
	return sum;
}

int CPlotApp::run(const std::vector<std::string>& args, std::ostream& out, std::ostream& err)
{
	if (std::find(args.begin(), args.end(), "--help") != args.end() ||
		std::find(args.begin(), args.end(), "-h") != args.end())
	{
		out << usage();
		return 0;
	}
	if (std::find(args.begin(), args.end(), "--version") != args.end())
	{
		out << "lrgc-plot " << LRGC_VERSION << "\n";
		return 0;
	}
	TPlotOptions o;
	try
	{
		o = parseArguments(args);
	}
	catch (const std::invalid_argument& e)
	{
		err << "lrgc-plot: " << e.what() << "; lrgc-plot --help lists the options\n";
		return 2;
	}
	try
	{
		const TPlotSummary s = render(o);
		if (!s.warning.empty()) err << "lrgc-plot: warning: " << s.warning << "\n";
		out << mrpt::format("wrote %s (%dx%d): %zu poses, %zu loop links, %zu timed scans\n",
							o.out.c_str(), s.width, s.height, s.trajectoryPoses, s.loopLinks,
							s.timedScans);
		return 0;
	}
	catch (const std::exception& e)
	{
		err << "lrgc-plot: " << userMessage(e) << "\n";
		return 1;
	}
}

}  // namespace lrgc::apps::eval
