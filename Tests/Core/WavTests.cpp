#include "Core/Errors.h"
#include "Core/AtomicFile.h"
#include "Core/Wav.h"
#include <catch2/catch.hpp>
#include <sndfile.h>
#include <algorithm>
#include <vector>
#include <cmath>
#include <filesystem>
#include <fcntl.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <unistd.h>

using namespace armadillo;
using namespace armadillo::core;

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

namespace {
std::string tempPath(const std::string& name)
{
    return (std::filesystem::temp_directory_path() / ("arm-" + std::to_string(::getpid()) + "-" + name)).string();
}
/// The RIFF chunk ids of a file, in order (top level).
std::vector<std::string> chunks(const std::string& bytes)
{
    std::vector<std::string> ids {bytes.substr(0, 4)};
    for (std::size_t pos = 12; pos + 8 <= bytes.size();) {
        ids.push_back(bytes.substr(pos, 4));
        const auto* p = reinterpret_cast<const unsigned char*>(bytes.data() + pos + 4);
        const std::uint32_t len = p[0] | (p[1] << 8) | (p[2] << 16) | (std::uint32_t(p[3]) << 24);
        pos += 8 + len + (len & 1);
    }
    return ids;
}
} // namespace

TEST_CASE("WAV: written files are plain RIFF/WAVE below 4 GiB; float ones carry the fact chunk", "[wav]")
{
    AudioBuffer a;
    a.sampleRate = 48000;
    a.channels.assign(2, std::vector<float>(4800, 0.25f));
    const std::string p16 = tempPath("plain16.wav"), pf = tempPath("plainf.wav");
    writeWav(p16, a);
    writeWav(pf, a, true);
    const auto c16 = chunks(readWholeFile(p16)), cf = chunks(readWholeFile(pf));
    CHECK(c16.front() == "RIFF");   // downgraded from RF64: an ordinary WAV
    CHECK(std::find(c16.begin(), c16.end(), "data") != c16.end());
    CHECK(cf.front() == "RIFF");
    CHECK(std::find(cf.begin(), cf.end(), "fact") != cf.end());
    CHECK(std::find(cf.begin(), cf.end(), "fact") < std::find(cf.begin(), cf.end(), "data"));
    CHECK(readWav(pf).frames() == 4800);
    // Nothing is left beside the file (the temporary was renamed in).
    int beside = 0;
    for (const auto& e : std::filesystem::directory_iterator(std::filesystem::temp_directory_path()))
        beside += e.path().filename().string().rfind("arm-" + std::to_string(::getpid()) + "-plain16.wav.tmp", 0) == 0;
    CHECK(beside == 0);
    std::filesystem::remove(p16);
    std::filesystem::remove(pf);
}

TEST_CASE("WAV: 8-bit WAV, AIFF and FLAC recordings are read", "[wav]")
{
    const int rate = 44100, frames = 2000;
    std::vector<float> ramp(frames * 2);
    for (int i = 0; i < frames; ++i) {
        ramp[2 * i] = 0.8f * std::sin(0.01f * i);
        ramp[2 * i + 1] = -0.5f;
    }
    struct Kind {
        const char* name;
        int format;
        float tolerance;   // quantisation of the format
    };
    // 8-bit: libsndfile writes x·127 and reads n/128, so the error reaches about 1.3 steps.
    for (const Kind& k : {Kind {"u8.wav", SF_FORMAT_WAV | SF_FORMAT_PCM_U8, 1.5f / 128}, Kind {"s16.aiff", SF_FORMAT_AIFF | SF_FORMAT_PCM_16, 1e-4f},
                          Kind {"s24.flac", SF_FORMAT_FLAC | SF_FORMAT_PCM_24, 1e-6f}, Kind {"s8.aiff", SF_FORMAT_AIFF | SF_FORMAT_PCM_S8, 1.5f / 128}}) {
        INFO(k.name);
        const std::string path = tempPath(k.name);
        SF_INFO info {};
        info.samplerate = rate;
        info.channels = 2;
        info.format = k.format;
        SNDFILE* f = sf_open(path.c_str(), SFM_WRITE, &info);
        REQUIRE(f != nullptr);
        REQUIRE(sf_writef_float(f, ramp.data(), frames) == frames);
        sf_close(f);
        const AudioBuffer b = readWav(path);
        CHECK(b.sampleRate == rate);
        REQUIRE(b.channels.size() == 2);
        REQUIRE(b.frames() == static_cast<std::size_t>(frames));
        float worst = 0.0f;
        for (int i = 0; i < frames; ++i)
            worst = std::max({worst, std::abs(b.channels[0][i] - ramp[2 * i]), std::abs(b.channels[1][i] - ramp[2 * i + 1])});
        CHECK(worst <= k.tolerance);
        std::filesystem::remove(path);
    }
    CHECK_THROWS_AS(readWav(tempPath("does-not-exist.wav")), IoError);
}

TEST_CASE("WAV: a recording past 4 GiB stays one valid file (RF64)", "[.][wav][large]")
{
    // Hidden (run with "[large]"): writes 4.1 GiB. The old writer wrapped the 32-bit sizes here.
    const std::string path = tempPath("large.wav");
    {
        WavStreamWriter out(path, 48000, 2, true);
        std::vector<float> block(2 * 65536, 0.1f);
        const std::uint64_t frames = (std::uint64_t(4) << 30) / 8 + 65536 * 4;   // > 4 GiB of float stereo
        for (std::uint64_t done = 0; done < frames; done += 65536) REQUIRE(out.write(block.data(), 65536));
        out.finish();
    }
    SF_INFO info {};
    SNDFILE* f = sf_open(path.c_str(), SFM_READ, &info);
    REQUIRE(f != nullptr);
    CHECK((info.format & SF_FORMAT_TYPEMASK) == SF_FORMAT_RF64);
    CHECK(static_cast<std::uint64_t>(info.frames) * 8 > (std::uint64_t(4) << 30));
    sf_close(f);
    std::filesystem::remove(path);
}

namespace {

/// What is at `path` now: 'p' a FIFO, 'c' a character device, 'f' a regular file, '-' nothing.
char kindOf(const std::string& path)
{
    struct stat st {};
    if (::lstat(path.c_str(), &st) != 0) return '-';
    return S_ISFIFO(st.st_mode) ? 'p' : S_ISCHR(st.st_mode) ? 'c' : S_ISREG(st.st_mode) ? 'f' : '?';
}

/// Everything waiting in a non-blocking read end.
std::string drain(int fd)
{
    std::string got;
    char buf[4096];
    for (ssize_t n; (n = ::read(fd, buf, sizeof buf)) > 0;) got.append(buf, static_cast<std::size_t>(n));
    return got;
}

} // namespace

TEST_CASE("an output that is a device or a pipe is written through, never replaced by a file", "[wav][atomic]")
{
    // `armadillo fuse --out /dev/null` as root once turned the machine's /dev/null into a regular
    // file: the temporary was renamed over the device. A FIFO shows it without root: renamed
    // over, it would be a regular file afterwards and its reader would get nothing.
    const std::string fifo = tempPath("out.fifo");
    std::filesystem::remove(fifo);
    REQUIRE(::mkfifo(fifo.c_str(), 0600) == 0);
    const int reader = ::open(fifo.c_str(), O_RDONLY | O_NONBLOCK);   // a reader, so a writer's open does not wait
    REQUIRE(reader >= 0);
    CHECK(isDeviceOrPipe(fifo));
    CHECK_FALSE(isDeviceOrPipe(tempPath("nothing-here")));

    writeFileAtomically(fifo, "t,qw,qx,qy,qz\n0,1,0,0,0\n");
    CHECK(kindOf(fifo) == 'p');
    CHECK(drain(reader) == "t,qw,qx,qy,qz\n0,1,0,0,0\n");

    // A WAV cannot stream into a pipe (its header is rewritten at the end): a clear error, and
    // the pipe is still the pipe.
    CHECK_THROWS_AS(WavStreamWriter(fifo, 48000.0, 2, false), IoError);
    CHECK(kindOf(fifo) == 'p');
    ::close(reader);
    std::filesystem::remove(fifo);

    // The device itself, where the test may make one (root, as CI runs): a null device of its own.
    if (::geteuid() == 0) {
        const std::string null = tempPath("null");
        std::filesystem::remove(null);
        REQUIRE(::mknod(null.c_str(), S_IFCHR | 0666, makedev(1, 3)) == 0);
        writeFileAtomically(null, "x\n");
        CHECK(kindOf(null) == 'c');
        {
            WavStreamWriter wav(null, 48000.0, 1, true);
            const std::vector<float> frames(480, 0.25f);
            CHECK(wav.write(frames.data(), 480));
            wav.finish();
        }
        CHECK(kindOf(null) == 'c');
        std::filesystem::remove(null);
    }
}
