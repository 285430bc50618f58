#include "FuzzTarget.h"
#include <cstdio>
#include <unistd.h>

namespace armadillo::fuzz {

std::vector<Target>& registry()
{
    static std::vector<Target> targets;
    return targets;
}

std::string scratchFile(const char* target, const char* extension, const std::uint8_t* data, std::size_t size)
{
    // /dev/shm when there is one (no disk traffic at thousands of runs a second), else /tmp.
    const char* dir = access("/dev/shm", W_OK) == 0 ? "/dev/shm" : "/tmp";
    const std::string path = std::string(dir) + "/armadillo-fuzz-" + target + "-" + std::to_string(getpid()) + extension;
    std::FILE* f = std::fopen(path.c_str(), "wb");
    if (!f) throw core::IoError("cannot write " + path);
    if (size > 0 && std::fwrite(data, 1, size, f) != size) {
        std::fclose(f);
        throw core::IoError("cannot write " + path);
    }
    std::fclose(f);
    return path;
}

} // namespace armadillo::fuzz
