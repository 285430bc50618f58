#pragma once
#include <string>
#include <string_view>

namespace armadillo::core {

/// Writes `content` to `path` whole or not at all: a temporary file in the same folder, flushed
/// to disk, then renamed over the target. Throws IoError naming the path on any failure, and
/// leaves no temporary behind.
void writeFileAtomically(const std::string& path, std::string_view content);

/// Largest file readWholeFile reads (motion files of hours at 1 kHz stay far below it).
inline constexpr std::size_t kMaxInputFileBytes = std::size_t(1) << 30;
/// Reads a whole file; throws IoError naming the path when it cannot be read, is a folder or a
/// device, or is larger than kMaxInputFileBytes.
std::string readWholeFile(const std::string& path);

} // namespace armadillo::core
