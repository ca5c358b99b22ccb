/* CDelayedStop (see DelayedStop.h). */
#include "live/DelayedStop.h"

#include <chrono>
#include <optional>

namespace lrgc::apps
{
CDelayedStop::CDelayedStop(CStopToken trigger, double graceSeconds)
{
	m_thread = std::thread(
		[this, trigger, graceSeconds]
		{
			using clock = std::chrono::steady_clock;
			std::optional<clock::time_point> seen;
			while (!m_quit)
			{
				if (!seen && trigger.stopRequested()) seen = clock::now();
				if (seen &&
					std::chrono::duration<double>(clock::now() - *seen).count() >= graceSeconds)
				{
					m_source.requestStop();
					return;
				}
				std::this_thread::sleep_for(std::chrono::milliseconds(50));
			}
		});
}

CDelayedStop::~CDelayedStop()
{
	m_quit = true;
	m_thread.join();
}

}  // namespace lrgc::apps
