#include "Cli/CommandLine.h"
#include "Cli/Commands.h"

namespace armadillo::cli {

int runFuse(const Arguments& args)
{
    return guarded("fuse", [&] {
        CommandLine cl("fuse", "[options]", "Not built yet.", {});
        if (!cl.parse(args)) return 0;
        return notBuiltYet("'armadillo fuse'");
    });
}

} // namespace armadillo::cli
