#include "lms1xx_emulator.h"

#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CRawlog.h>
#include <mrpt/obs/registerAllClasses.h>
#include <mrpt/serialization/CArchive.h>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>
#include <sstream>
#include <stdexcept>

namespace lrgc::test
{
namespace
{
constexpr char STX = 0x02, ETX = 0x03;
constexpr double kDriverAperture = 4.712385;  // [rad] CLMS100Eth's constant (270 deg)
constexpr double kLms1xxMaxRange = 20.0;      // [m] CLMS100Eth's maxRange

void appendScan(const mrpt::obs::CObservation2DRangeScan& src, TLms1xxRecording& out)
{
	if (out.scans.empty()) out.sensorPose = src.sensorPose;
	TLms1xxScan scan;
	scan.distancesMm.assign(kLms1xxBeams, 0);
	const size_t n = src.getScanSize();
	if (n >= 2)
	{
		const double a0 = src.getScanAngle(0), step = src.getScanAngle(1) - a0;
		for (size_t j = 0; j < kLms1xxBeams; ++j)
		{
			const double k = (lms1xxBeamAngle(j) - a0) / step;
			const long i = std::lround(k);
			if (i < 0 || i >= static_cast<long>(n) || std::abs(k - i) > 0.5) continue;
			const double r = src.getScanRange(i);
			if (!src.getScanRangeValidity(i) || !std::isfinite(r) || r <= 0 ||
				r >= kLms1xxMaxRange)
				continue;
			scan.distancesMm[j] = static_cast<uint32_t>(std::lround(1000 * r));
		}
	}
	out.scans.push_back(std::move(scan));
}

void sendAll(int fd, const std::string& data)
{
	size_t done = 0;
	while (done < data.size())
	{
		const ssize_t n = ::send(fd, data.data() + done, data.size() - done, MSG_NOSIGNAL);
		if (n <= 0) return;  // the peer went away: its problem, not the emulator's
		done += static_cast<size_t>(n);
	}
}

std::string framed(const std::string& body)
{
	return std::string(1, STX) + body + ETX;
}

std::string garbageTelegram(std::mt19937& rng)
{
	// Printable noise with spaces, starting with a token that is no CoLa-A command.
	static const char alphabet[] = "0123456789ABCDEF sRAxyz#";
	std::uniform_int_distribution<size_t> pick(0, sizeof(alphabet) - 2);
	std::string body = "#";
	for (int i = 0; i < 400; ++i) body += alphabet[pick(rng)];
	return framed(body);
}
}  // namespace

double lms1xxBeamAngle(size_t j)
{
	return 0.5 * kDriverAperture - j * kDriverAperture / (kLms1xxBeams - 1);
}

TLms1xxRecording lms1xxScansFromRawlog(const std::string& rawlogPath, size_t maxScans)
{
	mrpt::obs::registerAllClasses_mrpt_obs();
	mrpt::io::CFileGZInputStream in;
	if (!in.open(rawlogPath)) throw std::runtime_error("cannot open " + rawlogPath);
	auto arch = mrpt::serialization::archiveFrom(in);
	TLms1xxRecording rec;
	mrpt::obs::CActionCollection::Ptr actions;
	mrpt::obs::CSensoryFrame::Ptr frame;
	mrpt::obs::CObservation::Ptr obs;
	size_t entry = 0;
	while (rec.scans.size() < maxScans &&
		   mrpt::obs::CRawlog::getActionObservationPairOrObservation(arch, actions, frame, obs,
																	 entry))
	{
		if (frame)
		{
			for (const auto& o : *frame)
				if (auto s = std::dynamic_pointer_cast<mrpt::obs::CObservation2DRangeScan>(o))
					if (rec.scans.size() < maxScans) appendScan(*s, rec);
		}
		else if (auto s = std::dynamic_pointer_cast<mrpt::obs::CObservation2DRangeScan>(obs))
			appendScan(*s, rec);
	}
	return rec;
}

std::string lms1xxScanTelegram(const TLms1xxScan& scan, uint32_t counter)
{
	// Fields 1..26 as the LMS1xx telegram listing orders them; CLMS100Eth checks field 1
	// (sRA), 2 (LMDscandata), 6 (status), 21 (DIST1) and reads the count from field 26.
	std::ostringstream t;
	t << std::uppercase << std::hex;
	t << "sRA LMDscandata 1 1 89A27F 0 0 " << counter << ' ' << counter << ' '
	  << 0x1000 + 40 * counter << ' ' << 0x1010 + 40 * counter
	  << " 0 0 0 0 0 9C4 168 0 1 DIST1 3F800000 00000000 FFF92230 1388 "
	  << scan.distancesMm.size();
	for (const uint32_t d : scan.distancesMm) t << ' ' << d;
	t << " 0 0 0 0 0 0";  // no 8-bit channel, position, name, comment, time, event
	return framed(t.str());
}

CLms1xxEmulator::CLms1xxEmulator(std::vector<TLms1xxScan> scans, TLms1xxEmulatorOptions options)
	: m_scans(std::move(scans)), m_options(options)
{
	m_listener = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
	if (m_listener < 0) throw std::runtime_error("emulator: socket() failed");
	const int one = 1;
	::setsockopt(m_listener, SOL_SOCKET, SO_REUSEADDR, &one, sizeof(one));
	sockaddr_in addr{};
	addr.sin_family = AF_INET;
	addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
	addr.sin_port = 0;  // a free port
	socklen_t len = sizeof(addr);
	if (::bind(m_listener, reinterpret_cast<sockaddr*>(&addr), sizeof(addr)) != 0 ||
		::listen(m_listener, 2) != 0 ||
		::getsockname(m_listener, reinterpret_cast<sockaddr*>(&addr), &len) != 0)
	{
		::close(m_listener);
		throw std::runtime_error("emulator: cannot listen on 127.0.0.1");
	}
	m_port = ntohs(addr.sin_port);
	m_thread = std::thread([this] { threadMain(); });
}

CLms1xxEmulator::~CLms1xxEmulator()
{
	m_stop = true;
	if (m_thread.joinable()) m_thread.join();
	if (m_listener >= 0) ::close(m_listener);
}

bool CLms1xxEmulator::answer(int client, const std::string& request)
{
	static std::mt19937 rng(12345);
	std::istringstream in(request);
	std::string kind, name;
	in >> kind >> name;
	if (name == "SetAccessMode")
		sendAll(client, framed("sAN SetAccessMode 1"));
	else if (name == "mLMPsetscancfg")
		sendAll(client, framed("sAN mLMPsetscancfg 0 1388 1 1388 FFF92230 225510"));
	else if (name == "LMDscandatacfg")
		sendAll(client, framed("sWA LMDscandatacfg"));
	else if (name == "LMCstartmeas")
		sendAll(client, framed("sAN LMCstartmeas 0"));
	else if (name == "LMCstopmeas")
		sendAll(client, framed("sAN LMCstopmeas 0"));
	else if (name == "STlms")  // status 7: ready, measuring
		sendAll(client, framed("sRA STlms 7 0 8 00:00:00 8 01.01.2000 0 0 0"));
	else if (name == "LMDscandata")
	{
		const bool firstConnection = m_connections == 1;
		if (m_options.dropAfterScans > 0 && firstConnection &&
			m_servedThisConnection >= m_options.dropAfterScans)
		{
			if (m_garbage >= m_options.garbageBeforeDrop) return false;  // drop
			sendAll(client, garbageTelegram(rng));
			++m_garbage;
			return true;
		}
		if (m_served >= m_scans.size()) return false;
		sendAll(client, lms1xxScanTelegram(m_scans[m_served], static_cast<uint32_t>(m_served)));
		++m_served;
		++m_servedThisConnection;
		if (m_served == m_scans.size())
		{
			m_finished = true;  // all served: close everything
			return false;
		}
	}
	else
		sendAll(client, framed("sFA 1"));
	return true;
}

void CLms1xxEmulator::threadMain()
{
	const auto deadline = std::chrono::steady_clock::now() +
						  std::chrono::duration_cast<std::chrono::steady_clock::duration>(
							  std::chrono::duration<double>(m_options.lifetimeSeconds));
	int client = -1;
	std::string inbox;
	while (!m_stop && !m_finished && std::chrono::steady_clock::now() < deadline)
	{
		pollfd fd{client >= 0 ? client : m_listener, POLLIN, 0};
		if (::poll(&fd, 1, 50) <= 0) continue;
		if (client < 0)
		{
			client = ::accept4(m_listener, nullptr, nullptr, SOCK_CLOEXEC);
			if (client >= 0)
			{
				++m_connections;
				m_servedThisConnection = 0;
				inbox.clear();
			}
			continue;
		}
		char buf[4096];
		const ssize_t n = ::recv(client, buf, sizeof(buf), 0);
		bool keep = n > 0;
		if (keep) inbox.append(buf, static_cast<size_t>(n));
		for (size_t stx; keep && (stx = inbox.find(STX)) != std::string::npos;)
		{
			const size_t etx = inbox.find(ETX, stx);
			if (etx == std::string::npos) break;
			const std::string request = inbox.substr(stx + 1, etx - stx - 1);
			inbox.erase(0, etx + 1);
			keep = answer(client, request);
		}
		if (!keep)
		{
			::close(client);
			client = -1;
		}
	}
	if (client >= 0) ::close(client);
	::close(m_listener);
	m_listener = -1;
	m_finished = true;
}

bool waitUntil(const std::function<bool()>& done, double timeoutSeconds)
{
	const auto end = std::chrono::steady_clock::now() +
					 std::chrono::duration_cast<std::chrono::steady_clock::duration>(
						 std::chrono::duration<double>(timeoutSeconds));
	while (!done())
	{
		if (std::chrono::steady_clock::now() >= end) return done();
		std::this_thread::sleep_for(std::chrono::milliseconds(20));
	}
	return true;
}

}  // namespace lrgc::test
