// The structured QR factor (dense block on a diagonal block) against the dense definition and
// against Eigen's own Householder QR of the full compound matrix.
#include "Fusion/QrFactor.h"
#include <Eigen/QR>
#include <catch2/catch.hpp>
#include <random>

using namespace armadillo;
using namespace armadillo::fusion;

namespace {
template <int Dense, int K>
void checkAgainstEigen(std::mt19937& rng, double denseScale, double sigmaScale)
{
    std::normal_distribution<double> n(0.0, 1.0);
    Eigen::Matrix<double, Dense, K> D;
    for (int i = 0; i < Dense; ++i)
        for (int j = 0; j < K; ++j) D(i, j) = denseScale * n(rng);
    Eigen::Matrix<double, K, 1> sigma;
    for (int j = 0; j < K; ++j) sigma(j) = sigmaScale * std::abs(n(rng));
    const Eigen::Matrix<double, K, K> R = qr::upperFactor<Dense, K>(D, sigma);

    Eigen::Matrix<double, Dense + K, K> A;
    A.template topRows<Dense>() = D;
    A.template bottomRows<K>() = sigma.asDiagonal();
    const Eigen::Matrix<double, K, K> AtA = A.transpose() * A;
    CHECK(R.isUpperTriangular(0.0));
    CHECK((R.diagonal().array() > 0.0).all());
    CHECK((R.transpose() * R - AtA).norm() <= 1e-13 * AtA.norm());
    // R is unique once its diagonal is positive: Eigen's R with rows sign-flipped must match.
    Eigen::Matrix<double, K, K> ref = Eigen::HouseholderQR<Eigen::Matrix<double, Dense + K, K>>(A)
                                          .matrixQR().template topRows<K>().template triangularView<Eigen::Upper>();
    for (int k = 0; k < K; ++k)
        if (ref(k, k) < 0.0) ref.row(k) = -ref.row(k);
    CHECK((R - ref).norm() <= 1e-12 * ref.norm());
}
} // namespace

TEST_CASE("qr: upper factor of [D; diag(sigma)] equals the dense QR's R", "[fusion][qr]")
{
    std::mt19937 rng(21);
    for (int trial = 0; trial < 40; ++trial) {
        checkAgainstEigen<24, 12>(rng, 1.0, 1e-3);    // the prediction's shape
        checkAgainstEigen<24, 3>(rng, 1e-2, 0.05);    // a 3-vector observation's shape
        checkAgainstEigen<12, 3>(rng, 1.0, 3e-3);     // the linear update's shape
        checkAgainstEigen<24, 1>(rng, 0.1, 0.6);      // a scalar observation
        checkAgainstEigen<4, 6>(rng, 1.0, 1.0);       // fewer dense rows than columns
    }
}

TEST_CASE("qr: zero spread and zero noise give a finite factor with a positive diagonal", "[fusion][qr]")
{
    const Eigen::Matrix<double, 6, 3> D = Eigen::Matrix<double, 6, 3>::Zero();
    const Eigen::Matrix<double, 3, 3> R = qr::upperFactor<6, 3>(D, Eigen::Vector3d::Zero());
    CHECK(R.allFinite());
    CHECK((R.diagonal().array() > 0.0).all());
    // A zero column among non-zero ones: that direction gets the floor, the others are exact.
    Eigen::Matrix<double, 6, 3> E = Eigen::Matrix<double, 6, 3>::Zero();
    E.col(0).setConstant(1.0);
    E.col(2).setConstant(2.0);
    const Eigen::Matrix<double, 3, 3> R2 = qr::upperFactor<6, 3>(E, Eigen::Vector3d::Zero());
    CHECK(R2(0, 0) == Approx(std::sqrt(6.0)));
    CHECK(R2(1, 1) == 1e-12);
    CHECK((R2.transpose() * R2 - E.transpose() * E).norm() < 1e-9);
    // A column of subnormal-squared dust (1e-156: its squared norm underflows): still finite.
    Eigen::Matrix<double, 6, 3> F = E;
    F.col(1).setConstant(1e-156);
    const Eigen::Matrix<double, 3, 3> R3 = qr::upperFactor<6, 3>(F, Eigen::Vector3d::Zero());
    CHECK(R3.allFinite());
    CHECK((R3.diagonal().array() > 0.0).all());
}
