/* Global correlation timings at realistic sizes: an old map of 40 x 40 m at 5 cm (an office
 * floor of 5 m rooms with doors and clutter), patches of 20 scans x 180 beams, search window
 * +-3 m, +-20 deg (and a smaller +-1 m, +-10 deg). Branch and bound against the paper's
 * exhaustive grid, which is run once per case; both give the same pose (counter same_pose).
 *
 * The small synthetic office generator is local to this file (a shared synthetic world is
 * written separately). Run: build/bin/patch_correlator_benchmark
 */
#include <benchmark/benchmark.h>

#include <lrgc/loop_closing/PatchCorrelator.h>
#include <lrgc/common/se2.h>

#include <cmath>
#include <random>

namespace
{
using lrgc::TPose2D;
using Points = std::vector<Eigen::Vector2d>;
struct Segment
{
	Eigen::Vector2d a, b;
};

// 8 x 8 rooms of 5 m; every wall between rooms has a 1 m door at a random place; each room
// holds 3 random pieces of furniture (0.4 to 1.5 m).
std::vector<Segment> office(std::mt19937& rng)
{
	std::vector<Segment> w;
	std::uniform_real_distribution<double> u(0, 1);
	const double room = 5, n = 8, door = 1;
	for (int k = 0; k <= n; ++k)
		for (int r = 0; r < n; ++r)
			for (int axis = 0; axis < 2; ++axis)
			{
				const double c = k * room, s0 = r * room, d0 = s0 + 0.5 + u(rng) * (room - 2);
				const bool outer = k == 0 || k == n;
				const auto seg = [&](double from, double to) {
					w.push_back(axis == 0 ? Segment{{c, from}, {c, to}}
										  : Segment{{from, c}, {to, c}});
				};
				if (outer)
					seg(s0, s0 + room);
				else
					seg(s0, d0), seg(d0 + door, s0 + room);
			}
	for (int rx = 0; rx < n; ++rx)
		for (int ry = 0; ry < n; ++ry)
			for (int f = 0; f < 3; ++f)
			{
				const Eigen::Vector2d a(rx * room + 0.5 + 4 * u(rng),
										ry * room + 0.5 + 4 * u(rng));
				const double t = 2 * M_PI * u(rng), l = 0.4 + 1.1 * u(rng);
				w.push_back({a, a + l * Eigen::Vector2d(std::cos(t), std::sin(t))});
			}
	return w;
}

Points rasterise(const std::vector<Segment>& w)
{
	Points pts;
	for (const auto& s : w)
	{
		const int n = std::max(1, int(std::ceil((s.b - s.a).norm() / 0.02)));
		for (int k = 0; k <= n; ++k) pts.push_back(s.a + (s.b - s.a) * (double(k) / n));
	}
	return pts;
}

// 180-beam scan (-90..+90 deg, 1 cm noise, 8 m range) in the robot frame.
Points raycast(const std::vector<Segment>& w, const TPose2D& robot, std::mt19937& rng)
{
	std::normal_distribution<double> noise(0, 0.01);
	Points pts;
	const Eigen::Vector2d o(robot.x, robot.y);
	for (int k = 0; k < 180; ++k)
	{
		const double beam = -M_PI / 2 + M_PI * k / 179.0;
		const Eigen::Vector2d d(std::cos(robot.phi + beam), std::sin(robot.phi + beam));
		double best = 8.0;
		for (const auto& s : w)
		{
			const Eigen::Vector2d e = s.b - s.a, r = s.a - o;
			const double den = d.x() * e.y() - d.y() * e.x();
			if (std::abs(den) < 1e-12) continue;
			const double t = (r.x() * e.y() - r.y() * e.x()) / den;
			const double v = (r.x() * d.y() - r.y() * d.x()) / den;
			if (t > 0.05 && v >= 0 && v <= 1) best = std::min(best, t);
		}
		if (best < 8.0)
			pts.emplace_back((best + noise(rng)) * std::cos(beam),
							 (best + noise(rng)) * std::sin(beam));
	}
	return pts;
}

struct Case
{
	Points patch;  // 20 scans in the frame of the last one
	TPose2D truth, center;
};

struct Fixture
{
	lrgc::CPatchCorrelator corr;
	lrgc::CCorrelationGrid map;
	std::vector<Case> cases;
	std::vector<Segment> world;
	Points mapPoints;

	Fixture()
	{
		std::mt19937 rng(1);
		world = office(rng);
		mapPoints = rasterise(world);
		map = corr.makeGrid(mapPoints, 0.5);
		std::uniform_real_distribution<double> u(-1, 1), cell(1.2, 3.8);
		for (int c = 0; c < 8; ++c)
		{
			Case k;
			const int room = int(64 * (0.5 + 0.5 * u(rng))) % 64;
			k.truth =
				TPose2D((room % 8) * 5 + cell(rng), (room / 8) * 5 + cell(rng), M_PI * u(rng));
			// 20 scans over a 3 m arc ending at the truth.
			for (int s = 19; s >= 0; --s)
			{
				const TPose2D robot = lrgc::compose(k.truth, TPose2D(-0.15 * s, 0, -0.02 * s));
				const TPose2D inPatch = lrgc::between(k.truth, robot);
				for (const auto& p : raycast(world, robot, rng))
					k.patch.push_back(lrgc::transformPoint(inPatch, p));
			}
			k.center = TPose2D(k.truth.x + 0.5 * u(rng), k.truth.y + 0.5 * u(rng),
							   k.truth.phi + 0.1 * u(rng));
			cases.push_back(std::move(k));
		}
	}
};

const Fixture& fixture()
{
	static const Fixture f;
	return f;
}

void BM_GridBuild(benchmark::State& st)
{
	const Fixture& f = fixture();
	for (auto _ : st) benchmark::DoNotOptimize(f.corr.makeGrid(f.mapPoints, 0.5));
	st.counters["cells"] = double(f.map.width()) * f.map.height();
	st.counters["map_points"] = double(f.mapPoints.size());
}
BENCHMARK(BM_GridBuild)->Unit(benchmark::kMillisecond);

// Arguments: half window [cm], half window [deg], exhaustive (0/1).
void BM_Correlate(benchmark::State& st)
{
	const Fixture& f = fixture();
	const double hxy = st.range(0) / 100.0, hth = st.range(1) * M_PI / 180;
	const bool exhaustive = st.range(2) != 0;
	size_t k = 0, found = 0, accepted = 0, scored = 0, cells = 0, samePose = 0, runs = 0;
	double errXY = 0;
	for (auto _ : st)
	{
		const Case& c = f.cases[k++ % f.cases.size()];
		const auto r = exhaustive
						   ? f.corr.correlateExhaustive(f.map, c.patch, c.center, hxy, hth)
						   : f.corr.correlate(f.map, c.patch, c.center, hxy, hth);
		++runs;
		if (!r) continue;
		++found;
		accepted += r->passesFilters(f.corr.params());
		scored += r->posesScored;
		cells += r->patchCells;
		errXY = std::max(errXY,
						 std::hypot(r->patchInMap.x - c.truth.x, r->patchInMap.y - c.truth.y));
		if (!exhaustive && runs <= f.cases.size())
		{  // check against the reference once per case (outside the timing)
			st.PauseTiming();
			const auto e = f.corr.correlateExhaustive(f.map, c.patch, c.center, hxy, hth);
			samePose += e && e->patchInMap.x == r->patchInMap.x &&
						e->patchInMap.y == r->patchInMap.y &&
						e->patchInMap.phi == r->patchInMap.phi;
			st.ResumeTiming();
		}
	}
	st.counters["found"] = double(found) / double(runs);
	st.counters["accepted"] = double(accepted) / double(runs);
	st.counters["evals"] = found ? double(scored) / double(found) : 0;
	st.counters["cells"] = found ? double(cells) / double(found) : 0;
	st.counters["max_err_m"] = errXY;
	if (!exhaustive) st.counters["same_pose"] = double(samePose);
}
BENCHMARK(BM_Correlate)
	->Args({300, 20, 0})
	->Args({100, 10, 0})
	->Args({300, 20, 1})
	->Args({100, 10, 1})
	->Unit(benchmark::kMillisecond)
	->Iterations(8);

}  // namespace

BENCHMARK_MAIN();
