// Rank-1 Cholesky update/downdate (LINPACK DCHUD/DCHDD behaviour) against the dense definition.
#include "Fusion/Cholesky.h"
#include <Eigen/Cholesky>
#include <catch2/catch.hpp>
#include <random>

using namespace armadillo;
using namespace armadillo::fusion;

namespace {
template <int N>
Eigen::Matrix<double, N, N> randomSpd(std::mt19937& rng)
{
    std::normal_distribution<double> n(0.0, 1.0);
    Eigen::Matrix<double, N, N> A;
    for (int i = 0; i < N; ++i)
        for (int j = 0; j < N; ++j) A(i, j) = n(rng);
    return A * A.transpose() + Eigen::Matrix<double, N, N>::Identity() * 0.1;
}
} // namespace

TEST_CASE("cholesky: rank-1 update equals the factor of P + x x^T", "[fusion][cholesky]")
{
    std::mt19937 rng(4);
    std::normal_distribution<double> n(0.0, 1.0);
    for (int trial = 0; trial < 50; ++trial) {
        const Eigen::Matrix<double, 9, 9> P = randomSpd<9>(rng);
        Eigen::Matrix<double, 9, 9> L = P.llt().matrixL();
        Eigen::Matrix<double, 9, 1> x;
        for (int i = 0; i < 9; ++i) x(i) = n(rng);
        REQUIRE(cholesky::update<9>(L, x) == cholesky::Rank1Result::Ok);
        CHECK((L * L.transpose() - (P + x * x.transpose())).norm() < 1e-10 * P.norm());
        CHECK(L.isLowerTriangular(0.0));
        CHECK((L.diagonal().array() > 0.0).all());
    }
}

TEST_CASE("cholesky: rank-1 downdate equals the factor of P - x x^T when it exists", "[fusion][cholesky]")
{
    std::mt19937 rng(5);
    std::normal_distribution<double> n(0.0, 1.0);
    for (int trial = 0; trial < 50; ++trial) {
        const Eigen::Matrix<double, 9, 9> P0 = randomSpd<9>(rng);
        Eigen::Matrix<double, 9, 1> x;
        for (int i = 0; i < 9; ++i) x(i) = n(rng);
        // P = P0 + x xᵀ, so P − x xᵀ = P0 is positive definite.
        const Eigen::Matrix<double, 9, 9> P = P0 + x * x.transpose();
        Eigen::Matrix<double, 9, 9> L = P.llt().matrixL();
        REQUIRE(cholesky::downdate<9>(L, x) == cholesky::Rank1Result::Ok);
        CHECK((L * L.transpose() - P0).norm() < 1e-9 * P.norm());
        CHECK((L.diagonal().array() > 0.0).all());
    }
}

TEST_CASE("cholesky: a downdate that would lose definiteness is refused and leaves L unchanged", "[fusion][cholesky]")
{
    Eigen::Matrix3d L = Eigen::Matrix3d::Identity();
    const Eigen::Matrix3d before = L;
    CHECK(cholesky::downdate<3>(L, Eigen::Vector3d(1.0, 0.0, 0.0)) == cholesky::Rank1Result::NotPositiveDefinite);
    CHECK(L == before);
    CHECK(cholesky::downdate<3>(L, Eigen::Vector3d(0.8, 0.8, 0.0)) == cholesky::Rank1Result::NotPositiveDefinite);
    CHECK(L == before);
    CHECK(cholesky::downdate<3>(L, Eigen::Vector3d(NAN, 0.0, 0.0)) == cholesky::Rank1Result::NonFinite);
    CHECK(L == before);
    CHECK(cholesky::downdate<3>(L, Eigen::Vector3d(0.6, 0.0, 0.0)) == cholesky::Rank1Result::Ok);
    CHECK(L(0, 0) == Approx(0.8));
    // A factor with a negative diagonal (as QR may give) is still handled.
    Eigen::Matrix2d M;
    M << -2.0, 0.0, 1.0, 3.0;
    const Eigen::Matrix2d P = M * M.transpose();
    REQUIRE(cholesky::update<2>(M, Eigen::Vector2d(0.5, -0.5)) == cholesky::Rank1Result::Ok);
    CHECK((M * M.transpose() - (P + Eigen::Vector2d(0.5, -0.5) * Eigen::Vector2d(0.5, -0.5).transpose())).norm() < 1e-12);
}

TEST_CASE("cholesky: the interleaved M-column downdate is bit-identical to M downdates in turn", "[fusion][cholesky]")
{
    std::mt19937 rng(6);
    std::normal_distribution<double> n(0.0, 1.0);
    for (int trial = 0; trial < 50; ++trial) {
        const Eigen::Matrix<double, 12, 12> P0 = randomSpd<12>(rng);
        Eigen::Matrix<double, 12, 3> X;
        for (int i = 0; i < 12; ++i)
            for (int j = 0; j < 3; ++j) X(i, j) = n(rng);
        const Eigen::Matrix<double, 12, 12> P = P0 + X * X.transpose();
        Eigen::Matrix<double, 12, 12> together = P.llt().matrixL();
        Eigen::Matrix<double, 12, 12> inTurn = together;
        REQUIRE(cholesky::downdateColumns<12, 3>(together, X) == cholesky::Rank1Result::Ok);
        for (int j = 0; j < 3; ++j)
            REQUIRE(cholesky::downdate<12>(inTurn, Eigen::Matrix<double, 12, 1>(X.col(j))) == cholesky::Rank1Result::Ok);
        CHECK(together == inTurn);
        CHECK((together * together.transpose() - P0).norm() < 1e-9 * P.norm());
    }
    // One column too many for definiteness: refused as a whole, L untouched.
    Eigen::Matrix3d L = Eigen::Matrix3d::Identity();
    Eigen::Matrix<double, 3, 2> X;
    X << 0.5, 0.9, 0.0, 0.0, 0.0, 0.0;   // 1 − 0.25 − 0.81 < 0 on the first pivot
    CHECK(cholesky::downdateColumns<3, 2>(L, X) == cholesky::Rank1Result::NotPositiveDefinite);
    CHECK(L == Eigen::Matrix3d::Identity());
}
