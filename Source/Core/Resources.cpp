// Finding the shipped files: search folders first (a user's own files win), then the bytes the
// build compiled in. See Core/Resources.h.
#include "Core/Resources.h"
#include "Core/AtomicFile.h"
#include "Core/Errors.h"
#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <system_error>

namespace armadillo::core {

namespace fs = std::filesystem;

namespace {

std::string environment(const char* name)
{
    const char* value = std::getenv(name);
    return value != nullptr ? std::string(value) : std::string();
}

bool isRegularFile(const fs::path& path)
{
    std::error_code ec;
    return fs::is_regular_file(path, ec);
}

} // namespace

std::string userResourceDir()
{
    const std::string xdg = environment("XDG_DATA_HOME");
    if (!xdg.empty() && xdg.front() == '/') return xdg + "/armadillo";
    const std::string home = environment("HOME");
    if (home.empty()) return {};
    return home + "/.local/share/armadillo";
}

std::vector<std::string> resourceSearchDirs(const std::string& extraDir)
{
    std::vector<std::string> dirs;
    auto add = [&dirs](const std::string& d) {
        if (!d.empty() && std::find(dirs.begin(), dirs.end(), d) == dirs.end()) dirs.push_back(d);
    };
    add(extraDir);
    add(environment("ARMADILLO_RESOURCES"));
    add(userResourceDir());
    return dirs;
}

std::optional<ResourceFile> findResource(std::string_view relative, const std::string& extraDir)
{
    for (const std::string& dir : resourceSearchDirs(extraDir)) {
        const fs::path path = fs::path(dir) / fs::path(relative);
        if (isRegularFile(path)) return ResourceFile {readWholeFile(path.string()), path.string()};
    }
    for (const EmbeddedFile& f : embeddedResources())
        if (f.path == relative) return ResourceFile {std::string(f.bytes), "built-in:" + std::string(relative)};
    return std::nullopt;
}

ResourceFile readResource(std::string_view relative, const std::string& extraDir)
{
    if (auto found = findResource(relative, extraDir)) return std::move(*found);
    std::string where;
    for (const std::string& dir : resourceSearchDirs(extraDir)) where += "'" + dir + "', ";
    throw IoError("cannot find resource '" + std::string(relative) + "' (looked in " + where +
                  "and the files built into this program)");
}

std::vector<ScoreEntry> listScores(const std::string& extraDir)
{
    std::map<std::string, std::string> byName;   // name → origin; the first folder found wins
    for (const std::string& dir : resourceSearchDirs(extraDir)) {
        std::error_code ec;
        for (fs::directory_iterator it(fs::path(dir) / "Scores", ec), end; !ec && it != end; it.increment(ec)) {
            const fs::path& p = it->path();
            if (p.extension() != ".score" || !isRegularFile(p)) continue;
            byName.try_emplace(p.stem().string(), p.string());
        }
    }
    constexpr std::string_view prefix = "Scores/", suffix = ".score";
    for (const EmbeddedFile& f : embeddedResources()) {
        if (!f.path.starts_with(prefix) || !f.path.ends_with(suffix)) continue;
        const std::string_view name = f.path.substr(prefix.size(), f.path.size() - prefix.size() - suffix.size());
        if (name.find('/') != std::string_view::npos) continue;
        byName.try_emplace(std::string(name), "built-in:" + std::string(f.path));
    }
    std::vector<ScoreEntry> out;
    for (auto& [name, origin] : byName) out.push_back({name, origin});
    return out;
}

} // namespace armadillo::core
