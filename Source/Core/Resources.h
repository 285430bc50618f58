#pragma once
// The files ARMadillo ships (tactile scores, braille word lists, example motion files, an
// example calibration) and where they are found. The bytes of Resources/ are compiled into the
// core (cmake/EmbedResources.cmake), so the CLI and the plugin work wherever they are copied;
// folders on disk add files or override the built-in ones. Nothing here runs on the audio thread.
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace armadillo::core {

/// One file of Resources/, by its path relative to that folder ("Scores/polytope.score").
struct EmbeddedFile {
    std::string_view path;
    std::string_view bytes;
};

/// Every file compiled in (generated at build time), sorted by path.
std::span<const EmbeddedFile> embeddedResources() noexcept;

/// The user's own folder: $XDG_DATA_HOME/armadillo, or ~/.local/share/armadillo when
/// XDG_DATA_HOME is unset or not absolute (the XDG base-directory rule). Empty without HOME.
std::string userResourceDir();

/// The folders searched, first match wins: `extraDir` (SceneConfig::resourceDir, when not
/// empty), $ARMADILLO_RESOURCES, then the user folder. The built-in files come after them all.
std::vector<std::string> resourceSearchDirs(const std::string& extraDir = {});

/// A found file: its contents and where they came from (a path, or "built-in:Scores/x.score").
struct ResourceFile {
    std::string bytes;
    std::string origin;
};

/// The file `relative` (e.g. "Braille/signwords.txt") from the first folder that has it, else
/// the built-in copy; nullopt when neither has it. IoError when a file exists but cannot be read.
std::optional<ResourceFile> findResource(std::string_view relative, const std::string& extraDir = {});

/// As findResource, but IoError naming the places searched when the file is nowhere.
ResourceFile readResource(std::string_view relative, const std::string& extraDir = {});

/// A tactile score that can be asked for by name (--score NAME, the plugin's score setting).
struct ScoreEntry {
    std::string name;     ///< file name without ".score"
    std::string origin;   ///< the file that wins for this name (a path or "built-in:…")
};

/// Every score name: Scores/*.score in the search folders and built in, sorted by name, each
/// with the copy that readResource would use.
std::vector<ScoreEntry> listScores(const std::string& extraDir = {});

} // namespace armadillo::core
