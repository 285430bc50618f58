// CSV tables (Core/Csv.h): motion recordings (IMU, quaternions, poses) and tactile rows, as
// `render`, `score` and the tests read them.
#include "Core/Csv.h"
#include "FuzzTarget.h"

ARMADILLO_FUZZ_TARGET(csv)
{
    using namespace armadillo::core;
    const CsvTable table = CsvTable::parse(armadillo::fuzz::text(data, size), "fuzz.csv");
    try { (void)readImu(table); } catch (const InputError&) {}
    try { (void)readQuaternions(table); } catch (const InputError&) {}
    try { (void)readPoses(table); } catch (const InputError&) {}
    int motors = 0;
    try { (void)readTactile(table, &motors); } catch (const InputError&) {}
}
