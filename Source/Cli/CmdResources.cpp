#include "Cli/CommandLine.h"
#include "Cli/Commands.h"
#include "Core/AtomicFile.h"
#include "Core/Errors.h"
#include "Core/Resources.h"
#include "Mapping/MappingSpec.h"
#include <filesystem>
#include <iostream>

namespace armadillo::cli {

int runResources(const Arguments& args)
{
    return guarded("resources", [&] {
        CommandLine cl("resources", "[--scores | --mappings] [--export DIR]",
                       "Lists where ARMadillo looks for its files and the tactile scores it can play by name.\n"
                       "Files are searched in $ARMADILLO_RESOURCES, then the user folder ($XDG_DATA_HOME/armadillo,\n"
                       "or ~/.local/share/armadillo), then among the files built into the program; the first wins.\n"
                       "A score of your own: put NAME.score into <folder>/Scores/ and play it with --score NAME;\n"
                       "a mapping preset of your own: put NAME.json into <folder>/Mappings/ and use it with --map NAME.",
                       {{"--scores", "", "print only the score names, one a line"},
                        {"--mappings", "", "print only the mapping preset names (--map PRESET), one a line"},
                        {"--export", "DIR", "write the built-in files (scores, braille lists, examples) into DIR"}});
        if (!cl.parse(args)) return 0;
        if (cl.has("--export")) {
            const std::filesystem::path dir = cl.value("--export");
            for (const core::EmbeddedFile& f : core::embeddedResources()) {
                const std::filesystem::path target = dir / std::filesystem::path(f.path);
                std::error_code ec;
                std::filesystem::create_directories(target.parent_path(), ec);
                if (ec) throw core::IoError("cannot create '" + target.parent_path().string() + "': " + ec.message());
                core::writeFileAtomically(target.string(), f.bytes);
                std::cout << target.string() << "\n";
            }
            return 0;
        }
        if (cl.has("--mappings")) {
            for (const std::string& n : mapping::presetNames()) std::cout << n << "\n";
            return 0;
        }
        const auto scores = core::listScores();
        if (cl.has("--scores")) {
            for (const core::ScoreEntry& s : scores) std::cout << s.name << "\n";
            return 0;
        }
        std::cout << "search folders (first match wins, then the built-in files):\n";
        for (const std::string& d : core::resourceSearchDirs())
            std::cout << "  " << d << (std::filesystem::is_directory(d) ? "" : "   (absent)") << "\n";
        std::cout << "scores:\n";
        for (const core::ScoreEntry& s : scores) {
            std::string name = "  " + s.name;
            if (name.size() < 24) name.resize(24, ' ');
            std::cout << name << " " << s.origin << "\n";
        }
        std::cout << "mapping presets (--map NAME):\n";
        for (const std::string& n : mapping::presetNames()) {
            std::string name = "  " + n;
            if (name.size() < 24) name.resize(24, ' ');
            const auto found = core::findResource("Mappings/" + n + ".json");
            std::cout << name << " " << (found ? found->origin : std::string("?")) << "\n";
        }
        std::cout << "built-in files:\n";
        for (const core::EmbeddedFile& f : core::embeddedResources()) std::cout << "  " << f.path << " (" << f.bytes.size() << " bytes)\n";
        return 0;
    });
}

} // namespace armadillo::cli
