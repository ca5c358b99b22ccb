/* Time of CScanMatcher::match (and of building its CReferenceCloud) on synthetic room scans:
 * 180- and 361-beam scans, against one scan and against a patch of 10 scans. Guesses are the
 * truth perturbed by 5 cm / 2 deg, so the figure includes a realistic number of iterations.
 * Run: build/bin/scan_matcher_benchmark [--benchmark_min_time=0.5] */
#include <benchmark/benchmark.h>
#include <lrgc/scan_matching/ScanMatcher.h>
#include <lrgc/common/se2.h>

#include "synthetic_world.h"

namespace
{
using lrgc::test::TLaserSimParams;
using mrpt::math::TPose2D;

struct TCase
{
	std::vector<lrgc::CReferenceCloud> refs;
	std::vector<lrgc::TScan2D> scans;
	std::vector<TPose2D> guesses;
	std::vector<std::vector<lrgc::TScan2D>> refScans;
	std::vector<std::vector<TPose2D>> refPoses;
};

/** 32 seeded situations: a robot in a room, `patch` scans 15 cm apart, then the scan to match.
 */
TCase makeCase(int beams, int patch)
{
	TCase c;
	TLaserSimParams laser;
	laser.beams = beams;
	const lrgc::TScanMatcherParams params;
	std::mt19937 rng(1234);
	std::normal_distribution<double> N(0, 1);
	for (int t = 0; t < 32; ++t)
	{
		const auto world = lrgc::test::makeRoomWorld(100 + t);
		const auto start = *lrgc::test::sampleFreePose(world, {{2, 2}, {8, 5}}, 0.8, rng);
		std::vector<lrgc::TScan2D> scans;
		std::vector<TPose2D> poses;
		TPose2D p = start;
		for (int k = 0; k < patch; ++k)
		{
			poses.push_back(p);
			scans.push_back(lrgc::test::simulateScan(world, p, laser, rng));
			p = lrgc::compose(p, TPose2D(0.15, 0, 0.03));
		}
		// ref frame = first scan of the patch
		std::vector<TPose2D> inRef;
		for (const auto& q : poses) inRef.push_back(lrgc::between(poses[0], q));
		c.refs.push_back(lrgc::CReferenceCloud::fromScans(scans, inRef, params));
		c.refScans.push_back(scans);
		c.refPoses.push_back(inRef);
		c.scans.push_back(lrgc::test::simulateScan(world, p, laser, rng));
		const TPose2D truth = lrgc::between(poses[0], p);
		c.guesses.emplace_back(truth.x + 0.05 * N(rng), truth.y + 0.05 * N(rng),
							   truth.phi + 0.035 * N(rng));
	}
	return c;
}

void BM_match(benchmark::State& state)
{
	const auto c = makeCase(static_cast<int>(state.range(0)), static_cast<int>(state.range(1)));
	const lrgc::CScanMatcher matcher;
	size_t i = 0, ok = 0, n = 0;
	double iterations = 0;
	for (auto _ : state)
	{
		const size_t k = i++ % c.refs.size();
		const auto m = matcher.match(c.refs[k], c.scans[k], c.guesses[k]);
		benchmark::DoNotOptimize(m);
		++n;
		if (m) ++ok, iterations += m->iterations;
	}
	state.counters["matched"] = static_cast<double>(ok) / n;
	state.counters["iterations"] = ok ? iterations / ok : 0;
	state.counters["refAnchors"] = static_cast<double>(c.refs[0].size());
}

void BM_buildReference(benchmark::State& state)
{
	const auto c = makeCase(static_cast<int>(state.range(0)), static_cast<int>(state.range(1)));
	const lrgc::TScanMatcherParams params;
	size_t i = 0;
	for (auto _ : state)
	{
		const size_t k = i++ % c.refs.size();
		auto ref = lrgc::CReferenceCloud::fromScans(c.refScans[k], c.refPoses[k], params);
		benchmark::DoNotOptimize(ref);
	}
}

void BM_matchWide(benchmark::State& state)
{
	const auto c = makeCase(static_cast<int>(state.range(0)), 1);
	const lrgc::CScanMatcher matcher;
	size_t i = 0;
	for (auto _ : state)
	{
		const size_t k = i++ % c.refs.size();
		TPose2D g = c.guesses[k];
		g.phi += 70 * M_PI / 180;
		benchmark::DoNotOptimize(matcher.matchWide(c.refs[k], c.scans[k], g, 90 * M_PI / 180));
	}
}
}  // namespace

// Args: beams, scans in the reference patch.
BENCHMARK(BM_match)->Args({180, 1})->Args({361, 1})->Args({180, 10})->Args({361, 10})->Unit(
	benchmark::kMicrosecond);
BENCHMARK(BM_buildReference)
	->Args({180, 1})
	->Args({361, 1})
	->Args({180, 10})
	->Args({361, 10})
	->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_matchWide)->Args({180})->Args({361})->Unit(benchmark::kMillisecond);
BENCHMARK_MAIN();
