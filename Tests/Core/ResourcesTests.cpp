// Where the shipped files are found: the built-in copy is the source tree's bytes, folders on
// disk override it in a fixed order, and a user's own scores are listed by name.
#include "Common/ScratchDir.h"
#include "Core/AtomicFile.h"
#include "Core/Errors.h"
#include "Core/Resources.h"
#include <catch2/catch.hpp>
#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <unistd.h>

namespace fs = std::filesystem;
using namespace armadillo;
using namespace armadillo::core;

namespace {

/// Sets an environment variable for one scope and puts the old value back.
class ScopedEnv {
public:
    ScopedEnv(const char* name, const char* value) : name_(name)
    {
        if (const char* old = std::getenv(name)) old_ = old, had_ = true;
        if (value) ::setenv(name, value, 1);
        else ::unsetenv(name);
    }
    ~ScopedEnv()
    {
        if (had_) ::setenv(name_, old_.c_str(), 1);
        else ::unsetenv(name_);
    }

private:
    const char* name_;
    std::string old_;
    bool had_ = false;
};

fs::path tempDir(const std::string& name)
{
    const fs::path p = test::scratchDir("armadillo-res") / name;
    fs::remove_all(p);
    fs::create_directories(p);
    return p;
}

void put(const fs::path& file, const std::string& text)
{
    fs::create_directories(file.parent_path());
    writeFileAtomically(file.string(), text);
}

const ScoreEntry* findScore(const std::vector<ScoreEntry>& list, const std::string& name)
{
    const auto it = std::find_if(list.begin(), list.end(), [&](const ScoreEntry& e) { return e.name == name; });
    return it == list.end() ? nullptr : &*it;
}

} // namespace

TEST_CASE("Resources: the built-in table holds every shipped file with the source tree's bytes", "[resources]")
{
    const fs::path source = fs::path(ARMADILLO_SOURCE_DIR) / "Resources";
    std::size_t onDisk = 0;
    for (const auto& entry : fs::recursive_directory_iterator(source)) {
        if (!entry.is_regular_file() || entry.path().filename() == "README.md") continue;
        const std::string relative = fs::relative(entry.path(), source).generic_string();
        // The web page's files are compiled into the web room alone (cmake/EmbedWeb.cmake);
        // Tests/Web checks them there with the same rule.
        if (relative.rfind("web/", 0) == 0) continue;
        ++onDisk;
        const auto table = embeddedResources();
        const auto it = std::find_if(table.begin(), table.end(), [&](const EmbeddedFile& f) { return f.path == relative; });
        INFO(relative);
        REQUIRE(it != table.end());
        CHECK(it->bytes == readWholeFile(entry.path().string()));
    }
    CHECK(embeddedResources().size() == onDisk);
    CHECK(onDisk >= 4);   // two scores and the braille files at least
}

TEST_CASE("Resources: without any folder the built-in copy is found", "[resources]")
{
    const fs::path home = tempDir("empty-home");
    ScopedEnv h("HOME", home.c_str()), x("XDG_DATA_HOME", nullptr), a("ARMADILLO_RESOURCES", nullptr);
    const auto score = findResource("Scores/rite-of-spring.score");
    REQUIRE(score);
    CHECK(score->origin == "built-in:Scores/rite-of-spring.score");
    CHECK_FALSE(findResource("Scores/no-such.score"));
    CHECK_THROWS_AS(readResource("Scores/no-such.score"), IoError);
    const auto scores = listScores();
    REQUIRE(findScore(scores, "rite-of-spring"));
    REQUIRE(findScore(scores, "polytope"));
    CHECK(userResourceDir() == home.string() + "/.local/share/armadillo");
}

TEST_CASE("Resources: the user folder adds and overrides; ARMADILLO_RESOURCES and an explicit folder come first", "[resources]")
{
    const fs::path data = tempDir("xdg"), env = tempDir("env"), explicitDir = tempDir("explicit");
    ScopedEnv h("HOME", "/nonexistent-home"), x("XDG_DATA_HOME", data.c_str()), a("ARMADILLO_RESOURCES", nullptr);
    CHECK(userResourceDir() == (data / "armadillo").string());

    put(data / "armadillo/Scores/mine.score", "user's own");
    put(data / "armadillo/Scores/polytope.score", "user's polytope");
    put(data / "armadillo/Scores/notes.txt", "not a score");
    auto scores = listScores();
    REQUIRE(findScore(scores, "mine"));
    CHECK(findScore(scores, "mine")->origin == (data / "armadillo/Scores/mine.score").string());
    CHECK(findScore(scores, "polytope")->origin == (data / "armadillo/Scores/polytope.score").string());
    CHECK(findScore(scores, "rite-of-spring")->origin == "built-in:Scores/rite-of-spring.score");
    CHECK_FALSE(findScore(scores, "notes"));
    CHECK(std::is_sorted(scores.begin(), scores.end(), [](const auto& l, const auto& r) { return l.name < r.name; }));
    CHECK(readResource("Scores/polytope.score").bytes == "user's polytope");

    put(env / "Scores/polytope.score", "env polytope");
    ScopedEnv a2("ARMADILLO_RESOURCES", env.c_str());
    CHECK(readResource("Scores/polytope.score").bytes == "env polytope");
    CHECK(readResource("Scores/mine.score").bytes == "user's own");   // still found further down

    put(explicitDir / "Scores/polytope.score", "explicit polytope");
    CHECK(readResource("Scores/polytope.score", explicitDir.string()).bytes == "explicit polytope");
    const auto dirs = resourceSearchDirs(explicitDir.string());
    REQUIRE(dirs.size() == 3);
    CHECK(dirs[0] == explicitDir.string());
    CHECK(dirs[1] == env.string());
    CHECK(dirs[2] == (data / "armadillo").string());
}

TEST_CASE("Resources: a relative XDG_DATA_HOME is ignored, as the XDG rule says", "[resources]")
{
    ScopedEnv h("HOME", "/home/someone"), x("XDG_DATA_HOME", "relative/data");
    CHECK(userResourceDir() == "/home/someone/.local/share/armadillo");
    ScopedEnv h2("HOME", nullptr);
    CHECK(userResourceDir().empty());
}
