#pragma once
// The app's message loop run by a test (timers, async updates) for a while, as JUCE's own loop
// would run it: the tests of Tests/Plugin that drive the processor and its windows.
#include <juce_events/juce_events.h>

namespace juce {
bool dispatchNextMessageOnSystemQueue(bool returnIfNoPendingMessages);   // juce_linux_Messaging.cpp
}

namespace armadillo::testing {

/// Runs the message loop for `ms` milliseconds.
inline void pumpMessages(double ms)
{
    const double end = juce::Time::getMillisecondCounterHiRes() + ms;
    while (juce::Time::getMillisecondCounterHiRes() < end)
        if (! juce::dispatchNextMessageOnSystemQueue(true)) juce::Thread::sleep(1);
}

} // namespace armadillo::testing
