// `armadillo touch-profile --port PTY` against a simulated reader on a pseudo-terminal (issue 26's
// done-when): the reader plays the device (answers each motor packet with a sensor packet),
// decodes the motor packets itself per docs/DEVICE.md (5 bytes: motor 1 in the high nibble of
// byte 0, …, motor 9 in the high nibble of byte 4, end nibble 0x8 in its low nibble) and answers
// each "? " prompt with y or n by comparing the level the stimulated motor got with its own
// hidden threshold.
#include "CliRun.h"
#include "Core/AtomicFile.h"
#include <array>
#include <catch2/catch.hpp>
#include <cerrno>
#include <fcntl.h>
#include <poll.h>
#include <pty.h>
#include <regex>
#include <signal.h>
#include <sys/wait.h>
#include <termios.h>
#include <unistd.h>

using namespace armadillo::cli;

namespace {

/// A sensor packet of the thesis protocol with every channel at mid-scale 2048, built bit by bit:
/// nine 12-bit samples most significant bit first, then the end nibble 0x0.
std::array<unsigned char, 14> midScaleSensorPacket()
{
    std::array<unsigned char, 14> p {};
    int bit = 0;
    for (int ch = 0; ch < 9; ++ch)
        for (int b = 11; b >= 0; --b, ++bit)
            if ((2048 >> b) & 1) p[static_cast<std::size_t>(bit / 8)] |= static_cast<unsigned char>(0x80 >> (bit % 8));
    return p;
}

struct ReaderResult {
    int code = -1;
    int prompts = 0;
    long motorPackets = 0;
    long onPackets = 0;   ///< motor packets with some motor on: the stimuli's on-time
    std::string err;
};

/// Runs touch-profile with the reader whose hidden thresholds are `hidden` (m1..m9).
ReaderResult runSimulatedReader(const std::array<int, 9>& hidden, const std::string& outFile)
{
    int master = -1, slave = -1;
    termios raw {};
    ::cfmakeraw(&raw);
    REQUIRE(::openpty(&master, &slave, nullptr, &raw, nullptr) == 0);
    const std::string slaveName = ::ttyname(slave);
    int toChild[2], fromChild[2];
    REQUIRE(::pipe(toChild) == 0);
    REQUIRE(::pipe(fromChild) == 0);
    const pid_t pid = ::fork();
    REQUIRE(pid >= 0);
    if (pid == 0) {
        ::dup2(toChild[0], 0);
        ::dup2(fromChild[1], 2);
        const int devnull = ::open("/dev/null", O_WRONLY);
        ::dup2(devnull, 1);
        ::close(toChild[1]);
        ::close(fromChild[0]);
        ::close(master);
        ::execl(ARMADILLO_BIN, ARMADILLO_BIN, "touch-profile", "--port", slaveName.c_str(), "--unpaced", "--out", outFile.c_str(), nullptr);
        ::_exit(127);
    }
    ::close(toChild[0]);
    ::close(fromChild[1]);
    ::signal(SIGPIPE, SIG_IGN);
    ::fcntl(master, F_SETFL, O_NONBLOCK);

    const auto sensor = midScaleSensorPacket();
    std::vector<unsigned char> wire;
    std::array<int, 9> maxSincePrompt {};
    ReaderResult r;
    std::string errLine;
    bool errOpen = true;
    auto pumpDevice = [&](int timeoutMs) {
        pollfd p {master, POLLIN, 0};
        if (::poll(&p, 1, timeoutMs) <= 0) {
            if (timeoutMs > 0) (void)!::write(master, sensor.data(), sensor.size());   // a device that streams
            return;
        }
        unsigned char buf[4096];
        const ssize_t n = ::read(master, buf, sizeof buf);
        if (n <= 0) return;
        wire.insert(wire.end(), buf, buf + n);
        std::size_t i = 0;
        while (wire.size() - i >= 5) {
            if ((wire[i + 4] & 0x0F) != 0x8) {   // not at a packet boundary: skip a byte
                ++i;
                continue;
            }
            for (int m = 0; m < 9; ++m) {
                const unsigned char byte = wire[i + static_cast<std::size_t>(m / 2)];
                const int level = m % 2 == 0 ? byte >> 4 : byte & 0x0F;
                maxSincePrompt[static_cast<std::size_t>(m)] = std::max(maxSincePrompt[static_cast<std::size_t>(m)], level);
            }
            ++r.motorPackets;
            bool on = false;
            for (int m = 0; m < 9; ++m) on = on || wire[i + static_cast<std::size_t>(m / 2)] >> (m % 2 == 0 ? 4 : 0) & 0x0F;
            r.onPackets += on;
            (void)!::write(master, sensor.data(), sensor.size());   // lock-step: one answer per motor packet
            i += 5;
        }
        wire.erase(wire.begin(), wire.begin() + static_cast<long>(i));
    };
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::minutes(3);
    while (errOpen && std::chrono::steady_clock::now() < deadline) {
        pumpDevice(2);
        pollfd e {fromChild[0], POLLIN, 0};
        if (::poll(&e, 1, 0) <= 0) continue;
        char c;
        const ssize_t n = ::read(fromChild[0], &c, 1);
        if (n <= 0) {
            errOpen = false;
            break;
        }
        if (c != '\n') {
            errLine += c;
            continue;
        }
        r.err += errLine + "\n";
        if (errLine.rfind("? ", 0) == 0) {
            ++r.prompts;
            for (int k = 0; k < 20; ++k) pumpDevice(0);   // packets written before the prompt
            // The stimulated motor is the one that was on; the reader's hidden rule decides.
            int motor = -1, level = 0;
            for (int m = 0; m < 9; ++m)
                if (maxSincePrompt[static_cast<std::size_t>(m)] > level) {
                    level = maxSincePrompt[static_cast<std::size_t>(m)];
                    motor = m;
                }
            bool yes = false;
            if (motor >= 0) {
                const int t = hidden[static_cast<std::size_t>(motor)];
                yes = errLine.find("comfortable") != std::string::npos ? level >= t + 2 : level >= t;
            }
            const char* answer = yes ? "y\n" : "n\n";
            (void)!::write(toChild[1], answer, 2);
            maxSincePrompt.fill(0);
        }
        errLine.clear();
    }
    ::close(toChild[1]);
    int status = 0;
    if (errOpen) ::kill(pid, SIGTERM);
    ::waitpid(pid, &status, 0);
    ::close(fromChild[0]);
    ::close(master);
    ::close(slave);
    r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return r;
}

std::vector<int> jsonIntArray(const std::string& json, const std::string& key)
{
    const std::regex re("\"" + key + "\": \\[([0-9, ]*)\\]");
    std::smatch m;
    std::vector<int> out;
    if (!std::regex_search(json, m, re)) return out;
    std::string list = m[1];
    for (std::size_t at = 0; at < list.size();) {
        const auto comma = list.find(',', at);
        out.push_back(std::stoi(list.substr(at, comma - at)));
        if (comma == std::string::npos) break;
        at = comma + 1;
    }
    return out;
}

} // namespace

TEST_CASE("touch-profile over a pty finds nine different thresholds within one level in under 5 minutes of stimuli", "[cli][touch-profile][pty]")
{
    const std::array<int, 9> hidden {2, 5, 9, 3, 7, 12, 4, 6, 10};
    const std::string out = path("touch-profile.json");
    const ReaderResult r = runSimulatedReader(hidden, out);
    INFO(r.err);
    REQUIRE(r.code == 0);
    const std::string json = armadillo::readWholeFile(out);
    INFO(json);
    const std::vector<int> found = jsonIntArray(json, "threshold");
    REQUIRE(found.size() == 9);
    for (std::size_t m = 0; m < 9; ++m) {
        INFO("motor m" << m + 1);
        CHECK(std::abs(found[m] - hidden[m]) <= 1);
    }
    // Stimulus time, counted by the reader itself: each motor packet with a motor on stood for
    // 1/303 s (--unpaced: the 57 600-baud lock-step period, 10 bits × 19 bytes per exchange),
    // and each stimulus is followed by the documented 0.5 s of stillness. The reader's own
    // answering time is not stimulus time (here it is wall-clock milliseconds, during which the
    // link keeps exchanging all-off packets).
    const double seconds = r.onPackets * (10.0 * 19.0 / 57600.0) + r.prompts * 0.5;
    INFO(r.prompts << " prompts, " << r.onPackets << " packets with a motor on: " << seconds << " s of stimuli");
    CHECK(r.prompts > 9 * 5);
    CHECK(seconds < 300.0);
    // The comfortable level: the first level at least two above m5's threshold.
    CHECK(json.find("\"comfort\": " + std::to_string(hidden[4] + 2)) != std::string::npos);
}

TEST_CASE("touch-profile refuses bad usage and a missing port, and --profile checks its file", "[cli][touch-profile]")
{
    CHECK(runArmadillo("touch-profile --out x.json").code == 2);
    CHECK(runArmadillo("touch-profile --simulate").code == 2);
    CHECK(runArmadillo("touch-profile --port /dev/does-not-exist --out " + path("x.json")).code == 4);
    // stdin ends before the procedure does: exit 3, nothing written.
    const Run early = runArmadillo("touch-profile --simulate --unpaced --out " + path("early.json"), file("three.txt", "y\nn\ny\n"));
    CHECK(early.code == 3);
    CHECK_FALSE(std::filesystem::exists(path("early.json")));
    // A bad profile is refused with its file and key named (exit 3).
    const std::string bad = file("bad-profile.json", "{\"threshold\": [1, 2, 3]}");
    const Run r = runArmadillo("render --scene braille --text exit --motion " + std::string(ARMADILLO_SOURCE_DIR) +
                               "/Resources/Braille/read-word.pose.csv --out " + path("o.wav") + " --profile " + bad);
    CHECK(r.code == 3);
    CHECK(r.err.find("bad-profile.json") != std::string::npos);
    CHECK(r.err.find("threshold") != std::string::npos);
}
