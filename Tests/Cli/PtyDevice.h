#pragma once
// A simulated device on a pseudo-terminal for `armadillo` runs that talk to --port: it answers
// every motor packet with a sensor packet (lock-step, as fast as the host goes), decodes the
// motor packets itself per docs/DEVICE.md — 5 bytes: motor 1 in the high nibble of byte 0,
// motor 2 in its low nibble, …, motor 9 in the high nibble of byte 4, whose low nibble is the
// end nibble 0x8 — and hands each one's nine levels to the test. The program's stdin and stderr
// are pipes the test writes answers to and reads prompts from.
#include <array>
#include <catch2/catch.hpp>
#include <chrono>
#include <fcntl.h>
#include <functional>
#include <poll.h>
#include <pty.h>
#include <signal.h>
#include <string>
#include <sys/wait.h>
#include <termios.h>
#include <unistd.h>
#include <vector>

namespace armadillo::cli::test {

using Levels = std::array<int, 9>;

/// A sensor packet of the thesis protocol, built bit by bit: nine 12-bit samples in the order
/// ax ay az gx gy gz mx my mz, most significant bit first, then the end nibble 0x0.
inline std::array<unsigned char, 14> sensorPacket(const std::array<int, 9>& counts)
{
    std::array<unsigned char, 14> p {};
    int bit = 0;
    for (int ch = 0; ch < 9; ++ch)
        for (int b = 11; b >= 0; --b, ++bit)
            if ((counts[static_cast<std::size_t>(ch)] >> b) & 1) p[static_cast<std::size_t>(bit / 8)] |= static_cast<unsigned char>(0x80 >> (bit % 8));
    return p;
}
/// Every channel at mid-scale 2048 (at rest in the default calibration, docs/DEVICE.md).
inline std::array<unsigned char, 14> midScaleSensorPacket() { return sensorPacket({2048, 2048, 2048, 2048, 2048, 2048, 2048, 2048, 2048}); }

class PtyDevice {
public:
    /// Starts `armadillo ARGS… --port PTY`.
    explicit PtyDevice(std::vector<std::string> args)
    {
        termios raw {};
        ::cfmakeraw(&raw);
        REQUIRE(::openpty(&master_, &slave_, nullptr, &raw, nullptr) == 0);
        args.push_back("--port");
        args.push_back(::ttyname(slave_));
        int toChild[2], fromChild[2];
        REQUIRE(::pipe(toChild) == 0);
        REQUIRE(::pipe(fromChild) == 0);
        // Built before the fork: the child only makes async-signal-safe calls until it execs.
        std::vector<char*> argv {const_cast<char*>(ARMADILLO_BIN)};
        for (auto& a : args) argv.push_back(a.data());
        argv.push_back(nullptr);
        pid_ = ::fork();
        REQUIRE(pid_ >= 0);
        if (pid_ == 0) {
            ::dup2(toChild[0], 0);
            ::dup2(fromChild[1], 2);
            const int devnull = ::open("/dev/null", O_WRONLY);
            ::dup2(devnull, 1);
            ::close(toChild[1]);
            ::close(fromChild[0]);
            ::close(master_);
            ::execv(ARMADILLO_BIN, argv.data());
            ::_exit(127);
        }
        ::close(toChild[0]);
        ::close(fromChild[1]);
        in_ = toChild[1];
        err_ = fromChild[0];
        ::signal(SIGPIPE, SIG_IGN);
        ::fcntl(master_, F_SETFL, O_NONBLOCK);
    }
    ~PtyDevice() { finish(); }

    /// Runs until the program closes stderr (or `minutes` pass): each motor packet goes to
    /// onPacket, each stderr line to onLine.
    void run(const std::function<void(const Levels&)>& onPacket, const std::function<void(const std::string&)>& onLine, int minutes = 3)
    {
        const auto deadline = std::chrono::steady_clock::now() + std::chrono::minutes(minutes);
        std::string line;
        while (std::chrono::steady_clock::now() < deadline) {
            pump(2, onPacket);
            pollfd e {err_, POLLIN, 0};
            if (::poll(&e, 1, 0) <= 0) continue;
            char c;
            if (::read(err_, &c, 1) <= 0) {
                stderrClosed_ = true;
                return;
            }
            if (c != '\n') {
                line += c;
                continue;
            }
            err += line + "\n";
            for (int k = 0; k < 20; ++k) pump(0, onPacket);   // packets written before the line
            onLine(line);
            line.clear();
        }
    }
    /// The gyroscope's x channel (the roll rate about the forearm) `offset` counts from mid-scale
    /// in the packets sent from now on.
    void setGyroX(int offset) { sensor_ = sensorPacket({2048, 2048, 2048, 2048 + offset, 2048, 2048, 2048, 2048, 2048}); }
    /// Asks the program to stop (SIGTERM, as a user's kill): it finishes and closes stderr, so run() returns.
    void terminate()
    {
        if (pid_ > 0) ::kill(pid_, SIGTERM);
    }
    void answer(const std::string& text) { (void)!::write(in_, (text + "\n").data(), text.size() + 1); }
    void closeInput()
    {
        if (in_ >= 0) ::close(in_);
        in_ = -1;
    }
    /// Waits for the program; its exit code.
    int finish()
    {
        if (pid_ <= 0) return code_;
        closeInput();
        int status = 0;
        if (::waitpid(pid_, &status, WNOHANG) == 0) {
            ::kill(pid_, SIGTERM);
            ::waitpid(pid_, &status, 0);
        }
        pid_ = -1;
        ::close(err_);
        ::close(master_);
        ::close(slave_);
        code_ = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
        return code_;
    }
    /// Waits for a normal exit after stderr closed (a program still running is stopped: −1).
    int wait()
    {
        if (!stderrClosed_) {
            finish();
            return -1;
        }
        int status = 0;
        ::waitpid(pid_, &status, 0);
        pid_ = -1;
        closeInput();
        ::close(err_);
        ::close(master_);
        ::close(slave_);
        code_ = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
        return code_;
    }
    long motorPackets = 0;
    std::string err;

private:
    void pump(int timeoutMs, const std::function<void(const Levels&)>& onPacket)
    {
        pollfd p {master_, POLLIN, 0};
        if (::poll(&p, 1, timeoutMs) <= 0) {
            if (timeoutMs > 0) (void)!::write(master_, sensor_.data(), sensor_.size());   // a device that streams
            return;
        }
        unsigned char buf[4096];
        const ssize_t n = ::read(master_, buf, sizeof buf);
        if (n <= 0) return;
        wire_.insert(wire_.end(), buf, buf + n);
        std::size_t i = 0;
        while (wire_.size() - i >= 5) {
            if ((wire_[i + 4] & 0x0F) != 0x8) {   // not at a packet boundary: skip a byte
                ++i;
                continue;
            }
            Levels levels {};
            for (int m = 0; m < 9; ++m) {
                const unsigned char byte = wire_[i + static_cast<std::size_t>(m / 2)];
                levels[static_cast<std::size_t>(m)] = m % 2 == 0 ? byte >> 4 : byte & 0x0F;
            }
            ++motorPackets;
            onPacket(levels);
            (void)!::write(master_, sensor_.data(), sensor_.size());   // lock-step: one answer per motor packet
            i += 5;
        }
        wire_.erase(wire_.begin(), wire_.begin() + static_cast<long>(i));
    }

    int master_ = -1, slave_ = -1, in_ = -1, err_ = -1;
    pid_t pid_ = -1;
    int code_ = -1;
    bool stderrClosed_ = false;
    std::vector<unsigned char> wire_;
    std::array<unsigned char, 14> sensor_ = midScaleSensorPacket();
};

} // namespace armadillo::cli::test
