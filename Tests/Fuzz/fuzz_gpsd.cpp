// gpsd's JSON reports as the navigation's gpsd source reads them (Navigation/GpsdSource.h
// readGpsdJson: libgps unpacks the line, then the checks every report gets), and `--gpsd`
// endpoints. Input: lines; each is one report.
#include "FuzzTarget.h"
#include "Navigation/GpsdSource.h"

ARMADILLO_FUZZ_TARGET(gpsd)
{
    using namespace armadillo::navigation;
    const auto text = armadillo::fuzz::text(data, size);
    std::size_t at = 0;
    while (at <= text.size()) {
        const auto end = std::min(text.find('\n', at), text.size());
        PositionFix fix;
        (void)readGpsdJson(text.substr(at, end - at), fix);
        at = end + 1;
    }
    (void)parseGpsdEndpoint(std::string(text.substr(0, std::min<std::size_t>(text.size(), 64))));
}
