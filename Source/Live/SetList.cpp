#include "Live/SetList.h"
#include "Core/AtomicFile.h"
#include "Core/Errors.h"
#include "Core/Json.h"
#include "Engine/ArmTracker.h"
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstring>
#include <stdexcept>

namespace armadillo::live {

namespace {
using device::JsonValue;

[[noreturn]] void refuse(const std::string& source, const JsonValue& at, const std::string& path, const std::string& message)
{
    throw InputError(source, at.line, path, message);
}

/// An InputError's message without its "<input>: column 'x': " prefix (to re-issue it with the
/// set list's file and line).
std::string bareMessage(const InputError& e)
{
    std::string m = e.what();
    if (m.rfind("<input>: ", 0) == 0) m.erase(0, 9);
    if (m.rfind("column '", 0) == 0) {
        const auto end = m.find("': ");
        if (end != std::string::npos) m.erase(0, end + 3);
    }
    return m;
}

std::string numberText(double v)
{
    std::string s;
    appendNumber(s, v, 9);
    return s;
}

const std::string& requireString(const std::string& source, const JsonValue& v, const std::string& path)
{
    if (v.kind != JsonValue::Kind::String) refuse(source, v, path, std::string("must be a string, not ") + JsonValue::kindName(v.kind));
    return v.string;
}
} // namespace

SetList parseSetList(std::string_view text, const std::string& source)
{
    const JsonValue root = device::parseJson(text, source);
    if (root.kind != JsonValue::Kind::Object) refuse(source, root, "", "a set list is a JSON object");
    SetList list;
    list.source = source;
    const JsonValue* version = root.find("armadillo_setlist");
    if (!version) refuse(source, root, "armadillo_setlist", "missing: a set list starts with \"armadillo_setlist\": 1");
    if (version->kind != JsonValue::Kind::Number || version->number != SetList::kVersion)
        refuse(source, *version, "armadillo_setlist", "unsupported version (this program reads version 1)");
    for (const auto& [key, value] : root.object)
        if (key != "armadillo_setlist" && key != "cues") refuse(source, value, key, "unknown key (a set list has armadillo_setlist and cues)");
    const JsonValue* cues = root.find("cues");
    if (!cues || cues->kind != JsonValue::Kind::Array || cues->array.empty())
        refuse(source, cues ? *cues : root, "cues", "needs a non-empty array of cues");
    for (std::size_t i = 0; i < cues->array.size(); ++i) {
        const JsonValue& c = cues->array[i];
        const std::string path = "cues[" + std::to_string(i) + "]";
        if (c.kind != JsonValue::Kind::Object) refuse(source, c, path, "a cue is an object with at least \"scene\"");
        Cue cue;
        cue.line = c.line;
        cue.name = "cue " + std::to_string(i);
        for (const auto& [key, value] : c.object) {
            const std::string at = path + "." + key;
            if (key == "name") cue.name = requireString(source, value, at);
            else if (key == "scene") cue.scene = requireString(source, value, at);
            else if (key == "mapping") cue.mapping = requireString(source, value, at);
            else if (key == "profile") cue.profile = requireString(source, value, at);
            else if (key == "score") cue.score = requireString(source, value, at);
            else if (key == "text") cue.text = requireString(source, value, at);
            else if (key == "parameters") {
                if (value.kind != JsonValue::Kind::Object) refuse(source, value, at, "must be an object of \"id\": value");
                for (const auto& [id, v] : value.object) {
                    if (v.kind == JsonValue::Kind::Number) cue.parameters.push_back(id + "=" + numberText(v.number));
                    else if (v.kind == JsonValue::Kind::String) cue.parameters.push_back(id + "=" + v.string);
                    else if (v.kind == JsonValue::Kind::Bool) cue.parameters.push_back(id + "=" + (v.boolean ? "1" : "0"));
                    else refuse(source, v, at + "." + id, "a parameter is a number or a choice name");
                }
            } else {
                refuse(source, value, at, "unknown key (a cue has name, scene, parameters, mapping, profile, score, text)");
            }
        }
        if (cue.scene.empty()) refuse(source, c, path + ".scene", "missing: every cue names its scene");
        const auto& names = sceneNames();
        if (std::find(names.begin(), names.end(), cue.scene) == names.end()) {
            std::string all;
            for (const auto& n : names) all += (all.empty() ? "" : ", ") + n;
            refuse(source, *c.find("scene"), path + ".scene", "unknown scene '" + cue.scene + "' (scenes: " + all + ")");
        }
        list.cues.push_back(std::move(cue));
    }
    return list;
}

SetList loadSetList(const std::string& path) { return parseSetList(readWholeFile(path), path); }

CuePlayer::CuePlayer(const SetList& list, const SceneConfig& base, int motorCount, bool twoArms, const std::array<float, kMaxMotors>& motorGain)
    : cues_(list.cues), twoArms_(twoArms)
{
    if (cues_.empty()) throw InputError(list.source, 0, "cues", "the set list has no cues");
    for (std::size_t i = 0; i < cues_.size(); ++i) {
        const Cue& c = cues_[i];
        EngineConfig config;
        config.scene = c.scene;
        config.sceneConfig = base;
        config.sceneConfig.score = c.score;
        config.sceneConfig.text = c.text;
        config.motorCount = motorCount;
        config.parameters = c.parameters;
        config.twoArms = twoArms;
        config.motorGain = motorGain;   // the reader's touch profile, as the single engine has it
        try {
            engines_.push_back(std::make_unique<Engine>(config));
        } catch (const InputError& e) {
            throw InputError(list.source, c.line, "cues[" + std::to_string(i) + "]" + (e.column().empty() ? "" : "." + e.column()), bareMessage(e));
        } catch (const std::exception& e) {
            throw InputError(list.source, c.line, "cues[" + std::to_string(i) + "]", std::string("scene '") + c.scene + "' cannot start: " + e.what());
        }
    }
    SafetyParams safety;
    safety_.prepare(safety, std::clamp(motorCount, kGridMotors, kMaxMotors));
    leftSafety_.prepare(safety, std::clamp(motorCount, kGridMotors, kMaxMotors));
    const double fs = base.sampleRate > 0.0 ? base.sampleRate : 48000.0;
    fadeLength_ = std::max(1, static_cast<int>(std::lround(kFadeSeconds * fs)));
    scratchL_.assign(kMaxBlock, 0.0f);
    scratchR_.assign(kMaxBlock, 0.0f);
}

CuePlayer::~CuePlayer() = default;

void CuePlayer::request(int index) noexcept { requested_.store(std::clamp(index, 0, cueCount() - 1), std::memory_order_release); }

void CuePlayer::next() noexcept
{
    int r = requested_.load(std::memory_order_acquire);
    while (!requested_.compare_exchange_weak(r, std::min(r + 1, cueCount() - 1), std::memory_order_acq_rel)) {}
}

void CuePlayer::previous() noexcept
{
    int r = requested_.load(std::memory_order_acquire);
    while (!requested_.compare_exchange_weak(r, std::max(r - 1, 0), std::memory_order_acq_rel)) {}
}

MotorLevels CuePlayer::control(const ArmState& arm, const Transport& transport, double dt) noexcept { return step(arm, nullptr, transport, dt); }

MotorLevels CuePlayer::control(const ArmState& arm, const ArmState& leftArm, const Transport& transport, double dt) noexcept
{
    return step(arm, twoArms_ ? &leftArm : nullptr, transport, dt);
}

MotorLevels CuePlayer::step(const ArmState& arm, const ArmState* leftArm, const Transport& transport, double dt) noexcept
{
    const int want = requested_.load(std::memory_order_acquire);
    if (want != controlCue_) {
        // The old cue's motors (both arms') off through its own tactile engines; the new cue starts afresh.
        engines_[static_cast<std::size_t>(controlCue_)]->allOff();
        controlCue_ = want;
        engines_[static_cast<std::size_t>(controlCue_)]->scene().reset();
        active_.store(controlCue_, std::memory_order_release);
        changes_.fetch_add(1, std::memory_order_relaxed);
    }
    Engine& e = *engines_[static_cast<std::size_t>(controlCue_)];
    const MotorLevels levels = leftArm ? e.control(arm, *leftArm, transport, dt) : e.control(arm, transport, dt);
    // One safety stage per arm across the whole set list: a cue change cannot restart a heat budget.
    const double step = std::isfinite(dt) && dt >= 0.0 ? std::min(dt, 0.1) : 0.0;
    leftLevels_ = twoArms_ ? leftSafety_.process(e.leftLevels(), step) : MotorLevels {};
    return safety_.process(levels, step);
}

void CuePlayer::processInput(const float* const* in, int channels, int numSamples) noexcept
{
    for (auto& e : engines_)
        if (e->listensToAudio()) e->processInput(in, channels, numSamples);
}

void CuePlayer::processMidi(const MidiNoteEvent* events, int count) noexcept
{
    for (auto& e : engines_)
        if (e->listensToMidi()) e->processMidi(events, count);
}

void CuePlayer::renderAudio(float* left, float* right, int numSamples) noexcept
{
    for (int done = 0; done < numSamples;) {
        const int n = std::min(kMaxBlock, numSamples - done);
        renderChunk(left + done, right + done, n);
        done += n;
    }
}

void CuePlayer::renderChunk(float* left, float* right, int n) noexcept
{
    const int active = active_.load(std::memory_order_acquire);
    if (active != audioCue_) {
        // A change mid-fade starts a new fade from the cue that was fading in (the one that
        // was fading out stops: it is at most kFadeSeconds from silence anyway).
        fadeFrom_ = audioCue_;
        audioCue_ = active;
        fadePos_ = 0;
    }
    engines_[static_cast<std::size_t>(audioCue_)]->renderAudio(left, right, n);
    if (fadeFrom_ < 0) return;
    engines_[static_cast<std::size_t>(fadeFrom_)]->renderAudio(scratchL_.data(), scratchR_.data(), n);
    for (int i = 0; i < n; ++i) {
        // Equal-gain linear cross-fade: the step it adds is at most |old − new| / fade length.
        const float g = fadePos_ < fadeLength_ ? static_cast<float>(fadePos_) / static_cast<float>(fadeLength_) : 1.0f;
        left[i] = g * left[i] + (1.0f - g) * scratchL_[static_cast<std::size_t>(i)];
        right[i] = g * right[i] + (1.0f - g) * scratchR_[static_cast<std::size_t>(i)];
        if (fadePos_ < fadeLength_) ++fadePos_;
    }
    if (fadePos_ >= fadeLength_) fadeFrom_ = -1;
}

void CuePlayer::panic() noexcept
{
    for (auto& e : engines_) e->panic();
}

void CuePlayer::resume() noexcept
{
    for (auto& e : engines_) e->resume();
}

CueChange parseCueChange(const std::string& text)
{
    const auto colon = text.find(':');
    if (colon == std::string::npos) throw std::invalid_argument("'" + text + "' is not T:INDEX (e.g. 2.5:1)");
    CueChange c;
    const char* b = text.data();
    const auto [e1, ec1] = std::from_chars(b, b + colon, c.t);
    const auto [e2, ec2] = std::from_chars(b + colon + 1, b + text.size(), c.cue);
    if (ec1 != std::errc() || e1 != b + colon || ec2 != std::errc() || e2 != b + text.size() || !std::isfinite(c.t) || c.t < 0.0 || c.cue < 0)
        throw std::invalid_argument("'" + text + "' is not T:INDEX (a time >= 0 in seconds, a cue index >= 0)");
    return c;
}

RenderResult renderSetList(const CsvTable& motion, const SetList& list, const RenderSettings& settings, std::vector<CueChange> changes)
{
    const MotionRows source = MotionRows::load(motion, settings.mount, "--mount");
    const std::size_t rows = source.size();
    if (rows == 0) throw InputError(motion.source(), 0, "", "the motion file has no rows");
    auto timeOf = [&](std::size_t i) { return source.time(i); };
    // A set list renders into memory: its span is bounded like any collected render.
    checkRenderSpan(motion, rows, timeOf, settings.tailSeconds, std::min(settings.maxSeconds, kMaxCollectedRenderSeconds));

    const bool rateOfInput = settings.audioIn != nullptr && settings.audioIn->sampleRate == settings.engine.sceneConfig.sampleRate;
    const double sampleRate = engineSampleRate(settings.engine.sceneConfig.sampleRate,
                                               rateOfInput && !settings.audioInName.empty() ? settings.audioInName : std::string("--sample-rate"));
    const bool twoArms = settings.leftMotion != nullptr;
    MotionRows leftSource;
    if (twoArms) {
        leftSource = MotionRows::load(*settings.leftMotion, settings.leftMount, "--mount-left");
        if (leftSource.size() == 0) throw InputError(settings.leftMotion->source(), 0, "--motion-left", "the left arm's motion file has no rows");
    }
    CuePlayer player(list, settings.engine.sceneConfig, settings.engine.motorCount, twoArms, settings.engine.motorGain);
    for (const CueChange& c : changes)
        if (c.cue >= player.cueCount())
            throw InputError(list.source, 0, "--cue-at", "cue " + std::to_string(c.cue) + " does not exist (the set list has " +
                                                             std::to_string(player.cueCount()) + " cues, 0.." + std::to_string(player.cueCount() - 1) + ")");
    std::stable_sort(changes.begin(), changes.end(), [](const CueChange& a, const CueChange& b) { return a.t < b.t; });

    // The recording (`--audio-in`): every listening cue hears it all the time (a follower keeps
    // its place while another cue plays), from sample 0 = the first motion row.
    const AudioBuffer* input = settings.audioIn;
    const std::string inputName = settings.audioInName.empty() ? std::string("--audio-in") : settings.audioInName;
    if (input) {
        bool listens = false;
        for (int c = 0; c < player.cueCount(); ++c) listens = listens || player.engine(c).listensToAudio();
        if (!listens) throw InputError(inputName, 0, "", "--audio-in: no cue of " + list.source + " listens to audio (score, audio-touch and layered-keyboard do)");
        if (input->channels.empty() || input->frames() == 0) throw InputError(inputName, 0, "", "--audio-in: the recording holds no audio");
        if (std::fabs(input->sampleRate - sampleRate) > 0.5)
            throw InputError(inputName, 0, "", "--audio-in: the recording's sample rate (" + std::to_string(static_cast<long>(input->sampleRate)) +
                                                   " Hz) differs from the engine's (" + std::to_string(static_cast<long>(sampleRate)) +
                                                   " Hz); give --sample-rate to match it");
    }

    ArmTracker tracker, leftTracker;
    ArmState leftArm;
    std::size_t leftRow = 0;
    RenderResult result;
    const double t0 = timeOf(0);
    const double tEnd = timeOf(rows - 1) + std::max(0.0, settings.tailSeconds);
    const auto totalFrames = static_cast<std::size_t>(std::llround((tEnd - t0) * sampleRate)) + 1;
    result.audio.sampleRate = sampleRate;
    result.audio.channels.assign(2, std::vector<float>(totalFrames, 0.0f));
    const int block = std::clamp(settings.blockSize, 1, 8192);
    std::vector<const float*> inputChannels(input ? input->channels.size() : 0, nullptr);
    std::vector<std::vector<float>> inputScratch(inputChannels.size(), std::vector<float>(static_cast<std::size_t>(block), 0.0f));
    std::size_t frame = 0;
    const auto renderUntil = [&](double t) {
        const auto target = std::min(totalFrames, static_cast<std::size_t>(std::llround((t - t0) * sampleRate)));
        while (frame < target) {
            const int n = static_cast<int>(std::min<std::size_t>(static_cast<std::size_t>(block), target - frame));
            if (input) {   // past the recording's end silence still comes in
                for (std::size_t c = 0; c < inputChannels.size(); ++c) {
                    auto& scratch = inputScratch[c];
                    for (int i = 0; i < n; ++i) {
                        const std::size_t at = frame + static_cast<std::size_t>(i);
                        scratch[static_cast<std::size_t>(i)] = at < input->frames() ? input->channels[c][at] : 0.0f;
                    }
                    inputChannels[c] = scratch.data();
                }
                player.processInput(inputChannels.data(), static_cast<int>(inputChannels.size()), n);
            }
            float* left = result.audio.channels[0].data() + frame;
            float* right = result.audio.channels[1].data() + frame;
            player.renderAudio(left, right, n);
            for (int i = 0; i < n; ++i) result.scenePeak = std::max({result.scenePeak, std::fabs(left[i]), std::fabs(right[i])});
            if (input && settings.mixAudioIn) {   // the recording as the listener hears it, under the cues' sound
                const float* first = inputChannels[0];
                const float* second = inputChannels[inputChannels.size() > 1 ? 1 : 0];
                for (int i = 0; i < n; ++i) {
                    left[i] = std::clamp(left[i] + first[i], -1.0f, 1.0f);
                    right[i] = std::clamp(right[i] + second[i], -1.0f, 1.0f);
                }
            }
            frame += static_cast<std::size_t>(n);
        }
    };
    if (input) {   // the recording itself, from sample 0
        for (std::size_t c = 0; c < inputChannels.size(); ++c) inputChannels[c] = input->channels[c].data();
        player.processInput(inputChannels.data(), static_cast<int>(inputChannels.size()), 0);
    }
    std::size_t nextChange = 0;
    double previous = t0;
    for (std::size_t i = 0; i < rows; ++i) {
        const double t = timeOf(i);
        renderUntil(t);
        while (nextChange < changes.size() && changes[nextChange].t <= t - t0 + 1e-9) player.request(changes[nextChange++].cue);
        const ArmState arm = source.apply(tracker, i);
        if (twoArms)   // the left arm's rows up to this time (both files on one clock)
            while (leftRow < leftSource.size() && leftSource.time(leftRow) <= t + 1e-9) leftArm = leftSource.apply(leftTracker, leftRow++);
        Transport transport;
        transport.valid = true;
        transport.playing = true;
        transport.seconds = t - t0;
        transport.bpm = settings.bpm;
        transport.ppq = transport.seconds * settings.bpm / 60.0;
        MotorLevels levels {};
        if (arm.valid) levels = twoArms ? player.control(arm, leftArm, transport, t - previous) : player.control(arm, transport, t - previous);
        else ++result.invalidRows;
        Engine& current = player.engine(player.current());
        if (current.failed())
            throw std::runtime_error("scene '" + current.config().scene + "' failed at t = " + std::to_string(t) + " s (motors off): " + current.failure());
        previous = t;
        result.tactile.push_back({t, levels});
        if (twoArms) {
            result.leftTactile.push_back({t, arm.valid ? player.leftLevels() : MotorLevels {}});
            result.rightOrientation.push_back({t, arm.valid ? arm.q : Eigen::Quaterniond::Identity()});
            result.leftOrientation.push_back({t, leftArm.valid ? leftArm.q : Eigen::Quaterniond::Identity()});
        }
        ++result.controlUpdates;
        GestureEvent g;
        for (int c = 0; c < player.cueCount(); ++c)
            while (player.engine(c).popGesture(g)) result.gestures.push_back(g);
    }
    renderUntil(tEnd + 1.0 / sampleRate);
    return result;
}

} // namespace armadillo::live
