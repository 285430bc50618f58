#include "Core/Errors.h"
#include "Core/AtomicFile.h"
#include "Core/Wav.h"
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <unistd.h>

using namespace armadillo;

TEST_CASE("WAV: 16-bit and float round trips", "[wav]")
{
    AudioBuffer a;
    a.sampleRate = 44100;
    a.channels.assign(2, std::vector<float>(1000));
    for (int i = 0; i < 1000; ++i) {
        a.channels[0][i] = 0.5f * std::sin(i * 0.05f);
        a.channels[1][i] = (i % 2) ? 1.5f : -1.5f;   // clipped in 16-bit
    }
    const auto dir = std::filesystem::temp_directory_path();
    const std::string p16 = (dir / ("arm-wav16-" + std::to_string(::getpid()) + ".wav")).string();
    const std::string pf = (dir / ("arm-wavf-" + std::to_string(::getpid()) + ".wav")).string();
    writeWav(p16, a);
    writeWav(pf, a, true);
    const AudioBuffer b = readWav(p16), f = readWav(pf);
    REQUIRE(b.frames() == 1000);
    CHECK(b.sampleRate == 44100);
    CHECK(b.channels[0][100] == Approx(a.channels[0][100]).margin(1.0 / 32767));
    CHECK(std::abs(b.channels[1][1]) <= 1.0f);
    CHECK(f.channels[1][1] == 1.5f);   // float keeps everything
    std::filesystem::remove(p16);
    std::filesystem::remove(pf);
}

TEST_CASE("WAV: bad files are refused, not crashed on", "[wav]")
{
    const auto path = (std::filesystem::temp_directory_path() / ("arm-bad-" + std::to_string(::getpid()) + ".wav")).string();
    for (const std::string& content : {std::string("RIFF"), std::string("RIFF\x10\0\0\0WAVEfmt \xff\xff\xff\x7f", 20),
                                      std::string("not audio at all"), std::string(44, '\0')}) {
        writeFileAtomically(path, content);
        CHECK_THROWS_AS(readWav(path), InputError);
    }
    std::filesystem::remove(path);
}
