#include "test_data.h"

#include <cstdlib>
#include <filesystem>

namespace fs = std::filesystem;

namespace lrgc::test
{
std::string senaRawlogPath()
{
	return "/usr/share/mrpt/datasets/2006-01ENE-21-SENA_Telecom Faculty_one_loop_only.rawlog";
}

std::string sharedDatasetPath(const std::string& relative)
{
	if (const char* env = std::getenv("LRGC_SHARED_DATASETS"); env && *env)
		return (fs::path(env) / relative).string();
	return (fs::path(LRGC_SOURCE_DIR).parent_path() / "shared" / "datasets" / relative)
		.string();
}

std::string makeTempDir(const std::string& name)
{
	const fs::path dir = fs::path(LRGC_BINARY_DIR) / "test-output" / name;
	fs::remove_all(dir);
	fs::create_directories(dir);
	return dir.string();
}

bool fileExists(const std::string& path)
{
	return fs::exists(path);
}

}  // namespace lrgc::test
