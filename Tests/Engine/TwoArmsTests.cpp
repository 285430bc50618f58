// Two arms (docs/STAGE.md): each arm fused by its own tracker, both reaching the scene, the left
// arm's motors through their own tactile engine; and the theremin-duo scene's sound measured
// while one arm at a time moves.
#include "Common/RealtimeGuard.h"
#include "Core/Csv.h"
#include "Core/Pose.h"
#include "Fusion/ArmTracker.h"
#include "Engine/Engine.h"
#include "Engine/RenderSettings.h"
#include "Live/Session/RowClock.h"
#include <catch2/catch.hpp>
#include <cmath>
#include <complex>
#include <functional>
#include <random>
#include <string>

using namespace armadillo;
using namespace armadillo::core;
using namespace armadillo::engine;
using armadillo::live::renderOffline;
using namespace armadillo::fusion;

namespace {
constexpr double kFs = 48000.0;
constexpr double kPiT = 3.14159265358979323846;

/// A pose file at 200 Hz: pose(t) for t in 0..seconds.
CsvTable poses(double seconds, const std::function<Pose(double)>& pose, const std::string& name)
{
    std::string s = "t,elevation,azimuth,roll\n";
    for (int i = 0; i <= static_cast<int>(seconds * 200.0); ++i) {
        const double t = i / 200.0;
        const Pose p = pose(t);
        s += std::to_string(t) + "," + std::to_string(p.elevationDeg) + "," + std::to_string(p.azimuthDeg) + "," + std::to_string(p.rollDeg) + "\n";
    }
    return CsvTable::parse(s, name);
}

/// IMU samples a device would give along pose(t) at 200 Hz (gravity, a 65°-dip field, the gyro
/// from consecutive orientations), plus white noise; as an IMU CSV. Truth returned too.
CsvTable imu(double seconds, const std::function<Pose(double)>& pose, std::uint64_t seed, std::vector<Eigen::Quaterniond>& truth, const std::string& name)
{
    std::mt19937_64 rng(seed);
    std::normal_distribution<double> n(0.0, 1.0);
    const double dip = 65.0 * kPiT / 180.0;
    const Eigen::Vector3d field(0.0, -std::sin(dip), -std::cos(dip));
    std::string s = "t,gx,gy,gz,ax,ay,az,mx,my,mz\n";
    Eigen::Quaterniond previous = poseToQuaternion(pose(0.0));
    for (int i = 0; i <= static_cast<int>(seconds * 200.0); ++i) {
        const double t = i / 200.0;
        const Eigen::Quaterniond q = poseToQuaternion(pose(t));
        truth.push_back(q);
        Eigen::Vector3d w = Eigen::Vector3d::Zero();
        if (i > 0) {
            const Eigen::AngleAxisd d(previous.conjugate() * q);
            w = d.axis() * d.angle() * 200.0;
        }
        previous = q;
        const Eigen::Vector3d g = w + 0.003 * Eigen::Vector3d(n(rng), n(rng), n(rng));
        const Eigen::Vector3d a = q.conjugate() * Eigen::Vector3d(0.0, 9.80665, 0.0) + 0.05 * Eigen::Vector3d(n(rng), n(rng), n(rng));
        const Eigen::Vector3d m = q.conjugate() * field + 0.01 * Eigen::Vector3d(n(rng), n(rng), n(rng));
        s += std::to_string(t);
        for (const double v : {g.x(), g.y(), g.z(), a.x(), a.y(), a.z(), m.x(), m.y(), m.z()}) s += "," + std::to_string(v);
        s += "\n";
    }
    return CsvTable::parse(s, name);
}

double angleDeg(const Eigen::Quaterniond& a, const Eigen::Quaterniond& b) { return 2.0 * std::acos(std::min(1.0, std::fabs(a.dot(b)))) * 180.0 / kPiT; }

/// The strongest frequency 60..2000 Hz of x[from, to) (Hann-windowed DFT, 1 Hz grid then 0.05 Hz).
double peakHz(const std::vector<float>& x, std::size_t from, std::size_t to, double lo = 60.0, double hi = 2000.0)
{
    const std::size_t n = to - from;
    auto power = [&](double hz) {
        std::complex<double> acc {0.0, 0.0}, w {1.0, 0.0};
        const std::complex<double> step = std::polar(1.0, -2.0 * kPiT * hz / kFs);
        for (std::size_t i = 0; i < n; ++i) {
            acc += (0.5 - 0.5 * std::cos(2.0 * kPiT * static_cast<double>(i) / static_cast<double>(n))) * static_cast<double>(x[from + i]) * w;
            w *= step;
        }
        return std::norm(acc);
    };
    double best = lo, bestP = -1.0;
    for (double f = lo; f <= hi; f += 1.0)
        if (const double p = power(f); p > bestP) bestP = p, best = f;
    const double c = best;
    for (double f = c - 1.0; f <= c + 1.0; f += 0.05)
        if (const double p = power(f); p > bestP) bestP = p, best = f;
    return best;
}

/// Share of the signal's energy above 1.5 × its fundamental (first difference against the
/// signal: a brighter tone has relatively more high-frequency energy).
double brightness(const std::vector<float>& x, std::size_t from, std::size_t to)
{
    double e = 0.0, d = 0.0;
    for (std::size_t i = from + 1; i < to; ++i) {
        e += static_cast<double>(x[i]) * static_cast<double>(x[i]);
        const double v = static_cast<double>(x[i]) - static_cast<double>(x[i - 1]);
        d += v * v;
    }
    return d / std::max(e, 1e-20);
}

double rmsOf(const std::vector<float>& x, std::size_t from, std::size_t to)
{
    double s = 0.0;
    for (std::size_t i = from; i < to; ++i) s += static_cast<double>(x[i]) * static_cast<double>(x[i]);
    return std::sqrt(s / static_cast<double>(to - from));
}

/// theremin-duo held still for 1 s with these poses; measured over the last 0.6 s.
struct Heard {
    double hz, bright, rms;
    std::vector<TactileRow> left;
};
Heard duo(Pose right, const Pose* left)
{
    RenderSettings s;
    s.engine.scene = "theremin-duo";
    const CsvTable r = poses(1.0, [&](double) { return right; }, "right.csv");
    CsvTable l;
    if (left) {
        l = poses(1.0, [&](double) { return *left; }, "left.csv");
        s.leftMotion = &l;
        s.engine.twoArms = true;
    }
    const RenderResult out = renderOffline(r, s);
    const auto& x = out.audio.channels[0];
    const auto from = static_cast<std::size_t>(0.4 * kFs), to = static_cast<std::size_t>(1.0 * kFs);
    return {peakHz(x, from, to), brightness(x, from, to), rmsOf(x, from, to), out.leftTactile};
}

double semitonesOf(double hz, double base = 220.0) { return 12.0 * std::log2(hz / base); }
} // namespace

TEST_CASE("two arms: each arm's orientation is fused on its own, as accurate as that arm alone", "[engine][twoarms]")
{
    std::vector<Eigen::Quaterniond> truthRight, truthLeft;
    // Right: elevation swings; left: rolls and turns — different, independent motions.
    const CsvTable right = imu(8.0, [](double t) { return Pose {30.0 * std::sin(0.8 * t), 20.0, 10.0 * std::sin(0.3 * t)}; }, 1, truthRight, "right-imu.csv");
    const CsvTable left = imu(8.0, [](double t) { return Pose {-20.0 + 10.0 * std::sin(0.5 * t), 300.0 + 30.0 * std::sin(0.4 * t), 60.0 * std::sin(1.1 * t)}; }, 2,
                              truthLeft, "left-imu.csv");
    RenderSettings s;
    s.engine.scene = "theremin-duo";
    s.engine.twoArms = true;
    s.leftMotion = &left;
    const RenderResult both = renderOffline(right, s);
    REQUIRE(both.rightOrientation.size() == truthRight.size());
    REQUIRE(both.leftOrientation.size() == truthLeft.size());
    // Each arm alone through its own tracker.
    auto alone = [](const CsvTable& table) {
        ArmTracker tracker;
        std::vector<Eigen::Quaterniond> q;
        for (const ImuSample& sample : readImu(table)) q.push_back(tracker.update(sample).q);
        return q;
    };
    const auto rightAlone = alone(right), leftAlone = alone(left);
    double errRight = 0.0, errLeft = 0.0, errRightAlone = 0.0, errLeftAlone = 0.0, maxDiff = 0.0;
    std::size_t counted = 0;
    for (std::size_t i = 400; i < truthRight.size(); ++i, ++counted) {   // after 2 s of convergence
        errRight += std::pow(angleDeg(both.rightOrientation[i].q, truthRight[i]), 2);
        errLeft += std::pow(angleDeg(both.leftOrientation[i].q, truthLeft[i]), 2);
        errRightAlone += std::pow(angleDeg(rightAlone[i], truthRight[i]), 2);
        errLeftAlone += std::pow(angleDeg(leftAlone[i], truthLeft[i]), 2);
        maxDiff = std::max({maxDiff, angleDeg(both.rightOrientation[i].q, rightAlone[i]), angleDeg(both.leftOrientation[i].q, leftAlone[i])});
    }
    const auto rms = [&](double e) { return std::sqrt(e / static_cast<double>(counted)); };
    std::printf("two arms: RMS orientation error right %.3f deg (alone %.3f), left %.3f deg (alone %.3f); largest difference to alone %.2e deg\n",
                rms(errRight), rms(errRightAlone), rms(errLeft), rms(errLeftAlone), maxDiff);
    CHECK(rms(errRight) <= rms(errRightAlone) + 1e-6);
    CHECK(rms(errLeft) <= rms(errLeftAlone) + 1e-6);
    CHECK(rms(errRight) < 3.0);
    CHECK(rms(errLeft) < 3.0);
    // Independent: the left arm's log is not the right arm's.
    CHECK(angleDeg(both.rightOrientation[1000].q, both.leftOrientation[1000].q) > 20.0);
}

TEST_CASE("two arms: a mount per arm turns each IMU recording from its sensor's axes into the forearm's", "[engine][twoarms][mount]")
{
    // The same motions recorded by sensors strapped on turned (v_sensor = M⁻¹ · v_device, each
    // arm its own M): rendered with each arm's mount, the orientations are those of the recordings
    // made in the forearm's own axes.
    std::vector<Eigen::Quaterniond> tr, tl;
    const CsvTable right = imu(2.0, [](double t) { return Pose {20.0 * std::sin(t), 40.0 + 10.0 * t, 5.0}; }, 11, tr, "right.csv");
    const CsvTable left = imu(2.0, [](double t) { return Pose {-30.0 + 15.0 * t, 250.0, 30.0 * std::cos(t)}; }, 12, tl, "left.csv");
    const Eigen::Quaterniond mr(Eigen::AngleAxisd(kPiT / 2.0, Eigen::Vector3d::UnitZ()));
    const Eigen::Quaterniond ml(Eigen::AngleAxisd(2.0, Eigen::Vector3d(1.0, -1.0, 2.0).normalized()));
    const auto inSensorAxes = [](const CsvTable& table, const Eigen::Quaterniond& m, const std::string& name) {
        std::string s = "t,gx,gy,gz,ax,ay,az,mx,my,mz\n";
        char b[64];
        for (std::size_t r = 0; r < table.rowCount(); ++r) {
            s += std::to_string(table.value(r, 0));
            for (int k = 0; k < 3; ++k) {
                const Eigen::Vector3d v(table.value(r, 1 + 3 * k), table.value(r, 2 + 3 * k), table.value(r, 3 + 3 * k));
                const Eigen::Vector3d sv = m.conjugate() * v;
                for (int c = 0; c < 3; ++c) {
                    std::snprintf(b, sizeof b, ",%.12g", sv[c]);
                    s += b;
                }
            }
            s += "\n";
        }
        return CsvTable::parse(s, name);
    };
    const CsvTable rightS = inSensorAxes(right, mr, "right-sensor.csv"), leftS = inSensorAxes(left, ml, "left-sensor.csv");
    RenderSettings s;
    s.engine.scene = "theremin-duo";
    s.engine.twoArms = true;
    s.leftMotion = &left;
    const RenderResult plain = renderOffline(right, s);
    s.leftMotion = &leftS;
    s.mount = mr;
    s.leftMount = ml;
    const RenderResult mounted = renderOffline(rightS, s);
    s.mount = s.leftMount = Eigen::Quaterniond::Identity();
    const RenderResult unmounted = renderOffline(rightS, s);
    REQUIRE(mounted.leftOrientation.size() == plain.leftOrientation.size());
    double worstR = 0.0, worstL = 0.0, offR = 0.0;
    for (std::size_t i = 0; i < plain.leftOrientation.size(); ++i) {
        worstR = std::max(worstR, angleDeg(mounted.rightOrientation[i].q, plain.rightOrientation[i].q));
        worstL = std::max(worstL, angleDeg(mounted.leftOrientation[i].q, plain.leftOrientation[i].q));
        offR = std::max(offR, angleDeg(unmounted.rightOrientation[i].q, plain.rightOrientation[i].q));
    }
    std::printf("render with a mount per arm: largest difference from the forearm-axes recordings right %.2e deg, left %.2e deg "
                "(without the mounts up to %.1f deg)\n", worstR, worstL, offR);
    CHECK(worstR < 1e-3);   // the files' 12 significant digits
    CHECK(worstL < 1e-3);
    CHECK(offR > 10.0);     // the mount matters: without it the sensor's axes are taken for the forearm's
}

TEST_CASE("theremin-duo: the sound depends on both arms, one arm varied at a time; one arm still plays", "[engine][twoarms]")
{
    const Pose rightLow {-20.0, 0.0, 0.0}, rightHigh {30.0, 0.0, 0.0};
    const Pose leftDark {-40.0, 0.0, 0.0}, leftBright {40.0, 0.0, 0.0}, leftWide {-40.0, 0.0, 90.0}, leftHanging {-80.0, 0.0, 0.0};
    // Right arm moves, left arm still: the pitch follows the right arm (its semitones from the
    // formula with the range the left arm's roll gives: roll 0° → 24 semitones), the timbre stays.
    const auto s = [](double el) { return std::sin(el * kPiT / 180.0); };
    const auto expected = [&](double el, double range) { return range * (s(el) - s(-45.0)) / (s(45.0) - s(-45.0)); };
    const Heard a = duo(rightLow, &leftDark), b = duo(rightHigh, &leftDark);
    CHECK(semitonesOf(a.hz) == Approx(expected(-20.0, 24.0)).margin(0.05));
    CHECK(semitonesOf(b.hz) == Approx(expected(30.0, 24.0)).margin(0.05));
    // Left arm moves, right arm still: the pitch stays, the timbre brightens.
    const Heard c = duo(rightLow, &leftBright);
    CHECK(c.hz == Approx(a.hz).margin(0.5));
    CHECK(c.bright > 2.0 * a.bright);
    // The left arm's roll sets the range: the same right-arm pose plays higher with roll +90°.
    const Heard d = duo(rightHigh, &leftWide);
    CHECK(semitonesOf(d.hz) == Approx(expected(30.0, 36.0)).margin(0.05));
    // The left arm hanging stops the note.
    const Heard e = duo(rightHigh, &leftHanging);
    CHECK(e.rms < 1e-4);
    CHECK(b.rms > 0.05);
    // The left arm's motors: its middle row shows the brightness (its own tactile engine).
    bool leftMiddle = false;
    for (const auto& row : c.left) leftMiddle = leftMiddle || row.levels[4] > 0;
    CHECK(leftMiddle);
    // One arm: still plays (default range 24, default timbre), no left motors.
    const Heard one = duo(rightHigh, nullptr);
    CHECK(semitonesOf(one.hz) == Approx(expected(30.0, 24.0)).margin(0.05));
    CHECK(one.rms > 0.05);
    CHECK(one.left.empty());
}

TEST_CASE("two arms: panic stops both arms' motors; every scene runs with two arms", "[engine][twoarms][panic]")
{
    EngineConfig config;
    config.scene = "theremin-duo";
    config.twoArms = true;
    Engine engine(config);
    ArmState right, left;
    right.valid = left.valid = true;
    right.features.pose = Pose {10.0, 0.0, 0.0};
    left.features.pose = Pose {40.0, 0.0, 0.0};
    right.q = poseToQuaternion(right.features.pose);
    left.q = poseToQuaternion(left.features.pose);
    int leftOn = 0;
    for (int i = 0; i < 100; ++i) {
        right.t = left.t = i * 0.005;
        (void) engine.control(right, left, Transport {}, 0.005);
        for (auto v : engine.leftLevels()) leftOn += v > 0;
    }
    CHECK(leftOn > 0);
    engine.panic();
    (void) engine.control(right, left, Transport {}, 0.005);
    for (auto v : engine.leftLevels()) CHECK(v == 0);
    // Every scene accepts a left arm (and ignores it unless it uses it).
    for (const std::string& name : sceneNames()) {
        if (name == "braille" || name == "score") continue;   // need their text / score
        EngineConfig c;
        c.scene = name;
        c.twoArms = true;
        Engine e(c);
        for (int i = 0; i < 50; ++i) {
            right.t = left.t = i * 0.005;
            (void) e.control(right, left, Transport {}, 0.005);
        }
        INFO(name);
        CHECK_FALSE(e.failed());
    }
}

TEST_CASE("two arms: the control step with both arms and the duo's audio allocate, lock and throw nothing", "[engine][twoarms][realtime]")
{
    ARMADILLO_REQUIRE_GUARD();
    EngineConfig config;
    config.scene = "theremin-duo";
    config.twoArms = true;
    Engine engine(config);
    ArmState right, left;
    right.valid = left.valid = true;
    std::vector<float> l(64), r(64);
    test::RealtimeGuard guard;
    for (int i = 0; i < 4000; ++i) {
        const double t = i * 0.005;
        right.t = left.t = t;
        right.features.pose = Pose {40.0 * std::sin(t), 10.0 * std::sin(0.3 * t), 0.0};
        left.features.pose = Pose {60.0 * std::sin(0.7 * t), 0.0, 90.0 * std::sin(0.2 * t)};
        right.q = poseToQuaternion(right.features.pose);
        left.q = poseToQuaternion(left.features.pose);
        (void) engine.control(right, left, Transport {}, 0.005);
        engine.renderAudio(l.data(), r.data(), 64);
    }
    CHECK(guard.allocations() == 0);
    CHECK(guard.deallocations() == 0);
    CHECK(guard.locks() == 0);
    CHECK(guard.throws() == 0);
}
