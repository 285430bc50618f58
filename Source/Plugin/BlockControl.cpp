#include "Plugin/BlockControl.h"
#include "Core/Clock.h"
#include "Engine/Engine.h"
#include <cmath>
#include <cstring>

namespace armadillo::plugin {

int MidiMap::noteFor(const char* gesture) noexcept
{
    struct Entry { const char* name; int note; };
    static constexpr Entry table[] {{"roll", kNoteRoll}, {"punch", kNotePunch}, {"strike", kNoteStrike}};
    if (gesture != nullptr)
        for (const auto& e : table)
            if (std::strcmp(e.name, gesture) == 0) return e.note;
    return kNoteOther;
}

BlockControl::BlockControl(live::ControlLoop& loop, ControlToken& token, const Cells& cells, device::LevelSchedule& motors)
    : loop_(loop), token_(token), cells_(cells), motors_(motors)
{
    jassert(cells.elevation && cells.azimuth && cells.roll && cells.source);
}

SourceKind BlockControl::source() const noexcept
{
    return static_cast<SourceKind>(juce::jlimit(0, 3, static_cast<int>(cells_.source->load(std::memory_order_relaxed))));
}

void BlockControl::prepare(double sampleRate)
{
    sampleRate_.store(sampleRate > 0.0 ? sampleRate : 48000.0);
    samplesToTick_ = 0;
    noteOffs_ = {};
    midiStorage_.ensureSize(kMidiStorageBytes);   // off the audio thread; processBlock hands it over
    midiStorageGiven_ = false;
}

void BlockControl::step(double dt, double wall, bool toMotors, const Transport& transport, juce::MidiBuffer* midi,
                        int sampleOffset) noexcept
{
    // The motor timeline. Levels leave the link at their stamp: the audio timeline's steady
    // spacing while the host keeps time, the wall clock when it falls behind (late, stalled) or
    // races ahead of it (stamps never run backwards). After a stall the previous levels were on
    // until the link went all-off, not one tick: the safety stage is charged that.
    live::ControlStep s;
    double stamp = 0.0;
    if (toMotors) {
        stamp = lastStamp_ < 0.0 ? wall : lastStamp_ + dt;
        if (stamp < wall - kMaxLag) stamp = wall;
        if (stamp > wall + kMaxLead) stamp = std::max(lastStamp_ + 1e-6, wall + kMaxLead);
        if (lastStamp_ >= 0.0) s.motorOnTime = motors_.onTime(lastStamp_, stamp);
    }
    s.source = source();
    s.automation = Pose {cells_.elevation->load(std::memory_order_relaxed), cells_.azimuth->load(std::memory_order_relaxed),
                         cells_.roll->load(std::memory_order_relaxed)};
    s.transport = transport;
    s.dt = dt;
    const live::ControlResult result = loop_.tick(s);   // swap-in, parameters, fusion, Engine::control
    if (! result.ran) return;
    if (toMotors) {
        motors_.push(stamp, result.levels);   // full (no link consuming): dropped and counted
        lastStamp_ = stamp;
        motorsOff_ = false;
    } else if (! motorsOff_) {
        motors_.allOff();
        motorsOff_ = true;
        lastStamp_ = -1.0;
    }

    Engine& engine = *loop_.active()->engine;
    clock_ += dt;
    const ArmState& arm = result.arm;
    ArmFrame f;
    f.t = clock_;
    f.valid = arm.valid;
    f.q[0] = arm.q.w();
    f.q[1] = arm.q.x();
    f.q[2] = arm.q.y();
    f.q[3] = arm.q.z();
    f.pose[0] = arm.features.pose.elevationDeg;
    f.pose[1] = arm.features.pose.azimuthDeg;
    f.pose[2] = arm.features.pose.rollDeg;
    for (int i = 0; i < 3; ++i) f.gyro[i] = arm.gyro[i];
    if (toMotors) f.motors = result.levels;   // what goes to the motors; zeros when nothing does
    f.motorCount = engine.config().motorCount;
    f.serial = ++frameSerial_;
    frame_.store(f);
    ticks_.fetch_add(1, std::memory_order_relaxed);

    GestureEvent g;
    while (engine.popGesture(g)) {
        gestures_.push(g);
        lastGesture_.store(g.name, std::memory_order_relaxed);
        gestureCount_.fetch_add(1, std::memory_order_relaxed);
        if (midi != nullptr) emitNote(*midi, MidiMap::noteFor(g.name), g.value, sampleOffset);
    }

    if (midi != nullptr && arm.valid) {
        const double values[3] {(f.pose[0] + 90.0) / 180.0, f.pose[1] / 360.0, (f.pose[2] + 180.0) / 360.0};
        const int ccs[3] {MidiMap::kCcElevation, MidiMap::kCcAzimuth, MidiMap::kCcRoll};
        const int channel = juce::jlimit(1, 16, midiChannel_.load(std::memory_order_relaxed));
        for (int i = 0; i < 3; ++i) {
            const int v = juce::jlimit(0, 127, static_cast<int>(std::lround(values[i] * 127.0)));
            if (v != lastCc_[i]) {
                midi->addEvent(juce::MidiMessage::controllerEvent(channel, ccs[i], v), sampleOffset);
                lastCc_[i] = v;
            }
        }
    }
}

void BlockControl::emitNote(juce::MidiBuffer& midi, int note, float value, int sampleOffset) noexcept
{
    const int channel = juce::jlimit(1, 16, midiChannel_.load(std::memory_order_relaxed));
    const auto velocity = static_cast<juce::uint8>(juce::jlimit(1, 127, static_cast<int>(std::lround(std::fabs(value) * 127.0f))));
    for (auto& off : noteOffs_) {
        if (off.note == note) {   // retrigger: close the sounding note first
            midi.addEvent(juce::MidiMessage::noteOff(channel, note), sampleOffset);
            off.note = -1;
        }
    }
    midi.addEvent(juce::MidiMessage::noteOn(channel, note, velocity), sampleOffset);
    const int length = std::max(1, static_cast<int>(MidiMap::kNoteLengthS * sampleRate_.load(std::memory_order_relaxed)));
    for (auto& off : noteOffs_) {
        if (off.note < 0) {
            off.note = note;
            off.samplesLeft = sampleOffset + length;
            return;
        }
    }
}

void BlockControl::flushNoteOffs(juce::MidiBuffer& midi, int blockSamples) noexcept
{
    const int channel = juce::jlimit(1, 16, midiChannel_.load(std::memory_order_relaxed));
    for (auto& off : noteOffs_) {
        if (off.note < 0) continue;
        if (off.samplesLeft < blockSamples) {
            midi.addEvent(juce::MidiMessage::noteOff(channel, off.note), std::max(0, off.samplesLeft));
            off.note = -1;
        } else {
            off.samplesLeft -= blockSamples;
        }
    }
}

void BlockControl::processBlock(juce::AudioBuffer<float>& buffer, juce::MidiBuffer& midi, juce::AudioPlayHead* playHead,
                                bool offline) noexcept
{
    const int n = buffer.getNumSamples();
    buffer.clear();
    // No MIDI input is used; the buffer carries our gestures out. The host's buffer may be sized
    // for a few events only, and a roll that emits several would grow it here: the first block
    // hands it storage sized in prepare() (swapWith moves pointers, and clear() keeps the
    // storage), so adding events never allocates while the host reuses its buffer, as JUCE's
    // wrappers do. A host that hands a fresh small buffer each block could still make it grow
    // (JUCE's own wrappers do not): the plugin test measures the real hosts' path.
    if (! midiStorageGiven_) {
        midi.swapWith(midiStorage_);
        midiStorageGiven_ = true;
    }
    midi.clear();
    const double wall = monotonicSeconds();
    lastAudioMs_.store(wall * 1e3, std::memory_order_relaxed);
    if (buffer.getNumChannels() < 2 || n <= 0) return;
    if (! token_.tryTake()) return;   // the idle clock is finishing an update: one silent block

    const double sr = sampleRate_.load(std::memory_order_relaxed);
    Transport transport;
    if (playHead != nullptr) {
        if (const auto pos = playHead->getPosition()) {
            transport.valid = pos->getTimeInSeconds().hasValue() || pos->getPpqPosition().hasValue();
            transport.playing = pos->getIsPlaying();
            transport.looping = pos->getIsLooping();
            transport.seconds = pos->getTimeInSeconds().orFallback(0.0);
            transport.ppq = pos->getPpqPosition().orFallback(0.0);
            transport.bpm = pos->getBpm().orFallback(120.0);
        }
    }

    const int samplesPerTick = std::max(1, static_cast<int>(std::lround(sr / kControlRateHz)));
    float* left = buffer.getWritePointer(0);
    float* right = buffer.getWritePointer(1);
    int pos = 0;
    while (pos < n) {
        if (samplesToTick_ <= 0) {
            Transport t = transport;
            if (t.valid && t.playing) {
                const double ahead = pos / sr;
                t.seconds += ahead;
                t.ppq += ahead * t.bpm / 60.0;
            }
            // Each step's levels belong to its place in the block: a 4096-sample block's 17 steps
            // reach the motors over 85 ms, not all at once.
            step(samplesPerTick / sr, wall + pos / sr, ! offline, t, &midi, pos);
            samplesToTick_ = samplesPerTick;
        }
        const int len = std::min(n - pos, samplesToTick_);
        loop_.render(left + pos, right + pos, len);
        pos += len;
        samplesToTick_ -= len;
    }
    flushNoteOffs(midi, n);
    token_.release();
}

void BlockControl::idleTick(double dt) noexcept
{
    const double now = monotonicSeconds();
    if (now * 1e3 - lastAudioMs_.load(std::memory_order_relaxed) <= kIdleAfterMs || ! token_.tryTake()) return;
    // A late timer (loaded machine) catches up with several updates so the control rate stays
    // at 200 Hz on average, as it does under an audio callback.
    const int updates = juce::jlimit(1, 4, static_cast<int>(std::lround(dt * kControlRateHz)));
    const bool toMotors = idleDrivesMotors_.load(std::memory_order_relaxed);
    for (int i = 0; i < updates; ++i) step(dt / updates, now - (updates - 1 - i) * dt / updates, toMotors, Transport {}, nullptr, 0);
    token_.release();
}

} // namespace armadillo::plugin
