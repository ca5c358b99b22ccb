/* Test-only access to the live app: a periodic save made slow on purpose, to test that saving
 * never holds up mapping. lrgc-slam and TLiveSlamSetup have no such hook. */
#pragma once

#include "live/LiveSlam.h"

namespace lrgc::apps
{
struct TLiveSlamTestAccess
{
	/** `hook` runs on the saver thread at the start of every periodic save of `app`, with the
	 * count of scans mapped so far (read when called). */
	static void setPeriodicSaveHook(CLiveSlam& app, TPeriodicSaveHook hook)
	{
		app.m_periodicSaveHook = std::move(hook);
	}
};

}  // namespace lrgc::apps
