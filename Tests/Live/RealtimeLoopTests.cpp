// The control step and the audio of every scene are real-time (Core/Scene.h): no allocation or
// free, no lock, no throw on the thread that runs them. Proved with RealtimeGuard around
// ControlLoop::tick (ArmTracker + Engine::control + Scene::control + TactileEngine) and
// ControlLoop::processInput + render (Engine::processInput, renderAudio; the input a C5 in bursts,
// which the listening scenes follow) for every scene × every source × sweeps of every
// exposed parameter × the step in which the scene swaps in. The guard first proves that it sees
// each kind of violation, so its zeros mean something.
#define ARMADILLO_REALTIME_GUARD_IMPLEMENTATION
#include "Common/RealtimeGuard.h"
#include "Braille/BrailleScene.h"
#include "Core/Pose.h"
#include "Core/Wav.h"
#include "Live/Step/ControlLoop.h"
#include "Live/Session/LiveSession.h"
#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <limits>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <unistd.h>

using namespace armadillo;
using namespace armadillo::core;
using namespace armadillo::engine;
using namespace armadillo::live;
using namespace armadillo::test;

namespace {

#ifdef ARMADILLO_GUARD_UNDER_SANITIZER
constexpr bool kGuardUsable = false;
#else
constexpr bool kGuardUsable = true;
#endif

/// Sanitizer builds replace malloc and operator new themselves: the guard is left out there.
bool guardUsableHere()
{
    if (kGuardUsable) return true;
    WARN("sanitizer build: the real-time guard is not installed; run the normal build for this test");
    SUCCEED("skipped under the sanitizer");
    return false;
}

struct Totals {
    std::uint64_t allocations = 0, deallocations = 0, locks = 0, throws = 0, calls = 0;
    void add(const RealtimeGuard& g)
    {
        allocations += g.allocations();
        deallocations += g.deallocations();
        locks += g.locks();
        throws += g.throws();
        ++calls;
    }
    bool clean() const { return allocations == 0 && deallocations == 0 && locks == 0 && throws == 0; }
    std::string text() const
    {
        return "allocations " + std::to_string(allocations) + ", frees " + std::to_string(deallocations) + ", locks "
             + std::to_string(locks) + ", throws " + std::to_string(throws) + " in " + std::to_string(calls) + " guarded calls";
    }
};

/// The front end's parameter cells for one engine (what the plugin's APVTS holds).
struct Cells {
    std::vector<ParamSpec> specs;
    std::unique_ptr<std::atomic<float>[]> values;
};

std::unique_ptr<EngineSlot> makeSlot(const std::string& scene, Cells& cells, std::uint64_t generation)
{
    EngineConfig config;
    config.scene = scene;
    config.sceneConfig.sampleRate = 48000.0;
    config.sceneConfig.seed = 7;
    config.sceneConfig.text = "ab cd";
    config.sceneConfig.score = "rite-of-spring";
    config.sceneConfig.resourceDir = std::string(ARMADILLO_SOURCE_DIR) + "/Resources";
    auto slot = std::make_unique<EngineSlot>();
    slot->engine = std::make_unique<Engine>(config);
    slot->sceneName = scene;
    slot->generation = generation;
    cells.specs = slot->engine->scene().parameters();
    cells.values = std::make_unique<std::atomic<float>[]>(cells.specs.size());
    for (std::size_t i = 0; i < cells.specs.size(); ++i) {
        cells.values[i].store(cells.specs[i].defaultValue);
        slot->params.push_back(&cells.values[i]);
    }
    slot->sent.assign(cells.specs.size(), std::numeric_limits<float>::quiet_NaN());
    return slot;
}

/// Every value a parameter is swept through: each choice, or both ends, the default and steps between.
std::vector<std::pair<std::size_t, float>> sweep(const std::vector<ParamSpec>& specs)
{
    std::vector<std::pair<std::size_t, float>> out;
    for (std::size_t i = 0; i < specs.size(); ++i) {
        const ParamSpec& p = specs[i];
        if (!p.choices.empty()) {
            for (std::size_t c = 0; c < p.choices.size(); ++c) out.emplace_back(i, static_cast<float>(c));
        } else {
            for (float u : {0.0f, 1.0f, 0.25f, 0.5f, 0.75f}) out.emplace_back(i, p.min + u * (p.max - p.min));
        }
        out.emplace_back(i, p.defaultValue);
    }
    return out;
}

/// A busy performance: sweeps of elevation and azimuth, quick strikes, rolls back and forth.
Pose poseAt(double t)
{
    const double phase = std::fmod(t, 2.0);
    double el = 40.0 * std::sin(1.3 * t);
    if (phase > 1.5 && phase < 1.6) el = 60.0 - 900.0 * (phase - 1.5);   // a strike
    return {el, 180.0 + 90.0 * std::sin(0.4 * t), 70.0 * std::sin(2.1 * t)};
}

/// What an IMU on that arm would measure (calibrated SI): gravity and north in the device frame,
/// the body rate from successive orientations.
ImuSample imuAt(double t, double dt)
{
    const Eigen::Quaterniond q = poseToQuaternion(poseAt(t));
    const Eigen::Quaterniond q0 = poseToQuaternion(poseAt(t - dt));
    const Eigen::AngleAxisd delta(q0.conjugate() * q);
    double angle = delta.angle();
    if (angle > kPi) angle -= 2.0 * kPi;
    ImuSample s;
    s.t = t;
    s.gyro = delta.axis() * (angle / dt);
    s.accel = q.conjugate() * Eigen::Vector3d(0.0, kStandardGravity, 0.0);
    s.mag = q.conjugate() * Eigen::Vector3d(0.0, -0.4, -0.5);   // north (−Z) with a downward dip
    return s;
}

const char* sourceName(SourceKind s)
{
    switch (s) {
    case SourceKind::Device: return "device";
    case SourceKind::Simulator: return "simulator";
    case SourceKind::Osc: return "OSC";
    case SourceKind::HostAutomation: return "host automation";
    }
    return "?";
}

struct RunResult {
    Totals control, audio;
    bool swappedInGuardedStep = false;
    std::string runningAfterSwap;
    double energy = 0.0;
    int motorSteps = 0;     ///< steps with any motor above 0
    int validSteps = 0;     ///< steps with a valid arm
    bool failed = false;
    int trainingAnswered = 0, trainingLogRows = 0;   ///< braille: trials answered, log rows written
};

/// One scene under one source: a warm-up scene runs, the scene under test is offered and swaps
/// in at a guarded step, then every parameter is swept while the arm moves.
RunResult run(const std::string& scene, SourceKind source)
{
    constexpr double kDt = 1.0 / 200.0;
    constexpr int kSamplesPerStep = 240;   // 48 kHz / 200 Hz
    RunResult r;
    ControlLoop loop;
    Cells warmCells, cells;
    const std::string warm = scene == "monitor" ? "theremin" : "monitor";
    loop.replace(makeSlot(warm, warmCells, 1));
    auto slot = makeSlot(scene, cells, 2);
    const auto values = sweep(cells.specs);
    auto* braille = dynamic_cast<braille::BrailleSceneControls*>(&slot->engine->scene());

    std::vector<float> left(8192), right(8192);
    // The audio input the listening scenes hear (score, audio-touch): bursts of a C5 with two
    // overtones, 4 a second (the Rite's first note for the score, the middle band for audio-touch).
    std::vector<float> inLeft(8192), inRight(8192);
    double inputTime = 0.0;
    const int blocks[] {kSamplesPerStep, 1, 64, 4096, 513};
    ControlStep step;
    step.source = source;
    step.dt = kDt;
    step.panicGesture = true;   // the hang detector runs in every guarded step too
    step.transport.valid = true;
    step.transport.playing = true;
    const int steps = 200 + 6 * static_cast<int>(values.size()) + 200;
    LiveInput& in = loop.input(source);
    for (int i = 0; i < steps; ++i) {
        const double t = i * kDt;
        // --- other threads' side (not guarded): producers, the UI, the builder -------------
        if (i == 100) {
            REQUIRE(loop.offer(slot));   // swaps in at the next (guarded) step
        }
        if (i > 100) loop.collect();
        if (i > 200 && (i - 200) % 6 == 0 && static_cast<std::size_t>((i - 200) / 6) <= values.size()) {
            const auto& [index, value] = values[static_cast<std::size_t>((i - 200) / 6 - 1)];
            cells.values[index].store(value);
        }
        step.automation = poseAt(t);
        step.transport.seconds = t;
        step.transport.ppq = t * 2.0;
        if (i % 700 == 350) step.transport.seconds = 0.5 * t;   // a seek back
        step.transport.playing = !(i % 500 >= 460);             // transport stops now and then
        switch (source) {
        case SourceKind::Device: in.pushImu(imuAt(t, kDt)); break;
        case SourceKind::Simulator: in.storeOrientation(t, poseToQuaternion(poseAt(t))); break;
        case SourceKind::Osc:
            if (i % 400 < 200) {
                in.storeOrientation(t, poseToQuaternion(poseAt(t)));
            } else if (i % 50 == 0) {   // a burst after a stall: more than a step may fuse
                for (int k = 0; k < 30; ++k) in.pushImu(imuAt(t - (29 - k) * kDt / 10.0, kDt / 10.0));
            } else {
                in.pushImu(imuAt(t, kDt));
            }
            break;
        case SourceKind::HostAutomation: break;
        }
        // The last 200 steps: the braille scene in its training mode, answered as a reader would.
        if (braille != nullptr && i == steps - 200) cells.values[braille::kParamMode].store(static_cast<float>(braille::BrailleMode::Training));
        if (braille != nullptr && i > 100 && i % 30 == 0) {
            braille->submitAnswer(i % 180 == 0 ? "left" : "here");
            braille->collectTrainingLog();
        }

        // --- the control side (guarded) --------------------------------------------------------
        ControlResult result;
        {
            RealtimeGuard guard;
            result = loop.tick(step);
            r.control.add(guard);
        }
        if (i == 100) {   // offered just before this step
            r.swappedInGuardedStep = result.swapped;
            r.runningAfterSwap = loop.active() ? loop.active()->sceneName : std::string();
        }
        const int n = blocks[i % 5];
        std::fill(left.begin(), left.begin() + n, 0.0f);
        std::fill(right.begin(), right.begin() + n, 0.0f);
        for (int k = 0; k < n; ++k) {
            const double ts = inputTime + k / 48000.0;
            inLeft[static_cast<std::size_t>(k)] = inRight[static_cast<std::size_t>(k)] =
                std::fmod(ts, 0.25) < 0.1 ? static_cast<float>(0.2 * std::sin(2.0 * 3.14159265358979 * 523.25 * ts) +
                                                               0.15 * std::sin(2.0 * 3.14159265358979 * 1046.5 * ts) +
                                                               0.1 * std::sin(2.0 * 3.14159265358979 * 1569.75 * ts))
                                           : 0.0f;
        }
        inputTime += n / 48000.0;
        {
            const float* input[2] = {inLeft.data(), inRight.data()};
            RealtimeGuard guard;
            loop.processInput(input, 2, n);
            loop.render(left.data(), right.data(), n);
            r.audio.add(guard);
        }
        if (i > 100) {
            for (int k = 0; k < n; ++k) r.energy += double(left[static_cast<std::size_t>(k)]) * double(left[static_cast<std::size_t>(k)]);
            bool any = false;
            for (auto level : result.levels) any = any || level > 0;
            r.motorSteps += any;
            r.validSteps += result.arm.valid;
        }
    }
    r.failed = loop.active() && loop.active()->engine->failed();
    if (braille != nullptr) {
        r.trainingAnswered = braille->trainingTrial();
        const std::string log = braille->trainingLogCsv();
        r.trainingLogRows = static_cast<int>(std::count(log.begin(), log.end(), '\n'));
    }
    return r;
}

/// A scene that breaks its contract: it throws from control() after a few steps.
class ThrowingScene final : public Scene {
public:
    std::string_view name() const override { return "throwing"; }
    void prepare(const SceneConfig&) override {}
    void control(const ControlInput&, SceneOutput& out) override
    {
        out.motors.setLevel(0, 15.0f);
        if (++calls_ > 3) throw std::runtime_error("scene bug");
    }

private:
    int calls_ = 0;
};

} // namespace

TEST_CASE("the real-time guard sees every kind of violation before it is trusted", "[realtime][guard]")
{
    if (!guardUsableHere()) return;
    REQUIRE(RealtimeGuard::installed());
    const auto once = [](auto&& what) {
        RealtimeGuard guard;
        what();
        return Totals {guard.allocations(), guard.deallocations(), guard.locks(), guard.throws(), 1};
    };
    // Opaque to the optimiser, so no allocation below can be elided.
    static void* volatile sink = nullptr;
    CHECK(once([] { sink = std::malloc(24); }).allocations == 1);
    CHECK(once([] { std::free(sink); }).deallocations == 1);
    CHECK(once([] { sink = std::calloc(3, 8); }).allocations == 1);
    CHECK(once([] { sink = std::realloc(sink, 4096); }).allocations == 1);
    CHECK(once([] { std::free(sink); }).deallocations == 1);
    CHECK(once([] { sink = std::aligned_alloc(64, 128); }).allocations == 1);
    CHECK(once([] { std::free(sink); }).deallocations == 1);
    CHECK(once([] { void* p = nullptr; if (posix_memalign(&p, 64, 100) == 0) sink = p; }).allocations == 1);
    CHECK(once([] { std::free(sink); }).deallocations == 1);
    CHECK(once([] { auto* p = new int(3); sink = p; delete p; }).allocations == 1);
    CHECK(once([] { auto* p = new int[5]; sink = p; delete[] p; }).deallocations == 1);
    CHECK(once([] { auto* p = new (std::nothrow) double(1.0); sink = p; delete p; }).allocations == 1);
    struct alignas(64) Wide { double v[8]; };
    CHECK(once([] { auto* p = new Wide; sink = p; delete p; }).allocations == 1);          // aligned new
    CHECK(once([] { auto* p = new Wide[2]; sink = p; delete[] p; }).deallocations == 1);   // aligned delete[]
    CHECK(once([] { std::vector<float> v(100); sink = v.data(); }).allocations == 1);
    std::mutex m;
    CHECK(once([&] { const std::lock_guard<std::mutex> lock(m); }).locks == 1);
    CHECK(once([&] { if (m.try_lock()) m.unlock(); }).locks == 1);
    CHECK(once([] {
              try {
                  throw std::runtime_error("x");
              } catch (const std::exception&) {
              }
          }).throws == 1);
    CHECK(once([] {
              try {
                  throw 42;
              } catch (int) {
              }
          }).throws == 1);
    const Totals quiet = once([] {
        volatile double x = 1.0;
        for (int i = 0; i < 100; ++i) x = x * 1.0001;
    });
    CHECK(quiet.clean());
}

TEST_CASE("every scene under every source: control step, audio and scene swap are real-time", "[realtime][loop]")
{
    if (!guardUsableHere()) return;
    REQUIRE(RealtimeGuard::installed());
    for (const std::string& scene : sceneNames()) {
        for (int s = 0; s < kSourceCount; ++s) {
            const auto source = static_cast<SourceKind>(s);
            const RunResult r = run(scene, source);
            INFO(scene << " / " << sourceName(source) << ": control " << r.control.text() << "; audio " << r.audio.text());
            CHECK(r.swappedInGuardedStep);            // the guarded step is the one that swapped …
            CHECK(r.runningAfterSwap == scene);       // … and the new scene is the one running
            CHECK(r.validSteps > 100);                // the arm was tracked: the scenes had work
            CHECK_FALSE(r.failed);
            CHECK(r.control.clean());
            CHECK(r.audio.clean());
            if (scene == "theremin" || scene == "cymbal" || scene == "panel" || scene == "sound-design") CHECK(r.energy > 0.0);
            if (scene != "monitor") CHECK(r.motorSteps > 0);
            if (scene == "braille") {
                CHECK(r.trainingAnswered >= 3);      // training ran inside the guarded steps
                CHECK(r.trainingLogRows > 20);
            }
        }
    }
}

namespace armadillo::live {
/// The session's audio block (LiveSession::renderBlock: the recording or the stems heard by the
/// scene, then played out under its sound), called here as the audio thread calls it.
struct LiveSessionAudioProbe {
    static void render(LiveSession& s, float* left, float* right, int n) { s.renderBlock(left, right, n); }
};
} // namespace armadillo::live

TEST_CASE("play's audio block with stems and with a recording is real-time, past the recording's end and looping", "[realtime][stems]")
{
    if (!guardUsableHere()) return;
    const auto dir = std::filesystem::temp_directory_path() / ("armadillo-rt-stems-" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    AudioBuffer tone;
    tone.channels.assign(2, std::vector<float>(12000));
    for (std::size_t i = 0; i < 12000; ++i)
        tone.channels[0][i] = tone.channels[1][i] = static_cast<float>(0.3 * std::sin(2.0 * 3.14159265358979 * 80.0 * static_cast<double>(i) / 48000.0));
    const std::string a = (dir / "bass.wav").string(), b = (dir / "drums.wav").string(), c = (dir / "vocals.wav").string();
    writeWav(a, tone);
    writeWav(b, tone);
    tone.channels[0].resize(5000);   // a shorter stem, padded with silence
    tone.channels[1].resize(5000);
    writeWav(c, tone);
    for (const bool stems : {true, false})
        for (const bool loop : {false, true}) {
            live::LiveConfig config;
            config.engine.scene = "audio-touch";
            config.engine.sceneConfig.sampleRate = 48000.0;
            if (stems) {
                config.audioStems = {a, b, c};
                config.engine.sceneConfig.stems = {"bass", "drums", "vocals"};
            } else {
                config.audioIn = a;
            }
            config.audioInLoop = loop;
            live::LiveSession session(config);
            std::vector<float> left(1024), right(1024);
            Totals totals;
            float peak = 0.0f;
            for (int k = 0; k < 80; ++k) {   // 80 blocks of 17..1024 frames: well past the 12000-frame recording
                const int n = 17 + (k * 389) % 1008;
                std::fill(left.begin(), left.end(), 0.0f);
                std::fill(right.begin(), right.end(), 0.0f);
                {
                    RealtimeGuard guard;
                    live::LiveSessionAudioProbe::render(session, left.data(), right.data(), n);
                    totals.add(guard);
                }
                if (k < 10)
                    for (int i = 0; i < n; ++i) peak = std::max(peak, std::fabs(left[static_cast<std::size_t>(i)]));
            }
            INFO((stems ? "stems" : "recording") << (loop ? ", looping: " : ": ") << totals.text());
            CHECK(totals.clean());
            CHECK(peak > (stems ? 0.45f : 0.25f));   // played out: the stems as their sum (two at 0.3 in phase), the recording as it is
        }
    std::filesystem::remove_all(dir);
}

TEST_CASE("a burst of IMU samples is fused at most kMaxImuPerStep at a time; the rest are dropped and counted", "[realtime][loop]")
{
    ControlLoop loop;
    Cells cells;
    loop.replace(makeSlot("monitor", cells, 1));
    LiveInput& in = loop.input(SourceKind::Device);
    ControlStep step;
    step.source = SourceKind::Device;
    for (int i = 0; i < 100; ++i) REQUIRE(in.pushImu(imuAt(i * 0.001 + 0.01, 0.001)));
    loop.tick(step);
    CHECK(in.imuWaiting() == 0);
    CHECK(loop.droppedImu() == 100 - ControlLoop::kMaxImuPerStep);
    for (int i = 0; i < ControlLoop::kMaxImuPerStep; ++i) REQUIRE(in.pushImu(imuAt(0.2 + i * 0.001, 0.001)));
    loop.tick(step);
    CHECK(loop.droppedImu() == 100 - ControlLoop::kMaxImuPerStep);   // a normal step drops nothing
}

TEST_CASE("a scene that throws is stopped: motors off, silence, a reported failure, nothing escapes", "[realtime][engine]")
{
    EngineConfig config;
    config.scene = "throwing";
    Engine engine(config, std::make_unique<ThrowingScene>());
    ArmState arm;
    arm.valid = true;
    bool anyOn = false;
    for (int i = 0; i < 3; ++i) {
        const MotorLevels l = engine.control(arm, {}, 0.005);
        for (auto v : l) anyOn = anyOn || v > 0;
    }
    REQUIRE(anyOn);   // the scene did drive a motor before it broke
    CHECK_FALSE(engine.failed());
    const MotorLevels broken = engine.control(arm, {}, 0.005);   // throws inside: must not escape
    CHECK(engine.failed());
    CHECK(std::string(engine.failure()) == "scene bug");
    for (auto v : broken) CHECK(v == 0);
    for (int i = 0; i < 10; ++i)
        for (auto v : engine.control(arm, {}, 0.005)) CHECK(v == 0);
    std::vector<float> l(64, 1.0f), r(64, 1.0f);
    engine.renderAudio(l.data(), r.data(), 64);
    for (float x : l) CHECK(x == 0.0f);
}
