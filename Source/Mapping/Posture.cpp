#include "Mapping/Posture.h"
#include "Core/Errors.h"

namespace armadillo::mapping {
// Implementation follows (API committed first so the plugin half can build on it).
double quaternionDistanceDeg(const Eigen::Quaterniond&, const Eigen::Quaterniond&) noexcept { return 180.0; }
void PostureRecorder::clear() { samples_.clear(); speeds_.clear(); }
void PostureRecorder::add(const Eigen::Quaterniond&, double) {}
std::size_t PostureRecorder::count() const noexcept { return samples_.size(); }
PostureSpec PostureRecorder::finish(const std::string&) const { throw InputError("", 0, "", "posture learning: not implemented yet"); }
PostureClassifier::PostureClassifier(const std::vector<PostureSpec>&) {}
int PostureClassifier::indexOf(const std::string&) const noexcept { return -1; }
void PostureClassifier::update(const Eigen::Quaterniond&, double) noexcept {}
void PostureClassifier::reset() noexcept {}
} // namespace armadillo::mapping
