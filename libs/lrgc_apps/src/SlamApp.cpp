#include "SlamApp.h"

#include "AppConfig.h"
#include "ErrorText.h"
#include "IcpSlamIni.h"
#include "lrgc_apps/RunOutputs.h"
#include "OutputsVsInputs.h"
#include "atomic_file.h"

#include <mrpt/core/format.h>

#include <algorithm>
#include <filesystem>

namespace lrgc::apps
{
namespace
{
// --write-default-config FILE: a file, never a folder, and an existing one only with --force.
void writeDefaultConfig(const std::string& path, bool force, bool expert)
{
	namespace fs = std::filesystem;
	std::error_code ec;
	const std::string option = "--write-default-config '" + path + "'";
	if (fs::is_directory(path, ec))
		throw CSetupError(option + " is a directory; name a file, e.g. '" +
						  (fs::path(path) / "lrgc.ini").string() + "'");
	if (fs::exists(path, ec) && !force)
		throw CSetupError(option +
						  ": the file exists; add --force to replace it, or name "
						  "another file");
	const fs::path folder = fs::path(path).parent_path();
	if (!folder.empty() && !fs::is_directory(folder, ec))
		throw CSetupError(option + ": '" + folder.string() +
						  "' is not a directory; create it first, or name another file");
	try
	{
		writeTextFileAtomically(path, expert ? expertAppConfigText() : defaultAppConfigText());
	}
	catch (const std::exception& e)
	{
		throw CSetupError(
			option + ": " + oneLineError(e) + "; name a file in a folder you may write into",
			errorDetails(e));
	}
}

}  // namespace

void CSlamApp::report(const std::string& line)
{
	std::fprintf(m_err, "%s\n", line.c_str());
	std::fflush(m_err);
}

void CSlamApp::reportError(const std::string& line, const std::string& details)
{
	report("lrgc-slam: " + line);
	if (m_verbose && !details.empty()) report("details:\n" + details);
}

void CSlamApp::reportError(const std::exception& e)
{
	reportError(oneLineError(e), errorDetails(e));
}

int CSlamApp::run(const std::vector<std::string>& args)
{
	// Known before the command line is parsed, so that its errors can be detailed too.
	m_verbose = std::any_of(args.begin(), args.end(),
							[](const std::string& a) { return a == "--verbose" || a == "-v"; });
	TSlamCommandLine cl;
	try
	{
		cl = parseSlamCommandLine(args);
		if (cl.help)
		{
			std::fputs(slamUsage().c_str(), stdout);
			return kExitOk;
		}
		if (cl.version)
		{
			std::printf("lrgc-slam %s\n", LRGC_VERSION);
			return kExitOk;
		}
		if (!cl.writeDefaultConfig.empty())
		{
			writeDefaultConfig(cl.writeDefaultConfig, cl.force, cl.expert);
			return kExitOk;
		}
		if (!cl.icpSlamIni.empty()) takeIcpSlamIni(cl);
		if (!cl.outDir.empty()) checkOutputDirectory(cl.outDir);
		if (!cl.saveRawlog.empty()) checkOutputFile("--save-rawlog", cl.saveRawlog);
		if (const std::string clash = slamOutputOverInput(cl); !clash.empty())
			throw CSetupError(clash);
		if (!cl.live.empty())
		{
			if (!m_live)
				throw CUsageError(
					"--live: this program was built without live sensor support (link "
					"lrgc_live and pass lrgc::apps::runLiveSlam to CSlamApp)");
			return m_live(cl, m_err);
		}
		if (!cl.saveRawlog.empty())
			if (const int rc = convertOnly(cl); rc != kExitOk || cl.outDir.empty()) return rc;
		if (!cl.localize.empty()) return runLocalize(cl);
		if (!cl.mergeA.empty()) return runMerge(cl);
		return runOffline(cl);
	}
	catch (const CSetupError& e)
	{
		reportError(e.what(), e.details());
		return kExitUsage;
	}
	catch (const CUsageError& e)
	{
		reportError(e.what());
		return kExitUsage;
	}
	catch (const std::exception& e)
	{
		reportError(e);
		return kExitInputError;
	}
}

void CSlamApp::takeIcpSlamIni(TSlamCommandLine& cl)
{
	if (!isIcpSlamIni(cl.icpSlamIni))
		throw CUsageError(
			"unknown argument '" + cl.icpSlamIni +
			"': not an option, nor an icp-slam .ini (a file with a "
			"[MappingApplication] section); to map a log: lrgc-slam --input FILE --out "
			"DIR (lrgc-slam --help lists the options)");
	const TIcpSlamRun icp = readIcpSlamIni(cl.icpSlamIni, cl.icpSlamRawlog);
	cl.input = icp.rawlog;
	cl.outDir = icp.outDir;
	m_skipObjects = icp.rawlogOffset;
	m_icpSlam = true;
	if (const std::string line = ignoredIcpSlamSettings(cl.icpSlamIni, icp); !line.empty())
		report("lrgc-slam: " + line);
}

int CSlamApp::convertOnly(const TSlamCommandLine& cl)
{
	const TAppConfig cfg = loadAppConfig(cl.config);
	for (const auto& w : cfg.warnings) report("warning: " + w);  // old key names, all shown
	try
	{
		const TConversionStats st = convertToRawlog(cl.input, cl.saveRawlog, cfg.reader);
		if (!cl.quiet)
			report(mrpt::format(
				"converted '%s' -> '%s': %zu scans, %zu odometry readings, %zu warnings",
				cl.input.c_str(), cl.saveRawlog.c_str(), st.scans, st.odometry, st.warnings));
		return kExitOk;
	}
	catch (const std::exception& e)
	{
		reportError("cannot convert: " + oneLineError(e), errorDetails(e));
		return kExitInputError;
	}
}

}  // namespace lrgc::apps
