/* Back-end timings on simulated Manhattan worlds (simulateManhattanPoseGraph: 1 m steps,
 * sigma 5 cm / 0.01 rad, about 1.5 visits per grid cell so loops are frequent but not
 * everywhere), with the default [PoseGraphOptimizer] parameters (DCS on loop closures):
 *   FullColdStart     whole graph from dead reckoning (the worst case: metres of drift)
 *   FullNewLoop       the mapper's case: an optimised graph receives its newest loop
 *                     closure (disabled during set-up) and is optimised again
 *   Window            local registration: the last K = 10 poses, all others fixed
 *   Uncertainty       propagateUncertainty from the newest pose over the whole graph
 * Counters: lm_iterations, nodes, links. Run: build/bin/pose_graph_benchmark.
 * With --lrgc_figures=DIR it also writes the SVG figures of doc/back-end.md and exits. */
#include <benchmark/benchmark.h>
#include <lrgc/pose_graph/PoseGraphOptimizer.h>
#include "manhattan_pose_graph.h"
#include <lrgc/loop_closing/UncertaintyPropagation.h>
#include <lrgc/common/se2.h>

#include <cmath>
#include <fstream>
#include <map>
#include <random>
#include <string>

using namespace lrgc;

namespace
{
TSimulatedPoseGraph simulate(size_t n)
{
	const auto side = static_cast<size_t>(std::lround(std::sqrt(double(n) / 1.5)));
	return simulateManhattanPoseGraph(n, side, 0.05, 0.01, 2024);
}

/** Optimised graph whose newest loop closure is disabled; its id in `lastLoop`. */
struct TWarm
{
	CPoseGraph graph;
	size_t lastLoop = 0;
};
const TWarm& warmGraph(size_t n)
{
	static std::map<size_t, TWarm> cache;
	if (auto it = cache.find(n); it != cache.end()) return it->second;
	TWarm w;
	w.graph = simulate(n).graph;
	for (size_t id = 0; id < w.graph.numLinks(); ++id)
		if (w.graph.link(id).type == LinkType::LoopClosure) w.lastLoop = id;
	w.graph.setLinkEnabled(w.lastLoop, false);
	const CPoseGraphOptimizer opt;
	for (int k = 0; k < 5 && !opt.optimize(w.graph, 0).converged; ++k)
	{
	}
	return cache.emplace(n, std::move(w)).first->second;
}

void setCounters(benchmark::State& st, const TOptimizationReport& r)
{
	st.counters["lm_iterations"] = r.iterations;
	st.counters["nodes"] = double(r.numFreeNodes);
	st.counters["links"] = double(r.numLinks);
}

void FullColdStart(benchmark::State& st)
{
	const CPoseGraph start = simulate(size_t(st.range(0))).graph;
	const CPoseGraphOptimizer opt;
	TOptimizationReport r;
	for (auto _ : st)
	{
		st.PauseTiming();
		CPoseGraph g = start;
		st.ResumeTiming();
		r = opt.optimize(g, 0);
	}
	setCounters(st, r);
}

void FullNewLoop(benchmark::State& st)
{
	const TWarm& w = warmGraph(size_t(st.range(0)));
	const CPoseGraphOptimizer opt;
	TOptimizationReport r;
	for (auto _ : st)
	{
		st.PauseTiming();
		CPoseGraph g = w.graph;
		g.setLinkEnabled(w.lastLoop, true);
		st.ResumeTiming();
		r = opt.optimize(g, 0);
	}
	setCounters(st, r);
}

void Window(benchmark::State& st)
{
	const TWarm& w = warmGraph(size_t(st.range(0)));
	CPoseGraph g = w.graph;
	const size_t K = size_t(st.range(1)), n = g.numNodes();
	std::vector<size_t> window;
	for (size_t i = n - K; i < n; ++i) window.push_back(i);
	const CPoseGraphOptimizer opt;
	TOptimizationReport r;
	for (auto _ : st)
	{
		st.PauseTiming();
		for (size_t i : window) g.setPose(i, compose(w.graph.pose(i), {0.05, -0.05, 0.02}));
		st.ResumeTiming();
		r = opt.optimizeSubset(g, window);
	}
	setCounters(st, r);
}

void Uncertainty(benchmark::State& st)
{
	const TWarm& w = warmGraph(size_t(st.range(0)));
	size_t reached = 0;
	for (auto _ : st) reached = propagateUncertainty(w.graph, w.graph.numNodes() - 1).size();
	st.counters["nodes"] = double(reached);
}

BENCHMARK(FullColdStart)
	->Arg(1000)
	->Arg(10000)
	->Arg(30000)
	->Unit(benchmark::kMillisecond)
	->Iterations(1);
BENCHMARK(FullNewLoop)
	->Arg(1000)
	->Arg(10000)
	->Arg(30000)
	->Unit(benchmark::kMillisecond)
	->Iterations(3);
BENCHMARK(Window)->Args({30000, 10})->Unit(benchmark::kMicrosecond);
BENCHMARK(Uncertainty)->Arg(30000)->Unit(benchmark::kMillisecond)->Iterations(3);

// ------------------------------------------------------------------------------ figures
/** Trajectories (blue: the estimate, grey: ground truth) and red links, as an SVG. */
void writeSvg(const std::string& file, const std::string& title, const CPoseGraph& g,
			  const std::vector<TPose2D>& truth, const std::vector<size_t>& redLinks)
{
	double x0 = 1e9, y0 = 1e9, x1 = -1e9, y1 = -1e9;
	for (const auto* poses : {&g.poses(), &truth})
		for (const TPose2D& p : *poses)
			x0 = std::min(x0, p.x), y0 = std::min(y0, p.y), x1 = std::max(x1, p.x),
			y1 = std::max(y1, p.y);
	const double s = 400.0 / std::max(x1 - x0, y1 - y0), m = 10;
	auto X = [&](double x) { return m + (x - x0) * s; };
	auto Y = [&](double y) { return m + (y1 - y) * s; };
	std::ofstream f(file);
	f << "<svg xmlns='http://www.w3.org/2000/svg' width='" << 2 * m + (x1 - x0) * s
	  << "' height='" << 2 * m + 20 + (y1 - y0) * s << "'>\n<rect width='100%' height='100%' "
	  << "fill='white'/>\n";
	auto polyline = [&](const std::vector<TPose2D>& ps, const char* colour, double w)
	{
		f << "<polyline fill='none' stroke='" << colour << "' stroke-width='" << w
		  << "' points='";
		for (const auto& p : ps) f << X(p.x) << ',' << Y(p.y) << ' ';
		f << "'/>\n";
	};
	polyline(truth, "#bbbbbb", 2.5);
	polyline(g.poses(), "#1f5fbf", 1.0);
	for (size_t id : redLinks)
	{
		const TLink& l = g.link(id);
		f << "<line stroke='#d02020' stroke-width='1.5' x1='" << X(g.pose(l.from).x) << "' y1='"
		  << Y(g.pose(l.from).y) << "' x2='" << X(g.pose(l.to).x) << "' y2='"
		  << Y(g.pose(l.to).y) << "'/>\n";
	}
	f << "<text x='" << m << "' y='" << 2 * m + 12 + (y1 - y0) * s
	  << "' font-family='sans-serif' font-size='12'>" << title << "</text>\n</svg>\n";
}

/** 1000-pose world, optimised, then 10 confident false loop closures; LS vs DCS. */
void writeFigures(const std::string& dir)
{
	const auto sim = simulateManhattanPoseGraph(1000, 12, 0.05, 0.01, 31);
	CPoseGraph g = sim.graph;
	const CPoseGraphOptimizer robust;
	for (int k = 0; k < 5 && !robust.optimize(g, 0).converged; ++k)
	{
	}
	std::mt19937 rng(32);
	std::uniform_int_distribution<size_t> node(0, 999);
	std::vector<size_t> falseIds;
	while (falseIds.size() < 10)
	{
		const size_t i = node(rng), j = node(rng);
		if (translationNorm(between(sim.groundTruth[i], sim.groundTruth[j])) < 5.0) continue;
		falseIds.push_back(g.addLink({i,
									  j,
									  {0, 0, 0},
									  Eigen::Vector3d(400, 400, 10000).asDiagonal(),
									  LinkType::LoopClosure}));
	}
	TPoseGraphOptimizerParams plain;
	plain.robust_loop_closures = false;
	CPoseGraph ls = g;
	CPoseGraphOptimizer(plain).optimize(ls, 0);
	writeSvg(dir + "/back-end-false-loops-least-squares.svg",
			 "Least squares: 10 false loop closures (red) bend the map", ls, sim.groundTruth,
			 falseIds);
	const TOptimizationReport r = robust.optimize(g, 0);
	writeSvg(dir + "/back-end-false-loops-dcs.svg",
			 "DCS: the same 10 false links are rejected (" +
				 std::to_string(r.downweightedLinks.size()) + " reported)",
			 g, sim.groundTruth, falseIds);
}
}  // namespace

int main(int argc, char** argv)
{
	const std::string flag = "--lrgc_figures=";
	for (int i = 1; i < argc; ++i)
		if (std::string(argv[i]).rfind(flag, 0) == 0)
		{
			writeFigures(std::string(argv[i]).substr(flag.size()));
			return 0;
		}
	benchmark::Initialize(&argc, argv);
	benchmark::RunSpecifiedBenchmarks();
	return 0;
}
