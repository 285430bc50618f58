#pragma once
// The host's side of one audio block, handed to the rig's block clock (Live/Session/BlockControl.h): the
// AudioBuffer as an AudioBlock, the play head as a Transport, and the MidiBuffer as a BlockMidi.
// The host's MIDI buffer may be sized for a few events only, and a control step that emits
// several would grow it on the audio thread: the first block hands it storage sized in prepare()
// (swapWith moves pointers, and clear() keeps the storage), so adding events never allocates
// while the host reuses its buffer, as JUCE's wrappers do; events beyond that storage in one
// block are dropped (BlockControl counts them). A host that hands a fresh small buffer each block
// could still make it grow (JUCE's own wrappers do not): the plugin tests measure the real hosts'
// path.
// Threads: prepare() on the message thread with the audio stopped; the rest on the audio thread.
#include "Live/Session/BlockControl.h"
#include <juce_audio_processors/juce_audio_processors.h>

namespace armadillo::plugin {

class HostBlock final : private live::BlockMidi {
public:
    /// Bytes of MIDI events one block may carry (the storage handed to the host's buffer).
    static constexpr std::size_t kMidiStorageBytes = 64 * 1024;

    void prepare()
    {
        storage_.ensureSize(kMidiStorageBytes);
        storageGiven_ = false;
    }
    /// One block through the rig: `playHead` may be null; `offline` is the host's non-realtime render.
    void process(live::BlockControl& control, juce::AudioBuffer<float>& buffer, juce::MidiBuffer& midi, juce::AudioPlayHead* playHead,
                 bool offline, const live::BlockControl::Listen& listen) noexcept
    {
        attach(midi);
        control.processBlock(blockOf(buffer), *this, transportOf(playHead), offline, listen);
    }
    void process(live::BlockControl& control, juce::AudioBuffer<float>& buffer, juce::MidiBuffer& midi, juce::AudioPlayHead* playHead,
                 bool offline) noexcept
    {
        process(control, buffer, midi, playHead, offline, live::BlockControl::Listen {});
    }
    /// The host's bypass (BlockControl::bypassBlock).
    void bypass(live::BlockControl& control, juce::AudioBuffer<float>& buffer, juce::MidiBuffer& midi) noexcept
    {
        attach(midi);
        control.bypassBlock(blockOf(buffer), *this);
    }

    static live::AudioBlock blockOf(juce::AudioBuffer<float>& buffer) noexcept
    {
        return {buffer.getArrayOfWritePointers(), buffer.getNumChannels(), buffer.getNumSamples()};
    }
    static core::Transport transportOf(juce::AudioPlayHead* playHead) noexcept
    {
        core::Transport t;
        if (playHead == nullptr) return t;
        if (const auto pos = playHead->getPosition()) {
            t.valid = pos->getTimeInSeconds().hasValue() || pos->getPpqPosition().hasValue();
            t.playing = pos->getIsPlaying();
            t.looping = pos->getIsLooping();
            t.seconds = pos->getTimeInSeconds().orFallback(0.0);
            t.ppq = pos->getPpqPosition().orFallback(0.0);
            t.bpm = pos->getBpm().orFallback(120.0);
        }
        return t;
    }

private:
    void attach(juce::MidiBuffer& midi) noexcept
    {
        buffer_ = &midi;
        next_ = midi.cbegin();
        end_ = midi.cend();
        bytes_ = 0;
    }
    bool nextInput(Event& e) noexcept override
    {
        if (next_ == end_) return false;
        const auto m = *next_;
        ++next_;
        e.data = m.data;
        e.size = m.numBytes;
        e.offset = m.samplePosition;
        return true;
    }
    void beginOutput() noexcept override
    {
        if (! storageGiven_) {
            buffer_->swapWith(storage_);
            storageGiven_ = true;
        }
        buffer_->clear();
        next_ = end_ = buffer_->cend();
        bytes_ = 0;
    }
    bool add(const std::uint8_t* data, int size, int offset) noexcept override
    {
        const std::size_t bytes = static_cast<std::size_t>(size) + sizeof(juce::int32) + sizeof(juce::uint16);   // MidiBuffer's record
        if (bytes_ + bytes > kMidiStorageBytes) return false;
        buffer_->addEvent(data, size, offset);
        bytes_ += bytes;
        return true;
    }

    juce::MidiBuffer storage_;
    bool storageGiven_ = false;
    juce::MidiBuffer* buffer_ = nullptr;
    juce::MidiBufferIterator next_ {}, end_ {};
    std::size_t bytes_ = 0;
};

} // namespace armadillo::plugin
