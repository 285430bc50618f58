#pragma once
// A UDP or TCP port on 127.0.0.1 that is free right now (bound to port 0, read back, closed), for tests
// that start a receiver on a port of their choosing. Another process could take it in between;
// on a test machine that does not happen in practice.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

namespace armadillo::test {

/// A port of `type` (SOCK_DGRAM, SOCK_STREAM) on 127.0.0.1 that is free right now; 0 if none.
inline int freeLoopbackPort(int type)
{
    const int fd = ::socket(AF_INET, type, 0);
    if (fd < 0) return 0;
    sockaddr_in a {};
    a.sin_family = AF_INET;
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    socklen_t len = sizeof a;
    const bool ok = ::bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) == 0 && ::getsockname(fd, reinterpret_cast<sockaddr*>(&a), &len) == 0;
    ::close(fd);
    return ok ? ntohs(a.sin_port) : 0;
}

inline int freeUdpPort() { return freeLoopbackPort(SOCK_DGRAM); }
/// For servers a test starts (mosquitto, gpsd): a TCP port free right now.
inline int freeTcpPort() { return freeLoopbackPort(SOCK_STREAM); }

} // namespace armadillo::test
