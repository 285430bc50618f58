#include "Cli/CommandLine.h"
#include "Cli/Commands.h"

namespace armadillo::cli {

int runPlay(const Arguments& args)
{
    return guarded("play", [&] {
        CommandLine cl("play", "[options]", "Not built yet.", {});
        if (!cl.parse(args)) return 0;
        return notBuiltYet("'armadillo play'");
    });
}

} // namespace armadillo::cli
