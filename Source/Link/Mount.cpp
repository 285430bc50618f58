#include "Link/Mount.h"
#include "Core/AtomicFile.h"
#include "Core/Errors.h"
#include "Core/Types.h"
#include "Core/Json.h"
#include <Eigen/SVD>
#include <cmath>
#include <cstdio>
#include <filesystem>

namespace armadillo::link {

namespace {

/// The rotation whose rows say which sensor axis each device axis is (rows: device x, y, z).
Eigen::Quaterniond fromRows(const Eigen::Vector3d& dx, const Eigen::Vector3d& dy, const Eigen::Vector3d& dz)
{
    Eigen::Matrix3d m;
    m.row(0) = dx.transpose();
    m.row(1) = dy.transpose();
    m.row(2) = dz.transpose();
    return Eigen::Quaterniond(m).normalized();
}

struct Preset {
    const char* name;
    Eigen::Quaterniond (*make)();
};

const Preset kPresets[] = {
    {"identity", [] { return Eigen::Quaterniond::Identity(); }},
    {"thesis", [] { return Eigen::Quaterniond::Identity(); }},
    {"armadillo", [] { return Eigen::Quaterniond::Identity(); }},
    // Phone axes (Android SensorEvent and iOS Core Motion alike): x right, y toward the top edge,
    // z out of the screen. Screen up, top toward the hand: device x = phone y, device y = phone z,
    // device z = phone x.
    {"phone-screen-up", [] { return fromRows(Eigen::Vector3d::UnitY(), Eigen::Vector3d::UnitZ(), Eigen::Vector3d::UnitX()); }},
    // Screen up, top toward the elbow: device x = −phone y, device y = phone z, device z = −phone x.
    {"phone-screen-up-top-to-elbow", [] { return fromRows(-Eigen::Vector3d::UnitY(), Eigen::Vector3d::UnitZ(), -Eigen::Vector3d::UnitX()); }},
    // NGIMU: its x axis toward the hand, its z axis (the lid) out of the back of the forearm:
    // device x = sensor x, device y = sensor z, device z = −sensor y.
    {"ngimu", [] { return fromRows(Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitZ(), -Eigen::Vector3d::UnitY()); }},
};

} // namespace

bool mountPreset(std::string_view name, Mount& out)
{
    for (const Preset& p : kPresets)
        if (name == p.name) {
            out = Mount {};
            out.rotation = p.make();
            out.name = p.name;
            return true;
        }
    return false;
}

std::string mountPresetNames()
{
    std::string s;
    for (const Preset& p : kPresets) {
        if (!s.empty()) s += ", ";
        s += p.name;
    }
    return s;
}

const char* defaultMountPresetForFormat(std::string_view format)
{
    if (format == "sensors2osc" || format == "zigsim" || format == "gyrosc" || format == "touchosc") return "phone-screen-up";
    if (format == "ngimu") return "ngimu";
    return "identity";
}

Mount loadMount(const std::string& path)
{
    return parseMount(core::readWholeFile(path), path); // IoError (exit 4) naming the file when it cannot be read
}

Mount parseMount(std::string_view json, const std::string& path)
{
    const core::JsonValue root = core::parseJson(json, path);
    const core::JsonValue* m = root.kind == core::JsonValue::Kind::Object ? root.find("mount") : nullptr;
    if (!m || m->kind != core::JsonValue::Kind::Object) throw core::InputError(path, root.line, "mount", "expected an object {\"mount\": {\"quaternion\": [w, x, y, z]}}");
    const core::JsonValue* q = m->find("quaternion");
    if (!q || q->kind != core::JsonValue::Kind::Array || q->array.size() != 4)
        throw core::InputError(path, m->line, "mount.quaternion", "expected 4 numbers [w, x, y, z]");
    double v[4];
    for (int i = 0; i < 4; ++i) {
        const core::JsonValue& e = q->array[static_cast<std::size_t>(i)];
        if (e.kind != core::JsonValue::Kind::Number || !std::isfinite(e.number))
            throw core::InputError(path, e.line, "mount.quaternion", "expected 4 finite numbers [w, x, y, z]");
        v[i] = e.number;
    }
    const double n = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2] + v[3] * v[3]);
    if (!(std::abs(n - 1.0) < 0.01))
        throw core::InputError(path, q->line, "mount.quaternion", "is not a unit quaternion (norm " + std::to_string(n) + ")");
    Mount out;
    out.rotation = Eigen::Quaterniond(v[0], v[1], v[2], v[3]).normalized();
    out.name = "file";
    if (const core::JsonValue* d = m->find("device"); d && d->kind == core::JsonValue::Kind::String) out.device = d->string;
    return out;
}

void saveMount(const std::string& path, const Mount& mount)
{
    const Eigen::Quaterniond& q = mount.rotation;
    char nums[160];
    std::snprintf(nums, sizeof nums, "[%.9f, %.9f, %.9f, %.9f]", q.w(), q.x(), q.y(), q.z());
    std::string s = "{\n  \"mount\": {\n    \"quaternion\": ";
    s += nums;
    s += ",\n    \"name\": ";
    core::appendJsonString(s, mount.name);
    s += ",\n    \"device\": ";
    core::appendJsonString(s, mount.device);
    s += ",\n    \"note\": \"sensor axes to the ARMadillo device frame: v_device = q v_sensor q^-1\"\n  }\n}\n";
    core::writeFileAtomically(path, s);
}

Mount mountFromArgument(const std::string& presetOrPath)
{
    Mount m;
    if (mountPreset(presetOrPath, m)) return m;
    const bool isPath = presetOrPath.find('/') != std::string::npos || presetOrPath.ends_with(".json");
    if (isPath && !std::filesystem::exists(presetOrPath))   // a file that is not there: I/O, as for any input file
        throw core::IoError("cannot read mount file '" + presetOrPath + "': no such file");
    if (!std::filesystem::exists(presetOrPath))
        throw core::InputError(presetOrPath, 0, "", "neither a mount preset (" + mountPresetNames() + ") nor an existing mount file");
    return loadMount(presetOrPath);
}

// --- MountCalibration ----------------------------------------------------------------------------

MountCalibration::MountCalibration() : MountCalibration(Params {}) {}
MountCalibration::MountCalibration(const Params& p) : params_(p) {}

const char* MountCalibration::poseName(Pose p)
{
    switch (p) {
    case Pose::LevelForward: return "level forward";
    case Pose::HangingDown: return "hanging down";
    case Pose::RolledRight: return "rolled right";
    case Pose::Done: return "done";
    }
    return "?";
}

const char* MountCalibration::instruction(Pose p)
{
    switch (p) {
    case Pose::LevelForward: return "hold the arm level, pointing straight ahead, palm down; keep still";
    case Pose::HangingDown: return "let the arm hang straight down, relaxed; keep still";
    case Pose::RolledRight:
        return "(optional) arm level and ahead again, turned a quarter turn clockwise seen from the elbow (the back of "
               "the forearm faces right); keep still";
    case Pose::Done: return "mount calibration complete";
    }
    return "";
}

void MountCalibration::feed(const Eigen::Vector3d& accel, const Eigen::Vector3d& gyro)
{
    if (pose_ == Pose::Done || !accel.allFinite()) return;
    if (gyro.allFinite() && gyro.norm() > params_.stillGyro) return;
    if (std::abs(accel.norm() - core::kStandardGravity) > params_.stillAccelDev) return;
    // Still in a pose already taken (the person has not moved on yet): not this pose.
    for (std::size_t i = 0; i < means_.size(); ++i)
        if (have_[i] && std::acos(std::clamp(means_[i].dot(accel.normalized()), -1.0, 1.0)) < core::degToRad(params_.minSeparationDeg))
            return;
    // A sample far from the running mean restarts the pose (the arm moved to get there).
    if (count_ > 0) {
        const Eigen::Vector3d mean = sum_ / count_;
        if (std::acos(std::clamp(mean.normalized().dot(accel.normalized()), -1.0, 1.0)) > core::degToRad(8.0)) {
            sum_.setZero();
            count_ = 0;
        }
    }
    sum_ += accel;
    ++count_;
}

void MountCalibration::finishStep()
{
    if (pose_ == Pose::Done) return;
    const int i = static_cast<int>(pose_);
    if (count_ > 0) {
        means_[static_cast<std::size_t>(i)] = (sum_ / count_).normalized();
        have_[static_cast<std::size_t>(i)] = true;
    }
    sum_.setZero();
    count_ = 0;
    pose_ = static_cast<Pose>(i + 1);
}

void MountCalibration::skipRoll()
{
    if (pose_ == Pose::RolledRight) {
        sum_.setZero();
        count_ = 0;
        pose_ = Pose::Done;
    }
}

Eigen::Quaterniond MountCalibration::wahba(const Eigen::Vector3d* a, const Eigen::Vector3d* b, const double* w, int n)
{
    Eigen::Matrix3d B = Eigen::Matrix3d::Zero();   // Σ w b aᵀ
    for (int i = 0; i < n; ++i) B += w[i] * b[i] * a[i].transpose();
    const Eigen::JacobiSVD<Eigen::Matrix3d> svd(B, Eigen::ComputeFullU | Eigen::ComputeFullV);
    const double d = (svd.matrixU() * svd.matrixV().transpose()).determinant() < 0.0 ? -1.0 : 1.0;
    const Eigen::Matrix3d R = svd.matrixU() * Eigen::Vector3d(1.0, 1.0, d).asDiagonal() * svd.matrixV().transpose();
    return Eigen::Quaterniond(R).normalized();
}

bool MountCalibration::solve(Mount& out, std::string& why) const
{
    // Where "up" is in the device frame in each pose (INTERFACES.md frames).
    const Eigen::Vector3d target[3] = {Eigen::Vector3d::UnitY(), -Eigen::Vector3d::UnitX(), -Eigen::Vector3d::UnitZ()};
    Eigen::Vector3d a[3], b[3];
    double w[3];
    int n = 0;
    for (int i = 0; i < 3; ++i)
        if (have_[static_cast<std::size_t>(i)]) {
            a[n] = means_[static_cast<std::size_t>(i)];
            b[n] = target[i];
            w[n] = 1.0;
            ++n;
        }
    if (!have_[0] || !have_[1]) {
        why = "the first two poses (level forward, hanging down) are needed";
        return false;
    }
    const double sep = core::radToDeg(std::acos(std::clamp(means_[0].dot(means_[1]), -1.0, 1.0)));
    if (sep < params_.minSeparationDeg) {
        char buf[160];
        std::snprintf(buf, sizeof buf, "the two poses differ by only %.0f degrees (about 90 expected): hold the arm level, then hanging down", sep);
        why = buf;
        return false;
    }
    out = Mount {};
    out.rotation = wahba(a, b, w, n);
    out.name = "calibrated";
    why.clear();
    return true;
}

} // namespace armadillo::link
