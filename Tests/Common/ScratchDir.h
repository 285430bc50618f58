#pragma once
// A test executable's own scratch folder under the system's temporary directory, named
// PREFIX-PID and removed with everything in it when the process ends — so test runs do not
// leave folders behind. Set ARMADILLO_KEEP_TEST_FILES=1 to keep it for a look after a failure.
#include <cstdlib>
#include <filesystem>
#include <map>
#include <string>
#include <system_error>
#include <unistd.h>

namespace armadillo::test {

class ScratchDir {
public:
    explicit ScratchDir(const std::string& prefix)
        : path_(std::filesystem::temp_directory_path() / (prefix + "-" + std::to_string(::getpid())))
    {
        std::filesystem::create_directories(path_);
    }
    ~ScratchDir()
    {
        if (std::getenv("ARMADILLO_KEEP_TEST_FILES") != nullptr) return;
        std::error_code ignored;
        std::filesystem::remove_all(path_, ignored);
    }
    ScratchDir(const ScratchDir&) = delete;
    ScratchDir& operator=(const ScratchDir&) = delete;
    const std::filesystem::path& path() const noexcept { return path_; }

private:
    std::filesystem::path path_;
};

/// The process's scratch folder for `prefix` (made on first use, removed at exit).
inline const std::filesystem::path& scratchDir(const std::string& prefix)
{
    static std::map<std::string, ScratchDir> dirs;
    return dirs.try_emplace(prefix, prefix).first->second.path();
}

} // namespace armadillo::test
