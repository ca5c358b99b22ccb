/* Reading the objects of an MRPT archive one at a time, safely.
 *
 * readArchiveObject() tells a clean end (no byte of a next object) from an object cut short
 * by the end of the data (truncation) and from an object MRPT cannot decode (corruption),
 * which CRawlog::getActionObservationPairOrObservation() lumps together as "false".
 *
 * CDeserializationGuard. MRPT's deserializers trust the sizes and enums they read: one
 * corrupted byte of a rawlog can make CActionRobotMovement2D draw hundreds of millions of
 * particles or dereference garbage (found by corrupting single bytes of the SENA rawlog: a
 * segfault inside CActionRobotMovement2D::serializeFrom). No C++ exception reaches us then,
 * so "never a crash" needs a disposable process to meet each object first. The guard forks a
 * child when the reader opens the file; the child reads the same file with the same code,
 * under a memory limit (its address space at fork + 2 GiB) and with the highest OOM-killer
 * score, and reports through a pipe each object it got through (running ahead of the reader
 * by up to a pipe's worth of objects). The reader asks before deserializing an object: if
 * the child died on it or failed on it, the reader throws CLogReadError naming the object's
 * byte without touching it. Cost: a second deserialization, on the other core. If fork()
 * fails, or the child sends no report for 30 s (stuck, e.g. on a lock another thread held
 * at fork time), the reader goes on unguarded and warns. The child ignores SIGINT and SIGTERM
 * (a Ctrl-C reaches the whole process group: the reader, not the child, decides to stop, and
 * kills it), dies of SIGPIPE at its next report once the reader is gone, restores the
 * default action of the fatal signals (so it dies of MRPT's fault itself, whatever handlers the
 * host installed) and writes only to the pipe. In a sanitizer build (fuzz/), where RLIMIT_AS
 * cannot bound the heap, it counts its allocations instead (against 64 MiB: the fuzzers' inputs
 * are small).
 */
#pragma once

#include "io/LogInputFile.h"
#include <mrpt/serialization/CArchive.h>

#include <cstdint>
#include <string>

namespace lrgc::apps
{
using TArchive = mrpt::serialization::CArchiveStreamBase<CLogInputFile>;

struct TObjectRead
{
	enum class Result : char
	{
		Parsed = 'o',
		End = 'e',    //!< clean end of the data
		Failed = 'f'  //!< see place, problem
	};
	Result result = Result::End;
	mrpt::serialization::CSerializable::Ptr object;  //!< when Parsed
	std::string place, problem;                      //!< when Failed: "byte N", what is wrong
};

/** Reads the next object; never throws for bad data (Failed says why). */
TObjectRead readArchiveObject(CLogInputFile& in, TArchive& archive);

class CDeserializationGuard
{
public:
	/** Starts the child on `path`. Call after the MRPT classes are registered. */
	explicit CDeserializationGuard(const std::string& path);
	/** Kills and reaps the child. */
	~CDeserializationGuard();
	CDeserializationGuard(const CDeserializationGuard&) = delete;
	CDeserializationGuard& operator=(const CDeserializationGuard&) = delete;

	/** False if the child could not be started or was given up: then every object counts
	 * as safe. */
	bool active() const { return m_pid > 0; }
	/** True if the child sent no report for 30 s and was killed (the reader goes on). */
	bool gaveUp() const { return m_gaveUp; }
	/** Blocks until the child has met the next object. Parsed or End: safe to read it.
	 * Failed: the child's verdict (the reader must not deserialize it); if the child died,
	 * the problem says how ("MRPT's deserializer crashed on it (signal 11 ...)"). */
	TObjectRead checkNextObject(uint64_t objectStart);

private:
	int m_pid = -1;
	int m_fd = -1;             // read end of the pipe
	bool m_childDone = false;  // the child sent its last report and exited
	bool m_gaveUp = false;
};

}  // namespace lrgc::apps
