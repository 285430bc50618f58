#pragma once
// The tactor rig of the app and the plugin (issue 33, docs/TACTORS.md), the message thread's side:
// the VST3's Tactors output bus (a renderer built from the settings and handed to the control
// step, BlockControl::installTactors / offerTactors) and the standalone app's tactor output on a
// sound card or JACK (Live/TactorOutput.h, the same output `armadillo play --tactors` opens),
// fed by every control step that reaches the motors. The rendering, the safety guard on the
// samples and the outputs are the core's (Source/Tactors, Source/Live); this only turns the
// settings (SettingIds::tactor*) into them and reports what went wrong.
//
// Threads: the message thread (and prepareToPlay, with the control token held where said).
#include "Live/BlockControl.h"
#include "Live/ControlToken.h"
#include <juce_data_structures/juce_data_structures.h>
#include <memory>

namespace armadillo::live {
class TactorOutput;
}

namespace armadillo::plugin {

class TactorRig {
public:
    TactorRig(live::BlockControl& control, live::ControlToken& token);
    ~TactorRig();

    /// The settings' rig for `channels` output channels (the bus's, 0 = no limit), `motors` (9 or
    /// 12) and `sampleRate`: a prepared renderer, or null with `why` set.
    static std::unique_ptr<tactors::TactorRenderer> build(const juce::ValueTree& settings, int channels, int motors,
                                                          double sampleRate, juce::String& why);

    /// prepareToPlay, the token held by the caller: the bus (count 0: disabled) gets a renderer
    /// from the settings. "" or why the bus stays silent.
    juce::String prepareBus(const juce::ValueTree& settings, int busChannels, int motors, double sampleRate);
    /// A tactor setting changed (message thread): the bus gets a renderer of the new settings
    /// (handed over at the next block), and an open output is opened again with them. "" or why not.
    juce::String settingsChanged(const juce::ValueTree& settings, int motors);
    /// Timer: a renderer waiting for the hand-over is offered, the one given up is deleted.
    void tick();
    int busChannels() const noexcept { return busChannels_; }

    /// The app's output (the tactorDevice setting: "jack" or an ALSA PCM): opened, started and
    /// fed by the control step. "" or why not (the device missing, too few channels, no JACK
    /// server, a gain file out of range: nothing is left half-started).
    juce::String openOutput(const juce::ValueTree& settings, int motors);
    void closeOutput();
    bool outputOpen() const noexcept { return output_ != nullptr; }
    /// "jack: armadillo:tactor_1…tactor_9, 48000 Hz, 256 frames", "off", or the failure.
    juce::String outputStatus() const;
    /// The motor channel k plays (0-based; −1: silent or no such channel) in the output's map, or
    /// the bus's when no output is open, else in the settings' map for `motors` motors.
    int motorOfChannel(int channel, const juce::ValueTree& settings, int motors) const;

private:
    live::BlockControl& control_;
    live::ControlToken& token_;
    int busChannels_ = 0;
    double sampleRate_ = 48000.0;
    std::unique_ptr<tactors::TactorRenderer> waiting_;   // built, not yet taken by the hand-over
    tactors::ChannelMap busMap_ {};
    std::unique_ptr<live::TactorOutput> output_;
};

} // namespace armadillo::plugin
