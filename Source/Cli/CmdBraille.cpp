#include "Cli/CommandLine.h"
#include "Cli/Commands.h"

namespace armadillo::cli {

int runBraille(const Arguments& args)
{
    return guarded("braille", [&] {
        CommandLine cl("braille", "[options]", "Not built yet.", {});
        if (!cl.parse(args)) return 0;
        return notBuiltYet("'armadillo braille'");
    });
}

} // namespace armadillo::cli
