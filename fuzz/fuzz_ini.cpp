/* Fuzz target: the .ini loader of lrgc-slam (loadAppConfig: every stage's section of
 * TLRGCParams, [LogReader], [LiveMapping]) on the input as a config file.
 *
 * Invariants: a bad file is reported as CSetupError (exit 2 in the app), nothing else is
 * thrown; a file that loads saves to a text that loads again and saves to the same text (the
 * parameter structs' load and save agree, and a saved value passes validation on load). */
#include "AppConfig.h"
#include "CommandLine.h"
#include <mrpt/config/CConfigFileMemory.h>

#include "fuzz_common.h"

using namespace lrgc::apps;

namespace
{
std::string savedText(const TAppConfig& cfg)
{
	mrpt::config::CConfigFileMemory mem;
	cfg.lrgc.saveToConfigFile(mem, {});
	cfg.reader.saveToConfigFile(mem, "LogReader");
	cfg.live.saveToConfigFile(mem, "LiveMapping");
	return mem.getContent();
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
	const std::string& path = lrgc::fuzz::writeScratch("config.ini", data, size);
	TAppConfig cfg;
	try
	{
		cfg = loadAppConfig(path);
	}
	catch (const CSetupError&)
	{
		return 0;
	}
	const std::string once = savedText(cfg);
	const std::string& again = lrgc::fuzz::writeScratch(
		"saved.ini", reinterpret_cast<const uint8_t*>(once.data()), once.size());
	TAppConfig reloaded;
	try
	{
		reloaded = loadAppConfig(again);
	}
	catch (const CSetupError& e)
	{
		std::fprintf(stderr, "saved config does not load: %s\n--- saved:\n%s\n", e.what(),
					 once.c_str());
		LRGC_FUZZ_CHECK(false, "a saved config loads again");
	}
	LRGC_FUZZ_CHECK(savedText(reloaded) == once, "save(load(save(x))) == save(x)");
	return 0;
}
