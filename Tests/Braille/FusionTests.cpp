// End to end with the real orientation filter: synthetic IMU samples of a reader's arm (gravity,
// magnetic field and gyro, with gyro bias and noise) → SR-UKF → roll reader. The text must
// advance in proportion to the roll and never while the arm is still, however biased the gyro.
#include "Braille/RollReader.h"
#include "Fusion/OrientationFilter.h"
#include "TestArm.h"
#include <catch2/catch.hpp>
#include <random>

using namespace armadillo;
using namespace armadillo::core;
using namespace armadillo::fusion;
using namespace armadillo::braille;
using namespace armadillo::braille::test;

namespace {
/// IMU samples a perfect device would give along a motion, plus bias and white noise.
std::vector<ImuSample> synthesise(const Motion& m, const Eigen::Vector3d& gyroBias, double noise, std::uint64_t seed)
{
    std::mt19937_64 rng(seed);
    std::normal_distribution<double> n(0.0, noise);
    const double dip = degToRad(65.0);
    const Eigen::Vector3d field(0.0, -std::sin(dip), -std::cos(dip));   // north = −Z, dipping down
    std::vector<ImuSample> out;
    for (std::size_t i = 0; i < m.states.size(); ++i) {
        const Eigen::Quaterniond q = m.states[i].q;
        ImuSample s;
        s.t = m.states[i].t;
        Eigen::Vector3d w = Eigen::Vector3d::Zero();
        if (i > 0) {   // the rate over the interval that ends at this sample, device frame
            const Eigen::AngleAxisd d(m.states[i - 1].q.conjugate() * q);
            w = d.axis() * d.angle() / kDt;
        }
        s.gyro = w + gyroBias + Eigen::Vector3d(n(rng), n(rng), n(rng));
        s.accel = q.conjugate() * Eigen::Vector3d(0.0, kStandardGravity, 0.0) + 10.0 * Eigen::Vector3d(n(rng), n(rng), n(rng));
        s.mag = q.conjugate() * field + Eigen::Vector3d(n(rng), n(rng), n(rng));
        out.push_back(s);
    }
    return out;
}

int advancesThroughFilter(const Motion& m, const Eigen::Vector3d& bias, std::size_t settle)
{
    OrientationFilter filter;
    RollReader reader;
    int advances = 0;
    const auto samples = synthesise(m, bias, 0.003, 9);
    for (std::size_t i = 0; i < samples.size(); ++i) {
        filter.update(samples[i]);
        if (i < settle || !filter.initialised()) continue;   // let the filter converge first
        const Eigen::Quaterniond q = filter.orientation();
        const auto u = reader.update(samples[i].t, q * Eigen::Vector3d::UnitX(), q * Eigen::Vector3d::UnitY(), true);
        advances += u.advanced;
    }
    return advances;
}
} // namespace

TEST_CASE("Through the real filter a biased gyro never advances text", "[braille][fusion]")
{
    Motion still;
    still.hold(hanging(10), 60.0);
    CHECK(advancesThroughFilter(still, Eigen::Vector3d(0.03, -0.02, 0.02), 1000) == 0);   // ~1.7 deg/s bias
    Motion level;
    level.hold(test::level(-20, 5), 60.0);
    CHECK(advancesThroughFilter(level, Eigen::Vector3d(0.03, 0.01, -0.02), 1000) == 0);
}

TEST_CASE("Through the real filter text advances in proportion to the roll", "[braille][fusion]")
{
    // Thesis §4.3.1: thresholds re-arm where they were crossed, so a sweep advances
    // floor(total roll / 15°) times however it is broken into steps: 8 × 20° = 160° ⇒ 10.
    Motion m;
    m.hold(hanging(0), 5.0);
    double r = 0.0;
    for (int i = 0; i < 8; ++i) {
        m.move(hanging(r), hanging(r + 20), 0.2);
        r += 20;
        m.hold(hanging(r), 0.8);
    }
    CHECK(advancesThroughFilter(m, Eigen::Vector3d(0.01, 0.0, -0.01), 1000) == 10);

    // The level arm reading backward, 7 × 20° the other way = 140° ⇒ 9.
    Motion k;
    k.hold(level(0, 5), 5.0);
    r = 0.0;
    for (int i = 0; i < 7; ++i) {
        k.move(level(r, 5), level(r - 20, 5), 0.2);
        r -= 20;
        k.hold(level(r, 5), 0.8);
    }
    CHECK(advancesThroughFilter(k, Eigen::Vector3d(0.0, 0.02, 0.01), 1000) == 9);
}
