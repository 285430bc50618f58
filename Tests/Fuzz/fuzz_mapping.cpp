// Mapping files (Mapping/MappingSpec.h parseMappingDocument), a parsed document compiled as the
// front ends do (MappingSet::build) and written back as JSON and read again.
#include "FuzzTarget.h"
#include "Mapping/Mapper.h"
#include "Mapping/MappingSpec.h"

ARMADILLO_FUZZ_TARGET(mapping)
{
    using namespace armadillo::mapping;
    const MappingDocument doc = parseMappingDocument(armadillo::fuzz::text(data, size), "fuzz.json");
    const std::string again = toJson(doc);
    (void)parseMappingDocument(again, "fuzz.json (written back)");
    (void)MappingSet::build(doc);
}
