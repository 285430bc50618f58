// simboard-pty: the reference firmware running in simavr behind a pseudo-terminal, so the real host
// program can talk to it: `armadillo play --port LINK ...`.
//
//   simboard-pty --link /tmp/armadillo-board [--seconds N] [--motion sweeps|wandering] [--elf FILE]
//
// UART0 is bridged to the pty master: bytes from the host enter the simulated UART when they are
// read; bytes from the firmware are written when their stop bit has arrived in simulated time.
// Simulated time is paced to the wall clock when simavr is faster than real time; when it is
// slower (the usual case: ~3–4× here), the board simply looks slower to the host, like a slow
// link, and the ratio is printed at the end. Quantitative figures come from tests_firmware_loop,
// which runs host and board together in simulated time.
#include "SimBoard.h"
#include "Core/Pose.h"
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <fcntl.h>
#include <poll.h>
#include <pty.h>
#include <string>
#include <termios.h>
#include <thread>
#include <unistd.h>

using namespace armadillo;
using namespace armadillo::core;
using armadillo::firmware_test::SimBoard;

namespace {
volatile std::sig_atomic_t g_stop = 0;
void onSignal(int) { g_stop = 1; }

int usage(const char* why)
{
    std::fprintf(stderr, "simboard-pty: %s\nusage: simboard-pty --link PATH [--seconds N] [--motion sweeps|wandering] [--elf FILE]\n", why);
    return 2;
}
} // namespace

int main(int argc, char** argv)
{
    std::string link, motionName = "sweeps", elf = firmware_test::firmwareElf();
    double seconds = 0.0;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        auto value = [&]() -> std::string { return i + 1 < argc ? argv[++i] : std::string(); };
        if (a == "--link") link = value();
        else if (a == "--seconds") seconds = std::atof(value().c_str());
        else if (a == "--motion") motionName = value();
        else if (a == "--elf") elf = value();
        else if (a == "--help") return usage("help") == 2 ? 0 : 0;
        else return usage(("unknown option " + a).c_str());
    }
    if (link.empty()) return usage("--link is required");
    if (motionName != "sweeps" && motionName != "wandering") return usage("--motion must be sweeps or wandering");

    std::shared_ptr<const link::MotionSource> motion;
    if (motionName == "wandering") motion = std::make_shared<link::WanderingMotion>(3);
    else motion = std::make_shared<link::FunctionMotion>([](double t) {
        Pose p;
        p.elevationDeg = 40.0 * std::sin(2.0 * kPi * t / 7.0);
        p.azimuthDeg = 360.0 + 60.0 * std::sin(2.0 * kPi * t / 11.0);
        p.rollDeg = 60.0 * std::sin(2.0 * kPi * t / 5.0);
        return poseToQuaternion(p);
    });

    termios raw {};
    ::cfmakeraw(&raw);
    int master = -1, slave = -1;
    if (::openpty(&master, &slave, nullptr, &raw, nullptr) != 0) {
        std::perror("simboard-pty: openpty");
        return 4;
    }
    ::fcntl(master, F_SETFL, ::fcntl(master, F_GETFL) | O_NONBLOCK);
    const std::string tmp = link + ".tmp";
    ::unlink(tmp.c_str());
    if (::symlink(::ttyname(slave), tmp.c_str()) != 0 || ::rename(tmp.c_str(), link.c_str()) != 0) {
        std::perror("simboard-pty: symlink");
        return 4;
    }
    std::signal(SIGINT, onSignal);
    std::signal(SIGTERM, onSignal);

    try {
        SimBoard::Options o;
        o.elf = elf;
        o.motion = motion;
        SimBoard board(o);
        std::printf("simboard-pty: firmware %s on %s -> %s\n", elf.c_str(), link.c_str(), ::ttyname(slave));
        std::fflush(stdout);
        const auto wall0 = std::chrono::steady_clock::now();
        std::uint64_t in = 0, out = 0;
        while (!g_stop) {
            const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
            if (seconds > 0.0 && wall >= seconds) break;
            // Pace: never run ahead of the wall clock; when behind, run in 1 ms slices.
            const double target = std::min(board.now() + 0.001, std::max(wall, board.now()));
            if (target > board.now()) board.runUntil(target);
            else std::this_thread::sleep_for(std::chrono::microseconds(200));
            std::uint8_t buf[256];
            const ssize_t n = ::read(master, buf, sizeof buf);
            if (n > 0) {
                board.send(buf, static_cast<std::size_t>(n));
                in += static_cast<std::uint64_t>(n);
            }
            // Whole packets at once: forward the firmware's bytes when the simulated line has been
            // quiet for two byte times after the last one. Trickled out at simavr's slower-than-real
            // pace, a 14-byte packet would look to the host like a stalled device (10 ms rule).
            auto& rx = board.received();
            const auto gap = static_cast<std::uint64_t>(2.0 * board.byteTime() * SimBoard::kClockHz);
            if (!rx.empty() && board.cycle() >= rx.back().cycle + gap) {
                std::uint8_t pkt[512];
                std::size_t k = 0;
                while (!rx.empty() && k < sizeof pkt) {
                    pkt[k++] = rx.front().b;
                    rx.pop_front();
                }
                const ssize_t w = ::write(master, pkt, k);
                if (w > 0) out += static_cast<std::uint64_t>(w);
            }
        }
        const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
        std::printf("simboard-pty: %.2f s simulated in %.2f s wall (%.2f x real time); %llu bytes in, %llu out\n",
                    board.now(), wall, board.now() / std::max(wall, 1e-9), static_cast<unsigned long long>(in),
                    static_cast<unsigned long long>(out));
    } catch (const std::exception& e) {
        std::fprintf(stderr, "simboard-pty: %s\n", e.what());
        ::unlink(link.c_str());
        return 4;
    }
    ::unlink(link.c_str());
    ::close(slave);
    ::close(master);
    return 0;
}
