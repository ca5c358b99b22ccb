/* Localisation's outputs, streamed (see LocalizationOutputs.h). */
#include "LocalizationOutputs.h"

#include "AppConfig.h"
#include "ErrorText.h"
#include "lrgc_apps/SavedMap.h"
#include <lrgc/map_builder/CMetricMapBuilderLRGC.h>
#include "RunConfigFile.h"
#include "atomic_file.h"
#include "lrgc_apps/MapExport.h"
#include "lrgc_apps/RunStats.h"

#include <mrpt/core/bits_math.h>
#include <mrpt/core/exceptions.h>
#include <mrpt/core/format.h>

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <sstream>
#include <vector>

namespace lrgc::apps
{
namespace fs = std::filesystem;

double threadCpuMs()
{
	timespec t{};
	clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
	return 1e3 * double(t.tv_sec) + 1e-6 * double(t.tv_nsec);
}

namespace
{
// One line per event: what a navigation stack is told (lost, kidnapped, relocalised, ...).
std::string eventsJson(const std::vector<TLocalizationEvent>& events)
{
	std::string j = "[";
	for (size_t i = 0; i < events.size(); ++i)
	{
		const auto& e = events[i];
		j += mrpt::format(
			"%s\n    {\"event\": \"%s\", \"stamp\": %.6f, \"pose\": [%.4f, %.4f, %.2f], "
			"\"jump_m\": %.3f, \"search_half_window_m\": %.2f}",
			i ? "," : "", e.name(), e.stamp, e.pose.x, e.pose.y, mrpt::RAD2DEG(e.pose.phi),
			e.jump_m, e.window_m);
	}
	return j + (events.empty() ? "]" : "\n  ]");
}

std::string localizationStatsJson(const TLocalizerStats& s, const TRunSummary& run,
								  const TLatencySummary& lat, double cpuMaxMs,
								  const std::string& map)
{
	std::ostringstream j;
	j.precision(6);
	j << std::fixed << "{\n"
	  << "  \"mode\": \"localize\",\n"
	  << "  \"input\": " << jsonString(run.input) << ",\n"
	  << "  \"map\": " << jsonString(map) << ",\n"
	  << "  \"status\": " << jsonString(run.status) << ",\n"
	  << "  \"log_entries\": " << run.logEntries << ",\n"
	  << "  \"scans\": " << s.scans << ",\n"
	  << "  \"localized_scans\": " << s.localizedScans << ",\n"
	  << "  \"scans_before_start\": " << s.scansBeforeStart << ",\n"
	  << "  \"good_matches\": " << s.goodMatches << ",\n"
	  << "  \"poor_matches\": " << s.poorMatches << ",\n"
	  << "  \"placed_by_recent_scans\": " << s.recentMatches << ",\n"
	  << "  \"lost\": " << s.lostEvents << ",\n"
	  << "  \"kidnapped\": " << s.kidnapEvents << ",\n"
	  << "  \"relocalizations\": " << s.relocalizations << ",\n"
	  << "  \"recovered_by_tracking\": " << s.recoveredByTracking << ",\n"
	  << "  \"global_localization\": {\"attempts\": " << s.globalAttempts
	  << ", \"refused_by_scan_check\": " << s.globalRefusedByScan
	  << ", \"total_s\": " << s.globalSeconds << ", \"modelled_s\": " << s.globalModelledSeconds
	  << ", \"replay_wait_s\": " << s.replayWaitSeconds
	  << ", \"replay_wait_max_ms\": " << 1e3 * s.replayWaitMaxSeconds
	  << ", \"on_tracking_thread\": " << s.searchesOnTrackingThread
	  << ", \"scans_during_searches\": " << s.scansDuringSearches << "},\n"
	  << "  \"events\": " << eventsJson(s.events) << ",\n"
	  << "  \"warnings\": " << run.warnings << ",\n"
	  << "  \"data_duration_s\": " << run.dataDurationSeconds << ",\n"
	  << "  \"wall_time_s\": " << run.wallSeconds << ",\n"
	  << "  \"cpu_time_s\": " << run.cpuSeconds << ",\n"
	  << "  \"peak_rss_mb\": " << run.peakRssMiB << ",\n"
	  << "  \"latency_ms\": {\"median\": " << lat.median_ms << ", \"p99\": " << lat.p99_ms
	  << ", \"max\": " << lat.max_ms << ", \"mean\": " << lat.mean_ms
	  << ", \"cpu_max\": " << cpuMaxMs << "}\n"
	  << "}\n";
	return j.str();
}

// Every byte through write(2), each call checked (as atomic_file.cpp).
void writeAll(int fd, const char* data, size_t size, const std::string& path)
{
	while (size > 0)
	{
		const ssize_t n = ::write(fd, data, size);
		if (n < 0 && errno == EINTR) continue;
		if (n <= 0)
			THROW_EXCEPTION_FMT("cannot write '%s': %s", path.c_str(), std::strerror(errno));
		data += n, size -= static_cast<size_t>(n);
	}
}

// The first `bytes` of the stream, then `tail`, into `path` atomically, copied 64 kB at a time
// (a save of hours of poses must not hold them all in memory).
void publish(const std::string& stream, uint64_t bytes, const std::string& tail,
			 const std::string& path)
{
	writeFileAtomically(
		path,
		[&](const std::string& tmp)
		{
			const int in = ::open(stream.c_str(), O_RDONLY | O_CLOEXEC);
			if (in < 0)
				THROW_EXCEPTION_FMT("cannot read '%s': %s", stream.c_str(),
									std::strerror(errno));
			const int out = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
			if (out < 0)
			{
				::close(in);
				THROW_EXCEPTION_FMT("cannot create '%s': %s", tmp.c_str(),
									std::strerror(errno));
			}
			std::vector<char> chunk(1 << 16);
			uint64_t left = bytes;
			try
			{
				while (left > 0)
				{
					const ssize_t n =
						::read(in, chunk.data(), std::min<uint64_t>(left, chunk.size()));
					if (n < 0 && errno == EINTR) continue;
					if (n <= 0)
						THROW_EXCEPTION_FMT("'%s' ends %llu bytes short", stream.c_str(),
											static_cast<unsigned long long>(left));
					writeAll(out, chunk.data(), static_cast<size_t>(n), path);
					left -= static_cast<uint64_t>(n);
				}
				writeAll(out, tail.data(), tail.size(), path);
			}
			catch (...)
			{
				::close(in), ::close(out);
				throw;
			}
			::close(in);
			if (::close(out) != 0)
				THROW_EXCEPTION_FMT("cannot write '%s': %s", path.c_str(),
									std::strerror(errno));
		});
}
}  // namespace

void writeLocalizationSave(const TLocalizationSave& s)
{
	fs::create_directories(s.outDir);
	const auto path = [&](const char* name) { return (fs::path(s.outDir) / name).string(); };
	if (s.localized)
	{
		publish(s.trajectoryStream, s.trajectoryBytes, s.trajectoryTail,
				path("trajectory.tum"));
		publish(s.timingStream, s.timingBytes, {}, path("timing.csv"));
	}
	writeTextFileAtomically(path(kRunConfigFile), s.configIni);
	writeTextFileAtomically(path("stats.json"), s.statsJson);
}

std::string noStartMessage(const std::string& map, size_t scans, size_t attempts,
						   const std::string& lastRejection)
{
	return mrpt::format(
		"no start found in the map '%s': %zu scans read, %zu global correlation attempts "
		"rejected (last: %s); the log may begin outside the mapped area",
		map.c_str(), scans, attempts, lastRejection.empty() ? "none" : lastRejection.c_str());
}

std::unique_ptr<CLocalizer> localizerOnSavedMap(const TSavedMap& map, const TAppConfig& cfg)
{
	CMetricMapBuilderLRGC restored(cfg.lrgc);
	restored.logging_enable_console_output = false;
	initializeFromSavedMap(restored, map);
	auto localizer = std::make_unique<CLocalizer>(restored.graph(), restored.keyframes(),
												  cfg.lrgc, cfg.localization);
	localizer->logging_enable_console_output = false;
	return localizer;
}

std::string localizationEventLine(const TLocalizationEvent& e)
{
	std::string line =
		mrpt::format("lrgc-slam: t=%.3f %s at (%.2f m, %.2f m, %.1f deg)", e.stamp, e.name(),
					 e.pose.x, e.pose.y, mrpt::RAD2DEG(e.pose.phi));
	if (e.kind == TLocalizationEvent::Kind::Relocalized)
		line += mrpt::format(": the pose moved %.2f m", e.jump_m);
	return line;
}

CLocalizationRecorder::CLocalizationRecorder(const std::string& outDir) : m_outDir(outDir)
{
	fs::create_directories(outDir);
	for (auto* s : {&m_trajectory, &m_timing})
	{
		s->path = (fs::path(outDir) /
				   (s == &m_trajectory ? ".trajectory.tum.stream" : ".timing.csv.stream"))
					  .string();
		s->file = std::fopen(s->path.c_str(), "wb");
		if (!s->file)
			THROW_EXCEPTION_FMT("cannot create '%s': %s", s->path.c_str(),
								std::strerror(errno));
	}
	append(m_timing, "scan_index,timestamp,latency_ms,replay_wait_ms,cpu_ms\n");
}

CLocalizationRecorder::~CLocalizationRecorder()
{
	for (auto* s : {&m_trajectory, &m_timing})
	{
		std::fclose(s->file);
		std::error_code ec;
		fs::remove(s->path, ec);
	}
}

void CLocalizationRecorder::append(TStream& s, const std::string& text)
{
	if (std::fwrite(text.data(), 1, text.size(), s.file) != text.size())
		THROW_EXCEPTION_FMT("cannot write '%s': %s", s.path.c_str(), std::strerror(errno));
	s.bytes += text.size();
}

void CLocalizationRecorder::flush(TStream& s)
{
	if (std::fflush(s.file) != 0)
		THROW_EXCEPTION_FMT("cannot write '%s': %s", s.path.c_str(), std::strerror(errno));
}

void CLocalizationRecorder::addScan(const TScanTiming& t, CLocalizer& localizer)
{
	m_firstStamp = m_latency.count() == 0 ? t.stamp : std::min(m_firstStamp, t.stamp);
	m_lastStamp = m_latency.count() == 0 ? t.stamp : std::max(m_lastStamp, t.stamp);
	append(m_timing, mrpt::format("%zu,%.6f,%.4f,%.4f,%.4f\n", m_latency.count(), t.stamp,
								  t.latencyMs, t.replayWaitMs, t.cpuMs));
	m_latency.add(t.latencyMs);
	m_cpuMaxMs = std::max(m_cpuMaxMs, t.cpuMs);
	if (const TTrajectory settled = localizer.takeSettledPoses(); !settled.empty())
		append(m_trajectory, trajectoryTumText(settled));
}

TLocalizationSave CLocalizationRecorder::snapshot(const CLocalizer& localizer, TRunSummary run,
												  const std::string& map)
{
	flush(m_trajectory);
	flush(m_timing);
	run.dataDurationSeconds = m_lastStamp - m_firstStamp;
	TLocalizationSave s;
	s.outDir = m_outDir;
	s.configIni = run.configIni;
	s.statsJson =
		localizationStatsJson(localizer.stats(), run, m_latency.summary(), m_cpuMaxMs, map);
	s.localized = localizer.stats().localizedScans > 0;
	s.trajectoryStream = m_trajectory.path;
	s.timingStream = m_timing.path;
	s.trajectoryBytes = m_trajectory.bytes;
	s.timingBytes = m_timing.bytes;
	s.trajectoryTail = trajectoryTumText(localizer.trajectory());
	return s;
}

}  // namespace lrgc::apps
