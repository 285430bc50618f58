#pragma once
// What the standalone app's wrapper (JUCE's StandalonePluginHolder) knows about the sound card,
// for the welcome and the status line: the output and input devices in use and whether JUCE muted
// the input ("Audio input is muted to avoid feedback loop"), which the app can unmute. In a
// plugin (a DAW owns the audio) all of it reports "not standalone" and changes nothing.
// Message thread only.
#include <juce_core/juce_core.h>

namespace armadillo::plugin {

struct StandaloneAudio {
    bool standalone = false;     ///< the app's wrapper was found (false in a plugin host)
    bool deviceOpen = false;     ///< an audio device is open
    juce::String deviceType;     ///< "ALSA", "JACK"...
    juce::String output;         ///< the output device's name ("" when none)
    juce::String input;          ///< the input device's name ("" when none)
    int inputChannels = 0;       ///< active input channels
    double sampleRate = 0.0;
    int inputMuted = -1;         ///< 1 muted, 0 not, -1 not standalone
};

StandaloneAudio standaloneAudio();
/// Unmutes (or mutes) the app's audio input; false outside the standalone app.
bool setStandaloneInputMuted(bool muted);
/// Opens JUCE's Audio/MIDI settings dialog of the app; false outside the standalone app.
bool showStandaloneAudioSettings();

} // namespace armadillo::plugin
