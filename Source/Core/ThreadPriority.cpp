#include "Core/ThreadPriority.h"
#include <algorithm>
#include <pthread.h>
#include <sched.h>

namespace armadillo::core {

bool requestRealtimePriority(int priority) noexcept
{
    if (priority <= 0) return false;
    sched_param sp {};
    sp.sched_priority = std::clamp(priority, sched_get_priority_min(SCHED_FIFO), sched_get_priority_max(SCHED_FIFO));
    return pthread_setschedparam(pthread_self(), SCHED_FIFO, &sp) == 0;
}

} // namespace armadillo::core
