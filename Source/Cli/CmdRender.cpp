#include "Cli/CommandLine.h"
#include "Cli/Commands.h"

namespace armadillo::cli {

int runRender(const Arguments& args)
{
    return guarded("render", [&] {
        CommandLine cl("render", "[options]", "Not built yet.", {});
        if (!cl.parse(args)) return 0;
        return notBuiltYet("'armadillo render'");
    });
}

} // namespace armadillo::cli
