// Test-only fake sensors (see FakeSensors.h); no tests in this file.
#include "FakeSensors.h"

#include <mrpt/core/exceptions.h>
#include <mrpt/system/datetime.h>

#include <cmath>
#include <mutex>
#include <thread>

#include "synthetic_world.h"

namespace lrgc_test_fakes
{
IMPLEMENTS_GENERIC_SENSOR(CFakeLiveLaser, lrgc_test_fakes)
IMPLEMENTS_GENERIC_SENSOR(CFakeDeadSensor, lrgc_test_fakes)

void TFakeScript::reset()
{
	scans.clear();
	odometry.clear();
	scansPerCall = 1;
	failStarts = 0;
	silentAfter = throwAfter = SIZE_MAX;
	block = false;
	next = 0;
	starts = failedStarts = throws = 0;
	allHandedOver = false;
}

TFakeScript& laserScript()
{
	static TFakeScript script;
	return script;
}

void registerFakeSensors()
{
	static std::once_flag once;
	std::call_once(once,
				   []
				   {
					   CFakeLiveLaser::doRegister();
					   CFakeDeadSensor::doRegister();
				   });
}

void CFakeLiveLaser::loadConfig_sensorSpecific(const mrpt::config::CConfigFileBase&,
											   const std::string&)
{
}

void CFakeLiveLaser::initialize()
{
	TFakeScript& s = laserScript();
	if (s.failedStarts < s.failStarts)
	{
		++s.failedStarts;
		THROW_EXCEPTION("fake laser: no device on the port");
	}
	++s.starts;
	m_state = ssWorking;
}

void CFakeLiveLaser::doProcess()
{
	TFakeScript& s = laserScript();
	while (s.block) std::this_thread::sleep_for(std::chrono::milliseconds(5));
	if (s.next >= s.scans.size())
	{
		s.allHandedOver = true;
		return;
	}
	if (s.next == s.throwAfter && s.throws == 0)
	{
		++s.throws;
		THROW_EXCEPTION("fake laser: checksum error");
	}
	if (m_silent || m_emittedHere >= s.silentAfter)
	{
		m_silent = true;
		auto empty = mrpt::obs::CObservation2DRangeScan::Create();
		empty->timestamp = mrpt::Clock::now();
		appendObservation(empty);
		return;
	}
	for (size_t k = 0; k < s.scansPerCall && s.next < s.scans.size(); ++k)
	{
		const size_t i = s.next++;
		if (i < s.odometry.size()) appendObservation(s.odometry[i]);
		appendObservation(s.scans[i]);
		++m_emittedHere;
	}
}

void CFakeDeadSensor::initialize()
{
	THROW_EXCEPTION("fake dead sensor: cable cut");
}

void makeRoomRun(size_t n, TFakeScript& script)
{
	using namespace lrgc::test;
	const CSyntheticWorld world = makeRoomWorld(3);
	const TTrajectory path =
		makeTrajectory({{1.5, 1.5}, {8.5, 1.5}, {8.5, 5.5}, {1.5, 5.5}, {1.5, 2.0}}, 0.1,
					   TOdometryNoise{}, 11);
	const auto t0 = mrpt::Clock::fromDouble(1.7e9);
	for (size_t k = 0; k < n && k < path.truePoses.size(); ++k)
	{
		const auto& p = path.truePoses[k];
		const auto stamp = t0 + std::chrono::milliseconds(100 * k);
		auto scan = mrpt::obs::CObservation2DRangeScan::Create();
		scan->sensorLabel = "FAKE_LASER";
		scan->timestamp = stamp;
		scan->aperture = static_cast<float>(M_PI);
		scan->maxRange = 20.0f;
		scan->resizeScan(181);
		for (size_t b = 0; b < 181; ++b)
		{
			const auto r = world.castRay({p.x, p.y}, p.phi + scan->getScanAngle(b), 20.0);
			scan->setScanRange(b, r ? static_cast<float>(*r) : 20.0f);
			scan->setScanRangeValidity(b, r.has_value());
		}
		auto odo = mrpt::obs::CObservationOdometry::Create();
		odo->sensorLabel = "FAKE_ODOMETRY";
		odo->timestamp = stamp;
		odo->odometry = mrpt::poses::CPose2D(path.odometryPoses[k]);
		script.scans.push_back(scan);
		script.odometry.push_back(odo);
	}
}

}  // namespace lrgc_test_fakes
