#include "Core/AtomicFile.h"
#include "Core/Errors.h"
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <fcntl.h>
#include <sys/stat.h>
#include <fstream>
#include <sstream>
#include <unistd.h>

namespace armadillo::core {

bool isDeviceOrPipe(const std::string& path) noexcept
{
    struct stat st {};
    return ::stat(path.c_str(), &st) == 0 && !S_ISREG(st.st_mode) && !S_ISDIR(st.st_mode);
}

namespace {

/// `content` written through to a device or a pipe that is there already (/dev/null, /dev/stdout,
/// a FIFO): nothing is created, truncated or renamed over it.
void writeThrough(const std::string& path, std::string_view content)
{
    const int fd = ::open(path.c_str(), O_WRONLY | O_CLOEXEC);
    if (fd < 0) throw IoError("cannot write '" + path + "': " + std::strerror(errno));
    const char* p = content.data();
    std::size_t left = content.size();
    while (left > 0) {
        const ssize_t n = ::write(fd, p, left);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) {
            const std::string reason = std::strerror(errno);
            ::close(fd);
            throw IoError("cannot write '" + path + "': " + reason);
        }
        p += n;
        left -= static_cast<std::size_t>(n);
    }
    if (::close(fd) != 0 && errno != EINTR) throw IoError("cannot close '" + path + "': " + std::strerror(errno));
}

} // namespace

void writeFileAtomically(const std::string& path, std::string_view content)
{
    // A temporary renamed over a device would replace the device itself (as root, /dev/null
    // becomes a regular file for the whole system): a device or a pipe is written as it is.
    if (isDeviceOrPipe(path)) {
        writeThrough(path, content);
        return;
    }
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

int openRecording(const std::string& path, std::string& keptAs)
{
    keptAs.clear();
    struct stat st {};
    if (::stat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode)) {
        // The first free PATH.N; RENAME_NOREPLACE so a name that appears meanwhile is not lost.
        for (int n = 1; n <= 9999 && keptAs.empty(); ++n) {
            const std::string aside = path + "." + std::to_string(n);
            if (::renameat2(AT_FDCWD, path.c_str(), AT_FDCWD, aside.c_str(), RENAME_NOREPLACE) == 0) {
                keptAs = aside;
            } else if (errno == EINVAL || errno == ENOSYS) {   // a file system without RENAME_NOREPLACE
                struct stat other {};
                if (::lstat(aside.c_str(), &other) == 0) continue;
                if (::rename(path.c_str(), aside.c_str()) != 0)
                    throw IoError("cannot keep the existing '" + path + "' aside as '" + aside + "': " + std::strerror(errno));
                keptAs = aside;
            } else if (errno != EEXIST) {
                throw IoError("cannot keep the existing '" + path + "' aside as '" + aside + "': " + std::strerror(errno));
            }
        }
        if (keptAs.empty()) throw IoError("cannot keep the existing '" + path + "' aside: " + path + ".1 … .9999 all exist");
    }
    // A device or a pipe (/dev/null) is written as it is; a regular file is new now.
    const bool regular = keptAs.empty() ? ::stat(path.c_str(), &st) != 0 || S_ISREG(st.st_mode) : true;
    const int fd = ::open(path.c_str(), O_WRONLY | O_CLOEXEC | (regular ? O_CREAT | O_TRUNC : 0), 0644);
    if (fd < 0) {
        const std::string reason = std::strerror(errno);
        if (!keptAs.empty()) ::rename(keptAs.c_str(), path.c_str());
        keptAs.clear();
        throw IoError("cannot write " + path + ": " + reason);
    }
    return fd;
}

void abandonRecording(const std::string& path, const std::string& keptAs) noexcept
{
    struct stat st {};
    if (::stat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode)) ::unlink(path.c_str());
    if (!keptAs.empty()) ::rename(keptAs.c_str(), path.c_str());
}

std::string keptAsideNote(const std::string& path, const std::string& keptAs)
{
    return keptAs.empty() ? std::string() : "'" + path + "' existed: kept as '" + keptAs + "'";
}

RecordingFile::RecordingFile(std::string path) : path_(std::move(path))
{
    fd_ = openRecording(path_, keptAs_);
}

RecordingFile::~RecordingFile()
{
    if (fd_ < 0) return;
    ::close(fd_);
    if (!wrote_) abandonRecording(path_, keptAs_);
}

void RecordingFile::append(std::string_view rows)
{
    if (fd_ < 0) throw IoError("cannot write " + path_ + ": already closed");
    const char* p = rows.data();
    std::size_t left = rows.size();
    while (left > 0) {
        const ssize_t n = ::write(fd_, p, left);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) throw IoError("cannot write " + path_ + ": " + std::strerror(n < 0 ? errno : ENOSPC));
        p += n;
        left -= static_cast<std::size_t>(n);
        wrote_ = true;
    }
    const double now = std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
    if (now - syncedAt_ >= 1.0) {
        ::fdatasync(fd_);
        syncedAt_ = now;
    }
}

void RecordingFile::finish()
{
    if (fd_ < 0) return;
    const bool synced = ::fsync(fd_) == 0;
    const int e = errno;
    const bool closed = ::close(fd_) == 0;
    fd_ = -1;
    wrote_ = true;   // (closed: the destructor leaves it)
    if (!synced || !closed) throw IoError("cannot write " + path_ + ": " + std::strerror(synced ? errno : e));
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
