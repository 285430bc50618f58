// The fuzz targets' bodies compiled normally (GCC, no libFuzzer): every seed of
// Tests/Fuzz/corpus/<target>/ and every input that ever crashed a target
// (Tests/Fuzz/regressions/<target>/, docs/SECURITY.md "Fuzzing") goes through the same entry
// functions. Passing means: nothing crashed and nothing but the expected refusals was thrown.
#include "FuzzTarget.h"
#include <catch2/catch.hpp>
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <set>
#include <sstream>

namespace fs = std::filesystem;
using armadillo::fuzz::registry;

namespace {

const fs::path kFuzzDir = fs::path(ARMADILLO_SOURCE_DIR) / "Tests" / "Fuzz";

std::vector<std::uint8_t> readBytes(const fs::path& p)
{
    std::ifstream in(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

std::vector<fs::path> filesOf(const fs::path& dir)
{
    std::vector<fs::path> out;
    if (!fs::is_directory(dir)) return out;
    for (const auto& e : fs::directory_iterator(dir))
        if (e.is_regular_file()) out.push_back(e.path());
    std::sort(out.begin(), out.end());
    return out;
}

std::set<std::string> listedNames()
{
    std::set<std::string> names;
    std::stringstream s(ARMADILLO_FUZZ_NAMES);
    for (std::string n; std::getline(s, n, ',');) names.insert(n);
    return names;
}

} // namespace

TEST_CASE("every fuzz target listed in CMake is registered once, with a seed corpus", "[fuzz]")
{
    const auto listed = listedNames();
    std::set<std::string> registered;
    for (const auto& t : registry()) {
        INFO(t.name);
        CHECK(registered.insert(t.name).second);
    }
    CHECK(registered == listed);
    CHECK(registered.size() >= 12);
    for (const auto& name : listed) {
        INFO("Tests/Fuzz/corpus/" << name << "/ holds the target's seeds");
        CHECK(!filesOf(kFuzzDir / "corpus" / name).empty());
    }
    // A directory of regressions or seeds for a target that does not exist is a typo.
    for (const char* kind : {"corpus", "regressions"})
        for (const auto& e : fs::directory_iterator(kFuzzDir / kind))
            if (e.is_directory()) {
                INFO(e.path());
                CHECK(listed.count(e.path().filename().string()) == 1);
            }
}

TEST_CASE("the seed corpora and every input that ever crashed go through the targets", "[fuzz]")
{
    std::size_t inputs = 0, regressions = 0;
    for (const auto& t : registry()) {
        for (const char* kind : {"corpus", "regressions"}) {
            for (const auto& file : filesOf(kFuzzDir / kind / t.name)) {
                const auto bytes = readBytes(file);
                INFO(t.name << ": " << file.string());
                // Anything but the expected refusals escapes runGuarded and fails here; a crash
                // or a hang fails the whole test.
                CHECK_NOTHROW(armadillo::fuzz::runGuarded(t.body, bytes.data(), bytes.size()));
                ++inputs;
                if (std::string(kind) == "regressions") ++regressions;
            }
        }
    }
    INFO(inputs << " inputs, " << regressions << " of them regressions");
    CHECK(inputs >= registry().size());
    WARN("fuzz replay: " << inputs << " inputs through " << registry().size() << " targets (" << regressions << " regressions)");
}
