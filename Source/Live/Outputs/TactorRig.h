#pragma once
// The tactors of an audio-clocked instrument (issue 33, docs/TACTORS.md; below JUCE since issue
// 45): the VST3's Tactors output bus (a renderer built from the settings and handed to the
// control step, BlockControl::installTactors / offerTactors) and the standalone app's tactor
// output on a sound card or JACK (Live/Outputs/TactorOutput.h, the same output `armadillo play --tactors`
// opens), fed by every control step that reaches the motors. The front end only turns its
// settings into a TactorSettings and shows what this says went wrong.
//
// Threads: the message thread (and prepareToPlay, with the control token held where said).
#include "Live/Session/BlockControl.h"
#include "Live/Step/ControlToken.h"
#include <memory>
#include <string>

namespace armadillo::live {

class TactorOutput;

/// The tactors as a front end's settings name them (plain text, as the CLI's options take them).
struct TactorSettings {
    std::string model;     ///< "erm" | "lra" | "voice-coil" ("" = the default)
    std::string map;       ///< the channel map's text ("" = channel k plays motor k)
    std::string gains;     ///< a gain file's path ("" = none)
    bool sound = false;    ///< a voice coil carries the scene's own sound
    std::string device;    ///< the app's output: "jack" or an ALSA PCM ("" = none chosen)
    std::string connect;   ///< JACK: connect tactor_k to ports matching this
};

class TactorRig {
public:
    TactorRig(BlockControl& control, ControlToken& token);
    ~TactorRig();
    TactorRig(const TactorRig&) = delete;
    TactorRig& operator=(const TactorRig&) = delete;

    /// The settings' rig for `channels` output channels (the bus's, 0 = no limit), `motors` (9 or
    /// 12) and `sampleRate`: a prepared renderer, or null with `why` set.
    static std::unique_ptr<tactors::TactorRenderer> build(const TactorSettings& settings, int channels, int motors, double sampleRate,
                                                          std::string& why);

    /// prepareToPlay, the token held by the caller: the bus (count 0: disabled) gets a renderer
    /// from the settings. "" or why the bus stays silent.
    std::string prepareBus(const TactorSettings& settings, int busChannels, int motors, double sampleRate);
    /// A tactor setting changed (message thread): the bus gets a renderer of the new settings
    /// (handed over at the next block), and an open output is opened again with them. "" or why not.
    std::string settingsChanged(const TactorSettings& settings, int motors);
    /// Timer: a renderer waiting for the hand-over is offered, the one given up is deleted.
    void tick();
    int busChannels() const noexcept { return busChannels_; }

    /// The app's output (TactorSettings::device): opened, started and fed by the control step.
    /// "" or why not (the device missing, too few channels, no JACK server, a gain file out of
    /// range: nothing is left half-started).
    std::string openOutput(const TactorSettings& settings, int motors);
    void closeOutput();
    bool outputOpen() const noexcept { return output_ != nullptr; }
    /// "jack: armadillo:tactor_1…tactor_9, 48000 Hz, 256 frames", "off", or the failure.
    std::string outputStatus() const;
    /// The motor channel k plays (0-based; −1: silent or no such channel) in the output's map, or
    /// the bus's when no output is open, else in the settings' map for `motors` motors.
    int motorOfChannel(int channel, const TactorSettings& settings, int motors) const;

private:
    BlockControl& control_;
    ControlToken& token_;
    int busChannels_ = 0;
    double sampleRate_ = 48000.0;
    std::unique_ptr<tactors::TactorRenderer> waiting_;   // built, not yet taken by the hand-over
    tactors::ChannelMap busMap_ {};
    std::unique_ptr<TactorOutput> output_;
};

} // namespace armadillo::live
