#include "Link/Calibration.h"
#include "Core/AtomicFile.h"
#include "Core/Csv.h"
#include "Core/Errors.h"
#include "Core/Json.h"
#include <algorithm>
#include <cmath>

namespace armadillo::link {

Eigen::Vector3d SensorCalibration::apply(double cx, double cy, double cz) const noexcept
{
    const Eigen::Vector3d v((cx - bias.x()) * scale.x(), (cy - bias.y()) * scale.y(), (cz - bias.z()) * scale.z());
    return cross * v;
}

Eigen::Vector3d SensorCalibration::toCounts(const Eigen::Vector3d& physical) const noexcept
{
    const Eigen::Vector3d v = cross.inverse() * physical;
    return Eigen::Vector3d(v.x() / scale.x() + bias.x(), v.y() / scale.y() + bias.y(), v.z() / scale.z() + bias.z());
}

core::ImuSample Calibration::apply(double t, const SensorCounts& c) const noexcept
{
    core::ImuSample s;
    s.t = t;
    s.accel = accel.apply(c[kAx], c[kAy], c[kAz]);
    s.gyro = gyro.apply(c[kGx], c[kGy], c[kGz]);
    s.mag = mag.apply(c[kMx], c[kMy], c[kMz]);
    return s;
}

Calibration defaultCalibration()
{
    Calibration c;
    c.accel.scale.setConstant(kDefaultAccelRange / 2048.0);
    c.gyro.scale.setConstant(kDefaultGyroRange / 2048.0);
    c.mag.scale.setConstant(kDefaultMagRange / 2048.0);
    c.device = "default (matches the built-in simulator)";
    return c;
}

// --- JSON --------------------------------------------------------------------------------------

namespace {

Eigen::Vector3d vector3(const core::JsonValue& v, const std::string& source, const std::string& key, double lo, double hi, bool nonZero)
{
    if (v.kind != core::JsonValue::Kind::Array || v.array.size() != 3)
        throw core::InputError(source, v.line, key, "expected an array of 3 numbers");
    Eigen::Vector3d out;
    for (int i = 0; i < 3; ++i) {
        const core::JsonValue& e = v.array[static_cast<std::size_t>(i)];
        if (e.kind != core::JsonValue::Kind::Number)
            throw core::InputError(source, e.line, key, std::string("element ") + std::to_string(i) + " is " + core::JsonValue::kindName(e.kind) + ", not a number");
        if (e.number < lo || e.number > hi)
            throw core::InputError(source, e.line, key, "element " + std::to_string(i) + " = " + std::to_string(e.number) + " is outside " +
                                                      std::to_string(lo) + ".." + std::to_string(hi));
        if (nonZero && std::abs(e.number) < 1e-12)
            throw core::InputError(source, e.line, key, "element " + std::to_string(i) + " is zero (a scale must be non-zero)");
        out[i] = e.number;
    }
    return out;
}

SensorCalibration sensor(const core::JsonValue& root, const char* name, const std::string& source)
{
    const core::JsonValue* s = root.find(name);
    if (!s) throw core::InputError(source, root.line, name, std::string("missing \"") + name + "\" (needs \"bias\" and \"scale\")");
    if (s->kind != core::JsonValue::Kind::Object) throw core::InputError(source, s->line, name, "expected an object with \"bias\" and \"scale\"");
    SensorCalibration out;
    const std::string k = name;
    const core::JsonValue* bias = s->find("bias");
    const core::JsonValue* scale = s->find("scale");
    if (!bias) throw core::InputError(source, s->line, k + ".bias", "missing (3 counts)");
    if (!scale) throw core::InputError(source, s->line, k + ".scale", "missing (3 SI units per count)");
    // A bias is the midpoint of observed counts, so it lies within the 12-bit range.
    out.bias = vector3(*bias, source, k + ".bias", 0.0, 4095.0, false);
    out.scale = vector3(*scale, source, k + ".scale", -1e3, 1e3, true);
    if (const core::JsonValue* cross = s->find("cross")) {
        if (cross->kind != core::JsonValue::Kind::Array || cross->array.size() != 3)
            throw core::InputError(source, cross->line, k + ".cross", "expected a 3×3 matrix (3 rows of 3 numbers)");
        for (int r = 0; r < 3; ++r)
            out.cross.row(r) = vector3(cross->array[static_cast<std::size_t>(r)], source, k + ".cross", -1e3, 1e3, false).transpose();
        if (std::abs(out.cross.determinant()) < 1e-9)
            throw core::InputError(source, cross->line, k + ".cross", "the cross-axis matrix is singular");
    }
    for (const auto& [key, value] : s->object)
        if (key != "bias" && key != "scale" && key != "cross" && key != "comment")
            throw core::InputError(source, value.line, k + "." + key, "unknown key (allowed: bias, scale, cross, comment)");
    return out;
}

} // namespace

Calibration parseCalibration(std::string_view json, const std::string& source)
{
    const core::JsonValue root = core::parseJson(json, source);
    if (root.kind != core::JsonValue::Kind::Object)
        throw core::InputError(source, root.line, "", "a calibration file is a JSON object with \"accel\", \"gyro\" and \"mag\"");
    Calibration c;
    c.accel = sensor(root, "accel", source);
    c.gyro = sensor(root, "gyro", source);
    c.mag = sensor(root, "mag", source);
    for (const char* key : {"device", "date"}) {
        if (const core::JsonValue* v = root.find(key)) {
            if (v->kind != core::JsonValue::Kind::String) throw core::InputError(source, v->line, key, "expected a string");
            (std::string_view(key) == "device" ? c.device : c.date) = v->string;
        }
    }
    return c;
}

Calibration loadCalibration(const std::string& path)
{
    return parseCalibration(core::readWholeFile(path), path);
}

std::string calibrationToJson(const Calibration& c)
{
    std::string out = "{\n";
    auto vec = [&](const Eigen::Vector3d& v) {
        std::string s = "[";
        for (int i = 0; i < 3; ++i) {
            if (i) s += ", ";
            core::appendNumber(s, v[i], 12);
        }
        return s + "]";
    };
    if (!c.device.empty()) {
        out += "  \"device\": ";
        core::appendJsonString(out, c.device);
        out += ",\n";
    }
    if (!c.date.empty()) {
        out += "  \"date\": ";
        core::appendJsonString(out, c.date);
        out += ",\n";
    }
    const std::pair<const char*, const SensorCalibration*> parts[] = {{"accel", &c.accel}, {"gyro", &c.gyro}, {"mag", &c.mag}};
    for (std::size_t i = 0; i < 3; ++i) {
        const SensorCalibration& s = *parts[i].second;
        out += std::string("  \"") + parts[i].first + "\": {\"bias\": " + vec(s.bias) + ", \"scale\": " + vec(s.scale);
        if (!s.cross.isIdentity(0.0)) {
            out += ", \"cross\": [";
            for (int r = 0; r < 3; ++r) out += (r ? ", " : "") + vec(s.cross.row(r).transpose());
            out += "]";
        }
        out += i < 2 ? "},\n" : "}\n";
    }
    return out + "}\n";
}

void saveCalibration(const std::string& path, const Calibration& calibration)
{
    core::writeFileAtomically(path, calibrationToJson(calibration));
}

// --- Guided procedure --------------------------------------------------------------------------

CalibrationProcedure::CalibrationProcedure(const Calibration& start) : CalibrationProcedure(start, Params {}) {}

CalibrationProcedure::CalibrationProcedure(const Calibration& start, const Params& params) : result_(start), params_(params)
{
    beginStep(Step::GyroStill);
}

const char* CalibrationProcedure::stepName(Step s) noexcept
{
    switch (s) {
    case Step::GyroStill: return "gyro-still";
    case Step::AccelExtremes: return "accel-extremes";
    case Step::MagHorizontal: return "mag-horizontal";
    case Step::MagVertical: return "mag-vertical";
    case Step::GyroTurnX: return "gyro-turn-x";
    case Step::GyroTurnY: return "gyro-turn-y";
    case Step::GyroTurnZ: return "gyro-turn-z";
    case Step::Done: return "done";
    }
    return "?";
}

std::string CalibrationProcedure::instruction() const
{
    switch (step_) {
    case Step::GyroStill: return "Rest the arm (or the board) completely still for a few seconds.";
    case Step::AccelExtremes:
        return "Point the forearm straight down, then straight up; then the board face down and up; then the thumb side "
               "down and up. Hold each position for a moment.";
    case Step::MagHorizontal: return "Hold the board level and turn slowly through a full circle in the horizontal plane.";
    case Step::MagVertical:
        return "Turn slowly through full vertical circles (forearm pointing north, then east), so every axis sees the "
               "dipping field at its strongest.";
    case Step::GyroTurnX: return "Roll the forearm exactly one full turn about its own axis, then stop.";
    case Step::GyroTurnY: return "With the board level, turn exactly one full circle about the vertical, then stop.";
    case Step::GyroTurnZ: return "Tip the forearm through exactly one full vertical circle (about the thumb-side axis), then stop.";
    case Step::Done: return "Calibration complete.";
    }
    return "";
}

void CalibrationProcedure::beginStep(Step s)
{
    step_ = s;
    stepStart_ = -1.0;
    sum_.setZero();
    count_ = 0;
    haveSmooth_ = false;
    min_.setConstant(1e300);
    max_.setConstant(-1e300);
    integral_.setZero();
}

void CalibrationProcedure::feed(double t, const SensorCounts& c)
{
    if (step_ == Step::Done) return;
    const double dt = lastT_ < 0.0 ? 0.0 : std::clamp(t - lastT_, 0.0, 0.1);
    lastT_ = t;
    if (stepStart_ < 0.0) stepStart_ = t;
    const Eigen::Vector3d gyroCounts(c[kGx], c[kGy], c[kGz]);
    const Eigen::Vector3d gyroRate = result_.gyro.apply(c[kGx], c[kGy], c[kGz]);
    switch (step_) {
    case Step::GyroStill:
        if (gyroRate.norm() > params_.maxStillRate ||
            (count_ > 0 && (gyroCounts - sum_ / static_cast<double>(count_)).cwiseProduct(result_.gyro.scale).norm() > params_.stillGyroLimit)) {
            // Movement: start again.
            sum_.setZero();
            count_ = 0;
            stepStart_ = t;
        }
        sum_ += gyroCounts;
        ++count_;
        break;
    case Step::AccelExtremes:
    case Step::MagHorizontal:
    case Step::MagVertical: {
        const bool accel = step_ == Step::AccelExtremes;
        const Eigen::Vector3d raw = accel ? Eigen::Vector3d(c[kAx], c[kAy], c[kAz]) : Eigen::Vector3d(c[kMx], c[kMy], c[kMz]);
        if (!haveSmooth_) {
            smooth_ = raw;
            haveSmooth_ = true;
        } else {
            const double a = 1.0 - std::exp(-dt / params_.smoothingSeconds);
            smooth_ += a * (raw - smooth_);
        }
        // Accelerometer extremes only while held (gravity alone); the magnetometer at any time.
        if (accel && gyroRate.norm() > params_.holdGyroLimit) break;
        min_ = min_.cwiseMin(smooth_);
        max_ = max_.cwiseMax(smooth_);
        ++count_;
        break;
    }
    case Step::GyroTurnX:
    case Step::GyroTurnY:
    case Step::GyroTurnZ: integral_ += (gyroCounts - result_.gyro.bias) * dt; break;
    case Step::Done: break;
    }
}

double CalibrationProcedure::progress() const noexcept
{
    switch (step_) {
    case Step::GyroStill: return count_ < 2 ? 0.0 : std::clamp((lastT_ - stepStart_) / params_.stillSeconds, 0.0, 1.0);
    case Step::AccelExtremes:
    case Step::MagHorizontal:
    case Step::MagVertical: {
        if (count_ == 0) return 0.0;
        const bool accel = step_ == Step::AccelExtremes;
        const SensorCalibration& s = accel ? result_.accel : result_.mag;
        if (step_ == Step::MagHorizontal) {
            // Level turn: only the two horizontal axes swing, and only by the field's horizontal part.
            double span[3];
            for (int i = 0; i < 3; ++i) span[i] = (max_[i] - min_[i]) * std::abs(s.scale[i]) / (2.0 * params_.minHorizontalSpanFraction);
            std::sort(span, span + 3);
            return std::clamp(span[1], 0.0, 1.0);
        }
        const double want = 2.0 * (accel ? core::kStandardGravity * params_.minAccelSpanFraction : params_.minMagSpanFraction);
        double p = 1.0;
        for (int i = 0; i < 3; ++i) p = std::min(p, (max_[i] - min_[i]) * std::abs(s.scale[i]) / want);
        return std::clamp(p, 0.0, 1.0);
    }
    case Step::GyroTurnX:
    case Step::GyroTurnY:
    case Step::GyroTurnZ: {
        const int axis = static_cast<int>(step_) - static_cast<int>(Step::GyroTurnX);
        return std::clamp(std::abs(integral_[axis] * result_.gyro.scale[axis]) / (params_.turnAngle * params_.minTurnFraction), 0.0, 1.0);
    }
    case Step::Done: return 1.0;
    }
    return 0.0;
}

bool CalibrationProcedure::ready() const noexcept { return step_ != Step::Done && progress() >= 1.0; }

void CalibrationProcedure::skipStep()
{
    if (step_ == Step::Done) return;
    Step next = static_cast<Step>(static_cast<int>(step_) + 1);
    // The magnetometer result needs both sweeps: skipping the horizontal one keeps its data for the vertical.
    beginStep(next);
}

void CalibrationProcedure::finishStep()
{
    if (step_ == Step::Done) return;
    if (!ready())
        throw core::InputError("calibration", 0, stepName(step_),
                         "not enough data yet (" + std::to_string(static_cast<int>(progress() * 100.0)) + "%): " + instruction());
    switch (step_) {
    case Step::GyroStill: result_.gyro.bias = sum_ / static_cast<double>(count_); break;
    case Step::AccelExtremes:
        for (int i = 0; i < 3; ++i) {
            result_.accel.bias[i] = 0.5 * (max_[i] + min_[i]);
            result_.accel.scale[i] = std::copysign(core::kStandardGravity / (0.5 * (max_[i] - min_[i])), result_.accel.scale[i]);
        }
        break;
    case Step::MagHorizontal: {
        // Keep the extremes: the vertical sweep continues the same search (the field dips).
        const Eigen::Vector3d lo = min_, hi = max_;
        beginStep(Step::MagVertical);
        min_ = lo;
        max_ = hi;
        count_ = 1;
        return;
    }
    case Step::MagVertical:
        for (int i = 0; i < 3; ++i) {
            result_.mag.bias[i] = 0.5 * (max_[i] + min_[i]);
            result_.mag.scale[i] = std::copysign(1.0 / (0.5 * (max_[i] - min_[i])), result_.mag.scale[i]);
        }
        break;
    case Step::GyroTurnX:
    case Step::GyroTurnY:
    case Step::GyroTurnZ: {
        const int axis = static_cast<int>(step_) - static_cast<int>(Step::GyroTurnX);
        result_.gyro.scale[axis] = std::copysign(params_.turnAngle / std::abs(integral_[axis]), result_.gyro.scale[axis]);
        break;
    }
    case Step::Done: break;
    }
    beginStep(static_cast<Step>(static_cast<int>(step_) + 1));
}

} // namespace armadillo::link
