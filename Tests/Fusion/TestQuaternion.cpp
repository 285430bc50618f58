// Property tests of the quaternion toolkit (thesis §2.6): maps both ways, small and large angles.
#include "Core/Types.h"
#include "Fusion/Quaternion.h"
#include <catch2/catch.hpp>
#include <cmath>
#include <random>

using namespace armadillo;
using namespace armadillo::core;
using namespace armadillo::fusion;
using Eigen::Quaterniond;
using Eigen::Vector3d;

namespace {
Vector3d randomVector(std::mt19937& rng, double scale)
{
    std::normal_distribution<double> n(0.0, 1.0);
    return Vector3d(n(rng), n(rng), n(rng)) * scale;
}
Quaterniond randomUnit(std::mt19937& rng)
{
    std::normal_distribution<double> n(0.0, 1.0);
    return Quaterniond(n(rng), n(rng), n(rng), n(rng)).normalized();
}
} // namespace

TEST_CASE("quaternion: exp and log are inverse for angles from 1e-12 rad to just below pi", "[fusion][quaternion]")
{
    std::mt19937 rng(1);
    for (double scale : {1e-12, 1e-9, 1e-6, 1e-4, 1e-2, 0.5, 2.0, 3.1}) {
        for (int i = 0; i < 50; ++i) {
            Vector3d e = randomVector(rng, 1.0).normalized() * scale;
            const Quaterniond q = quat::exp(e);
            CHECK(q.norm() == Approx(1.0).margin(1e-15));
            const Vector3d back = quat::log(q);
            CHECK((back - e).norm() <= 1e-14 * std::max(1.0, e.norm()) + 1e-15 * e.norm());
        }
    }
}

TEST_CASE("quaternion: the series branches of exp and log agree with long-double references to a few ulp", "[fusion][quaternion]")
{
    // exp uses a Taylor series below 0.5 rad, log below about 0.2 rad; both must be as exact as
    // the sin/cos/atan2 branch, across the whole range and on both sides of each switch.
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> angle(0.0, 1.0);
    const auto check = [](const Vector3d& e) {
        const long double th = std::sqrt(static_cast<long double>(e.x()) * e.x() + static_cast<long double>(e.y()) * e.y() +
                                         static_cast<long double>(e.z()) * e.z());
        const long double w = std::cos(th / 2);
        const long double k = th > 0 ? std::sin(th / 2) / th : 0.5L;
        const Quaterniond q = quat::exp(e);
        CHECK(std::abs(static_cast<long double>(q.w()) - w) <= 3e-16L);
        for (int i = 0; i < 3; ++i) CHECK(std::abs(static_cast<long double>(q.vec()(i)) - k * e(i)) <= 3e-16L * (1 + std::abs(e(i))));
        // log of the long-double-exact quaternion (rounded once) must give e back.
        const Quaterniond qr(static_cast<double>(w), static_cast<double>(k * e.x()), static_cast<double>(k * e.y()),
                             static_cast<double>(k * e.z()));
        CHECK((quat::log(qr) - e).norm() <= 1e-15 * std::max(1.0, e.norm()));
    };
    for (int i = 0; i < 2000; ++i) check(randomVector(rng, 1.0).normalized() * angle(rng));
    for (double th : {0.0, 1e-300, 1e-8, 0.19, 0.1999, 0.2, 0.2001, 0.2005, 0.21, 0.49999, 0.5, 0.50001, 0.9})
        check(Vector3d(0.6, -0.48, 0.64) * th);
}

TEST_CASE("quaternion: exp matches Eigen's AngleAxis, log picks the short way", "[fusion][quaternion]")
{
    std::mt19937 rng(2);
    for (int i = 0; i < 100; ++i) {
        const Vector3d e = randomVector(rng, 1.0);
        const Quaterniond ref(Eigen::AngleAxisd(e.norm(), e.normalized()));
        CHECK(std::abs(quat::exp(e).coeffs().dot(ref.coeffs())) == Approx(1.0).margin(1e-14));
        // −q is the same rotation: log must give the same rotation vector.
        const Quaterniond q = randomUnit(rng);
        Quaterniond neg = q;
        neg.coeffs() = -neg.coeffs();
        CHECK((quat::log(q) - quat::log(neg)).norm() < 1e-14);
        CHECK(quat::log(q).norm() <= kPi + 1e-12);
    }
    // The small-angle branch is continuous with the general one.
    const Vector3d tiny(1e-5, -2e-5, 3e-5);
    const double theta = tiny.norm();
    const Quaterniond q = quat::exp(tiny);
    CHECK(q.w() == Approx(std::cos(theta / 2)).epsilon(1e-16));
    CHECK(q.x() == Approx(std::sin(theta / 2) / theta * tiny.x()).epsilon(1e-15));
}

TEST_CASE("quaternion: rotation of vectors, conjugate, inverse and product", "[fusion][quaternion]")
{
    std::mt19937 rng(3);
    for (int i = 0; i < 100; ++i) {
        const Quaterniond a = randomUnit(rng), b = randomUnit(rng);
        const Vector3d v = randomVector(rng, 2.0);
        CHECK((quat::rotate(a, v) - a.toRotationMatrix() * v).norm() < 1e-13);
        CHECK((quat::rotateInverse(a, quat::rotate(a, v)) - v).norm() < 1e-13);
        CHECK(quat::rotate(a, v).norm() == Approx(v.norm()).epsilon(1e-14));
        // (ab) v = a (b v): apply b first.
        CHECK((quat::rotate(quat::multiply(a, b), v) - quat::rotate(a, quat::rotate(b, v))).norm() < 1e-13);
        // Inverse of a non-unit quaternion.
        Quaterniond big = a;
        big.coeffs() *= 3.0;
        const Quaterniond id = quat::multiply(big, quat::inverse(big));
        CHECK(std::abs(id.w() - 1.0) < 1e-14);
        CHECK(id.vec().norm() < 1e-14);
        CHECK((quat::conjugate(a).coeffs() - quat::inverse(a).coeffs()).norm() < 1e-14);
    }
    // The thesis's example (§2.6.3): x rotated 90° about z points along y.
    const Quaterniond q = quat::fromAxisAngle(Vector3d::UnitZ(), kPi / 2);
    CHECK((quat::rotate(q, Vector3d::UnitX()) - Vector3d::UnitY()).norm() < 1e-15);
}

TEST_CASE("quaternion: axis-angle round trip, normalisation and angleBetween", "[fusion][quaternion]")
{
    Vector3d axis;
    double angle = -1.0;
    quat::toAxisAngle(quat::fromAxisAngle(Vector3d(0, 2, 0), 0.7), axis, angle);
    CHECK(angle == Approx(0.7));
    CHECK((axis - Vector3d::UnitY()).norm() < 1e-15);
    quat::toAxisAngle(Quaterniond::Identity(), axis, angle);
    CHECK(angle == 0.0);
    CHECK(axis.norm() == Approx(1.0));

    bool ok = true;
    const Quaterniond n = quat::normalised(Quaterniond(-2.0, 0.0, 0.0, 0.0), &ok);
    CHECK(ok);
    CHECK(n.w() == Approx(1.0));
    quat::normalised(Quaterniond(0.0, 0.0, 0.0, 0.0), &ok);
    CHECK_FALSE(ok);
    quat::normalised(Quaterniond(NAN, 0.0, 0.0, 0.0), &ok);
    CHECK_FALSE(ok);

    const Quaterniond a = quat::fromAxisAngle(Vector3d::UnitX(), 0.3);
    const Quaterniond b = quat::fromAxisAngle(Vector3d::UnitX(), -0.2);
    CHECK(quat::angleBetween(a, b) == Approx(0.5).epsilon(1e-14));
    CHECK(quat::angleBetween(a, a) < 1e-15);
    // A 180° flip: log at the cut stays finite and has length π.
    CHECK(quat::log(quat::fromAxisAngle(Vector3d::UnitZ(), kPi)).norm() == Approx(kPi));
}
