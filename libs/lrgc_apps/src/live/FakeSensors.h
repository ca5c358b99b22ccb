/* Test-only mrpt::hwdrivers sensors for the live unit tests (compiled into
 * lrgc_live_unittests through FakeSensors_unittest.cpp, never into lrgc_live). They are
 * registered by class name like MRPT's drivers, so the live code creates them from an .ini
 * exactly as it creates CLMS100Eth. Their behaviour comes from a script shared by all instances
 * (a restart creates a new instance that goes on where the last one stopped). */
#pragma once

#include <mrpt/hwdrivers/CGenericSensor.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservationOdometry.h>

#include <atomic>
#include <mutex>
#include <vector>

namespace lrgc_test_fakes
{
struct TFakeScript
{
	std::vector<mrpt::obs::CObservation2DRangeScan::Ptr> scans;  //!< emitted in order
	std::vector<mrpt::obs::CObservationOdometry::Ptr> odometry;  //!< one before each scan
	size_t scansPerCall = 1;        //!< scans (each with its odometry) per doProcess(); <= 100
	int failStarts = 0;             //!< initialize() throws this many times in all
	size_t silentAfter = SIZE_MAX;  //!< from then on the instance sends 0-ray scans only
	size_t throwAfter = SIZE_MAX;   //!< doProcess() throws once at this scan count

	std::atomic<bool> block{false};  //!< doProcess() waits while this is true (a stuck driver)

	std::atomic<size_t> next{0};  //!< next scan to emit
	std::atomic<int> starts{0}, failedStarts{0}, throws{0};
	/** True once doProcess() ran again after the last scan was emitted: by then the live
	 * code has handed every scan over (it calls doProcess only after pushing the last batch).
	 */
	std::atomic<bool> allHandedOver{false};

	void reset();
};

/** The script of every CFakeLiveLaser (one per test process at a time). */
TFakeScript& laserScript();

/** A laser (with odometry if the script has it), scripted by laserScript(). */
class CFakeLiveLaser : public mrpt::hwdrivers::CGenericSensor
{
	DEFINE_GENERIC_SENSOR(CFakeLiveLaser)
public:
	void initialize() override;
	void doProcess() override;

protected:
	void loadConfig_sensorSpecific(const mrpt::config::CConfigFileBase& c,
								   const std::string& section) override;

private:
	bool m_silent = false;
	size_t m_emittedHere = 0;
};

/** A sensor that never starts (initialize() always throws). */
class CFakeDeadSensor : public mrpt::hwdrivers::CGenericSensor
{
	DEFINE_GENERIC_SENSOR(CFakeDeadSensor)
public:
	void initialize() override;
	void doProcess() override {}

protected:
	void loadConfig_sensorSpecific(const mrpt::config::CConfigFileBase&,
								   const std::string&) override
	{
	}
};

/** Registers the fakes (idempotent). */
void registerFakeSensors();

/** At most `n` scans (the path has about 230; 181 beams, 180 deg, 20 m) ray-cast along a path
 * through the synthetic room world, 10 Hz time stamps, with odometry; as a live laser would
 * deliver them. */
void makeRoomRun(size_t n, TFakeScript& script);

}  // namespace lrgc_test_fakes
