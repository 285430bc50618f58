#include "Engine/RenderSettings.h"
#include <stdexcept>
#include "Core/Errors.h"
#include "Fusion/ArmTracker.h"
#include <algorithm>
#include <cmath>
#include <cstdio>

namespace armadillo::engine {

std::size_t MotionRows::size() const { return kind == core::MotionKind::Imu ? imu.size() : orientations.size(); }
double MotionRows::time(std::size_t i) const { return kind == core::MotionKind::Imu ? imu[i].t : orientations[i].t; }
core::ArmState MotionRows::apply(fusion::ArmTracker& tracker, std::size_t i) const
{
    return kind == core::MotionKind::Imu ? tracker.update(imu[i]) : tracker.updateOrientation(orientations[i].t, orientations[i].q);
}

MotionRows MotionRows::load(const core::CsvTable& table, const Eigen::Quaterniond& mount, const char* mountOption)
{
    MotionRows m;
    m.kind = detectMotionKind(table);
    if (m.kind == core::MotionKind::Imu) m.imu = readImu(table);
    else m.orientations = motionAsQuaternions(table);   // throws for unknown headers
    if (mount.angularDistance(Eigen::Quaterniond::Identity()) == 0.0) return m;
    if (m.kind == core::MotionKind::Pose)
        throw core::InputError(table.source(), 0, mountOption, "a pose file is the forearm's own pose, not a sensor's: a mount applies to IMU and quaternion files");
    const Eigen::Quaterniond r = mount.normalized();
    for (core::ImuSample& s : m.imu) {
        s.gyro = r * s.gyro;
        s.accel = r * s.accel;
        if (s.mag.allFinite()) s.mag = r * s.mag;
    }
    for (core::TimedQuaternion& q : m.orientations) q.q = (q.q * r.conjugate()).normalized();
    return m;
}

void checkRenderSpan(const core::CsvTable& motion, std::size_t rows, const std::function<double(std::size_t)>& timeOf, double tailSeconds,
                     double maxSeconds)
{
    if (rows == 0) return;
    const double t0 = timeOf(0);
    const double tail = std::max(0.0, tailSeconds);
    for (std::size_t i = 0; i < rows; ++i)
        if (timeOf(i) - t0 + tail > maxSeconds) {
            char what[160];
            std::snprintf(what, sizeof what, "the file would render %.6g s from its first row (at most %.6g s): is the time column in seconds?",
                          timeOf(i) - t0 + tail, maxSeconds);
            motion.fail(i, motion.columnIndex("t"), what);
        }
}

std::string silenceReason(const RenderResult& r, const RenderSettings& settings)
{
    if (r.peak > 0.0f) return "";
    const std::string& scene = settings.engine.scene;
    // Scenes without a sound of their own (docs/INTERFACES.md, scene list).
    if (scene == "monitor") return "the monitor scene makes no sound (it is for recordings and link tests; motors stay off)";
    if (scene == "score" || scene == "audio-touch") {
        if (!settings.audioIn)
            return "the " + scene + " scene makes no sound of its own: it follows a recording (give --audio-in FILE.wav; "
                   "the recording is then mixed into the output)";
        if (!settings.mixAudioIn) return "the " + scene + " scene makes no sound of its own, and --no-audio-in-mix left the recording out";
        return "the recording given with --audio-in is silent, and the " + scene + " scene makes no sound of its own";
    }
    if (scene == "compass" || scene == "braille") return "the " + scene + " scene is felt, not heard: it makes no sound";
    if (r.controlUpdates > 0 && r.invalidRows == r.controlUpdates)
        return "no row of the motion file gave an orientation (the IMU samples never let fusion settle), so the scene never played";
    char range[200];
    std::snprintf(range, sizeof range, "the arm stayed within elevation %.1f..%.1f deg and azimuth %.1f..%.1f deg",
                  r.minElevation, r.maxElevation, r.minAzimuth, r.maxAzimuth);
    std::string why = "scene '" + scene + "' made no sound over this motion: " + range;
    if (scene == "cymbal") why += "; the cymbal sounds on a strike (a fast swing of the forearm)";
    else if (scene == "theremin" || scene == "panel" || scene == "sound-design") why += "; check the scene's range parameters (--param) against this motion";
    return why;
}

} // namespace armadillo::engine
