#include "Mapping/Posture.h"
#include "Core/Errors.h"
#include <algorithm>
#include <cmath>

namespace armadillo::mapping {

namespace {
double distanceDeg(const std::array<double, 4>& a, const Eigen::Quaterniond& b) noexcept
{
    const double dot = std::fabs(a[0] * b.w() + a[1] * b.x() + a[2] * b.y() + a[3] * b.z());
    return core::radToDeg(2.0 * std::acos(std::min(1.0, dot)));
}
Eigen::Quaterniond toQuaternion(const std::array<double, 4>& a) { return Eigen::Quaterniond(a[0], a[1], a[2], a[3]); }
} // namespace

double quaternionDistanceDeg(const Eigen::Quaterniond& a, const Eigen::Quaterniond& b) noexcept
{
    const double dot = std::fabs(a.w() * b.w() + a.x() * b.x() + a.y() * b.y() + a.z() * b.z()) / (a.norm() * b.norm());
    return core::radToDeg(2.0 * std::acos(std::min(1.0, dot)));
}

void PostureRecorder::clear()
{
    samples_.clear();
    speeds_.clear();
}

void PostureRecorder::add(const Eigen::Quaterniond& q, double angularSpeedDegS)
{
    const Eigen::Quaterniond n = q.normalized();
    samples_.push_back({n.w(), n.x(), n.y(), n.z()});
    speeds_.push_back(angularSpeedDegS);
}

std::size_t PostureRecorder::count() const noexcept { return samples_.size(); }

PostureSpec PostureRecorder::finish(const std::string& name) const
{
    PostureSpec spec;
    spec.name = name;
    std::vector<std::array<double, 4>> still;
    for (std::size_t i = 0; i < samples_.size(); ++i)
        if (std::isfinite(speeds_[i]) && speeds_[i] < spec.maxSpeedDegS) still.push_back(samples_[i]);
    if (still.size() < 5)
        throw core::InputError("", 0, "", "posture \"" + name + "\": only " + std::to_string(still.size()) +
                                        " still samples (hold the pose for a second or more, moving slower than " +
                                        std::to_string(static_cast<int>(spec.maxSpeedDegS)) + " deg/s)");
    // Mean orientation: the normalised sum with every sample put in the first one's hemisphere.
    Eigen::Vector4d sum = Eigen::Vector4d::Zero();
    const Eigen::Vector4d ref(still[0][0], still[0][1], still[0][2], still[0][3]);
    for (auto& s : still) {
        Eigen::Vector4d v(s[0], s[1], s[2], s[3]);
        if (v.dot(ref) < 0.0) v = -v;
        sum += v;
    }
    sum.normalize();
    const Eigen::Quaterniond mean(sum[0], sum[1], sum[2], sum[3]);
    double spread = 0.0;
    for (auto& s : still) spread = std::max(spread, quaternionDistanceDeg(mean, toQuaternion(s)));
    spec.radiusDeg = std::clamp(3.0 * spread, 15.0, 90.0);
    const std::size_t n = std::min(still.size(), static_cast<std::size_t>(kMaxPostureExamples));
    for (std::size_t k = 0; k < n; ++k) {
        const std::size_t i = n == 1 ? 0 : k * (still.size() - 1) / (n - 1);   // evenly spread over the recording
        spec.examples.push_back(still[i]);
    }
    return spec;
}

PostureClassifier::PostureClassifier(const std::vector<PostureSpec>& postures)
{
    for (const PostureSpec& p : postures) {
        if (count_ >= kMaxPostures) break;
        Entry& e = entries_[static_cast<std::size_t>(count_)];
        e.name = p.name;
        e.radiusDeg = p.radiusDeg;
        e.hysteresisDeg = p.hysteresisDeg >= 0.0 ? p.hysteresisDeg : kDefaultHysteresisDeg;
        e.maxSpeedDegS = p.maxSpeedDegS;
        for (const auto& q : p.examples) {
            if (e.exampleCount >= kMaxPostureExamples) break;
            e.examples[static_cast<std::size_t>(e.exampleCount++)] = q;
        }
        ++count_;
    }
}

int PostureClassifier::indexOf(const std::string& name) const noexcept
{
    for (int i = 0; i < count_; ++i)
        if (entries_[static_cast<std::size_t>(i)].name == name) return i;
    return -1;
}

void PostureClassifier::reset() noexcept
{
    states_ = {};
    current_ = -1;
    confidence_ = 0.0;
}

void PostureClassifier::update(const Eigen::Quaterniond& q, double angularSpeedDegS) noexcept
{
    if (count_ == 0) return;
    int nearest = -1;
    double best = 1e9, second = 1e9;
    for (int i = 0; i < count_; ++i) {
        const Entry& e = entries_[static_cast<std::size_t>(i)];
        double d = 180.0;
        for (int k = 0; k < e.exampleCount; ++k) d = std::min(d, distanceDeg(e.examples[static_cast<std::size_t>(k)], q));
        PostureState& s = states_[static_cast<std::size_t>(i)];
        s.distanceDeg = d;
        const bool still = std::isfinite(angularSpeedDegS) ? angularSpeedDegS <= e.maxSpeedDegS : true;
        s.closeness = still ? std::clamp(1.0 - d / e.radiusDeg, 0.0, 1.0) : 0.0;
        // Rank by distance relative to each posture's own radius, so a wide posture does not
        // swallow a narrow one next to it.
        const double score = d / e.radiusDeg;
        if (score < best) {
            second = best;
            best = score;
            nearest = i;
        } else if (score < second) {
            second = score;
        }
    }
    confidence_ = count_ == 1 ? (best < 1.0 ? 1.0 : 0.0) : std::clamp((second - best) / std::max(second, 1e-9), 0.0, 1.0);

    // Leave the current posture (with hysteresis).
    if (current_ >= 0) {
        const Entry& e = entries_[static_cast<std::size_t>(current_)];
        const PostureState& s = states_[static_cast<std::size_t>(current_)];
        const bool moving = std::isfinite(angularSpeedDegS) && angularSpeedDegS > e.maxSpeedDegS;
        bool leave = moving || s.distanceDeg > e.radiusDeg + 0.5 * e.hysteresisDeg;
        if (!leave && nearest >= 0 && nearest != current_) {
            // Another posture took over clearly: nearer by more than the hysteresis.
            leave = states_[static_cast<std::size_t>(nearest)].distanceDeg + e.hysteresisDeg < s.distanceDeg &&
                    states_[static_cast<std::size_t>(nearest)].distanceDeg < entries_[static_cast<std::size_t>(nearest)].radiusDeg;
        }
        if (leave) current_ = -1;
    }
    // Enter the nearest one.
    if (current_ < 0 && nearest >= 0) {
        const Entry& e = entries_[static_cast<std::size_t>(nearest)];
        const bool still = !std::isfinite(angularSpeedDegS) || angularSpeedDegS <= e.maxSpeedDegS;
        if (still && states_[static_cast<std::size_t>(nearest)].distanceDeg < e.radiusDeg - 0.5 * e.hysteresisDeg) current_ = nearest;
    }
    for (int i = 0; i < count_; ++i) states_[static_cast<std::size_t>(i)].inside = i == current_;
}

} // namespace armadillo::mapping
