#include "Core/AtomicFile.h"
#include "Core/Errors.h"
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fcntl.h>
#include <sys/stat.h>
#include <fstream>
#include <sstream>
#include <unistd.h>

namespace armadillo::core {

void writeFileAtomically(const std::string& path, std::string_view content)
{
    std::string tmpl = path + ".tmp-XXXXXX";
    const int fd = ::mkstemp(tmpl.data());
    if (fd < 0) throw IoError("cannot create a temporary file next to '" + path + "': " + std::strerror(errno));
    const auto fail = [&](const char* what) {
        const std::string reason = std::strerror(errno);
        ::close(fd);
        ::unlink(tmpl.c_str());
        throw IoError(std::string(what) + " '" + path + "': " + reason);
    };
    const char* p = content.data();
    std::size_t left = content.size();
    while (left > 0) {
        const ssize_t n = ::write(fd, p, left);
        if (n < 0) {
            if (errno == EINTR) continue;
            fail("cannot write");
        }
        p += n;
        left -= static_cast<std::size_t>(n);
    }
    if (::fsync(fd) != 0) fail("cannot flush");
    ::fchmod(fd, 0644);
    if (::close(fd) != 0) {
        const std::string reason = std::strerror(errno);
        ::unlink(tmpl.c_str());
        throw IoError("cannot close '" + path + "': " + reason);
    }
    if (::rename(tmpl.c_str(), path.c_str()) != 0) {
        const std::string reason = std::strerror(errno);
        ::unlink(tmpl.c_str());
        throw IoError("cannot replace '" + path + "': " + reason);
    }
}

std::string readWholeFile(const std::string& path)
{
    // Folders and devices are refused by name (a folder would read as an empty file, /dev/zero
    // would never end); pipes are read, up to the same bound as files.
    struct stat st {};
    if (::stat(path.c_str(), &st) == 0) {
        if (S_ISDIR(st.st_mode)) throw IoError("cannot read '" + path + "': it is a folder, not a file");
        if (S_ISCHR(st.st_mode) || S_ISBLK(st.st_mode)) throw IoError("cannot read '" + path + "': it is a device, not a file");
    }
    std::ifstream in(path, std::ios::binary);
    if (!in) throw IoError("cannot open '" + path + "': " + std::strerror(errno));
    std::string out;
    char buffer[1 << 16];
    while (in.read(buffer, sizeof buffer) || in.gcount() > 0) {
        out.append(buffer, static_cast<std::size_t>(in.gcount()));
        if (out.size() > kMaxInputFileBytes)
            throw IoError("cannot read '" + path + "': larger than " + std::to_string(kMaxInputFileBytes >> 20) + " MiB, more than any input needs");
    }
    if (in.bad()) throw IoError("cannot read '" + path + "'");
    return out;
}

} // namespace armadillo::core
