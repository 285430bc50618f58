#include "Live/Session/BlockControl.h"
#include "Access/TactilePlayer.h"
#include <algorithm>
#include "Core/Clock.h"
#include "Engine/Engine.h"
#include "Live/Outputs/TactorOutput.h"
#include "Mqtt/MessageService.h"
#include <cassert>
#include <cmath>
#include <cstring>
#include <limits>
#include <utility>

namespace armadillo::live {

namespace {

void addInto(float* to, const float* from, int n) noexcept
{
    for (int i = 0; i < n; ++i) to[i] += from[i];
}

void clearBlock(const AudioBlock& b) noexcept
{
    for (int c = 0; c < b.numChannels; ++c)
        if (b.numSamples > 0) std::fill_n(b.channels[c], b.numSamples, 0.0f);
}

} // namespace

BlockControl::BlockControl(Instrument& instrument, ControlToken& token, const Cells& cells, link::LevelSchedule& motors)
    : instrument_(instrument), loop_(instrument.loop()), token_(token), cells_(cells), motors_(motors), stage_(&instrument.stage()),
      runner_(instrument.runner()), published_(instrument.published())
{
    assert(cells.elevation && cells.azimuth && cells.roll && cells.source);
}

SourceKind BlockControl::source() const noexcept
{
    return static_cast<SourceKind>(std::clamp(static_cast<int>(cells_.source->load(std::memory_order_relaxed)), 0, 3));
}

void BlockControl::prepare(double sampleRate)
{
    sampleRate_.store(sampleRate > 0.0 ? sampleRate : 48000.0);
    samplesToTick_ = 0;
    skippedSamples_ = 0;
    offlineRender_.store(false, std::memory_order_relaxed);
    samplesSinceStep_ = std::max(1, static_cast<int>(std::lround(sampleRate_.load() / kControlRateHz)));
    notesOffPending_.store(true, std::memory_order_relaxed);   // a restart: nothing may hang
    runner_.forgetCues();   // the stage may have replaced its player (prepareToPlay): taken again at the next block
}

void BlockControl::step(double dt, double wall, bool toMotors, const core::Transport& transport, BlockMidi* midi,
                        int sampleOffset, double cutoff) noexcept
{
    // The motor timeline. Levels leave the link at their stamp: the audio timeline's steady
    // spacing while the host keeps time, the wall clock when it falls behind (late, stalled) or
    // races ahead of it (stamps never run backwards). After a stall the previous levels were on
    // until the link went all-off, not one tick: the safety stage is charged that.
    ControlStep s;
    double stamp = 0.0;
    if (toMotors) {
        stamp = lastStamp_ < 0.0 ? wall : lastStamp_ + dt;
        if (stamp < wall - kMaxLag) stamp = wall;
        if (stamp > wall + kMaxLead) stamp = std::max(lastStamp_ + 1e-6, wall + kMaxLead);
        if (lastStamp_ >= 0.0) s.motorOnTime = motors_.onTime(lastStamp_, stamp);
    }
    s.source = source();
    s.automation = core::Pose {cells_.elevation->load(std::memory_order_relaxed), cells_.azimuth->load(std::memory_order_relaxed),
                         cells_.roll->load(std::memory_order_relaxed)};
    s.transport = transport;
    s.dt = dt;
    s.arrivalCutoff = cutoff;
    // The instrument's step (Instrument.h): the left arm fused, the stage's cues and panic (the
    // panic gesture panics the stage, as CC 120 or F12 do), the frame published with what goes
    // to the motors (zeros when nothing does) at the step's time on this clock.
    const Instrument::Stepped stepped = instrument_.step(s, clock_ + dt, toMotors);
    const ControlResult& result = stepped.result;
    if (! result.ran) return;
    if (result.swapped) mapper_.resendSceneParams();   // the new scene starts from its defaults
    if (auto* bus = tactors_.active()) bus->setLevels(result.levels, dt);   // the Tactors bus (rendered by processBlock)
    if (toMotors) {
        if (auto* out = tactorOut_.load(std::memory_order_acquire)) out->push(clock_ + dt, result.levels);   // the app's tactor output
        motors_.push(stamp, result.levels);   // full (no link consuming): dropped and counted
        lastStamp_ = stamp;
        motorsOff_ = false;
    } else if (! motorsOff_) {
        motors_.allOff();
        motorsOff_ = true;
        lastStamp_ = -1.0;
    }
    clock_ += dt;

    // The mapping: every source of this step through the active set (docs/MAPPING.md). Its
    // events carry the step's time (clock_), which is this step's sample offset in the block.
    const double blockStart = clock_ - sampleOffset / sampleRate_.load(std::memory_order_relaxed);
    const int blockSamples = midi != nullptr ? blockSamples_ : 0;
    if (stepped.silenceMapping) {   // the panic gesture at this step: the mapping's notes end now
        mapper_.panic(clock_, mapOut_);
        deliver(midi, blockStart, blockSamples);
    }
    const mapping::MappingInput in = instrument_.mappingInput(stepped, clock_);
    mapper_.process(in, mapOut_);
    learnRange(in);
    deliver(midi, blockStart, blockSamples);
}

void BlockControl::learnRange(const mapping::MappingInput& in) noexcept
{
    const int kind = outputs_.learnSource.load(std::memory_order_relaxed);
    if (kind < 0) return;
    const std::uint32_t generation = outputs_.learnGeneration.load(std::memory_order_acquire);
    if (generation != learnGeneration_) {
        learnGeneration_ = generation;
        learner_.reset();
    }
    mapping::SourceSpec source;
    source.kind = static_cast<mapping::SourceKind>(kind);
    if (mapping::isEventSource(source.kind)) return;
    const double forward = outputs_.learnForward.load(std::memory_order_relaxed) ? mapper_.forwardAzimuth() : 0.0;
    const double v = mapping::readSource(source, in, forward);
    if (! std::isfinite(v)) return;
    learner_.add(v);
    outputs_.learnedLo.store(learner_.lo, std::memory_order_relaxed);
    outputs_.learnedHi.store(learner_.hi, std::memory_order_relaxed);
    outputs_.learnedCount.store(learner_.count, std::memory_order_release);
}

void BlockControl::deliver(BlockMidi* midi, double blockStart, int blockSamples) noexcept
{
    deliverMidi_ = midi;
    deliverStart_ = blockStart;
    deliverSamples_ = blockSamples;
    deliverMapping(mapOut_, *this, mapOut_.paramCount > 0 ? sceneParamTarget() : SceneParamTarget {}, tally_);
    deliverMidi_ = nullptr;
}

bool BlockControl::midi(const mapping::MidiEvent& e) noexcept
{
    if (port_ != nullptr) port_->push(e.bytes.data(), e.size);
    if (deliverMidi_ == nullptr || deliverSamples_ <= 0) return true;
    // Sample-accurate: the event's time on the mapping's timeline → its offset in this block.
    const double sr = sampleRate_.load(std::memory_order_relaxed);
    const int offset = std::clamp(static_cast<int>(std::lround((e.t - deliverStart_) * sr)), 0, deliverSamples_ - 1);
    return deliverMidi_->add(e.bytes.data(), e.size, offset);
}

bool BlockControl::osc(const mapping::OscPacket& p) noexcept
{
    return outputs_.pushOsc(p);   // to the clock that sends (the message thread's OscLink)
}

bool BlockControl::mqtt(const mapping::MqttMessage& m) noexcept
{
    // The arm as a remote (docs/MQTT.md): through the app's connection, if any.
    auto* service = mqtt_.load(std::memory_order_acquire);
    return service != nullptr && service->publishValue(std::string_view(m.topic.data(), m.topicLength),
                                                       std::string_view(m.payload.data(), m.payloadLength), m.qos, m.retain, m.rate);
}

void BlockControl::stage(const mapping::StageEvent& e) noexcept
{
    // A mapping's "stage" destinations (docs/STAGE.md): to the stage as its MIDI and OSC
    // commands go (atomics), applied at the start of the next block.
    if (stage_ != nullptr) stage_->apply(e.command);
}

SceneParamTarget BlockControl::sceneParamTarget() noexcept
{
    // The set names parameters by id; the active scene owns some of them (ids are unique across
    // scenes: SceneParameterTable). String compares over a constant table: no allocation.
    auto* set = mapper_.active();
    auto* slot = loop_.active();
    if (set == nullptr || slot == nullptr || sceneTable_ == nullptr || slot->engine == nullptr) return {};
    for (const auto& entry : sceneTable_->scenes)
        if (entry.scene == slot->sceneName) return {&slot->engine->scene(), &set->sceneParamIds(), &entry.specs};
    return {};
}

BlockControl::BlockPlan BlockControl::planBlock(const AudioBlock& buffer, const Listen& listen) noexcept
{
    BlockPlan plan;
    // The input channels are read step by step; the output is written over them.
    plan.listenCount = (listen.first >= 0 && listen.first + listen.count <= buffer.numChannels) ? std::min(listen.count, 2) : 0;
    plan.throughCount = std::min({listen.through, 2, buffer.numChannels});
    // Stems whose channels all lie in the buffer (a host that hands fewer channels than the
    // layout promised gets the stems up to the first that does not fit).
    while (plan.stemCount < std::min(listen.stemCount, kMaxStems)) {
        const Bus& bus = listen.stems[static_cast<std::size_t>(plan.stemCount)];
        if (bus.first < 0 || bus.count < 1 || bus.count > 2 || bus.first + bus.count > buffer.numChannels) break;
        ++plan.stemCount;
    }
    // The Tactors bus: a renderer offered since the last block first; the bus's channels, when
    // the host's buffer holds them all.
    tactors_.takeOffered([](tactors::TactorRenderer*) {});
    plan.tactorBus = tactors_.active();
    plan.busCount = std::clamp(listen.tactorCount, 0, tactors::kMaxChannels);
    for (int c = 0; c < plan.busCount; ++c) {
        const int channel = listen.tactorChannel[static_cast<std::size_t>(c)];
        if (channel < 2 || channel >= buffer.numChannels) plan.busCount = 0;   // not all in the buffer: none
    }
    plan.busRendered = plan.tactorBus != nullptr ? std::min(plan.tactorBus->channels(), plan.busCount) : 0;
    return plan;
}

void BlockControl::readMidiInput(BlockMidi& midi, int n) noexcept
{
    // The MIDI input is never played or passed through: its stage messages (Stage.h: program
    // change, the cue notes, CC 120/119) act at this block's start (beginStage), its other
    // channel messages go to the message thread for the mapping editor's "learn destination".
    // Its notes (note-on, note-off) also go to the scene (Scene::processMidi: the layered
    // keyboard takes exact notes from them), except the cue notes, on and off.
    notesInCount_ = notesInNext_ = 0;
    for (BlockMidi::Event event; midi.nextInput(event);) {
        if (stage_ != nullptr && stage_->handleMidi(event.data, event.size)) continue;   // cue steps, panic, resume
        if (event.size < 1 || event.size > 3 || event.data[0] < 0x80 || event.data[0] >= 0xF0) continue;
        const int status = event.data[0] & 0xF0;
        if ((status == 0x80 || status == 0x90) && event.size == 3
            && (stage_ == nullptr || (event.data[1] != stage_->nextNote() && event.data[1] != stage_->previousNote()))) {
            if (notesInCount_ < kMaxNotesIn) {
                core::MidiNoteEvent& e = notesIn_[static_cast<std::size_t>(notesInCount_++)];
                e.offset = std::clamp(event.offset, 0, std::max(0, n - 1));
                e.note = static_cast<std::uint8_t>(event.data[1] & 0x7F);
                e.velocity = static_cast<std::uint8_t>(status == 0x80 ? 0 : event.data[2] & 0x7F);
                e.channel = static_cast<std::uint8_t>(event.data[0] & 0x0F);
            } else {
                notesInDropped_.fetch_add(1, std::memory_order_relaxed);
            }
        }
        IncomingMidi m;
        for (int i = 0; i < event.size; ++i) m.bytes[i] = event.data[i];
        m.size = static_cast<std::uint8_t>(event.size);
        outputs_.pushIncoming(m);
    }
    // The buffer carries the mapping's events out from here (the host's adapter keeps it from
    // growing on the audio thread: Plugin/HostBlock.h).
    midi.beginOutput();
}

void BlockControl::hearStretch(const AudioBlock& buffer, const Listen& listen, const BlockPlan& plan, int pos, int len) noexcept
{
    notesRunning(pos, len);   // the notes of this stretch, before its input (Scene::processMidi)
    if (const int stems = engineStems(); stems > 0) {
        // Stems: each bus mixed to one mono channel, in the engine's stem order; an engine
        // built for another number of stems hears nothing (a layout change in flight).
        if (stems == plan.stemCount) {
            const float* in[kMaxStems + 2] {input_[0].data(), input_[1].data(), input_[2].data(),
                                            input_[3].data(), input_[4].data(), input_[5].data()};
            for (int k = 0; k < plan.stemCount; ++k) {
                const Bus& bus = listen.stems[static_cast<std::size_t>(k)];
                float* mono = input_[static_cast<std::size_t>(k)].data();
                std::copy_n(buffer.channels[bus.first] + pos, len, mono);
                for (int c = 1; c < bus.count; ++c) addInto(mono, buffer.channels[bus.first + c] + pos, len);
                if (bus.count > 1) std::transform(mono, mono + len, mono, [g = 1.0f / static_cast<float>(bus.count)](float x) { return x * g; });
            }
            // The main input after them (audio-touch's `mixed`, and its fallback while the
            // stems are silent).
            for (int c = 0; c < plan.listenCount; ++c)
                std::copy_n(buffer.channels[listen.first + c] + pos, len, input_[static_cast<std::size_t>(plan.stemCount + c)].begin());
            inputRunning(in, plan.stemCount + plan.listenCount, len);
        }
    } else if (plan.listenCount > 0) {
        // The scene hears this stretch of the input before its sound for it is rendered.
        const float* in[2] {input_[0].data(), input_[1].data()};
        for (int c = 0; c < plan.listenCount; ++c)
            std::copy_n(buffer.channels[listen.first + c] + pos, len, input_[static_cast<std::size_t>(c)].begin());
        inputRunning(in, plan.listenCount, len);
    }
    for (int c = 0; c < plan.throughCount; ++c)   // the main input, before the output overwrites it
        std::copy_n(buffer.channels[c] + pos, len, through_[static_cast<std::size_t>(c)].begin());
}

void BlockControl::renderStretch(const AudioBlock& buffer, const Listen& listen, const BlockPlan& plan, int pos, int len) noexcept
{
    float* left = buffer.channels[0];
    float* right = buffer.channels[1];
    std::fill_n(left + pos, len, 0.0f);
    std::fill_n(right + pos, len, 0.0f);
    renderRunning(left + pos, right + pos, len);
    if (plan.busRendered > 0 && plan.tactorBus->usesSound()) {   // the scene's own sound, before the track is mixed in
        for (int i = 0; i < len; ++i) tactorSound_[static_cast<std::size_t>(i)] = 0.5f * (left[pos + i] + right[pos + i]);
        plan.tactorBus->setSound(tactorSound_.data(), len);
    }
    if (plan.throughCount > 0) {
        addInto(left + pos, through_[0].data(), len);
        addInto(right + pos, through_[plan.throughCount > 1 ? 1 : 0].data(), len);
    }
    if (plan.busCount > 0) {   // after this stretch's input was read: the bus may share its channels
        std::array<float*, tactors::kMaxChannels> channels {};
        for (int c = 0; c < plan.busCount; ++c)
            channels[static_cast<std::size_t>(c)] = buffer.channels[listen.tactorChannel[static_cast<std::size_t>(c)]] + pos;
        if (plan.busRendered > 0) plan.tactorBus->render(channels.data(), len);
        for (int c = plan.busRendered; c < plan.busCount; ++c) std::fill_n(channels[static_cast<std::size_t>(c)], len, 0.0f);
    }
}

void BlockControl::finishBlock(const AudioBlock& buffer, BlockMidi& midi, const Listen& listen, const BlockPlan& plan, double blockStart) noexcept
{
    const int n = buffer.numSamples;
    // The app's tactor output with a voice coil handed the scene's sound: this block's output.
    if (auto* out = tactorOut_.load(std::memory_order_acquire); out != nullptr && out->wantsSound())
        out->pushSound(buffer.channels[0], buffer.channels[1], n);
    const auto busEnd = listen.tactorChannel.begin() + plan.busCount;
    for (int c = 2; c < buffer.numChannels; ++c)   // sidechain / extra inputs; not the Tactors bus
        if (std::find(listen.tactorChannel.begin(), busEnd, c) == busEnd) std::fill_n(buffer.channels[c], n, 0.0f);
    // Note-offs due before the block's end that no step reached (a gesture note's 50 ms).
    mapper_.flush(blockStart + (n - 0.5) / sampleRate_.load(std::memory_order_relaxed), mapOut_);
    deliver(&midi, blockStart, n);
}

void BlockControl::moveGridPastSkipped(int samplesPerTick) noexcept
{
    // Blocks skipped since the last one (the idle clock held the token) still passed on the host's
    // timeline: the 200 Hz grid moves on by their samples, so mapped MIDI stays on the samples of
    // the grid counted from prepare(). Their time is not added to the next step's dt: the idle
    // clock's steps covered it.
    if (const long long skipped = std::exchange(skippedSamples_, 0); skipped > 0) {
        const long long phase = (samplesToTick_ - skipped) % samplesPerTick;
        samplesToTick_ = static_cast<int>(phase < 0 ? phase + samplesPerTick : phase);
    }
}

void BlockControl::processBlock(const AudioBlock& buffer, BlockMidi& midi, const core::Transport& transport, bool offline,
                                const Listen& listen) noexcept
{
    const int n = buffer.numSamples;
    readMidiInput(midi, n);
    bypassed_ = false;
    const double wall = core::monotonicSeconds();
    lastAudioMs_.store(wall * 1e3, std::memory_order_relaxed);
    offlineRender_.store(offline, std::memory_order_relaxed);
    if (buffer.numChannels < 2 || n <= 0 || ! token_.tryTake()) {   // the idle clock is finishing an update: one silent block
        clearBlock(buffer);
        if (n > 0) skippedSamples_ += n;   // the grid still counts them
        return;
    }

    const double sr = sampleRate_.load(std::memory_order_relaxed);
    const int samplesPerTick = std::max(1, static_cast<int>(std::lround(sr / kControlRateHz)));
    moveGridPastSkipped(samplesPerTick);
    const BlockPlan plan = planBlock(buffer, listen);
    // The mapping's timeline at this block's first sample: the previous step's time plus the
    // samples rendered since.
    const double blockStart = clock_ + samplesSinceStep_ / sr;
    // Live samples step at their arrival's place (kMinStepSeconds): this block stands for the
    // wall-clock stretch [blockWall0, wall) just before this call.
    const SourceKind stepSource = source();
    const bool byArrival = ! offline && isLiveSource(stepSource);
    const double blockWall0 = wall - n / sr;
    const int minSpacing = std::max(1, static_cast<int>(std::lround(sr * kMinStepSeconds)));
    blockSamples_ = n;
    if (notesOffPending_.exchange(false, std::memory_order_relaxed)) {
        mapper_.allNotesOff(blockStart, mapOut_);   // after prepare(): nothing left hanging
        deliver(&midi, blockStart, n);
    }
    beginStage(&midi, blockStart, n);
    int pos = 0;
    while (pos < n) {
        if (samplesToTick_ <= 0) {
            core::Transport t = transport;
            if (t.valid && t.playing) {
                const double ahead = pos / sr;
                t.seconds += ahead;
                t.ppq += ahead * t.bpm / 60.0;
            }
            // Each step's levels belong to its place in the block: a 4096-sample block's 17 steps
            // reach the motors over 85 ms, not all at once.
            step(samplesSinceStep_ / sr, wall + pos / sr, ! offline, t, &midi, pos,
                 byArrival ? blockWall0 + (pos + 1) / sr : std::numeric_limits<double>::infinity());
            samplesToTick_ = samplesPerTick;
            samplesSinceStep_ = 0;
        }
        // A live sample waiting steps at its arrival's place when that comes before the grid's
        // next point (asked after every step: a block may hold several grid points).
        if (byArrival) {
            const double next = loop_.nextArrival(stepSource);
            if (next < wall) {   // arrived within (or before) this block's stretch
                const int at = std::clamp(static_cast<int>(std::floor((next - blockWall0) * sr)), 0, n - 1);
                const int when = std::max({at, pos, pos + minSpacing - samplesSinceStep_});
                if (when < pos + samplesToTick_) samplesToTick_ = when - pos;
                if (samplesToTick_ <= 0) continue;   // due now (no step closer than minSpacing, so this ends)
            }
        }
        const int len = std::min({n - pos, samplesToTick_, kInputScratch});
        hearStretch(buffer, listen, plan, pos, len);
        renderStretch(buffer, listen, plan, pos, len);
        pos += len;
        samplesToTick_ -= len;
        samplesSinceStep_ += len;
    }
    finishBlock(buffer, midi, listen, plan, blockStart);
    token_.release();
}

int BlockControl::engineStems() noexcept
{
    const engine::Engine* engine = runningEngine(); // a set list's current cue, else the single engine
    return engine != nullptr ? static_cast<int>(engine->config().sceneConfig.stems.size()) : 0;
}

void BlockControl::bypassBlock(const AudioBlock& buffer, BlockMidi& midi) noexcept
{
    clearBlock(buffer);
    for (BlockMidi::Event ignored; midi.nextInput(ignored);) {}   // the MIDI input is never passed through, bypassed or not
    midi.beginOutput();
    lastAudioMs_.store(core::monotonicSeconds() * 1e3, std::memory_order_relaxed);
    const int n = buffer.numSamples;
    if (bypassed_ || n <= 0 || ! token_.tryTake()) return;
    bypassed_ = true;
    mapper_.allNotesOff(clock_, mapOut_);
    deliver(&midi, clock_, n);
    token_.release();
}

void BlockControl::idleTick(double dt) noexcept
{
    const double now = core::monotonicSeconds();
    // A host rendering offline may take any time between blocks (a heavy bounce): its render is
    // not interrupted, whatever the gap, until a real-time block or prepare() comes.
    if (offlineRender_.load(std::memory_order_relaxed)) return;
    if (now * 1e3 - lastAudioMs_.load(std::memory_order_relaxed) <= kIdleAfterMs || ! token_.tryTake()) return;
    // A late timer (loaded machine) catches up with several updates so the control rate stays
    // at 200 Hz on average, as it does under an audio callback.
    const int updates = std::clamp(static_cast<int>(std::lround(dt * kControlRateHz)), 1, 4);
    const bool toMotors = idleDrivesMotors_.load(std::memory_order_relaxed);
    beginStage(nullptr, clock_, 0);
    for (int i = 0; i < updates; ++i) step(dt / updates, now - (updates - 1 - i) * dt / updates, toMotors, core::Transport {}, nullptr, 0);
    token_.release();
}

// ------------------------------------------------------------------------------------------------
// Stage (Stage.h): set list, panic, resume

engine::Engine* BlockControl::runningEngine() noexcept
{
    return runner_.running();
}

void BlockControl::renderRunning(float* left, float* right, int numSamples) noexcept
{
    instrument_.render(left, right, numSamples);
}

void BlockControl::inputRunning(const float* const* in, int channels, int numSamples) noexcept
{
    instrument_.processInput(in, channels, numSamples);
}

void BlockControl::notesRunning(int from, int len) noexcept
{
    const int first = notesInNext_;
    while (notesInNext_ < notesInCount_ && notesIn_[static_cast<std::size_t>(notesInNext_)].offset < from + len)
        notesIn_[static_cast<std::size_t>(notesInNext_++)].offset -= from;
    const int count = notesInNext_ - first;
    if (count == 0) return;
    instrument_.processMidi(notesIn_.data() + first, count);
}

void BlockControl::beginStage(BlockMidi* midi, double blockStart, int blockSamples) noexcept
{
    // Cue requests, panic and resume reach the engine and the cues (Live/Step/StepRunner.h) before
    // anything of this block is rendered.
    if (! instrument_.beginStage().silenceMapping) return;
    // Every note the mapping has sounding ends now, then All Sound Off and All Notes Off on all
    // 16 channels (MIDI 1.0, CC 120 / CC 123, value 0) for whatever the receivers still hold
    // (Mapper::panic, which `play --midi-out` sends too), at the block's first sample.
    mapper_.panic(blockStart, mapOut_);
    deliver(midi, blockStart, blockSamples);
}

} // namespace armadillo::live
