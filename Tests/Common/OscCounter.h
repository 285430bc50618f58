#pragma once
// The receiver of an `--osc-out` stream in a test: a UDP socket on a free loopback port and a
// thread that counts the datagrams by their OSC address, until it is destroyed.
//     armadillo::testing::OscCounter osc;
//     run("play … --osc-out 127.0.0.1:" + std::to_string(osc.port()));
//     CHECK(osc.count("/armadillo/orientation") > 100);
#include <arpa/inet.h>
#include <atomic>
#include <cstring>
#include <map>
#include <mutex>
#include <netinet/in.h>
#include <string>
#include <sys/socket.h>
#include <thread>
#include <unistd.h>

namespace armadillo::testing {

class OscCounter {
public:
    OscCounter()
    {
        fd_ = ::socket(AF_INET, SOCK_DGRAM, 0);
        sockaddr_in at {};
        at.sin_family = AF_INET;
        at.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
        socklen_t len = sizeof at;
        if (fd_ < 0 || ::bind(fd_, reinterpret_cast<sockaddr*>(&at), sizeof at) != 0
            || ::getsockname(fd_, reinterpret_cast<sockaddr*>(&at), &len) != 0)
            return;   // port() stays 0: the test's REQUIRE says so
        port_ = ntohs(at.sin_port);
        timeval tv {0, 200000};   // the thread looks at stop_ five times a second
        ::setsockopt(fd_, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
        thread_ = std::thread([this] {
            char buf[2048];
            while (!stop_.load()) {
                const auto n = ::recv(fd_, buf, sizeof buf, 0);
                if (n <= 0) continue;
                const std::string address(buf, ::strnlen(buf, static_cast<std::size_t>(n)));
                std::lock_guard<std::mutex> lock(mutex_);
                ++counts_[address];
            }
        });
    }
    ~OscCounter()
    {
        stop_ = true;
        if (thread_.joinable()) thread_.join();
        if (fd_ >= 0) ::close(fd_);
    }
    OscCounter(const OscCounter&) = delete;
    OscCounter& operator=(const OscCounter&) = delete;

    /// The loopback port it listens on (0: it could not bind).
    int port() const noexcept { return port_; }
    /// Datagrams whose OSC address is `address`, so far.
    int count(const std::string& address) const
    {
        std::lock_guard<std::mutex> lock(mutex_);
        const auto it = counts_.find(address);
        return it == counts_.end() ? 0 : it->second;
    }

private:
    int fd_ = -1, port_ = 0;
    std::atomic<bool> stop_ {false};
    mutable std::mutex mutex_;
    std::map<std::string, int> counts_;
    std::thread thread_;
};

} // namespace armadillo::testing
