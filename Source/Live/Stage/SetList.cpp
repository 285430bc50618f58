#include "Live/Stage/SetList.h"
#include "Core/AtomicFile.h"
#include "Core/Errors.h"
#include "Core/Json.h"
#include "Fusion/ArmTracker.h"
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstring>
#include <stdexcept>

namespace armadillo::live {

namespace {
using armadillo::core::JsonValue;

[[noreturn]] void refuse(const std::string& source, const core::JsonValue& at, const std::string& path, const std::string& message)
{
    throw core::InputError(source, at.line, path, message);
}

/// An InputError's message without its "<input>: column 'x': " prefix (to re-issue it with the
/// set list's file and line).
std::string bareMessage(const core::InputError& e)
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
    core::appendNumber(s, v, 9);
    return s;
}

const std::string& requireString(const std::string& source, const core::JsonValue& v, const std::string& path)
{
    if (v.kind != core::JsonValue::Kind::String) refuse(source, v, path, std::string("must be a string, not ") + core::JsonValue::kindName(v.kind));
    return v.string;
}
} // namespace

SetList parseSetList(std::string_view text, const std::string& source)
{
    const core::JsonValue root = armadillo::core::parseJson(text, source);
    if (root.kind != core::JsonValue::Kind::Object) refuse(source, root, "", "a set list is a JSON object");
    SetList list;
    list.source = source;
    const core::JsonValue* version = root.find("armadillo_setlist");
    if (!version) refuse(source, root, "armadillo_setlist", "missing: a set list starts with \"armadillo_setlist\": 1");
    if (version->kind != core::JsonValue::Kind::Number || version->number != SetList::kVersion)
        refuse(source, *version, "armadillo_setlist", "unsupported version (this program reads version 1)");
    for (const auto& [key, value] : root.object)
        if (key != "armadillo_setlist" && key != "cues") refuse(source, value, key, "unknown key (a set list has armadillo_setlist and cues)");
    const core::JsonValue* cues = root.find("cues");
    if (!cues || cues->kind != core::JsonValue::Kind::Array || cues->array.empty())
        refuse(source, cues ? *cues : root, "cues", "needs a non-empty array of cues");
    for (std::size_t i = 0; i < cues->array.size(); ++i) {
        const core::JsonValue& c = cues->array[i];
        const std::string path = "cues[" + std::to_string(i) + "]";
        if (c.kind != core::JsonValue::Kind::Object) refuse(source, c, path, "a cue is an object with at least \"scene\"");
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
                if (value.kind != core::JsonValue::Kind::Object) refuse(source, value, at, "must be an object of \"id\": value");
                for (const auto& [id, v] : value.object) {
                    if (v.kind == core::JsonValue::Kind::Number) cue.parameters.push_back(id + "=" + numberText(v.number));
                    else if (v.kind == core::JsonValue::Kind::String) cue.parameters.push_back(id + "=" + v.string);
                    else if (v.kind == core::JsonValue::Kind::Bool) cue.parameters.push_back(id + "=" + (v.boolean ? "1" : "0"));
                    else refuse(source, v, at + "." + id, "a parameter is a number or a choice name");
                }
            } else {
                refuse(source, value, at, "unknown key (a cue has name, scene, parameters, mapping, profile, score, text)");
            }
        }
        if (cue.scene.empty()) refuse(source, c, path + ".scene", "missing: every cue names its scene");
        const auto& names = engine::sceneNames();
        if (std::find(names.begin(), names.end(), cue.scene) == names.end()) {
            std::string all;
            for (const auto& n : names) all += (all.empty() ? "" : ", ") + n;
            refuse(source, *c.find("scene"), path + ".scene", "unknown scene '" + cue.scene + "' (scenes: " + all + ")");
        }
        list.cues.push_back(std::move(cue));
    }
    return list;
}

SetList loadSetList(const std::string& path) { return parseSetList(core::readWholeFile(path), path); }

CuePlayer::CuePlayer(const SetList& list, const core::SceneConfig& base, int motorCount, bool twoArms, const std::array<float, core::kMaxMotors>& motorGain)
    : cues_(list.cues), twoArms_(twoArms)
{
    if (cues_.empty()) throw core::InputError(list.source, 0, "cues", "the set list has no cues");
    for (std::size_t i = 0; i < cues_.size(); ++i) {
        const Cue& c = cues_[i];
        engine::EngineConfig config;
        config.scene = c.scene;
        config.sceneConfig = base;
        config.sceneConfig.score = c.score;
        config.sceneConfig.text = c.text;
        config.motorCount = motorCount;
        config.parameters = c.parameters;
        config.twoArms = twoArms;
        config.motorGain = motorGain;   // the reader's touch profile, as the single engine has it
        try {
            engines_.push_back(std::make_unique<engine::Engine>(config));
        } catch (const core::InputError& e) {
            throw core::InputError(list.source, c.line, "cues[" + std::to_string(i) + "]" + (e.column().empty() ? "" : "." + e.column()), bareMessage(e));
        } catch (const std::exception& e) {
            throw core::InputError(list.source, c.line, "cues[" + std::to_string(i) + "]", std::string("scene '") + c.scene + "' cannot start: " + e.what());
        }
    }
    tactile::SafetyParams safety;
    safety_.prepare(safety, std::clamp(motorCount, core::kGridMotors, core::kMaxMotors));
    leftSafety_.prepare(safety, std::clamp(motorCount, core::kGridMotors, core::kMaxMotors));
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

core::MotorLevels CuePlayer::control(const core::ArmState& arm, const core::Transport& transport, double dt) noexcept { return step(arm, nullptr, transport, dt); }

void CuePlayer::restart() noexcept { engines_[static_cast<std::size_t>(controlCue_)]->restart(); }

core::MotorLevels CuePlayer::control(const core::ArmState& arm, const core::ArmState& leftArm, const core::Transport& transport, double dt) noexcept
{
    return step(arm, twoArms_ ? &leftArm : nullptr, transport, dt);
}

core::MotorLevels CuePlayer::step(const core::ArmState& arm, const core::ArmState* leftArm, const core::Transport& transport, double dt) noexcept
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
    engine::Engine& e = *engines_[static_cast<std::size_t>(controlCue_)];
    const core::MotorLevels levels = leftArm ? e.control(arm, *leftArm, transport, dt) : e.control(arm, transport, dt);
    // One safety stage per arm across the whole set list: a cue change cannot restart a heat budget.
    const double step = std::isfinite(dt) && dt >= 0.0 ? std::min(dt, 0.1) : 0.0;
    leftLevels_ = twoArms_ ? leftSafety_.process(e.leftLevels(), step) : core::MotorLevels {};
    return safety_.process(levels, step);
}

void CuePlayer::processInput(const float* const* in, int channels, int numSamples) noexcept
{
    for (auto& e : engines_)
        if (e->listensToAudio()) e->processInput(in, channels, numSamples);
}

void CuePlayer::processMidi(const core::MidiNoteEvent* events, int count) noexcept
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

} // namespace armadillo::live
