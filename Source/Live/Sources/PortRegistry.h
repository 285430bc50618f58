#pragma once
// Only one ARMadillo (app or plugin instance, in this process or another) owns a serial port at a
// time. A claim is an exclusive flock() on a lock file named after the port: flock conflicts
// between separate open() calls even inside one process, and the kernel drops the lock when a
// crashed owner's process dies, so no stale claim survives. The owner's pid is written inside so
// the others can say who holds the port.
#include <memory>
#include <string>
#include <vector>

namespace armadillo::live {

class PortClaim {
public:
    ~PortClaim();
    PortClaim(const PortClaim&) = delete;
    PortClaim& operator=(const PortClaim&) = delete;
    const std::string& port() const noexcept { return port_; }

private:
    friend class PortRegistry;
    PortClaim(std::string port, int fd) : port_(std::move(port)), fd_(fd) {}
    std::string port_;
    int fd_ = -1;
};

class PortRegistry {
public:
    /// The claim, or nullptr with `whyNot` saying who owns the port.
    static std::unique_ptr<PortClaim> claim(const std::string& port, std::string& whyNot);
    /// Lock file used for a port (exposed for tests).
    static std::string lockFileFor(const std::string& port);
};

} // namespace armadillo::live
