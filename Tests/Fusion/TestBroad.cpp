// The filter on real recordings with optical truth (BROAD, ../shared/data/broad-dev), scored with
// the BROAD/VQF metric in C++: q_err = q_est(ENU) · q_truth⁻¹, total = 2 acos |w|, RMSE over the
// movement phase. Skipped (with a warning) when the data is not there.
#include "Core/Csv.h"
#include "Fusion/OrientationFilter.h"
#include "Fusion/Quaternion.h"
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <unistd.h>

using namespace armadillo;
namespace fs = std::filesystem;

namespace {
/// gunzip to a temporary file and parse it with the project's CSV reader.
CsvTable readGz(const fs::path& gz, const fs::path& tmpDir)
{
    const fs::path out = tmpDir / gz.stem();
    const std::string cmd = "gzip -dc '" + gz.string() + "' > '" + out.string() + "'";
    REQUIRE(std::system(cmd.c_str()) == 0);
    return CsvTable::read(out.string());
}

/// Total RMSE in degrees of the filter on one trial.
double broadRmse(const std::string& trial)
{
    const fs::path dir = fs::path(ARMADILLO_SHARED_DIR) / "data" / "broad-dev";
    const fs::path tmp = fs::temp_directory_path() / ("armadillo-broad-" + std::to_string(::getpid()));
    fs::create_directories(tmp);
    const std::vector<ImuSample> imu = readImu(readGz(dir / (trial + "_imu.csv.gz"), tmp));
    const CsvTable truth = readGz(dir / (trial + "_truth.csv.gz"), tmp);
    const CsvTable movement = readGz(dir / (trial + "_movement.csv.gz"), tmp);
    fs::remove_all(tmp);
    REQUIRE(truth.rowCount() == imu.size());
    REQUIRE(movement.rowCount() == imu.size());
    const int cw = truth.requireColumn("qw"), cx = truth.requireColumn("qx"), cy = truth.requireColumn("qy"),
              cz = truth.requireColumn("qz"), cm = movement.requireColumn("movement");
    // EUS (X east, Y up, Z south) → ENU: +90° about x.
    const Eigen::Quaterniond eusToEnu(std::sqrt(0.5), std::sqrt(0.5), 0.0, 0.0);
    OrientationFilter f;
    double sum2 = 0.0;
    long n = 0;
    for (std::size_t k = 0; k < imu.size(); ++k) {
        f.update(imu[k]);
        if (!(movement.value(k, cm) > 0.5)) continue;
        const Eigen::Quaterniond t(truth.value(k, cw), truth.value(k, cx), truth.value(k, cy), truth.value(k, cz));
        if (!t.coeffs().allFinite()) continue;
        const Eigen::Quaterniond e = (eusToEnu * f.orientation()) * t.normalized().conjugate();
        const double angle = 2.0 * std::acos(std::min(1.0, std::abs(e.w())));
        sum2 += angle * angle;
        ++n;
    }
    REQUIRE(n > 1000);
    return radToDeg(std::sqrt(sum2 / n));
}

bool haveData()
{
    return fs::exists(fs::path(ARMADILLO_SHARED_DIR) / "data" / "broad-dev" / "02_undisturbed_slow_rotation_B_imu.csv.gz");
}
} // namespace

TEST_CASE("broad: slow rotation and a stationary magnet stay within VQF-class error", "[fusion][broad]")
{
    if (!haveData()) {
        // A clone without ../shared beside it (the data is not part of this repository): say so
        // and skip. SUCCEED records the skip, since ctest runs Catch with --warn NoAssertions.
        WARN("BROAD data not found under " ARMADILLO_SHARED_DIR "/data/broad-dev: skipped");
        SUCCEED("skipped: no BROAD data");
        return;
    }
    // Bounds: VQF on these trials scores 1.38° and 2.38°; the bar is a 2.5° mean.
    const double slow = broadRmse("02_undisturbed_slow_rotation_B");
    INFO("02 slow rotation: " << slow << " deg");
    CHECK(slow < 2.0);
    const double magnet = broadRmse("29_disturbed_stationary_magnet_B");
    INFO("29 stationary magnet: " << magnet << " deg");
    CHECK(magnet < 3.0);
}
