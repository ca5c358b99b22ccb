/* Background threads that must not delay the mapping thread: a live run's loop-closing worker
 * (its results are taken whenever they are ready) and its map saver share the machine's cores
 * with the thread that registers each scan as it arrives. Measured on SENA live (2 cores shared
 * with other jobs): slow scans spent 2 to 3 times their own CPU time waiting for a core.
 *
 * On Linux a thread has its own nice value (setpriority on its thread id): raising it gives
 * the thread a smaller share of a busy core than the threads of its process at the default,
 * and any share of an idle one. Elsewhere this does nothing. */
#pragma once

namespace lrgc
{
/** Nice value increment for background threads: weight 110 against 1024, about a tenth of a
 * core shared with a default thread. */
constexpr int kBackgroundNiceIncrement = 10;

/** Raises the calling thread's nice value by `increment` (lowers its priority; no privilege
 * needed). False if the system refused or has no per-thread priorities. */
bool lowerCallingThreadPriority(int increment = kBackgroundNiceIncrement);

}  // namespace lrgc
