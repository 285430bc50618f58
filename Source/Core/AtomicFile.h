#pragma once
#include <string>
#include <string_view>

namespace armadillo::core {

/// Whether `path` is there and is neither a regular file nor a folder: a device (/dev/null,
/// /dev/stdout through /proc), a FIFO or a socket. Such an output is written as it is, never
/// replaced by a temporary renamed over it (which, as root, would turn /dev/null into a file).
bool isDeviceOrPipe(const std::string& path) noexcept;

/// Writes `content` to `path` whole or not at all: a temporary file in the same folder, flushed
/// to disk, then renamed over the target. Throws IoError naming the path on any failure, and
/// leaves no temporary behind. A device or a pipe already at `path` (isDeviceOrPipe) is written
/// through instead, left in place.
void writeFileAtomically(const std::string& path, std::string_view content);

/// A recording that grows while a session runs (the live session's audio, logs and tactile CSV):
/// written in place under its own name, so a crash leaves what was written so far. A regular
/// file already at `path` is never overwritten or half-replaced: it is first kept aside as the
/// first free `PATH.1`, `PATH.2`, … (`keptAs` gets that name, "" when there was none). Returns an
/// open descriptor for writing (O_CLOEXEC); throws IoError naming the path when it cannot.
int openRecording(const std::string& path, std::string& keptAs);
/// A recording that ended with nothing in it (the session never played): removed, and the file
/// kept aside (if any) put back under its own name. Never throws.
void abandonRecording(const std::string& path, const std::string& keptAs) noexcept;
/// "'PATH' existed: kept as 'PATH.1'" for the session's messages; "" when nothing was kept aside.
std::string keptAsideNote(const std::string& path, const std::string& keptAs);

/// A text recording appended as a session goes (the navigation log, a training log): opened
/// with openRecording (an existing file kept aside), each append() one write of whole rows, the
/// data synced to disk at most once a second. Not real-time: for a front end's loop or a writer
/// thread.
class RecordingFile {
public:
    explicit RecordingFile(std::string path);   ///< IoError naming the path
    /// Closes; a file that got nothing is removed and the one kept aside put back.
    ~RecordingFile();
    RecordingFile(const RecordingFile&) = delete;
    RecordingFile& operator=(const RecordingFile&) = delete;
    /// Whole rows (ending in a newline); IoError naming the file when it cannot be written.
    void append(std::string_view rows);
    /// Syncs and closes; IoError naming the file on failure.
    void finish();
    const std::string& path() const noexcept { return path_; }
    const std::string& keptAs() const noexcept { return keptAs_; }

private:
    std::string path_, keptAs_;
    int fd_ = -1;
    bool wrote_ = false;
    double syncedAt_ = 0.0;
};

/// Largest file readWholeFile reads (motion files of hours at 1 kHz stay far below it).
inline constexpr std::size_t kMaxInputFileBytes = std::size_t(1) << 30;
/// Reads a whole file; throws IoError naming the path when it cannot be read, is a folder or a
/// device, or is larger than kMaxInputFileBytes.
std::string readWholeFile(const std::string& path);

} // namespace armadillo::core
