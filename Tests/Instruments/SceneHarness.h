#pragma once
// Drives a scene through the Scene API the way the engine does: scripted poses → ArmState
// (quaternion from Core poseToQuaternion, gyro from consecutive orientations, features from
// Fusion computeArmFeatures) → control() at 200 Hz, then renderAudio() for the samples until the
// next control update. Records every MotorCanvas call and every event with its time.
#include "Core/Pose.h"
#include "Core/Scene.h"
#include "Fusion/ArmFeatures.h"
#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace armadillo::test {

class RecordingCanvas final : public core::MotorCanvas {
public:
    struct Call {
        enum Kind { Level, Clear, Trigger, Stop } kind;
        double t;              ///< s, harness time of the control update
        int motor = -1;        ///< Level: motor index; Stop: voice
        float level = 0.0f;    ///< Level
        core::PatternRequest request {};
    };
    std::vector<Call> calls;
    double now = 0.0;
    std::array<float, core::kMaxMotors> levels {};

    void setLevel(int motorIndex, float level) override
    {
        calls.push_back({Call::Level, now, motorIndex, level, {}});
        if (motorIndex >= 0 && motorIndex < core::kMaxMotors) levels[static_cast<std::size_t>(motorIndex)] = level;
    }
    void clearLevels() override
    {
        calls.push_back({Call::Clear, now, -1, 0.0f, {}});
        levels.fill(0.0f);
    }
    void trigger(const core::PatternRequest& r) override { calls.push_back({Call::Trigger, now, -1, r.level, r}); }
    void stopVoice(int voice) override { calls.push_back({Call::Stop, now, voice, 0.0f, {}}); }

    std::vector<Call> triggers(core::PatternKind kind) const
    {
        std::vector<Call> out;
        for (const auto& c : calls)
            if (c.kind == Call::Trigger && c.request.kind == kind) out.push_back(c);
        return out;
    }
};

class RecordingEvents final : public core::EventSink {
public:
    struct Event {
        std::string name;
        float value;
        double t;
    };
    std::vector<Event> events;
    double now = 0.0;
    void emit(const char* gesture, float value) override { events.push_back({gesture, value, now}); }
    int count(const std::string& name) const
    {
        int n = 0;
        for (const auto& e : events) n += e.name == name ? 1 : 0;
        return n;
    }
};

/// ArmState as the engine's tracker builds it from an orientation source.
inline core::ArmState armStateFromPose(const core::Pose& pose, const Eigen::Quaterniond* previous, double dt, double t)
{
    core::ArmState s;
    s.t = t;
    s.q = poseToQuaternion(pose);
    if (previous && dt > 0.0) {
        Eigen::Quaterniond d = previous->conjugate() * s.q;
        if (d.w() < 0.0) d.coeffs() = -d.coeffs();
        const Eigen::AngleAxisd aa(d);
        s.gyro = aa.axis() * (aa.angle() / dt);   // device frame
    }
    s.accel = s.q.conjugate() * Eigen::Vector3d(0.0, core::kStandardGravity, 0.0);
    s.features = fusion::computeArmFeatures(s.q, s.gyro, s.accel);
    s.valid = true;
    return s;
}

struct RenderedAudio {
    std::vector<float> left, right;
    double sampleRate = 48000.0;
    std::size_t sampleAt(double t) const { return static_cast<std::size_t>(std::max(0.0, t) * sampleRate); }
};

class SceneHarness {
public:
    static constexpr double kControlRate = 200.0;

    SceneHarness(std::unique_ptr<core::Scene> scene, std::uint64_t seed = 1, double sampleRate = 48000.0)
        : scene_(std::move(scene))
    {
        config_.sampleRate = sampleRate;
        config_.seed = seed;
        audio.sampleRate = sampleRate;
        if (scene_) scene_->prepare(config_);
    }

    core::Scene& scene() { return *scene_; }
    const core::SceneConfig& config() const { return config_; }

    /// Sets a parameter by its stable id; fails loudly (throws) on an unknown id.
    void set(const std::string& id, float value)
    {
        const auto specs = scene_->parameters();
        for (std::size_t i = 0; i < specs.size(); ++i)
            if (specs[i].id == id) {
                scene_->setParameter(static_cast<int>(i), value);
                return;
            }
        throw std::runtime_error("no parameter " + id);
    }

    /// One control update with this pose, then the audio until the next update.
    void step(const core::Pose& pose)
    {
        const double dt = 1.0 / kControlRate;
        core::ControlInput in;
        in.arm = armStateFromPose(pose, haveQ_ ? &lastQ_ : nullptr, dt, time_);
        in.dt = dt;
        lastQ_ = in.arm.q;
        haveQ_ = true;
        lastPose = pose;
        canvas.now = time_;
        events.now = time_;
        core::SceneOutput out {canvas, events};
        scene_->control(in, out);
        renderUntil(time_ + dt);
        time_ += dt;
    }

    /// Holds a pose for `seconds`.
    void hold(const core::Pose& pose, double seconds)
    {
        const int n = static_cast<int>(std::lround(seconds * kControlRate));
        for (int i = 0; i < n; ++i) step(pose);
    }

    /// Moves linearly (in pose coordinates) from `from` to `to` over `seconds`; the last step is `to`.
    void move(const core::Pose& from, const core::Pose& to, double seconds)
    {
        const int n = std::max(1, static_cast<int>(std::lround(seconds * kControlRate)));
        for (int i = 1; i <= n; ++i) {
            const double u = static_cast<double>(i) / n;
            step({from.elevationDeg + u * (to.elevationDeg - from.elevationDeg),
                  from.azimuthDeg + u * (to.azimuthDeg - from.azimuthDeg), from.rollDeg + u * (to.rollDeg - from.rollDeg)});
        }
    }

    double time() const { return time_; }

    RecordingCanvas canvas;
    RecordingEvents events;
    RenderedAudio audio;
    core::Pose lastPose {};
    /// Called with (left, right, n) around each renderAudio call when set (the real-time guard).
    std::function<void(const std::function<void()>&)> renderWrapper;
    int blockSize = 240;   ///< samples per renderAudio call (the engine's may differ)

private:
    void renderUntil(double t)
    {
        const auto target = static_cast<std::size_t>(std::llround(t * config_.sampleRate));
        while (audio.left.size() < target) {
            const std::size_t n = std::min<std::size_t>(static_cast<std::size_t>(blockSize), target - audio.left.size());
            const std::size_t at = audio.left.size();
            audio.left.resize(at + n, 0.0f);
            audio.right.resize(at + n, 0.0f);
            float* l = audio.left.data() + at;
            float* r = audio.right.data() + at;
            const auto call = [&] { scene_->renderAudio(l, r, static_cast<int>(n)); };
            if (renderWrapper) renderWrapper(call);
            else call();
        }
    }

    std::unique_ptr<core::Scene> scene_;
    core::SceneConfig config_ {};
    double time_ = 0.0;
    Eigen::Quaterniond lastQ_ = Eigen::Quaterniond::Identity();
    bool haveQ_ = false;
};

// ---- measurements ------------------------------------------------------------------------------

/// Frequency from positive-going zero crossings, each located by linear interpolation: the
/// crossings' times fit a line whose slope is the period (least squares, robust to one bad one).
inline double estimateFrequency(const std::vector<float>& x, std::size_t from, std::size_t to, double fs)
{
    std::vector<double> times;
    to = std::min(to, x.size());
    for (std::size_t i = from + 1; i < to; ++i) {
        const double a = x[i - 1], b = x[i];
        if (a < 0.0 && b >= 0.0) times.push_back((static_cast<double>(i - 1) + a / (a - b)) / fs);
    }
    if (times.size() < 3) return 0.0;
    // Least-squares slope of time vs crossing number.
    const double n = static_cast<double>(times.size());
    double sk = 0, st = 0, skk = 0, skt = 0;
    for (std::size_t k = 0; k < times.size(); ++k) {
        const double kk = static_cast<double>(k);
        sk += kk;
        st += times[k];
        skk += kk * kk;
        skt += kk * times[k];
    }
    const double period = (n * skt - sk * st) / (n * skk - sk * sk);
    return 1.0 / period;
}

inline double rms(const std::vector<float>& x, std::size_t from, std::size_t to)
{
    to = std::min(to, x.size());
    if (to <= from) return 0.0;
    double s = 0.0;
    for (std::size_t i = from; i < to; ++i) s += static_cast<double>(x[i]) * static_cast<double>(x[i]);
    return std::sqrt(s / static_cast<double>(to - from));
}

inline double cents(double f, double reference) { return 1200.0 * std::log2(f / reference); }
inline double dB(double ratio) { return 20.0 * std::log10(ratio); }

} // namespace armadillo::test
