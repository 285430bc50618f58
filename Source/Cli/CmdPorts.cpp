#include "Cli/CommandLine.h"
#include "Cli/Commands.h"

namespace armadillo::cli {

int runPorts(const Arguments& args)
{
    return guarded("ports", [&] {
        CommandLine cl("ports", "[options]", "Not built yet.", {});
        if (!cl.parse(args)) return 0;
        return notBuiltYet("'armadillo ports'");
    });
}

} // namespace armadillo::cli
