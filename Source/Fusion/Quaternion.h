#pragma once
// Quaternion toolkit of thesis §2.6 (ARMADILLO.md §4): product, conjugate/inverse, rotation of
// vectors, axis–angle and the "error angle" (rotation vector = axis × angle) maps both ways,
// normalisation. q = (w, x, y, z) as Eigen::Quaterniond; a unit q rotates v into q v q⁻¹.
//
// Everything is inline and allocation-free: the SR-UKF calls these ~100 times per update.
#include <Eigen/Geometry>
#include <cmath>

namespace armadillo::fusion::quat {

using Eigen::Quaterniond;
using Eigen::Vector3d;

/// Hamilton product a·b (apply b first, then a).
inline Quaterniond multiply(const Quaterniond& a, const Quaterniond& b) noexcept { return a * b; }

/// Conjugate (w, −x, −y, −z): the inverse of a unit quaternion (thesis §2.6.3).
inline Quaterniond conjugate(const Quaterniond& q) noexcept { return q.conjugate(); }

/// Inverse of any non-zero quaternion: conjugate / |q|². Zero in, NaN out (never a silent identity).
inline Quaterniond inverse(const Quaterniond& q) noexcept
{
    const double n2 = q.squaredNorm();
    Quaterniond c = q.conjugate();
    c.coeffs() /= n2;
    return c;
}

/// v' = q v q⁻¹ for a unit q (the vector part of the sandwich product, computed without it).
inline Vector3d rotate(const Quaterniond& q, const Vector3d& v) noexcept
{
    // v' = v + 2w (u × v) + 2 u × (u × v), u = vector part: 15 multiplies, no normalisation.
    const Vector3d u = q.vec();
    const Vector3d t = 2.0 * u.cross(v);
    return v + q.w() * t + u.cross(t);
}

/// q⁻¹ v q for a unit q: the inverse rotation (earth → device when q is device → earth).
inline Vector3d rotateInverse(const Quaterniond& q, const Vector3d& v) noexcept { return rotate(q.conjugate(), v); }

/// Unit quaternion with w ≥ 0 (the same rotation; q and −q are one rotation). A zero or
/// non-finite input gives the identity and `ok = false` so the caller can count it.
inline Quaterniond normalised(const Quaterniond& q, bool* ok = nullptr) noexcept
{
    const double n = q.norm();
    const bool good = std::isfinite(n) && n > 1e-300;
    if (ok) *ok = good;
    if (!good) return Quaterniond::Identity();
    Quaterniond r(q.coeffs() / n);
    if (r.w() < 0.0) r.coeffs() = -r.coeffs();
    return r;
}

/// Rescales a nearly unit quaternion (a product of unit quaternions, drifted by rounding) to
/// unit norm in place: one division, where Eigen's normalize() divides each coefficient.
inline void renormalise(Quaterniond& q) noexcept { q.coeffs() *= 1.0 / q.norm(); }

/// The cross-product matrix [v]×: [v]× w = v × w.
inline Eigen::Matrix3d skew(const Vector3d& v) noexcept
{
    Eigen::Matrix3d m;
    m << 0.0, -v.z(), v.y(), v.z(), 0.0, -v.x(), -v.y(), v.x(), 0.0;
    return m;
}

/// Error angle → quaternion: rotation vector e (axis × angle, rad) ↦ (cos |e|/2, sin(|e|/2) e/|e|).
/// Exact to rounding for every |e|, including 0. Below 0.5 rad (every sigma point and every
/// 3.5 ms step of the filter) both factors come from their Taylor series in u = θ²/4, which is
/// cheaper than sin/cos and needs no division by θ; the first omitted term is < 5e-20.
inline Quaterniond exp(const Vector3d& e) noexcept
{
    const double theta2 = e.squaredNorm();
    double w, k;   // k = sin(θ/2)/θ
    if (theta2 < 0.25) {
        const double u = 0.25 * theta2;
        // cos(θ/2) = Σ (−u)ⁿ/(2n)!,  sin(θ/2)/θ = ½ Σ (−u)ⁿ/(2n+1)!,  n = 0 … 6.
        w = 1.0 - u * (1.0 / 2 - u * (1.0 / 24 - u * (1.0 / 720 - u * (1.0 / 40320 - u * (1.0 / 3628800 - u * (1.0 / 479001600))))));
        k = 0.5 * (1.0 - u * (1.0 / 6 - u * (1.0 / 120 - u * (1.0 / 5040 - u * (1.0 / 362880 - u * (1.0 / 39916800 - u * (1.0 / 6227020800.0)))))));
    } else {
        const double theta = std::sqrt(theta2);
        w = std::cos(0.5 * theta);
        k = std::sin(0.5 * theta) / theta;
    }
    return Quaterniond(w, k * e.x(), k * e.y(), k * e.z());
}

/// Quaternion → error angle: the rotation vector of the shortest equivalent rotation (angle in
/// [0, π]), so log(exp(e)) = e for |e| < π. Uses atan2, accurate near 0 and near π.
/// Expects a unit quaternion (normalise first if it may have drifted).
inline Vector3d log(const Quaterniond& qIn) noexcept
{
    const double s = qIn.w() < 0.0 ? -1.0 : 1.0;   // q and −q: take the short way round
    const double w = s * qIn.w();
    const Vector3d u = s * qIn.vec();
    const double n2 = u.squaredNorm();
    if (w > 0.0 && n2 < 1e-2 * w * w) {
        // Angles below ~0.2 rad: θ/n = 2 atan(n/w)/n = (2/w) Σ (−x)ᵏ/(2k+1), x = (n/w)² < 0.01,
        // k = 0 … 8 (first omitted term < 6e-20): no atan2 and no division by n ≈ 0.
        const double invW = 1.0 / w;
        const double x = n2 * invW * invW;
        const double series = 1.0 - x * (1.0 / 3 - x * (1.0 / 5 - x * (1.0 / 7 - x * (1.0 / 9 - x * (1.0 / 11 - x * (1.0 / 13 - x * (1.0 / 15 - x * (1.0 / 17))))))));
        return (2.0 * invW * series) * u;
    }
    const double n = std::sqrt(n2);
    return (2.0 * std::atan2(n, w) / n) * u;
}

/// Axis (unit) and angle (rad) → quaternion. A zero axis gives the identity.
inline Quaterniond fromAxisAngle(const Vector3d& axis, double angle) noexcept
{
    const double n = axis.norm();
    if (!(n > 0.0)) return Quaterniond::Identity();
    return exp(axis * (angle / n));
}

/// Quaternion → axis (unit) and angle (rad, in [0, π]). For the identity the axis is x (any axis
/// is right; a fixed one keeps callers deterministic).
inline void toAxisAngle(const Quaterniond& q, Vector3d& axis, double& angle) noexcept
{
    const Vector3d e = log(q);
    angle = e.norm();
    axis = angle > 0.0 ? Vector3d(e / angle) : Vector3d::UnitX();
}

/// Angle (rad, [0, π]) of the rotation that takes a to b: 2 acos |⟨a, b⟩|, computed stably.
inline double angleBetween(const Quaterniond& a, const Quaterniond& b) noexcept
{
    return log(a.conjugate() * b).norm();
}

/// The smallest rotation taking unit vector `from` to unit vector `to` (antiparallel: 180° about
/// an axis perpendicular to `from`).
inline Quaterniond fromTwoVectors(const Vector3d& from, const Vector3d& to) noexcept
{
    return Quaterniond::FromTwoVectors(from, to);
}

} // namespace armadillo::fusion::quat
