// GPX routes for walking navigation (Navigation/Route.h parseGpx: pugixml, then our checks).
#include "FuzzTarget.h"
#include "Navigation/Route.h"

ARMADILLO_FUZZ_TARGET(gpx)
{
    const auto route = armadillo::navigation::parseGpx(armadillo::fuzz::text(data, size), "fuzz.gpx");
    (void)route.lengthM();
}
