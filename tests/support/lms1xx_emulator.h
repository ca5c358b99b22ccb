/* A SICK LMS1xx on the loopback interface, for testing live mapping without hardware.
 *
 * It speaks the part of SICK's CoLa-A protocol (ASCII telegrams framed by STX 0x02 ... ETX
 * 0x03, fields separated by single spaces, numbers in hexadecimal) that
 * mrpt::hwdrivers::CLMS100Eth uses: log-in (sMN SetAccessMode), scan configuration (sMN
 * mLMPsetscancfg, sWN LMDscandatacfg), start of measurement (sMN LMCstartmeas), device status
 * (sRN STlms, answered "ready", 7) and polled scans (sRN LMDscandata), each scan an "sRA
 * LMDscandata" telegram with one 16-bit DIST1 channel in millimetres (0: no echo). The emulator
 * answers only on 127.0.0.1, serves a fixed list of scans in order, one per request, and stops
 * by itself: after the last scan it closes the connection and the listening socket, and in any
 * case after its lifetime. To test failures it can drop the first connection after N scans,
 * answering a few requests with garbage first; it then accepts the driver's reconnection and
 * goes on with the next scan.
 *
 * Geometry. CLMS100Eth reads a telegram as 270 deg (its constant 4.712385 rad) from first to
 * last beam, clockwise (rightToLeft = false): beam j of n at +135 deg - j * 270/(n-1) deg. The
 * emulator sends 541 beams (0.5 deg), so that the driver's reading of the telegram reproduces
 * the scans given (e.g. SENA's 361 beams over 180 deg fall on beams 90..450).
 */
#pragma once

#include <mrpt/poses/CPose3D.h>

#include <atomic>
#include <cstdint>
#include <functional>
#include <string>
#include <thread>
#include <vector>

namespace lrgc::test
{
constexpr size_t kLms1xxBeams = 541;

/** One scan as the LMS1xx sends it: kLms1xxBeams distances [mm], 0 for no echo. */
struct TLms1xxScan
{
	std::vector<uint32_t> distancesMm;
};

/** Scans of a rawlog re-sampled to the LMS1xx beams, and the sensor pose of the first one. */
struct TLms1xxRecording
{
	std::vector<TLms1xxScan> scans;
	mrpt::poses::CPose3D sensorPose;
};

/** Direction [rad] of beam j as CLMS100Eth reads it. */
double lms1xxBeamAngle(size_t j);

/** Every 2D scan of `rawlogPath` (both layouts), at most `maxScans`: each LMS1xx beam takes the
 * source beam in its direction (within half a source step); no return when there is none, the
 * source ray is invalid, or the range is at or beyond the LMS1xx's 20 m. Throws on a bad file.
 */
TLms1xxRecording lms1xxScansFromRawlog(const std::string& rawlogPath,
									   size_t maxScans = SIZE_MAX);

/** The "sRA LMDscandata" telegram of `scan` (STX and ETX included). */
std::string lms1xxScanTelegram(const TLms1xxScan& scan, uint32_t counter);

struct TLms1xxEmulatorOptions
{
	size_t dropAfterScans = 0;     //!< > 0: drop the first connection after this many scans
	size_t garbageBeforeDrop = 0;  //!< requests answered with garbage just before that drop
	double lifetimeSeconds = 300;  //!< the emulator stops by itself after this long
};

class CLms1xxEmulator
{
public:
	/** Listens on 127.0.0.1 at a free port at once; throws if it cannot. */
	explicit CLms1xxEmulator(std::vector<TLms1xxScan> scans,
							 TLms1xxEmulatorOptions options = {});
	~CLms1xxEmulator();
	CLms1xxEmulator(const CLms1xxEmulator&) = delete;
	CLms1xxEmulator& operator=(const CLms1xxEmulator&) = delete;

	uint16_t port() const { return m_port; }
	size_t scansServed() const { return m_served; }
	size_t garbageServed() const { return m_garbage; }
	size_t connections() const { return m_connections; }
	/** All scans served (and the sockets closed), or the lifetime is over. */
	bool finished() const { return m_finished; }

private:
	void threadMain();
	/** Answers one telegram (without STX/ETX); false to close the connection. */
	bool answer(int client, const std::string& request);

	std::vector<TLms1xxScan> m_scans;
	TLms1xxEmulatorOptions m_options;
	int m_listener = -1;
	uint16_t m_port = 0;
	std::atomic<size_t> m_served{0}, m_garbage{0}, m_connections{0};
	size_t m_servedThisConnection = 0;
	std::atomic<bool> m_finished{false}, m_stop{false};
	std::thread m_thread;
};

/** Polls `done` every 20 ms until it holds or `timeoutSeconds` pass; returns done(). */
bool waitUntil(const std::function<bool()>& done, double timeoutSeconds);

}  // namespace lrgc::test
