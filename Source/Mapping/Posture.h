#pragma once
// Posture learning by example (issue 23; the idea of MiMU Glover and Wekinator): the performer
// holds a pose, names it, and a few seconds of orientations become its examples. A nearest-
// neighbour classifier on the quaternion distance, plus the angular speed as a feature (a moving
// arm holds no posture), turns the arm's orientation into "which posture, how close" with a
// confidence, and hysteresis so a pose on the edge does not chatter. Postures are saved in the
// mapping file (MappingSpec.h PostureSpec) and drive mappings as the `posture:NAME` source.
//
// classify() is real-time (fixed-size tables built in the constructor); learning is not.
#include "Core/ArmState.h"
#include "Mapping/MappingSpec.h"
#include <array>
#include <string>
#include <vector>

namespace armadillo::mapping {

inline constexpr int kMaxPostures = 16;
inline constexpr int kMaxPostureExamples = 64;   ///< per posture (learning keeps this many, evenly spread)

/// The angle between two orientations in degrees, 0…180 (2·acos|⟨a, b⟩|, sign-free: q and −q
/// are the same orientation).
double quaternionDistanceDeg(const Eigen::Quaterniond& a, const Eigen::Quaterniond& b) noexcept;

/// Records a posture from held samples (not real-time).
class PostureRecorder {
public:
    void clear();
    void add(const Eigen::Quaterniond& q, double angularSpeedDegS);
    std::size_t count() const noexcept;
    /// The posture: up to kMaxPostureExamples of the samples recorded while the arm was still
    /// (speed below the spec's maxSpeedDegS), evenly spread; radius = max(15°, 3 × the examples'
    /// spread around their mean). InputError when fewer than 5 still samples were recorded.
    PostureSpec finish(const std::string& name) const;

private:
    std::vector<std::array<double, 4>> samples_;
    std::vector<double> speeds_;
};

/// Per-update result for one posture.
struct PostureState {
    double distanceDeg = 180.0;   ///< to the nearest example
    double closeness = 0.0;       ///< 1 at an example, 0 at (or beyond) the radius; 0 while moving too fast
    bool inside = false;          ///< entered (with hysteresis) and the nearest posture
};

class PostureClassifier {
public:
    PostureClassifier() = default;
    /// Not real-time. At most kMaxPostures postures × kMaxPostureExamples examples are used.
    explicit PostureClassifier(const std::vector<PostureSpec>& postures);

    int size() const noexcept { return count_; }
    /// Index of a posture by name, −1 when absent. Not real-time (compares strings).
    int indexOf(const std::string& name) const noexcept;

    /// REAL-TIME. Updates every posture's state from one orientation: enters the nearest posture
    /// whose distance is below radius − hysteresis/2; leaves it when it is beyond radius +
    /// hysteresis/2, the arm moves faster than its maxSpeedDegS, or another posture is nearer by
    /// more than the hysteresis. At most one posture is inside at a time.
    void update(const Eigen::Quaterniond& q, double angularSpeedDegS) noexcept;
    const PostureState& state(int index) const noexcept { return states_[static_cast<std::size_t>(index)]; }
    /// The posture inside (−1: none) and the confidence of the decision 0…1: how much nearer the
    /// nearest posture is than the second nearest (1 when there is only one).
    int current() const noexcept { return current_; }
    double confidence() const noexcept { return confidence_; }
    void reset() noexcept;

private:
    struct Entry {
        std::array<std::array<double, 4>, kMaxPostureExamples> examples {};
        int exampleCount = 0;
        double radiusDeg = 20.0, hysteresisDeg = kDefaultHysteresisDeg, maxSpeedDegS = 90.0;
        std::string name;
    };
    std::array<Entry, kMaxPostures> entries_ {};
    std::array<PostureState, kMaxPostures> states_ {};
    int count_ = 0;
    int current_ = -1;
    double confidence_ = 0.0;
};

} // namespace armadillo::mapping
