#include "RunConfigFile.h"

#include "AppConfig.h"

namespace lrgc::apps
{
std::string runConfigText(const TAppConfig& cfg, const std::string& input)
{
	// '#' comments: MRPT's CConfigFile and our loader skip them. The input path is written
	// as a comment only (a path may hold any character; the .ini does not take it).
	std::string inputLine = input;
	for (char& c : inputLine)
		if (c == '\n' || c == '\r') c = ' ';
	return "# The configuration lrgc-slam used for the run that wrote this folder: every\n"
		   "# section and key with the value used (the --config .ini over the defaults, "
		   "--laser\n"
		   "# as [MapBuilder] laser_label). Repeat the run with\n"
		   "#   lrgc-slam --input LOG --config config.ini --out OTHER_DIR\n"
		   "# Input of the run: " +
		   inputLine + "\n" + appConfigSections(cfg);
}

}  // namespace lrgc::apps
