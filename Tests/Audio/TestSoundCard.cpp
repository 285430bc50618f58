// Sound-card output through ALSA's own software devices, so it runs on machines without a card:
// `file:'PATH',raw` keeps every sample written (bit-exact check), `null` discards them (pacing).
#include "Audio/SoundCard.h"
#include "Core/Errors.h"
#include "Common/Eventually.h"
#include <catch2/catch.hpp>
#include <chrono>
#include <cstring>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <thread>
#include <unistd.h>
#include <vector>

using namespace armadillo;
using namespace armadillo::core;
using Clock = std::chrono::steady_clock;

namespace {
std::string scratch(const std::string& name)   // per process: parallel runs do not collide
{
    return std::string(ARMADILLO_BINARY_DIR) + "/audio-test-" + std::to_string(::getpid()) + "-" + name;
}

using armadillo::testing::eventually;

std::vector<float> readFloats(const std::string& path)
{
    std::ifstream in(path, std::ios::binary);
    std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::vector<float> v(bytes.size() / sizeof(float));
    std::memcpy(v.data(), bytes.data(), v.size() * sizeof(float));
    return v;
}

float sampleAt(std::uint64_t i) { return static_cast<float>(0.5 * std::sin(0.01 * static_cast<double>(i))); }
} // namespace

TEST_CASE("sound card: every rendered sample reaches the device, in order, left/right interleaved", "[audio]")
{
    const std::string raw = scratch("exact.raw");
    std::filesystem::remove(raw);
    std::vector<std::uint64_t> blockSizes;
    {
        audio::SoundCard card("file:'" + raw + "',raw", 48000.0);
        CHECK(card.info().sampleRate == 48000.0);
        CHECK(card.info().format == "FLOAT_LE");
        CHECK(card.info().periodFrames > 0);
        std::uint64_t next = 0;
        card.start([&](float* l, float* r, int n) {
            for (int i = 0; i < n; ++i, ++next) {
                l[i] += sampleAt(next);   // the buffers arrive cleared: adding must give the sample
                r[i] += -sampleAt(next);
            }
        });
        REQUIRE(eventually([&] { return card.framesWritten() >= 9600; }));   // 0.2 s
        card.stop();
        CHECK(!card.failed());
        CHECK(card.underruns() == 0);
    }
    const std::vector<float> v = readFloats(raw);
    REQUIRE(v.size() >= 2 * 9600);
    std::size_t wrong = 0;
    for (std::size_t i = 0; i < v.size() / 2; ++i)
        if (v[2 * i] != sampleAt(i) || v[2 * i + 1] != -sampleAt(i)) ++wrong;
    CHECK(wrong == 0);
}

TEST_CASE("sound card: NaN and infinity from a scene become silence, never noise", "[audio]")
{
    const std::string raw = scratch("nan.raw");
    std::filesystem::remove(raw);
    {
        audio::SoundCard card("file:'" + raw + "',raw", 48000.0);
        card.start([](float* l, float* r, int n) {
            for (int i = 0; i < n; ++i) {
                l[i] = NAN;
                r[i] = i % 2 ? INFINITY : -INFINITY;
            }
        });
        REQUIRE(eventually([&] { return card.framesWritten() >= 2000; }));
        card.stop();
    }
    const std::vector<float> v = readFloats(raw);
    REQUIRE(!v.empty());
    for (float x : v) REQUIRE(x == 0.0f);
}

TEST_CASE("sound card: a device that does not block is held to the wall clock", "[audio]")
{
    // ALSA's null device swallows samples at any speed; unpaced, the loop would render minutes of
    // audio per second. Only an upper bound is checked (the loop may lag, never run ahead).
    audio::SoundCard card("null", 48000.0);
    const auto t0 = Clock::now();
    card.start([](float*, float*, int) {});
    REQUIRE(eventually([&] { return card.framesWritten() >= 24000; }));
    card.stop();
    const double elapsed = std::chrono::duration<double>(Clock::now() - t0).count();
    const auto frames = static_cast<double>(card.framesWritten());
    INFO("frames " << frames << " in " << elapsed << " s, buffer " << card.info().bufferFrames);
    CHECK(frames <= elapsed * 48000.0 + card.info().bufferFrames + 2.0 * card.info().periodFrames);
}

TEST_CASE("sound card: a missing device or a silly rate is a clear IoError naming the device", "[audio]")
{
    try {
        audio::SoundCard card("hw:97", 48000.0);
        FAIL("opened a card that does not exist");
    } catch (const IoError& e) {
        CHECK(std::string(e.what()).find("sound card 'hw:97'") != std::string::npos);
    }
    CHECK_THROWS_AS(audio::SoundCard("null", 0.0), IoError);
    CHECK_THROWS_AS(audio::SoundCard("null", NAN), IoError);
    CHECK_THROWS_AS(audio::SoundCard("no-such-pcm-name", 48000.0), IoError);
    // Started again after a stop, the card plays on and keeps counting.
    audio::SoundCard again("null", 48000.0);
    again.start([](float*, float*, int) {});
    REQUIRE(eventually([&] { return again.framesWritten() >= 1000; }));
    again.stop();
    const std::uint64_t first = again.framesWritten();
    again.start([](float*, float*, int) {});
    REQUIRE(eventually([&] { return again.framesWritten() >= first + 1000; }));
    again.stop();
    CHECK(!again.failed());
    // Stopping twice, or without starting, is harmless.
    audio::SoundCard idle("null", 44100.0);
    idle.stop();
    idle.stop();
    CHECK(idle.framesWritten() == 0);
}
