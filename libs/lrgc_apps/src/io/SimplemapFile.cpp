#include "lrgc_apps/io/SimplemapFile.h"

#include "ErrorText.h"
#include "lrgc_apps/io/LogReader.h"
#include "io/RawlogObjects.h"

#include <mrpt/maps/registerAllClasses.h>
#include <mrpt/obs/registerAllClasses.h>
#include <mrpt/poses/registerAllClasses.h>
#include <mrpt/serialization/CArchive.h>

#include <stdexcept>

namespace lrgc::apps
{
mrpt::maps::CSimpleMap readSimplemapFile(const std::string& file, const std::string& option)
{
	mrpt::obs::registerAllClasses_mrpt_obs();
	mrpt::maps::registerAllClasses_mrpt_maps();
	mrpt::poses::registerAllClasses_mrpt_poses();  // the keyframes' pose PDFs
	const auto unreadable = [&](const std::string& why)
	{
		return std::runtime_error(option + " '" + file + "': not a readable MRPT CSimpleMap (" +
								  why + ")");
	};
	std::shared_ptr<mrpt::maps::CSimpleMap> map;
	try
	{
		CLogInputFile in(file);
		TArchive archive(in);
		CDeserializationGuard guard(file);
		TObjectRead r = guard.checkNextObject(0);
		if (r.result != TObjectRead::Result::Failed) r = readArchiveObject(in, archive);
		if (r.result == TObjectRead::Result::Failed)
			throw unreadable(r.problem + " at " + r.place);
		if (r.result == TObjectRead::Result::End) throw unreadable("the file holds no object");
		map = std::dynamic_pointer_cast<mrpt::maps::CSimpleMap>(r.object);
		if (!map)
			throw unreadable(std::string("it holds a ") +
							 r.object->GetRuntimeClass()->className);
	}
	catch (const CLogReadError& e)
	{
		throw unreadable(oneLineError(e));
	}
	if (map->empty())
		throw std::runtime_error(option + " '" + file + "': the map holds no keyframe");
	return std::move(*map);
}

}  // namespace lrgc::apps
