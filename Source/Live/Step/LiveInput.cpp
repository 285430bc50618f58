#include "Live/Step/LiveInput.h"
#include "Core/Clock.h"

namespace armadillo::live {

void LiveInput::storeOrientation(double t, const Eigen::Quaterniond& q) noexcept
{
    LiveOrientation o;
    o.t = t;
    const auto n = q.normalized();
    o.w = n.w();
    o.x = n.x();
    o.y = n.y();
    o.z = n.z();
    o.arrival = core::monotonicSeconds();
    o.serial = serial_.fetch_add(1, std::memory_order_relaxed) + 1;
    orientation_.store(o);
}

bool LiveInput::pushImu(const LiveImu& sample) noexcept
{
    LiveImu stamped = sample;
    stamped.arrival = core::monotonicSeconds();
    return imu_.push(stamped);
}

LiveImu toLiveImu(const core::ImuSample& s) noexcept
{
    LiveImu out;
    out.t = s.t;
    for (int i = 0; i < 3; ++i) {
        out.g[i] = static_cast<float>(s.gyro[i]);
        out.a[i] = static_cast<float>(s.accel[i]);
        out.m[i] = static_cast<float>(s.mag[i]);
    }
    return out;
}

core::ImuSample toImuSample(const LiveImu& s) noexcept
{
    core::ImuSample out;
    out.t = s.t;
    out.gyro = Eigen::Vector3d(s.g[0], s.g[1], s.g[2]);
    out.accel = Eigen::Vector3d(s.a[0], s.a[1], s.a[2]);
    out.mag = Eigen::Vector3d(s.m[0], s.m[1], s.m[2]);
    return out;
}

} // namespace armadillo::live
