#include "Plugin/OscLink.h"
#include <juce_core/juce_core.h>
#include <cmath>

namespace armadillo::plugin {

bool OscOutput::configure(bool enabled, const std::string& host, int port, std::string& whyNot)
{
    std::lock_guard<std::mutex> lock(mutex_);
    if (connected_) sender_.disconnect();
    connected_ = false;
    whyNot.clear();
    if (! enabled) return true;
    if (port < 1 || port > 65535) {
        whyNot = "OSC port must be 1-65535";
        return false;
    }
    if (host.empty()) {
        whyNot = "no OSC host";
        return false;
    }
    connected_ = sender_.connect(juce::String(host), port);
    if (! connected_) whyNot = "cannot send to " + host + ":" + std::to_string(port);
    return connected_;
}

void OscOutput::sendFrame(const ArmFrame& f)
{
    std::lock_guard<std::mutex> lock(mutex_);
    if (! connected_ || ! f.valid) return;
    auto fl = [](double v) { return static_cast<float>(v); };
    juce::OSCBundle bundle;
    bundle.addElement(juce::OSCMessage("/armadillo/orientation", fl(f.q[0]), fl(f.q[1]), fl(f.q[2]), fl(f.q[3])));
    bundle.addElement(juce::OSCMessage("/armadillo/pose", fl(f.pose[0]), fl(f.pose[1]), fl(f.pose[2])));
    bundle.addElement(juce::OSCMessage("/armadillo/gyro", fl(f.gyro[0]), fl(f.gyro[1]), fl(f.gyro[2])));
    juce::OSCMessage motors("/armadillo/motors");
    for (int i = 0; i < f.motorCount; ++i) motors.addInt32(f.motors[static_cast<std::size_t>(i)]);
    bundle.addElement(motors);
    if (sender_.send(bundle)) sent_.fetch_add(4, std::memory_order_relaxed);
}

void OscOutput::sendGesture(const char* name, float value)
{
    std::lock_guard<std::mutex> lock(mutex_);
    if (! connected_) return;
    juce::OSCMessage m("/armadillo/gesture", juce::String(name));
    m.addFloat32(value);   // extra argument: Max/Pd patches may ignore it ([route] on the name)
    if (sender_.send(m)) sent_.fetch_add(1, std::memory_order_relaxed);
}

OscInput::~OscInput()
{
    receiver_.removeListener(this);
    receiver_.disconnect();
}

bool OscInput::configure(bool enabled, int port, std::string& whyNot)
{
    whyNot.clear();
    if (! enabled) {
        receiver_.disconnect();
        openPort_ = 0;
        return true;
    }
    if (port < 1 || port > 65535) {
        whyNot = "OSC input port must be 1-65535";
        return false;
    }
    if (openPort_ == port) return true;
    receiver_.disconnect();
    openPort_ = 0;
    if (! receiver_.connect(port)) {
        whyNot = "cannot listen on UDP port " + std::to_string(port) + " (in use?)";
        return false;
    }
    openPort_ = port;
    return true;
}

namespace {
bool numberAt(const juce::OSCMessage& m, int i, double& out)
{
    const auto& a = m[i];
    if (a.isFloat32()) out = a.getFloat32();
    else if (a.isInt32()) out = a.getInt32();
    else return false;
    return std::isfinite(out);
}
} // namespace

bool OscInput::handle(const juce::OSCMessage& m)
{
    const auto address = m.getAddressPattern().toString();
    double v[9] {};
    auto readAll = [&](int n) {
        if (m.size() < n) return false;
        for (int i = 0; i < n; ++i)
            if (! numberAt(m, i, v[i])) return false;
        return true;
    };
    const double now = juce::Time::getMillisecondCounterHiRes() * 1.0e-3;
    bool ok = false;
    if (address == "/armadillo/orientation" && readAll(4)) {
        const Eigen::Quaterniond q(v[0], v[1], v[2], v[3]);
        if (q.norm() > 1.0e-6) {
            live_.storeOrientation(now, q);
            ok = true;
        }
    } else if (address == "/armadillo/imu" && readAll(6)) {
        LiveImu s;
        s.t = now;
        for (int i = 0; i < 3; ++i) {
            s.g[i] = static_cast<float>(v[i]);
            s.a[i] = static_cast<float>(v[3 + i]);
            s.m[i] = std::numeric_limits<float>::quiet_NaN();
        }
        if (m.size() >= 9) {
            double mv[3] {};
            bool haveMag = true;
            for (int i = 0; i < 3; ++i) haveMag = haveMag && numberAt(m, 6 + i, mv[i]);
            if (haveMag)
                for (int i = 0; i < 3; ++i) s.m[i] = static_cast<float>(mv[i]);
        }
        ok = live_.pushImu(s);
    }
    (ok ? received_ : rejected_).fetch_add(1, std::memory_order_relaxed);
    return ok;
}

void OscInput::oscMessageReceived(const juce::OSCMessage& message)
{
    handle(message);
}

} // namespace armadillo::plugin
