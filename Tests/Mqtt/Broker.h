#pragma once
// A Mosquitto broker of the test's own (never a system service): a config file in the test's
// scratch folder (`listener PORT 127.0.0.1`, `allow_anonymous true`, no persistence), started
// with posix_spawn on a loopback port that was free, stopped (SIGTERM, then waited for) by
// stop() or the destructor. start() returns once the port accepts TCP connections, and can be
// called again after stop() to restart the broker on the same port (a broker killed mid-session).
#include "Common/Eventually.h"
#include "Common/FreePort.h"
#include "Common/ScratchDir.h"
#include <arpa/inet.h>
#include <csignal>
#include <fstream>
#include <netinet/in.h>
#include <spawn.h>
#include <stdexcept>
#include <string>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

extern char** environ;

namespace armadillo::test {

/// True when something accepts TCP connections on 127.0.0.1:port.
inline bool tcpAccepts(int port)
{
    const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
    if (fd < 0) return false;
    sockaddr_in a {};
    a.sin_family = AF_INET;
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    a.sin_port = htons(static_cast<std::uint16_t>(port));
    const bool ok = ::connect(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) == 0;
    ::close(fd);
    return ok;
}

inline std::string mosquittoPath()
{
    for (const char* p : {"/usr/sbin/mosquitto", "/usr/bin/mosquitto", "/usr/local/sbin/mosquitto"})
        if (::access(p, X_OK) == 0) return p;
    throw std::runtime_error("mosquitto (the broker) is not installed: scripts/install-deps.sh installs it");
}

class Broker {
public:
    /// `extra`: more configuration lines for this listener (TLS: cafile, certfile, keyfile).
    explicit Broker(const std::string& extra = {}) : port_(freeTcpPort())
    {
        static int count = 0;
        config_ = (scratchDir("armadillo-mqtt-tests") / ("mosquitto-" + std::to_string(++count) + ".conf")).string();
        // max_queued_messages: Mosquitto drops QoS 1/2 messages beyond 1000 queued for one slow
        // client (mosquitto.conf(5)); a flood test on a busy machine can exceed that, and what is
        // tested here is the client, not the broker's default (docs/MQTT.md says so for users).
        std::ofstream(config_) << "listener " << port_ << " 127.0.0.1\nallow_anonymous true\npersistence false\n"
                               << extra << "max_queued_messages 100000\nlog_dest none\n";
    }
    ~Broker() { stop(); }
    Broker(const Broker&) = delete;
    Broker& operator=(const Broker&) = delete;

    int port() const noexcept { return port_; }
    std::string address() const { return "localhost:" + std::to_string(port_); }
    bool running() const noexcept { return pid_ > 0; }

    /// Starts it (again) and waits until it accepts connections; throws when it does not.
    void start()
    {
        if (pid_ > 0) return;
        const std::string exe = mosquittoPath();
        std::string c = "-c";
        char* argv[] = {const_cast<char*>(exe.c_str()), c.data(), config_.data(), nullptr};
        if (::posix_spawn(&pid_, exe.c_str(), nullptr, nullptr, argv, environ) != 0) {
            pid_ = 0;
            throw std::runtime_error("cannot start " + exe);
        }
        if (!testing::eventually([&] { return tcpAccepts(port_) || exited(); }, 30.0) || exited())
            throw std::runtime_error("mosquitto did not start listening on port " + std::to_string(port_));
    }
    /// Stops it (SIGTERM) and waits for the process to end; the port then refuses connections.
    void stop()
    {
        if (pid_ <= 0) return;
        ::kill(pid_, SIGTERM);
        int st = 0;
        ::waitpid(pid_, &st, 0);
        pid_ = 0;
    }

private:
    bool exited()
    {
        int st = 0;
        if (pid_ > 0 && ::waitpid(pid_, &st, WNOHANG) == pid_) {
            pid_ = 0;
            return true;
        }
        return pid_ <= 0;
    }

    int port_ = 0;
    pid_t pid_ = 0;
    std::string config_;
};

} // namespace armadillo::test
