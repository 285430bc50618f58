#include "Live/Sources/PortRegistry.h"
#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

namespace armadillo::live {

PortClaim::~PortClaim()
{
    if (fd_ >= 0) {
        if (ftruncate(fd_, 0) != 0) { /* the lock is what matters; a stale pid is harmless */ }
        flock(fd_, LOCK_UN);
        close(fd_);
    }
}

std::string PortRegistry::lockFileFor(const std::string& port)
{
    std::string safe;
    for (char c : port) safe += (std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '-') ? c : '_';
    const char* dir = std::getenv("XDG_RUNTIME_DIR");
    std::string base = (dir != nullptr && *dir != '\0') ? dir : "/tmp";
    return base + "/armadillo-port-" + safe + ".lock";
}

std::unique_ptr<PortClaim> PortRegistry::claim(const std::string& port, std::string& whyNot)
{
    whyNot.clear();
    if (port.empty()) {
        whyNot = "no port chosen";
        return nullptr;
    }
    const auto path = lockFileFor(port);
    const int fd = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (fd < 0) {
        whyNot = "cannot create lock file " + path + ": " + std::strerror(errno);
        return nullptr;
    }
    if (flock(fd, LOCK_EX | LOCK_NB) != 0) {
        char buffer[32] {};
        const auto n = pread(fd, buffer, sizeof(buffer) - 1, 0);
        const long pid = n > 0 ? std::strtol(buffer, nullptr, 10) : 0;
        close(fd);
        whyNot = port + " is owned by another ARMadillo instance";
        if (pid > 0) whyNot += pid == static_cast<long>(getpid()) ? " in this program" : " (process " + std::to_string(pid) + ")";
        return nullptr;
    }
    const auto pid = std::to_string(getpid()) + "\n";
    if (ftruncate(fd, 0) != 0 || pwrite(fd, pid.data(), pid.size(), 0) != static_cast<ssize_t>(pid.size())) {
        // The claim holds without the pid; others just cannot name the owner.
    }
    return std::unique_ptr<PortClaim>(new PortClaim(port, fd));
}

} // namespace armadillo::live
