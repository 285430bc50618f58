#pragma once
// A UDP socket on 127.0.0.1 that collects the /armadillo/motors levels a hosted plugin sends over
// its OSC output (docs/PLUGIN.md "OSC out": i×9, or i×12 with back motors, levels 0–15).
// Shared by armadillo_host_scenes (HostScenes.cpp) and the hosted stem test (StemHostTests.cpp).
#include <arpa/inet.h>
#include <cstring>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>
#include <vector>

namespace armadillo::test::host {

/// A UDP socket on 127.0.0.1 that collects /armadillo/motors levels.
class MotorListener {
public:
    MotorListener()
    {
        fd_ = ::socket(AF_INET, SOCK_DGRAM | SOCK_NONBLOCK, 0);
        sockaddr_in a {};
        a.sin_family = AF_INET;
        a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
        ::bind(fd_, reinterpret_cast<sockaddr*>(&a), sizeof a);
        socklen_t len = sizeof a;
        ::getsockname(fd_, reinterpret_cast<sockaddr*>(&a), &len);
        port_ = ntohs(a.sin_port);
    }
    ~MotorListener() { ::close(fd_); }
    int port() const { return port_; }

    /// Reads what arrived; returns the motor messages' levels.
    std::vector<std::vector<int>> drain()
    {
        std::vector<std::vector<int>> out;
        unsigned char buf[2048];
        for (ssize_t n; (n = ::recv(fd_, buf, sizeof buf, 0)) > 0;) {
            static const char address[] = "/armadillo/motors";
            if (n < 24 || std::memcmp(buf, address, sizeof address) != 0) continue;
            const std::size_t tags = 20;   // "/armadillo/motors\0" padded to 20 bytes
            std::size_t count = 0;
            while (tags + 1 + count < static_cast<std::size_t>(n) && buf[tags + 1 + count] == 'i') ++count;
            std::size_t at = (tags + 1 + count + 1 + 3) & ~std::size_t(3);
            std::vector<int> levels;
            for (std::size_t i = 0; i < count && at + 4 <= static_cast<std::size_t>(n); ++i, at += 4)
                levels.push_back(static_cast<int>((buf[at] << 24) | (buf[at + 1] << 16) | (buf[at + 2] << 8) | buf[at + 3]));
            out.push_back(levels);
        }
        return out;
    }

private:
    int fd_ = -1;
    int port_ = 0;
};

} // namespace armadillo::test::host
