// Cost of one OrientationFilter::update() (issue 4 target: ≤ 10 µs on one core; the thesis took
// 480 µs). Prints numbers, never passes or fails on time. Input: a BROAD trial if present
// (real motion, magnetometer disturbances), otherwise a synthetic stream.
//   bench_fusion [IMU.csv]      (scripts/bench-fusion.sh adds the VQF comparison)
#include "Core/Csv.h"
#include "Fusion/OrientationFilter.h"
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

using namespace armadillo;
using namespace armadillo::core;
using namespace armadillo::fusion;

namespace {
std::vector<ImuSample> syntheticStream(std::size_t n)
{
    std::vector<ImuSample> out(n);
    for (std::size_t k = 0; k < n; ++k) {
        const double t = static_cast<double>(k) / 285.714;
        ImuSample& s = out[k];
        s.t = t;
        s.gyro = Eigen::Vector3d(std::sin(t), 0.5 * std::cos(1.3 * t), 0.2);
        s.accel = Eigen::Vector3d(0.3 * std::sin(2 * t), 9.7, 0.5 * std::cos(t));
        s.mag = Eigen::Vector3d(15.0 * std::cos(0.2 * t), -40.0, 15.0 * std::sin(0.2 * t));
    }
    return out;
}
} // namespace

int main(int argc, char** argv)
{
    std::vector<ImuSample> samples;
    std::string source = "synthetic";
    std::string path = argc > 1 ? argv[1] : "";
    if (path.empty()) {
        const std::filesystem::path gz = std::filesystem::path(ARMADILLO_SHARED_DIR) / "data" / "broad-dev" / "07_undisturbed_fast_rotation_B_imu.csv.gz";
        if (std::filesystem::exists(gz)) {
            path = (std::filesystem::temp_directory_path() / "armadillo-bench-fusion-imu.csv").string();
            const std::string cmd = "gzip -dc '" + gz.string() + "' > '" + path + "'";
            if (std::system(cmd.c_str()) != 0) path.clear();
        }
    }
    if (!path.empty()) {
        samples = readImu(CsvTable::read(path));
        source = path;
    } else {
        samples = syntheticStream(50000);
    }

    double best = 1e300, total = 0.0;
    const int repeats = 5;
    for (int r = 0; r < repeats; ++r) {
        OrientationFilter f;
        const auto t0 = std::chrono::steady_clock::now();
        for (const ImuSample& s : samples) f.update(s);
        const auto t1 = std::chrono::steady_clock::now();
        const double us = std::chrono::duration<double, std::micro>(t1 - t0).count() / static_cast<double>(samples.size());
        best = std::min(best, us);
        total += us;
        if (!f.orientation().coeffs().allFinite()) std::printf("warning: non-finite output\n");
    }
    std::printf("input: %s (%zu samples)\n", source.c_str(), samples.size());
    std::printf("OrientationFilter::update: best %.3f us, mean %.3f us per sample (%d runs)\n", best, total / repeats, repeats);
    std::printf("real-time factor at 285.7 Hz: %.0fx; thesis (480 us): %.0fx faster\n", 1e6 / 285.714 / best, 480.0 / best);
    std::printf("ARMADILLO_US_PER_UPDATE=%.4f\n", best);
    return 0;
}
