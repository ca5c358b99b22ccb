/* Maps an MRPT rawlog with lrgc::CMetricMapBuilderLRGC from the installed package, as the
 * README's "As a library" section shows, with the installed default .ini.
 *   map_rawlog FILE.rawlog  ->  prints "keyframes K scans S occupied_cells C", exit 0 if a
 *   map was built (K > 1, a grid with occupied cells), 1 otherwise. */
#include <lrgc/map_builder/CMetricMapBuilderLRGC.h>
#include <mrpt/config/CConfigFile.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/maps/CSimpleMap.h>
#include <mrpt/obs/CRawlog.h>
#include <mrpt/serialization/CArchive.h>

#include <cstdio>

int main(int argc, char** argv)
{
	if (argc != 2)
	{
		std::fprintf(stderr, "usage: map_rawlog FILE.rawlog\n");
		return 2;
	}
	lrgc::TLRGCParams params;
	params.loadFromConfigFile(mrpt::config::CConfigFile(LRGC_DATA_DIR "/lrgc-default.ini"), {});
	lrgc::CMetricMapBuilderLRGC mapper(params);
	mapper.initialize();

	mrpt::io::CFileGZInputStream file(argv[1]);
	auto archive = mrpt::serialization::archiveFrom(file);
	mrpt::obs::CActionCollection::Ptr actions;
	mrpt::obs::CSensoryFrame::Ptr frame;
	mrpt::obs::CObservation::Ptr observation;
	size_t index = 0;
	while (mrpt::obs::CRawlog::getActionObservationPairOrObservation(archive, actions, frame,
																	 observation, index))
	{
		if (actions && frame)
			mapper.processActionObservation(*actions, *frame);
		else if (observation)
			mapper.processObservation(observation);
	}
	mapper.finish();

	mrpt::maps::CSimpleMap keyframes;
	mapper.getCurrentlyBuiltMap(keyframes);
	const auto grid = mapper.buildOccupancyGrid();
	size_t occupied = 0;
	for (unsigned y = 0; y < grid->getSizeY(); ++y)
		for (unsigned x = 0; x < grid->getSizeX(); ++x) occupied += grid->getCell(x, y) < 0.3f;
	std::printf("keyframes %zu scans %zu occupied_cells %zu\n", keyframes.size(),
				mapper.stats().scans, occupied);
	return keyframes.size() > 1 && occupied > 100 ? 0 : 1;
}
