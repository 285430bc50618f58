// The filter on real recordings with optical truth (BROAD, ../shared/data/broad-dev), scored with
// the BROAD/VQF metric in C++: q_err = q_est(ENU) · q_truth⁻¹, total = 2 acos |w|, RMSE over the
// movement phase. Skipped (with a warning) when the data is not there on a developer's clone; in CI
// (CI set in the environment: ../shared is beside every clone CI makes) a missing file fails.
#include "Core/Csv.h"
#include "Fusion/OrientationFilter.h"
#include "Fusion/Quaternion.h"
#include <catch2/catch.hpp>
#include <algorithm>
#include <vector>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <unistd.h>

using namespace armadillo;
using namespace armadillo::core;
using namespace armadillo::fusion;
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

struct Trial {
    std::vector<ImuSample> imu;
    std::vector<Eigen::Quaterniond> truth;   ///< ENU; NaN where the optical truth is missing
    std::vector<bool> movement;
};

Trial loadTrial(const std::string& trial)
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
    Trial out;
    out.imu = imu;
    for (std::size_t k = 0; k < imu.size(); ++k) {
        out.truth.emplace_back(truth.value(k, cw), truth.value(k, cx), truth.value(k, cy), truth.value(k, cz));
        out.movement.push_back(movement.value(k, cm) > 0.5);
    }
    return out;
}

/// BROAD's total error angle (rad) of a filter output (EUS) against the ENU truth; NaN without truth.
double errorAngle(const Eigen::Quaterniond& estimateEus, const Eigen::Quaterniond& truthEnu)
{
    if (!truthEnu.coeffs().allFinite()) return kNaN;
    // EUS (X east, Y up, Z south) → ENU: +90° about x.
    const Eigen::Quaterniond eusToEnu(std::sqrt(0.5), std::sqrt(0.5), 0.0, 0.0);
    const Eigen::Quaterniond e = (eusToEnu * estimateEus) * truthEnu.normalized().conjugate();
    return 2.0 * std::acos(std::min(1.0, std::abs(e.w())));
}

/// Total RMSE in degrees of the filter on one trial.
double broadRmse(const std::string& trial, const OrientationFilter::Params& params = OrientationFilter::defaultParams())
{
    const Trial d = loadTrial(trial);
    OrientationFilter f(params);
    double sum2 = 0.0;
    long n = 0;
    for (std::size_t k = 0; k < d.imu.size(); ++k) {
        f.update(d.imu[k]);
        if (!d.movement[k]) continue;
        const double angle = errorAngle(f.orientation(), d.truth[k]);
        if (!std::isfinite(angle)) continue;
        sum2 += angle * angle;
        ++n;
    }
    REQUIRE(n > 1000);
    return radToDeg(std::sqrt(sum2 / n));
}

/// BROAD's inclination error (rad): the tilt part of the error, 2 acos √(w² + z²) in ENU.
double inclinationAngle(const Eigen::Quaterniond& estimateEus, const Eigen::Quaterniond& truthEnu)
{
    if (!truthEnu.coeffs().allFinite()) return kNaN;
    const Eigen::Quaterniond eusToEnu(std::sqrt(0.5), std::sqrt(0.5), 0.0, 0.0);
    const Eigen::Quaterniond e = ((eusToEnu * estimateEus) * truthEnu.normalized().conjugate()).normalized();
    return 2.0 * std::acos(std::min(1.0, std::sqrt(e.w() * e.w() + e.z() * e.z())));
}

/// Median error in degrees over [from, to) s after samples with t in [gapFrom, gapTo) were cut
/// out (the time column keeps the gap, as a host that stamps arrivals sees it). `tilt`: the
/// inclination error instead of the total.
double medianAfterGap(const Trial& d, double gapFrom, double gapTo, double from, double to,
                      const OrientationFilter::Params& params = OrientationFilter::defaultParams(), bool tilt = false,
                      std::size_t minSamples = 100)
{
    OrientationFilter f(params);
    std::vector<double> errors;
    for (std::size_t k = 0; k < d.imu.size(); ++k) {
        const double t = d.imu[k].t;
        if (t >= gapFrom && t < gapTo) continue;
        f.update(d.imu[k]);
        const double angle = tilt ? inclinationAngle(f.orientation(), d.truth[k]) : errorAngle(f.orientation(), d.truth[k]);
        if (t >= gapTo + from && t < gapTo + to && std::isfinite(angle)) errors.push_back(angle);
    }
    REQUIRE(errors.size() > minSamples);
    std::nth_element(errors.begin(), errors.begin() + static_cast<long>(errors.size() / 2), errors.end());
    return radToDeg(errors[errors.size() / 2]);
}

bool haveData()
{
    return fs::exists(fs::path(ARMADILLO_SHARED_DIR) / "data" / "broad-dev" / "02_undisturbed_slow_rotation_B_imu.csv.gz");
}

/// False (after recording why) when the test must skip; in CI a missing file is a failure.
bool dataOrSkip()
{
    if (haveData()) return true;
    const char* ci = std::getenv("CI");
    if (ci && *ci && std::string(ci) != "false" && std::string(ci) != "0")
        FAIL("BROAD data missing under " ARMADILLO_SHARED_DIR "/data/broad-dev, and CI always has it beside the clone");
    // A developer's clone without ../shared beside it (the data is not part of this repository):
    // say so and skip. SUCCEED records the skip, since ctest runs Catch with --warn NoAssertions.
    WARN("BROAD data not found under " ARMADILLO_SHARED_DIR "/data/broad-dev: skipped");
    SUCCEED("skipped: no BROAD data");
    return false;
}
} // namespace

TEST_CASE("broad: slow rotation and a stationary magnet stay within VQF-class error", "[fusion][broad]")
{
    if (!dataOrSkip()) return;
    // Bounds: VQF on these trials scores 1.38° and 2.38°; the bar is a 2.5° mean.
    const double slow = broadRmse("02_undisturbed_slow_rotation_B");
    INFO("02 slow rotation: " << slow << " deg");
    CHECK(slow < 2.0);
    const double magnet = broadRmse("29_disturbed_stationary_magnet_B");
    INFO("29 stationary magnet: " << magnet << " deg");
    CHECK(magnet < 3.0);
}

TEST_CASE("broad: real movement is re-acquired after dropouts of 0.3 s and 3 s", "[fusion][broad][gaps]")
{
    if (!dataOrSkip()) return;
    // Fast rotation: the hardest to bridge (scripts/bench_gaps.py measures all trials and VQF).
    const Trial d = loadTrial("07_undisturbed_fast_rotation_B");
    for (const double length : {0.3, 3.0}) {
        const double m13 = medianAfterGap(d, 80.0, 80.0 + length, 1.0, 3.0);
        const double m310 = medianAfterGap(d, 80.0, 80.0 + length, 3.0, 10.0);
        INFO("gap " << length << " s at 80 s: median error 1–3 s after " << m13 << "°, 3–10 s " << m310 << "°");
        CHECK(m13 < 5.0);
        CHECK(m310 < 3.0);
    }
}

TEST_CASE("broad: after a dropout in a fast rotation the joint gravity + heading step takes the new orientation", "[fusion][broad][gaps]")
{
    if (!dataOrSkip()) return;
    // Trial 07 at 40 s: during a 0.3 s or 3 s gap the arm turns so far that the orientation kept
    // from before the gap is far off (115° and 41° when the data returns). 0.1 s after the data returns the young
    // averages of accelerometer and field disagree with it by far more than their own error, so
    // the state takes theirs (issue 49, docs/FUSION.md). The probe: without the step
    // (reacquireWindow 0) the orientation kept from before the gap is far off when the data
    // returns (its median over the first 0.08 s, before any step or disagreement rule can act).
    // (Until the gyro step became the trapezoid, the probe was the whole first second without the
    // step, > 60°; the disagreement rule now turns the heading within it, 10° for the 3 s gap.)
    const Trial d = loadTrial("07_undisturbed_fast_rotation_B");
    // Since the field is also observed whole while acquiring (below), the probe switches that off too.
    OrientationFilter::Params noStep = OrientationFilter::defaultParams();
    noStep.reacquireWindow = 0.0;
    noStep.acquireFieldVector = false;
    for (const double length : {0.3, 3.0}) {
        const double with = medianAfterGap(d, 40.0, 40.0 + length, 0.0, 1.0);
        const double without = medianAfterGap(d, 40.0, 40.0 + length, 0.0, 0.08, noStep, false, 20);
        INFO("gap " << length << " s at 40 s: median error 0–1 s after " << with << "° with the step; " << without << "° kept from before the gap");
        CHECK(with < 10.0);
        CHECK(without > 30.0);
    }
}

TEST_CASE("broad: after a dropout in a fast translation the tilt does not follow the young gravity average", "[fusion][broad][gaps]")
{
    if (!dataOrSkip()) return;
    // Trial 16 (fast translation, up to 5 g): for the first half second after a gap the
    // accelerometer's young average is 30–150° off gravity even with a perfect gyro, while the field
    // (undisturbed) is good to 1–4°. While acquiring after a gap the filter observes a trusted field
    // as a whole direction, trusts the young gravity average as little as it misses the field's dip,
    // and lets no young-gravity disagreement level the state (issue 49, docs/FUSION.md). Measured:
    // median tilt error 0–1 s after the gap 1.9°/11.1°/13.1° (0.3 s at 40 s, 1 s at 120 s, 3 s at
    // 40 s; 0.65°/5.98°/9.61° since the third session's young-average weighting); the probe without
    // the field's direction (heading-only, as before) 37.9°/66.5°/81.2° (now 37.9°/66.9°/81.6°).
    const Trial d = loadTrial("16_undisturbed_fast_translation_B");
    OrientationFilter::Params headingOnly = OrientationFilter::defaultParams();
    headingOnly.acquireFieldVector = false;
    headingOnly.reacquireFieldVector = false;
    headingOnly.leverArmTau = 0.0;
    // … and with the young average's error judged as before the third session (∫ ||a| − g| dt,
    // per-sample independent, one joint step): that weighting alone keeps the tilt within
    // 21° of gravity here, so without it the probe would not show what the field's direction does.
    headingOnly.youngMotionTime = 0.0;
    headingOnly.reacquireRepeat = 0.0;
    for (const auto& [at, length] : {std::pair {40.0, 0.3}, std::pair {120.0, 1.0}, std::pair {40.0, 3.0}}) {
        const double with = medianAfterGap(d, at, at + length, 0.0, 1.0, OrientationFilter::defaultParams(), true);
        const double without = medianAfterGap(d, at, at + length, 0.0, 1.0, headingOnly, true);
        INFO("gap " << length << " s at " << at << " s: median tilt error 0–1 s after " << with << "°, heading-only field " << without << "°");
        CHECK(with < 20.0);
        CHECK(without > 30.0);
    }
}

TEST_CASE("broad: after a dropout in a fast turn the young gravity average is weighed by its samples' spread", "[fusion][broad][gaps]")
{
    if (!dataOrSkip()) return;
    // Trial 29 at 40 s, 1 s gap: the arm turns at 8 rad/s and the orientation before the gap is
    // 136° off when the data returns; the young gravity average is tens of degrees off along the cone
    // about the field, and the filter used to follow it round (139° median in the first second).
    // After a gap the young average's error is judged by its samples' spread in the inertial frame
    // (youngMotionTime), counted once per correlation time rather than once per sample
    // (youngCorrelated), and the joint step is taken again as the averages mature (reacquireRepeat;
    // issue 49, third session, docs/FUSION.md). The probe: the three off, as before.
    const Trial d = loadTrial("29_disturbed_stationary_magnet_B");
    OrientationFilter::Params before = OrientationFilter::defaultParams();
    before.youngMotionTime = 0.0;
    before.youngCorrelated = false;
    before.reacquireRepeat = 0.0;
    const double with = medianAfterGap(d, 40.0, 41.0, 0.0, 1.0);
    const double without = medianAfterGap(d, 40.0, 41.0, 0.0, 1.0, before);
    INFO("gap 1 s at 40 s: median error 0–1 s after " << with << "°, as before " << without << "°");
    CHECK(with < 50.0);
    CHECK(without > 100.0);
}

TEST_CASE("broad: after a dropout, a magnet carried with the sensor is taken off the young field", "[fusion][broad][gaps]")
{
    if (!dataOrSkip()) return;
    // Trial 34 (a magnet 3 cm from the sensor): its field is fixed in the device frame (hard iron),
    // so a long average in the inertial frame cancels it as the arm turns, but the young average
    // after a gap does not: 17–28° off in direction at 80 s while passing the norm and dip tests.
    // The filter learns the offset from its steady state and takes it off while the averages are
    // young (issue 49, docs/FUSION.md). Measured 1–3 s after gaps at 80 s: 8.0°/11.6° (0.3 s, 1 s);
    // the probe without the estimate (hardIronTau 0) 20.1°/25.8°. Since the acquisition noise holds
    // after a gap (acquireHoldAfterGap) 5.9°/11.6° and 14.9°/26.4°: the estimate still more than
    // halves the error, which is what the probe checks. Since the young field is taken against the
    // field as the steady filter saw it (reacquireKeepField), that too takes part of the offset
    // off (12.3° without the estimate for the 0.3 s gap): the probe compares with and without the
    // estimate against north alone, and the product check is the defaults'.
    const Trial d = loadTrial("34_disturbed_attached_magnet_3cm");
    OrientationFilter::Params north = OrientationFilter::defaultParams();
    north.reacquireKeepField = false;
    OrientationFilter::Params none = north;
    none.hardIronTau = 0.0;
    for (const double length : {0.3, 1.0}) {
        const double defaults = medianAfterGap(d, 80.0, 80.0 + length, 1.0, 3.0);
        const double with = medianAfterGap(d, 80.0, 80.0 + length, 1.0, 3.0, north);
        const double without = medianAfterGap(d, 80.0, 80.0 + length, 1.0, 3.0, none);
        INFO("gap " << length << " s at 80 s: median error 1–3 s after " << defaults << "°; against north " << with
                    << "°, and without the hard-iron estimate " << without << "°");
        CHECK(defaults < 15.0);
        CHECK(without > 2.0 * with);
    }
}

TEST_CASE("broad: after a dropout in a bent field, the field as the steady filter last saw it keeps the heading", "[fusion][broad][gaps]")
{
    if (!dataOrSkip()) return;
    // Trial 29: a magnet stands near the arm's path. The steady filter holds 1–2° there; after a gap
    // the young field average, taken against magnetic north at the reference dip, pulls the heading
    // to the magnet's bend for the whole acquisition. Taken against the field as the filter saw it
    // in the earth frame just before the gap (reacquireKeepField), it keeps the heading.
    const Trial d = loadTrial("29_disturbed_stationary_magnet_B");
    OrientationFilter::Params north = OrientationFilter::defaultParams();
    north.reacquireKeepField = false;
    for (const auto& [from, length] : {std::pair {80.0, 1.0}, std::pair {40.0, 3.0}}) {
        const double kept = medianAfterGap(d, from, from + length, 1.0, 3.0);
        const double toNorth = medianAfterGap(d, from, from + length, 1.0, 3.0, north);
        INFO("gap " << length << " s at " << from << " s: median error 1–3 s after " << kept << "° with the kept field, " << toNorth
                    << "° against north");
        CHECK(kept < 3.0);
        CHECK(toNorth > 4.0);   // the probe: the case is one where the bend shows
    }
}

TEST_CASE("broad: taps on the arm (trial 25) are shaken off, and it is the shock handling that does it", "[fusion][broad]")
{
    if (!dataOrSkip()) return;
    // Issue 36: a tap makes the accelerometer jump by many g and the gyro misread; the filter adds
    // rotation noise and restarts the field's low-pass (docs/FUSION.md, departure 10). Measured:
    // 1.40° with it, 1.93° without it (the 6 s field average then holds each tap's gyro error);
    // 1.75° before issue 36. The probe run with the handling switched off must show the damage.
    const double with = broadRmse("25_disturbed_tapping_B");
    OrientationFilter::Params off = OrientationFilter::defaultParams();
    off.shockRotationNoise = 0.0;
    off.shockRestartsFieldLowPass = false;
    const double without = broadRmse("25_disturbed_tapping_B", off);
    INFO("25 tapping: " << with << " deg with shock handling, " << without << " deg without");
    CHECK(without > 1.7);
    CHECK(with < 1.5);
}
