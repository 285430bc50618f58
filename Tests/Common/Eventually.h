#pragma once
// Waiting for a condition in tests without asserting on time: polls until it holds or a
// generous deadline passes (the deadline only stops a broken test from hanging CI).
//     #include "Common/Eventually.h"
//     REQUIRE(armadillo::testing::eventually([&] { return card.framesWritten() >= 9600; }));
#include <chrono>
#include <thread>

namespace armadillo::testing {

template <typename F>
bool eventually(F condition, double seconds = 30.0)
{
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
    while (!condition()) {
        if (std::chrono::steady_clock::now() > deadline) return false;
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
    return true;
}

} // namespace armadillo::testing
