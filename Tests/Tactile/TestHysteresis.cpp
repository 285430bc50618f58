// Hysteresis (thesis §3.2.4, Figures 3-5 and 3-6): a noisy signal drifting across one boundary
// switches exactly once; a single threshold would chatter.
#include "Tactile/Hysteresis.h"
#include <catch2/catch.hpp>
#include <random>

using namespace armadillo;
using namespace armadillo::tactile;

namespace {
// A slow ramp from −0.5 to +0.5 that lingers near 0, with uniform noise of ±noise.
std::vector<double> noisyCrossing(double noise, std::uint64_t seed)
{
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> n(-noise, noise);
    std::vector<double> x;
    for (int i = 0; i < 2000; ++i) {
        const double s = (i - 1000) / 2000.0;             // −0.5 .. 0.5
        const double lingering = s * s * s * 4.0;         // flat near 0: lots of time at the threshold
        x.push_back(lingering + n(rng));
    }
    return x;
}

int switches(Hysteresis h, const std::vector<double>& xs)
{
    int count = 0;
    bool state = h.on();
    for (double x : xs) {
        const bool now = h.update(x);
        count += now != state;
        state = now;
    }
    return count;
}
} // namespace

TEST_CASE("Hysteresis: a noisy signal near one threshold switches exactly once", "[hysteresis]")
{
    for (std::uint64_t seed = 1; seed <= 20; ++seed) {
        const auto xs = noisyCrossing(0.08, seed);
        // Thresholds ±0.1 around 0, wider than the noise.
        CHECK(switches(Hysteresis::around(0.0, 0.1), xs) == 1);
        // One threshold (the jitter of Figure 3-5): many switches. This proves the signal is noisy
        // enough for the check above to mean something.
        CHECK(switches(Hysteresis(0.0, 0.0), xs) > 5);
    }
}

TEST_CASE("Hysteresis: both directions, thresholds and state", "[hysteresis]")
{
    Hysteresis up(0.1, -0.1);
    CHECK_FALSE(up.update(0.05));
    CHECK(up.activeThreshold() == 0.1);
    CHECK(up.update(0.11));
    CHECK(up.activeThreshold() == -0.1);
    CHECK(up.update(-0.05));     // inside the band: stays on
    CHECK_FALSE(up.update(-0.11));

    // A downward boundary: on when the signal is low.
    Hysteresis down(-0.1, 0.1);
    CHECK_FALSE(down.update(0.0));
    CHECK(down.update(-0.2));
    CHECK(down.update(0.05));
    CHECK_FALSE(down.update(0.2));

    Hysteresis h = Hysteresis::around(30.0, 2.0, true);
    CHECK(h.on());
    CHECK(h.enter() == 32.0);
    CHECK(h.exit() == 28.0);
    h.reset();
    CHECK_FALSE(h.on());
    static_assert(Hysteresis(1.0, 0.0).update(2.0), "usable at compile time");
}
